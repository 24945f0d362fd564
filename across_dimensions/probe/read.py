"""Everything the probe reads from a running game, in one place.

Each of the game's systems keeps its state under its name in ``game.states`` (``weapons``,
``enemies``, ``manipulation``, ``crystals``, ...; None where a level has no use for it), or on
its entities' data; the camera rig and the energy bar have their own properties. When that
moves, only this module changes. Functions take the :class:`~across_dimensions.game.sim.Game` and return plain
numbers, arrays and small records, never the systems' own objects (except entity ids).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..game import section_collision
from ..game.enemies import WEAK_W
from ..game.player import EYE_HEIGHT, HALF_WIDTH, HEIGHT, player_box
from ..game.player_bodies import player_collide
from ..game.systems.manipulation import AXES as TURN_AXES
from ..game.systems.outcome import in_goal

#: ``TURN_AXES[i][0]``: the Actions field (forward, right, w) that turns a held object's
#: i-th plane; ``WEAK_W``: how near in w a bullet must come to an enemy's weak spot.
__all__ = ["EYE_HEIGHT", "HALF_WIDTH", "HEIGHT", "TURN_AXES", "WEAK_W", "in_goal", "player_box"]


@dataclass(frozen=True)
class Thing:
    """A 4D thing the probe may walk to, shoot or push: entity id, name and centre ``(4,)``."""

    id: int
    name: str
    center: np.ndarray
    radius: float


def _state(game, system: str):
    """A system's state (None where the level gives it nothing to keep)."""
    return getattr(game.states, system, None)


# ------------------------------------------------------------------ player and level
def feet(game) -> np.ndarray:
    """The player's feet ``[x, y, z, w]``, a copy."""
    return game.player.position.copy()


def view(game) -> tuple[float, float]:
    """The player's yaw and pitch, radians."""
    return float(game.player.yaw), float(game.player.pitch)


def eye(game) -> np.ndarray:
    """The player's eye ``(3,)``."""
    return game.player.eye()


def on_ground(game) -> bool:
    return bool(game.player.on_ground)


def velocity(game) -> np.ndarray:
    return game.player.velocity.copy()


def won(game) -> bool:
    return game.outcome == "complete"


def w_range(game) -> tuple[float, float]:
    return tuple(game.level.w_range)


def goal(game):
    """The goal's ``center (3,)``, ``size (3,)`` and ``w_range`` (None: any w)."""
    g = game.level.goal
    return g.center, g.size, g.w_range


def energy(game) -> float | None:
    """The bar in energy units, or None in a level without one."""
    return None if game.energy is None else game.energy.milli / 1000.0


def w_cost(game) -> float:
    """Energy per unit of w travelled (0 when free)."""
    return game.level.energy.w_cost if game.energy is not None else 0.0


def events(game) -> list:
    """This tick's events, in order (frozen records with a ``kind``)."""
    return list(game.events)


def count(game, kind: str) -> int:
    """Events of ``kind`` since the start."""
    return int(game.event_counts.get(kind, 0))


# ------------------------------------------------------------------ the world around the player
def blocked_box(game, lo, hi, w: float) -> bool:
    """Is the box ``lo..hi (3,)`` inside anything solid in the slice at ``w`` (boxes, sections)?"""
    boxes = game.colliders_at(w)
    if len(boxes) and np.any(np.all((lo < boxes[:, 1]) & (hi > boxes[:, 0]), axis=1)):
        return True
    found = [t for t in game.sections_at(w) if len(t)]
    if found and section_collision.box_blocked(lo, hi, np.concatenate(found)):
        return True
    return any(np.all(lo < c[:3] + h) and np.all(hi > c[:3] - h) for c, h in _body_boxes(game, w))


def _body_boxes(game, w: float) -> list:
    """Rigid bodies (not bullets) in the slice at ``w``: centre ``(4,)`` and half size, taken
    as a box of half its reach (exact for an unturned hypercube, a little small for a ball)."""
    out = []
    for e in game.entities.of_kind("body"):
        c = np.asarray(e.center(game), float)
        h = 0.5 * e.radius
        if abs(c[3] - w) < h:
            out.append((c, h))
    return out


def touched_bodies(game) -> list[int]:
    """Entity ids of the rigid bodies the player's box touches now."""
    if game.physics is None:
        return []
    p = game.player.position
    _, touched = player_collide(game.physics, p, HALF_WIDTH, HEIGHT)
    return [game.entity_of_body[b] for b in touched if b in game.entity_of_body]


# ------------------------------------------------------------------ 4D things
def names(game) -> dict[int, str]:
    """Every live entity's name, by id."""
    return {e.id: e.name for e in game.entities}


def center_of(game, entity_id: int) -> np.ndarray | None:
    """A live entity's centre ``(4,)``, or None once it is gone."""
    e = game.entities.get(entity_id)
    return None if e is None else np.asarray(e.center(game), float)


def _things(game, kind: str) -> list[Thing]:
    return [
        Thing(e.id, e.name, np.asarray(e.center(game), float), float(e.radius)) for e in game.entities.of_kind(kind)
    ]


def crystals(game) -> list[Thing]:
    """Crystals lying in the level now."""
    return _things(game, "crystal")


def regrowing(game) -> int:
    """Crystals taken that will grow back."""
    state = _state(game, "crystals")
    return 0 if state is None else len(state.regrowing)


def bodies(game) -> list[Thing]:
    """Rigid bodies (crates, balls), bullets excluded."""
    return _things(game, "body")


def body_named(game, name: str) -> Thing | None:
    return next((b for b in bodies(game) if b.name == name), None)


def targets(game, hit: bool | None = False) -> list[Thing]:
    """Switches: those not yet hit (default), those hit, or all (``hit=None``)."""
    out = []
    for e in game.entities.of_kind("target"):
        if hit is None or e.data.hit == hit:
            out.append(Thing(e.id, e.name, np.asarray(e.center(game), float), float(e.radius)))
    return out


def target_spec(game, target_id: int):
    """The level's entry of a target (``opens``, ``disguised``)."""
    return game.entities.get(target_id).data.spec


# ------------------------------------------------------------------ weapons
def weapons(game) -> list:
    """The weapons a run of the level can have (owned or lying in a pickup), in slot order."""
    return list(game.level.weapons)


def owned(game, k: int) -> bool:
    """Does the player own weapon ``k`` (brought along, or picked up)?"""
    ars = _state(game, "weapons")
    return ars is not None and bool(ars.owned[k])


def pickups(game, kind: str | None = None) -> list[Thing]:
    """Weapon pickups still lying in the level (of ``kind``, when given)."""
    return [t for t in _things(game, "pickup") if kind is None or game.entities.get(t.id).data.spec.weapon == kind]


def slot(game) -> int:
    ars = _state(game, "weapons")
    return 0 if ars is None else ars.slot


def weapon_ready(game) -> bool:
    """Has the weapon in hand finished its cooldown?"""
    ars = _state(game, "weapons")
    return ars is not None and bool(ars.specs) and game.tick >= ars.ready[ars.slot]


def live_bullets(game) -> int:
    ars = _state(game, "weapons")
    return 0 if ars is None else len(ars.bullets)


def rounds(game, k: int) -> int:
    """Rounds left in weapon ``k``; -1 for a weapon paid in energy."""
    ars = _state(game, "weapons")
    if ars is None:
        return weapons(game)[k].ammo if weapons(game)[k].kind == "gun" else -1
    return int(ars.rounds[k])


# ------------------------------------------------------------------ enemies
@dataclass(frozen=True)
class Foe:
    """An enemy: entity id, name, centre ``(4,)``, state, health and weak spot offset (or None)."""

    id: int
    name: str
    center: np.ndarray
    state: str
    health: int
    weak_spot: np.ndarray | None
    loot: bool
    opens: str


def foes(game, alive: bool = True) -> list[Foe]:
    """The level's enemies (only the living ones by default)."""
    hive = _state(game, "enemies")
    if hive is None:
        return []
    out = []
    for eid in hive.foes:
        e = game.entities.get(eid)
        if e is None or (alive and not e.data.alive):
            continue
        f = e.data
        out.append(
            Foe(eid, e.name, f.centre.copy(), f.state, f.health, f.spec.weak_spot, f.loot is not None, f.spec.opens)
        )
    return out


# ------------------------------------------------------------------ manipulation
@dataclass(frozen=True)
class Handle:
    """A manipulable object: entity id, name, centre ``(4,)``, angles now (degrees per plane,
    in the order the walking keys turn them), limits, reach and snapping step."""

    id: int
    name: str
    center: np.ndarray
    angles: dict
    limits: dict
    reach: float
    step: float | None


def handles(game) -> list[Handle]:
    out = []
    for e in game.entities.of_kind("manipulable"):
        d = e.data
        planes = [p for p in d.planes if p != "w"]
        out.append(
            Handle(
                e.id,
                e.name,
                np.asarray(e.center(game), float),
                {p: d.offsets[p] / 1000.0 for p in planes},
                {p: tuple(v / 1000.0 for v in d.limits(p)) for p in planes},
                float(d.spec.reach),
                d.spec.step,
            )
        )
    return out


def held(game) -> int | None:
    """The manipulable held now (entity id), or None."""
    tool = _state(game, "manipulation")
    return None if tool is None else tool.held


# ------------------------------------------------------------------ the 4D camera
def camera_mode(game) -> str:
    """``synced``, ``frustum`` or ``returning``."""
    return game.camera.mode


def slice_away_deg(game) -> float:
    """How far the slice is turned from the 90-degree orientation it last rested on, degrees."""
    from ..game.slice_pay import away_deg

    return away_deg(game.camera)


def slice_cost(game) -> float:
    """Energy per degree of slice turn (0: free, or no bar)."""
    return game.level.energy.slice_cost if game.energy is not None else 0.0


def orbit_deg(game) -> float:
    """How far the detached camera has orbited since the switch, degrees."""
    return float(np.degrees(game.camera.orbit))


def image_of(game, point4: np.ndarray) -> np.ndarray | None:
    """Where ``point4`` shows through the detached frustum camera, in slice space ``(3,)``;
    None while synced or when it is behind the camera."""
    from ..game.systems.camera import frustum_view

    v = frustum_view(game)
    if v is None:
        return None
    pose, place = v
    pts, scale = game.camera.project_points(np.asarray(point4, float)[None], pose, place)
    return None if scale[0] <= 0 else pts[0]
