"""Level tables of the enemies (level format 2): ``[[enemy]]``, their ``[[animation]]``
keyframes, ``[[checkpoint]]`` and the player's ``[health]``.

Like the other tables of the game's systems (:mod:`.gameplay`), each is a model of
:class:`~.fields.Field` s and a spec dataclass; a level without enemies has no health (the player
cannot be hurt).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fields import Field
from .limits import (
    ANGLE,
    COORD,
    ENEMY_DAMAGE,
    ENEMY_HEALTH,
    ENEMY_SIZE,
    ENEMY_SPEED,
    ENERGY,
    KEY_TIME,
    MAX_NAME_CHARS,
    MILLI,
    PLAYER_HEALTH,
    SIZE,
    WEAPON_REACH,
    WEAPON_TIME,
    Range,
)

ENEMY_KINDS = ("swarm", "morph")
ENEMY_COLORS = {"swarm": (0.95, 0.35, 0.85, 1.0), "morph": (0.55, 0.85, 0.35, 1.0)}
#: Each kind's defaults: ``size`` is the body's reach from its centre (metres).
ENEMY_DEFAULTS = {
    "swarm": {"size": 0.8, "asset": None},
    "morph": {"size": 1.0, "asset": "meshes/tree.obj"},
}
#: A weak spot must lie off the body's own w (else it would just be the body), and
#: within a bullet's swing: offsets in w between these, units of w.
WEAK_W = Range(0.3, 5.0, "units of w")
ENEMY_TABLE = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "kind": Field("string", choices=ENEMY_KINDS),
    "position": Field("vector", 4, range=COORD),
    "health": Field("number", default=3.0, range=ENEMY_HEALTH, sign="positive"),
    "size": Field("number", default=None, range=ENEMY_SIZE, sign="positive"),
    "asset": Field("asset", default=None),
    "depth": Field("number", default=1.2, range=SIZE, sign="positive"),
    "color": Field("color", default=None),
    "animation": Field("text", default="", range=Range(0, MAX_NAME_CHARS)),
    "weak_spot": Field("vector", 4, default=None, range=COORD),
    "loot": Field("number", default=0.0, range=ENERGY, sign="nonnegative"),
    "loot_offset": Field("vector", 4, default=None, range=COORD),
    "damage": Field("number", default=15.0, range=ENEMY_DAMAGE, sign="nonnegative"),
    "speed": Field("number", default=2.5, range=ENEMY_SPEED, sign="nonnegative"),
    "sight": Field("number", default=14.0, range=WEAPON_REACH, sign="positive"),
    "reach": Field("number", default=8.0, range=WEAPON_REACH, sign="positive"),
    "opens": Field("text", default="", range=Range(0, MAX_NAME_CHARS)),
}
ANIMATION_TABLE = {
    "name": Field("text", range=Range(0, MAX_NAME_CHARS)),
    "time": Field("number", range=KEY_TIME, sign="nonnegative"),
    "offset": Field("vector", 4, default=(0.0, 0.0, 0.0, 0.0), range=COORD),
    "rotation": Field("angles", default=None, range=ANGLE),
}
CHECKPOINT_TABLE = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "position": Field("vector", 4, range=COORD),
    "size": Field("vector", 3, default=(3.0, 3.0, 3.0), range=SIZE, sign="positive"),
    "yaw": Field("number", default=0.0, range=ANGLE),
}
HEALTH_TABLE = {
    "max": Field("number", default=100.0, range=PLAYER_HEALTH, sign="positive"),
    "invulnerable": Field("number", default=2.0, range=WEAPON_TIME, sign="nonnegative"),
}
#: The tables of this module, by top-level key.
MODELS = {"enemy": ENEMY_TABLE, "animation": ANIMATION_TABLE, "checkpoint": CHECKPOINT_TABLE, "health": HEALTH_TABLE}


@dataclass
class KeySpec:
    """One keyframe of an ``[[animation]]``: at ``time`` seconds the body is turned by
    ``rotation_deg`` (plane -> degrees) and moved by ``offset (4,) float64`` from its centre."""

    time: float
    offset: np.ndarray
    rotation_deg: dict


@dataclass
class EnemySpec:
    """An ``[[enemy]]``: a 4D creature guarding its post at ``position (4,) float64``.

    ``kind`` is ``"swarm"`` (hyperspheres) or ``"morph"`` (a 3D ``asset`` lifted
    ``depth`` deep); ``size`` its reach; ``health`` the hits it takes;
    ``keys`` its animation (None: the kind's own); ``weak_spot (4,)`` the
    offset of the only place it can be hurt (None: anywhere); ``loot_milli``
    the energy of the crystal inside it, at ``loot_offset (4,)``; ``damage``
    what one of its shots takes from the player; ``speed`` m/s; ``sight`` and
    ``reach`` how near the player must be for it to come, and to shoot;
    ``opens`` the ``[[object]]`` removed when it is defeated.
    """

    name: str
    kind: str
    position: np.ndarray
    health: int = 3
    size: float = 0.8
    asset: object = None
    depth: float = 1.2
    color: tuple = (1.0, 1.0, 1.0, 1.0)
    keys: list | None = None
    weak_spot: np.ndarray | None = None
    loot_milli: int = 0
    loot_offset: np.ndarray | None = None
    damage: float = 15.0
    speed: float = 2.5
    sight: float = 14.0
    reach: float = 8.0
    opens: str = ""


@dataclass
class CheckpointSpec:
    """A ``[[checkpoint]]``: touching the box ``size (3,)`` round ``position (4,)`` (feet,
    at its w) makes it where the player comes back after dying, facing ``yaw_deg``."""

    name: str
    position: np.ndarray
    size: np.ndarray
    yaw_deg: float = 0.0


@dataclass
class HealthSpec:
    """``[health]``: the player's health and the seconds of safety after coming back."""

    maximum: float = 100.0
    invulnerable: float = 2.0


def read_health(r, data, has_enemies: bool) -> HealthSpec | None:
    """The ``[health]`` table; absent: defaults when the level has enemies, else None (no health)."""
    v = r.values(data, "health", HEALTH_TABLE)
    if v is None:
        return HealthSpec() if has_enemies else None
    return HealthSpec(v["max"], v["invulnerable"])


def read_checkpoints(r, data, w_range) -> list[CheckpointSpec]:
    """The ``[[checkpoint]]`` tables, in order."""
    out = []
    for i, t in enumerate(r.entries(data, "checkpoint", "top level", lambda k: f"[[checkpoint]] #{k}"), 1):
        where = f"[[checkpoint]] #{i}"
        r.unknown(t, CHECKPOINT_TABLE, where)
        name = r.read(t, CHECKPOINT_TABLE, where, keys=("name",), name=f"checkpoint{i}")["name"]
        where = f"[[checkpoint]] #{i} '{name}'"
        n = len(r.problems)
        v = r.read(t, CHECKPOINT_TABLE, where, keys=("position", "size", "yaw"))
        w = v["position"][3]
        if len(r.problems) == n and w_range is not None and not w_range[0] <= w <= w_range[1]:
            lo, hi = w_range
            r.problem(where, f"field 'position': w = {w:g} is outside the level's w_range [{lo:g}, {hi:g}]")
        out.append(CheckpointSpec(name, v["position"], np.asarray(v["size"], np.float64), v["yaw"]))
    return out


def read_animations(r, data) -> dict[str, list[KeySpec]]:
    """The ``[[animation]]`` keyframes, grouped by name and sorted by time."""
    out: dict[str, list[KeySpec]] = {}
    for i, t in enumerate(r.entries(data, "animation", "top level", lambda k: f"[[animation]] #{k}"), 1):
        where = f"[[animation]] #{i}"
        r.unknown(t, ANIMATION_TABLE, where)
        v = r.read(t, ANIMATION_TABLE, where)
        if v["name"]:
            where = f"[[animation]] #{i} '{v['name']}'"
        keys = out.setdefault(v["name"], [])
        if any(k.time == v["time"] for k in keys):
            r.problem(where, f"field 'time': animation '{v['name']}' already has a keyframe at {v['time']:g} s")
        keys.append(KeySpec(v["time"], np.asarray(v["offset"], np.float64), v["rotation"]))
    for keys in out.values():
        keys.sort(key=lambda k: k.time)
    return out


def read_enemies(r, data, animations: dict, object_names) -> list[EnemySpec]:
    """The ``[[enemy]]`` tables; ``animation`` must name keyframes of ``animations``."""
    out = []
    for i, t in enumerate(r.entries(data, "enemy", "top level", lambda k: f"[[enemy]] #{k}"), 1):
        where = f"[[enemy]] #{i}"
        r.unknown(t, ENEMY_TABLE, where)
        name = r.read(t, ENEMY_TABLE, where, keys=("name",), name=f"enemy{i}")["name"]
        where = f"[[enemy]] #{i} '{name}'"
        n = len(r.problems)
        kind = r.read(t, ENEMY_TABLE, where, keys=("kind",))["kind"]
        kind_ok = len(r.problems) == n
        defaults = ENEMY_DEFAULTS.get(kind, ENEMY_DEFAULTS["swarm"])
        v = r.read(t, ENEMY_TABLE, where, keys=[k for k in ENEMY_TABLE if k not in ("name", "kind", "asset")],
                   size=defaults["size"], color=ENEMY_COLORS.get(kind))  # fmt: skip
        asset = None
        if "asset" in t:
            asset = r.read(t, ENEMY_TABLE, where, keys=("asset",))["asset"]
            if kind_ok and kind != "morph":
                r.problem(where, f"field 'asset': a {kind} is made of 4D primitives; only a morph lifts an asset")
        elif kind_ok and defaults["asset"] is not None:
            from .resources import resolve_asset

            asset = resolve_asset(defaults["asset"])
        if "health" in t and v["health"] != int(v["health"]):
            r.problem(where, f"field 'health': expected a whole number of hits, got {v['health']:g}")
        keys = None
        if v["animation"]:
            keys = animations.get(v["animation"])
            if not keys:
                r.problem(
                    where,
                    f"field 'animation': '{v['animation']}' has no keyframes "
                    f'(add [[animation]] tables with name = "{v["animation"]}", time and rotation/offset)',
                )
        weak = v["weak_spot"]
        if weak is not None and not WEAK_W.lo <= abs(weak[3]) <= WEAK_W.hi:
            r.problem(
                where,
                f"field 'weak_spot': its w offset {weak[3]:g} must be {WEAK_W.lo:g} to {WEAK_W.hi:g} either way "
                "(a weak spot hides at another w than the body)",
            )
        if v["opens"] and v["opens"] not in object_names:
            r.problem(where, f"field 'opens': no [[object]] is named {v['opens']!r}")
        out.append(
            EnemySpec(
                name,
                kind,
                v["position"],
                int(v["health"]),
                v["size"],
                asset,
                v["depth"],
                v["color"],
                keys,
                weak,
                int(round(v["loot"] * MILLI)),
                v["loot_offset"],
                v["damage"],
                v["speed"],
                v["sight"],
                v["reach"],
                v["opens"],
            )
        )
    return out
