"""The player's weapons: the 120-cell gun, the w-pull blast and the wire field (paper, section 5).

The player finds weapons in the level (``[[pickup]]``, :mod:`~..world.pickups`) or brings
them from earlier levels of the campaign (``level.arsenal``); ``level.weapons`` are those a
run of the level can have, as the level tunes them (``[[weapon]]``,
:class:`~..world.gameplay.WeaponSpec`). The weapons system keeps one :class:`Arsenal` for
them (``game.states.weapons``, made with the game by ``systems/weapons.py``). The systems
that use it:

- ``systems/weapons.py`` (before physics): picking weapons up, switching, firing, the
  blast's pull and the field's timer, and steering bullets that have not touched anything;
- ``systems/bullets.py`` (after physics): contacts, targets, expiry.

A bullet is a dynamic hypersphere body drawn as a small 120-cell. Until its
first contact its path is prescribed: straight ahead at the muzzle speed, with
``w = w0 + amplitude * sin(2 pi t / period)`` about the player's w at firing
(the paper's Fig. "4D Translation"). Each tick its velocity is set so that the
physics tick lands it exactly there; from its first contact on it is left to
physics (it pushes, falls and rolls: Fig. "4D Physics").
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.shapes import make_shape
from ..physics import BodyDef
from ..world.gameplay import TargetSpec, WeaponSpec
from ..world.pickups import KEY_OF, PickupSpec
from ..world.scene import Object4
from .entities import Motion, Rigid, Scripted, reach
from .events import WeaponAcquired
from .system import derived, fixed

#: Kinds of entity the blast pulls and the field shows (bullets are the gun's own).
AFFECTED_KINDS = ("object", "body", "target", "crystal")
BULLET_COLOR = (0.55, 0.95, 1.0, 1.0)
#: Muzzle offset beyond the player's box half width (0.3 m), metres: a new bullet
#: must not start inside the player, who is pushed out of bodies.
MUZZLE = 0.5
FLASH_TICKS = 8  # muzzle flash on the HUD
REFUSED_TICKS = 60  # "NOT ENOUGH ENERGY" stays a second
HIT_MARKER_TICKS = 18
ACQUIRED_TICKS = 6 * 60  # the notice that teaches a weapon just picked up: time to read it
#: How each kind of pickup looks: a small polychoron of its own shape and colour.
PICKUP_LOOKS = {
    "gun": ("120-cell", (0.55, 0.95, 1.0, 1.0)),
    "blast": ("24-cell", (1.0, 0.6, 0.25, 1.0)),
    "field": ("tesseract", (0.45, 1.0, 0.5, 1.0)),
}
PICKUP_SPIN = {"xw": 45.0, "zw": 30.0}  # degrees/s: turning through the slice, it reads as 4D


@dataclass
class Bullet:
    """A bullet's state (``Entity.data``).

    ``origin (4,)`` is where it was fired from, ``velocity (4,)`` its muzzle
    velocity (no w part), ``w0`` the player's w at firing, ``born`` the tick.
    ``contacted`` turns True at its first contact: from then on physics alone moves it.
    """

    spec: WeaponSpec = fixed()
    origin: np.ndarray
    velocity: np.ndarray
    w0: float
    born: int
    contacted: bool = False

    def planned(self, ticks: int, dt: float) -> np.ndarray:
        """Where the bullet is ``ticks`` ticks after firing if it touches nothing, ``(4,) float64``."""
        t = ticks * dt
        p = self.origin + self.velocity * t
        p[3] = self.w0 + self.spec.amplitude * np.sin(2.0 * np.pi * t / self.spec.period)
        return p


@dataclass
class Target:
    """A target's state (``Entity.data``)."""

    spec: TargetSpec = fixed()
    hit: bool = False


@dataclass
class Shifted(Motion):
    """A scripted motion moved along w by the blast: ``base`` plus ``offset`` in w.

    ``previous`` is the offset a tick ago, for drawing between ticks.
    """

    base: Motion = fixed()
    offset: float = 0.0
    previous: float = derived(default=0.0)  # drawing only

    def model(self, game, alpha=None):
        m = np.array(self.base.model(game, alpha), dtype=np.float64)
        m[3, 4] += self.offset if alpha is None else self.previous + alpha * (self.offset - self.previous)
        return m

    def center(self, game):
        c = np.array(self.base.center(game), dtype=np.float64)
        c[3] += self.offset
        return c


@dataclass
class Pull:
    """One entity on its way to ``to_w`` between ticks ``start`` and ``end`` (the blast)."""

    entity: int
    from_w: float
    to_w: float
    start: int
    end: int

    def w_at(self, tick: int) -> float:
        """Where it should be at ``tick``: a smoothstep, no teleport, no jolt at either end."""
        s = min(max((tick - self.start) / max(self.end - self.start, 1), 0.0), 1.0)
        s = s * s * (3.0 - 2.0 * s)
        return self.from_w + (self.to_w - self.from_w) * s


@dataclass
class Arsenal:
    """The player's weapons and what they have set going (``game.states.weapons``).

    Attributes
    ----------
    specs : list of WeaponSpec
        The weapons a run of the level can have (``level.weapons``), in key order.
    owned : list of bool
        Which of them the player has (brought along the campaign or picked up).
    slot : int
        The weapon in hand (index into ``specs``; it is owned whenever any is).
    ready : list of int
        Tick from which each weapon may be used again.
    bullets : list of int
        Live bullet entity ids, oldest first.
    pulls : list of Pull
    wired : dict of int to (str, int)
        Entities the field shows as wireframes: their own style and the tick it ends.
    """

    specs: list[WeaponSpec] = fixed()
    owned: list[bool] = field(default_factory=list)
    slot: int = 0
    ready: list[int] = field(default_factory=list)
    bullets: list[int] = field(default_factory=list)
    pulls: list[Pull] = field(default_factory=list)
    wired: dict[int, tuple[str, int]] = field(default_factory=dict)
    pulls_done: list[int] = field(default_factory=list)
    rounds: list[int] = field(default_factory=list)  # rounds left per weapon; -1 for those paid in energy
    crystals_seen: int = 0  # crystal pickups already turned into rounds
    fired_tick: int = -(10**9)
    refused_tick: int = -(10**9)
    refused_text: str = ""
    hit_tick: int = -(10**9)
    acquired_tick: int = -(10**9)
    acquired: int = 0  # the slot of the weapon picked up last (the notice teaches it)
    bullet_mesh: object = fixed(default=None)
    bullet_reach: float = fixed(default=1.0)

    @property
    def current(self) -> WeaponSpec:
        return self.specs[self.slot]

    @property
    def armed(self) -> bool:
        """Does the player hold a weapon (own any)?"""
        return bool(self.specs) and self.owned[self.slot]

    def slot_of(self, kind: str) -> int | None:
        """The slot of the owned weapon of ``kind``, or None."""
        return next((k for k, s in enumerate(self.specs) if s.kind == kind and self.owned[k]), None)


@dataclass
class Pickup:
    """A pickup's state (``Entity.data``): the level entry it came from."""

    spec: PickupSpec = fixed()


def spawn_pickup(game, spec: PickupSpec):
    """Put a weapon pickup in the game: a small glowing polychoron of its kind, turning through the slice."""
    shape, color = PICKUP_LOOKS[spec.weapon]
    mesh = make_shape(shape).with_color(color)
    scale = spec.size / max(reach(mesh), 1e-9)
    obj = Object4.prop(spec.name, mesh, spec.position, scale, {}, dict(PICKUP_SPIN))
    data = Pickup(spec)
    return game.entities.spawn("pickup", spec.name, mesh, Scripted(obj), style="glow", data=data, radius=spec.size)


def acquire(game, entity) -> None:
    """The player walked into ``entity``, a pickup: its weapon is theirs and in hand."""
    ars = game.states.weapons
    game.remove(entity.id)
    kind = entity.data.spec.weapon
    k = next(k for k, s in enumerate(ars.specs) if s.kind == kind)
    if ars.owned[k]:
        return  # brought along already: the pickup is just taken
    ars.owned[k] = True
    ars.slot = ars.acquired = k
    ars.acquired_tick = game.tick
    game.emit(WeaponAcquired(entity.id, kind))


def acquired_notice(spec: WeaponSpec, has_energy: bool) -> str:
    """What the notice says when ``spec`` is picked up: its key, how to use it, what it costs.
    ``{actions}`` are filled with the player's keys by the window."""
    key = "{" + KEY_OF[spec.kind] + "}"
    if spec.kind == "gun" and spec.ammo >= 0:
        pay = f"It holds {spec.max_ammo} rounds; crystals refill it."
    elif has_energy and spec.cost_milli > 0:
        pay = f"Each use costs {spec.cost_milli / 1000:g} energy."
    else:
        pay = ""
    use = {
        "gun": "Fire it with {fire}: its bullet swings along w as it flies.",
        "blast": "Fire it with {fire} to pull hidden 4D things nearby to your w.",
        "field": "Fire it with {fire} to show the 4D things nearby as glowing wireframes.",
    }[spec.kind]
    return f"You found the {spec.name} (key {key})! {use} {pay}".strip()


def refill(game) -> None:
    """Guns that fire rounds get ``refill`` rounds per crystal collected since the last call."""
    ars = game.states.weapons
    taken = game.event_counts["crystal_collected"]
    new, ars.crystals_seen = taken - ars.crystals_seen, taken
    if new <= 0:
        return
    for k, spec in enumerate(ars.specs):
        if ars.rounds[k] >= 0 and ars.owned[k]:
            ars.rounds[k] = min(spec.max_ammo, ars.rounds[k] + new * spec.refill)


def spawn_target(game, spec: TargetSpec):
    """Put a target in the game: a small polychoron, glowing unless disguised."""
    mesh = make_shape(spec.shape).with_color(spec.color)
    scale = spec.size / max(reach(mesh), 1e-9)  # the target's reach is its size
    obj = Object4.prop(spec.name, mesh, spec.position, scale, spec.rotation_deg, spec.spin_deg)
    return game.entities.spawn(
        "target",
        spec.name,
        mesh,
        Scripted(obj),
        radar=None if spec.disguised else "target",
        style="solid" if spec.disguised else "glow",
        data=Target(spec),
        radius=spec.size,
    )


def aim(game) -> tuple[np.ndarray, np.ndarray]:
    """The crosshair's ray: eye ``(3,)`` and unit direction ``(3,)``, float64."""
    p = game.player
    cp = np.cos(p.pitch)
    d = np.array([np.sin(p.yaw) * cp, np.sin(p.pitch), np.cos(p.yaw) * cp])
    return p.eye(), d


def fire_bullet(game, spec: WeaponSpec):
    """Spawn a bullet at the muzzle; the oldest goes when ``max_live`` are already flying."""
    ars = game.states.weapons
    while len(ars.bullets) >= spec.max_live:
        game.remove(ars.bullets.pop(0))
    eye, d = aim(game)
    w0 = float(game.player.position[3])
    origin = np.append(eye + d * (MUZZLE + spec.size), w0)
    velocity = np.append(d * spec.speed, 0.0)
    body = game.physics.add_body(
        BodyDef("hypersphere", radius=spec.size, mass=spec.mass, position=origin, velocity=velocity, restitution=0.3)
    )
    scale = np.full(4, spec.size / ars.bullet_reach)
    e = game.entities.spawn(
        "bullet",
        "bullet",
        ars.bullet_mesh,
        Rigid(body, scale),
        radar="bullet",
        style="glow",
        data=Bullet(spec, origin, velocity, w0, game.tick),
        radius=spec.size,
    )
    game.entity_of_body[body] = e.id
    ars.bullets.append(e.id)
    return e


def steer_bullets(game) -> None:
    """Set each free-flying bullet's velocity so this physics tick lands it on its planned path.

    The physics integrates ``v += g h; x += v h`` over ``n`` substeps of ``h``,
    which moves a body by ``v dt + g h^2 n (n + 1) / 2`` in a tick: the velocity
    set here subtracts that drop, so the bullet is exactly on the sine (up to
    rounding) until something touches it.
    """
    phys = game.physics
    n = phys.substeps
    h = game.dt / n
    drop = phys.gravity * h * (n + 1) / 2.0
    for eid in game.states.weapons.bullets:
        e = game.entities.get(eid)
        b = e.data
        if b.contacted:
            continue
        ticks = game.tick - b.born + 1
        want = b.planned(ticks, game.dt)
        here = phys.body_position(e.motion.body)
        phys.set_velocity(e.motion.body, (want - here) / game.dt - drop)


def in_reach(game, radius: float) -> list:
    """Entities of :data:`AFFECTED_KINDS` whose centre is within ``radius`` of the player's
    centre in x, y and z (w is what the blast changes and the field sees through)."""
    table = game.entity_table()
    if not table.entities:
        return []
    c = game.player.center()
    d = np.linalg.norm(table.centers[:, :3] - c[:3], axis=1)
    return [e for e, di in zip(table.entities, d) if di <= radius and e.kind in AFFECTED_KINDS]


def blast(game, spec: WeaponSpec) -> list[int]:
    """Start pulling everything within the blast's radius to the player's w; returns the ids."""
    ars = game.states.weapons
    w = float(game.player.position[3])
    end = game.tick + max(1, round(spec.duration / game.dt))
    moved = []
    busy = {p.entity for p in ars.pulls}
    for e in in_reach(game, spec.radius):
        if isinstance(e.data, Target) and e.data.spec.anchored:
            continue  # fixed at its w by the level
        if isinstance(e.motion, Scripted):
            e.motion = Shifted(e.motion)
            # Caches of the entity list tell scripted things (posed by time alone) from the
            # rest by their motion: this one is no longer scripted, so they must take it again
            # (else the pulled thing is drawn where it was until something comes or goes).
            game.entities.version += 1
        if not isinstance(e.motion, (Shifted, Rigid)):
            continue
        if e.id in busy:  # a second blast retargets the pull from where it is now
            ars.pulls = [p for p in ars.pulls if p.entity != e.id]
        ars.pulls.append(Pull(e.id, float(e.center(game)[3]), w, game.tick, end))
        moved.append(e.id)
    return moved


def advance_pulls(game) -> None:
    """Move pulled entities one tick along their smoothstep (before physics runs)."""
    ars = game.states.weapons
    keep = []
    phys = game.physics
    for p in ars.pulls:
        e = game.entities.get(p.entity)
        if e is None:
            continue
        target = p.w_at(game.tick + 1)
        if isinstance(e.motion, Shifted):
            e.motion.previous = e.motion.offset
            e.motion.offset += target - float(e.center(game)[3])
        else:  # a body: steer its w velocity, leave the rest to physics
            n = phys.substeps
            g_w = phys.gravity[3] * (game.dt / n) * (n + 1) / 2.0
            v, _ = phys.body_velocity(e.motion.body)
            here = float(phys.body_position(e.motion.body)[3])
            v[3] = (target - here) / game.dt - g_w
            phys.set_velocity(e.motion.body, v)
        if game.tick + 1 < p.end:
            keep.append(p)
        else:
            ars.pulls_done.append(p.entity)
    ars.pulls = keep


def settle_pulled_bodies(game) -> None:
    """After the last tick of a pull, a body keeps its motion in x, y, z but stops along w."""
    ars = game.states.weapons
    for eid in ars.pulls_done:
        e = game.entities.get(eid)
        if e is not None and isinstance(e.motion, Shifted):
            e.motion.previous = e.motion.offset  # at rest: nothing left to interpolate
        elif e is not None and isinstance(e.motion, Rigid):
            v, _ = game.physics.body_velocity(e.motion.body)
            v[3] = 0.0
            game.physics.set_velocity(e.motion.body, v)
    ars.pulls_done = []


def cast_field(game, spec: WeaponSpec) -> list[int]:
    """Draw everything within the field's radius as a wireframe for its duration; returns the ids."""
    ars = game.states.weapons
    until = game.tick + max(1, round(spec.duration / game.dt))
    shown = []
    for e in in_reach(game, spec.radius):
        style = ars.wired[e.id][0] if e.id in ars.wired else e.style
        ars.wired[e.id] = (style, until)
        e.style = "wire"
        shown.append(e.id)
    return shown


def expire_field(game) -> None:
    """Give back their own look to the entities whose field time is over."""
    ars = game.states.weapons
    for eid, (style, until) in list(ars.wired.items()):
        if game.tick >= until:
            e = game.entities.get(eid)
            if e is not None:
                e.style = style
            del ars.wired[eid]
