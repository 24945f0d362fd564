"""Enemies that hide along w (paper, section 5, "Fighting enemies").

Two kinds of 4D body:

- ``swarm``: a composition of 4D primitives, eight hyperspheres on a ring in the
  z-w plane and two beside it; its animation translates them along w and turns
  them in zw, so the slice shows spheres swelling, splitting and merging (the
  paper's Fig. "Animating 4D primitives").
- ``morph``: a 3D asset (the tree of ``assets/meshes``) lifted into 4D and
  animated only by keyframed 4D rototranslations, so its cross-section morphs:
  a tree, then a jellyfish, then a gun (Fig. "Animating enemies").

A body's model at time ``t`` is ``T(centre) @ A(t) @ S @ T(-pivot)``: the
pivot is the mesh's middle, ``S`` scales it to the enemy's size, ``A(t)`` is
the animation pose interpolated between keyframes (:func:`animation_pose`) and
the centre is where the enemy's state machine has taken it. The cross-section
drawn is that model cut at the player's w, nothing else.

Behaviour is a small deterministic state machine per enemy (see
``game/systems/enemies.py`` for the tick):

``hidden``
    off the slice, at least :data:`HIDE_W` from the player's w, drifting near its
    post in all four dimensions (draws from ``game.rng`` only);
``approaching``
    the player is within ``sight`` of its post: it moves to the standoff from them (never
    further than :data:`LEASH` from the post) and into the player's w;
``attacking``
    in the slice and within ``reach`` (it keeps 0.6 of its reach from the player): it glows and flickers for
    :data:`WINDUP` seconds, then fires a slow glowing shot at the player's
    chest at the player's w. The player sees it coming and can step aside or
    out of the slice along w. After :data:`BURST` shots it leaves;
``fleeing``
    out of the slice along w, away from the player: after its burst, when hurt
    to half its health or less, or when the player comes within
    :data:`FLEE_NEAR`; then hidden again for a few seconds;
``dragged`` / ``stunned``
    pulled into the slice by the blast, then dazed for :data:`STUN` seconds;
``dying``
    its body bursts outward and glows for :data:`DEFEAT_TIME`, then it is gone.

Bullets hurt an enemy when they pass through its body: within ``size`` of its
centre in x, y, z and within its w half-depth in w. An enemy with a
``weak_spot`` is armoured: only a bullet within :data:`WEAK_RADIUS` of the weak
spot in space and :data:`WEAK_W` of its w hurts it, and the weak spot lies at
another w than the body, so only a bullet's w swing reaches it.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field

import numpy as np

from ..core.lift import HyperDepth
from ..core.mesh import concatenate
from ..core.shapes import hypersphere, make_shape
from ..core.transform import pose, scaling, translation
from ..world.enemy_tables import EnemySpec, KeySpec
from .poses import angle_rows, poses, scalings, translations
from .system import fixed

# ------------------------------------------------------------------ tuning
HIDE_W = 1.3  # units of w off the player's slice where a hidden enemy keeps: beyond any body's half-depth
W_SPEED = 1.0  # units of w per second: a little slower than the player (1.2), so a step along w is a dodge
FLEE_W_SPEED = 1.6
FLEE_NEAR = 2.0  # metres: closer than this and an enemy backs off out of the slice
LEASH = 4.0  # metres an enemy comes from its post at most
STANDOFF = 0.6  # of its reach: the distance it attacks from
IN_SLICE = 0.05  # units of w: close enough to the player's w to shoot
WINDUP = 0.9  # seconds of warning (glowing, flickering) before each shot
RECOVER = 1.2  # seconds between shots, plus up to RECOVER_JITTER from the rng
RECOVER_JITTER = 0.5
BURST = 2  # shots before it leaves the slice
RETURN_MIN, RETURN_MAX = 2.0, 4.0  # seconds hidden before coming back
DRIFT_EVERY = 1.5  # seconds between new drift targets while hidden
DRIFT = np.array([1.0, 0.3, 1.0, 0.25])  # how far the drift wanders from the post, per axis
STUN = 1.0  # seconds dazed after the blast pulled it in
DEFEAT_TIME = 0.6  # seconds of the defeat burst
HIT_FLASH = 0.2  # seconds an enemy glows after a hit
SHOT_SPEED = 7.0  # m/s: from 5 m the player has 0.7 s after the shot leaves, plus the wind-up
SHOT_RADIUS = 0.25  # m: the shot's reach in x, y, z
SHOT_W = 0.3  # units of w: a player further than this from the shot's w is not hit
SHOT_LIFETIME = 4.0
SHOT_COLOR = (1.0, 0.3, 0.15, 1.0)
CHEST = 1.1  # metres above the feet where shots aim
WEAK_RADIUS = 0.35  # metres: a bullet within this of the weak spot in x, y, z ...
WEAK_W = 0.25  # ... and within this of its w hits it
WEAK_COLOR = (1.0, 0.85, 0.2, 1.0)
LOOT_SIZE = 0.3  # the hidden crystal's reach (its own w extent either side)
LOOT_COLOR = (0.35, 1.0, 0.85, 1.0)
#: How far the blast's pull reaches when the level's blast has no radius (never: every blast has one).
STATES = ("hidden", "approaching", "attacking", "fleeing", "dragged", "stunned", "dying")

#: Each kind's animation when the level gives none: (time s, offset (4,), rotation degrees).
DEFAULT_KEYS = {
    # Fig. "Animating 4D primitives": a translation along w, then a turn in zw (the paper's v).
    "swarm": [
        (0.0, (0.0, 0.0, 0.0, 0.0), {}),
        (1.5, (0.0, 0.0, 0.0, 0.3), {}),
        (3.0, (0.0, 0.0, 0.0, 0.3), {"zw": 180.0}),
        (4.5, (0.0, 0.0, 0.0, 0.0), {"zw": 360.0}),
    ],
    # Fig. "Animating enemies": the tree, turned into w it is a jellyfish, turned again a gun, and back.
    "morph": [
        (0.0, (0.0, 0.0, 0.0, 0.0), {}),
        (2.0, (0.0, 0.0, 0.0, 0.0), {"yw": 70.0}),
        (4.0, (0.0, 0.0, 0.0, 0.0), {"xy": 90.0, "xw": 40.0}),
        (6.0, (0.0, 0.0, 0.0, 0.0), {}),
    ],
}


def default_keys(kind: str) -> list[KeySpec]:
    """The kind's own animation as keyframes."""
    return [KeySpec(t, np.array(o, np.float64), dict(r)) for t, o, r in DEFAULT_KEYS[kind]]


def animation_pose(keys: list[KeySpec], t: float) -> np.ndarray:
    """The animation's rototranslation at ``t`` seconds, ``(5, 5) float64``.

    The keyframes loop with the period of the last key's time (a level repeats
    its first pose last for a seamless loop). Between two keys each rotation
    angle and the offset move along a smoothstep, so the motion starts and
    stops gently at every key; exactly at a key the pose is the key's.
    """
    offset, angles = animation_at(keys, t)
    return pose(offset, angles)


def animation_at(keys: list[KeySpec], t: float) -> tuple[np.ndarray, dict]:
    """The animation's offset ``(4,) float64`` and angles (plane to radians) at ``t`` seconds
    (see :func:`animation_pose`)."""
    track = Track(keys)
    if track.still:
        k = keys[0]
        return k.offset, {p: math.radians(a) for p, a in k.rotation_deg.items()}
    j, i, s = track.segment(t)
    a, b = keys[j], keys[i]
    planes = set(a.rotation_deg) | set(b.rotation_deg)
    angles = {
        p: math.radians(a.rotation_deg.get(p, 0.0) + s * (b.rotation_deg.get(p, 0.0) - a.rotation_deg.get(p, 0.0)))
        for p in planes
    }
    return a.offset + s * (b.offset - a.offset), angles


# ------------------------------------------------------------------ bodies
@dataclass(frozen=True)
class Body:
    """A kind's 4D mesh and how it is placed: ``pivot (4,)`` is moved to the origin and
    the mesh scaled by ``scale (4,)``; ``w_half`` is its half-depth in w (the bullets' hit zone)."""

    mesh: object
    pivot: np.ndarray
    scale: np.ndarray
    w_half: float


def swarm_mesh(color) -> object:
    """Ten hyperspheres: eight on a ring of radius 0.5 in the z-w plane, two beside it on x."""
    spheres = []
    for k in range(8):
        a = 2 * np.pi * k / 8
        spheres.append((0.0, 0.0, 0.5 * np.cos(a), 0.5 * np.sin(a)))
    spheres += [(0.45, 0.15, 0.0, 0.0), (-0.45, -0.15, 0.0, 0.0)]
    parts = []
    for i, c in enumerate(spheres):
        r = 0.24 if i < 8 else 0.2
        shade = 0.75 + 0.25 * (i % 2)
        col = (color[0] * shade, color[1] * shade, color[2] * shade, color[3])
        m = hypersphere(r, 0, color=col)
        v = m.vertices.astype(np.float64) + np.asarray(c)
        parts.append(type(m)(v.astype(np.float32), m.tets, m.colors, name="sphere"))
    return concatenate(parts, name="swarm")


def build_body(spec: EnemySpec, cache: dict) -> Body:
    """The enemy's body, built once per kind, asset and look (``cache`` keeps them for the game)."""
    key = (spec.kind, str(spec.asset), spec.depth, spec.color, spec.size)
    got = cache.get(key)
    if got is not None:
        return got
    if spec.kind == "swarm":
        mesh = swarm_mesh(spec.color)
        reach = 0.74  # ring radius plus a sphere
        s = spec.size / reach
        body = Body(mesh, np.zeros(4), np.full(4, s), 0.74 * s)
    else:
        from ..world.bake import lift_asset  # the bake (and its mesh library) only when a level lifts assets

        extent = HyperDepth(0.0, spec.depth, "round", layers=5)
        mesh = lift_asset(spec.asset, extent, color=spec.color[:3], progress=False)
        v = mesh.vertices.astype(np.float64)
        lo, hi = v.min(axis=0), v.max(axis=0)
        pivot = 0.5 * (lo + hi)
        s = spec.size / max(float(np.max((hi - lo)[:3]) / 2), 1e-9)
        # Space is scaled to the size; w keeps the level's depth, so the body is as deep as it says.
        body = Body(mesh, pivot, np.array([s, s, s, 1.0]), spec.depth / 2)
    cache[key] = body
    return body


def body_model(body: Body, keys, centre, t: float, grow: float = 1.0) -> np.ndarray:
    """The body's object-to-world ``(5, 5) float64`` at ``t``: ``T(centre) A(t) S T(-pivot)``."""
    return translation(centre) @ animation_pose(keys, t) @ scaling(body.scale * grow) @ translation(-body.pivot)


class Track:
    """An animation's keyframes as arrays, to pose many foes in one pass (:func:`body_models`)
    with the numbers :func:`animation_at` gives, bit for bit.

    Attributes
    ----------
    offsets : (k, 4) float64
        Each key's offset.
    degrees : (k, 6) float64
        Each key's angles in :data:`~core.transform.PLANES` order, degrees (a plane it leaves
        out is 0, which interpolates as :func:`animation_at`'s ``get(plane, 0.0)`` does).
    """

    def __init__(self, keys: list[KeySpec]):
        self.times = [k.time for k in keys]
        self.still = len(keys) == 1 or keys[-1].time <= 0.0
        self.offsets = np.array([k.offset for k in keys], np.float64).reshape(-1, 4)
        self.degrees = angle_rows([k.rotation_deg for k in keys])

    def segment(self, t: float) -> tuple[int, int, float]:
        """The keys ``t`` seconds lies between and the smoothstep from the first to the second."""
        if self.still:
            return 0, 0, 0.0
        times = self.times
        tm = float(t) % times[-1]
        j = max(0, bisect.bisect_right(times, tm) - 1)
        b = min(j + 1, len(times) - 1)
        span = times[b] - times[j]
        s = 0.0 if span <= 0 else (tm - times[j]) / span
        return j, b, s * s * (3.0 - 2.0 * s)


def body_models(foes: list, times: list[float], grows: list[float]) -> np.ndarray:
    """Every foe's :func:`body_model` in one pass, ``(n, 5, 5) float64``, bit for bit the same:
    foe ``i`` (a :class:`Foe`) at ``times[i]`` seconds, grown by ``grows[i]``."""
    n = len(foes)
    first, second = np.zeros((n, 10)), np.zeros((n, 10))  # per foe: the two keys' offset, degrees
    s, still = np.zeros((n, 1)), np.zeros(n, bool)
    for i, (foe, t) in enumerate(zip(foes, times)):
        track = foe.track
        j, b, s[i, 0] = track.segment(t)
        first[i, :4], first[i, 4:] = track.offsets[j], track.degrees[j]
        second[i, :4], second[i, 4:] = track.offsets[b], track.degrees[b]
        still[i] = track.still
    mix = first + s * (second - first)  # animation_at's a + s (b - a), every foe at once
    offsets = np.where(still[:, None], first[:, :4], mix[:, :4])  # a still key's own offset, -0.0 kept
    angles = np.radians(mix[:, 4:])
    centres = np.array([foe.centre for foe in foes], np.float64).reshape(n, 4)
    scales = np.array([foe.body.scale * g for foe, g in zip(foes, grows)], np.float64).reshape(n, 4)
    pivots = np.array([-foe.body.pivot for foe in foes], np.float64).reshape(n, 4)
    animation = poses(offsets, angles, np.ones((n, 4)))
    return translations(centres) @ animation @ scalings(scales) @ translations(pivots)


def body_reach(body: Body, keys) -> float:
    """How far the posed body reaches from its centre, every pose and the defeat burst included."""
    v = (body.mesh.vertices.astype(np.float64) - body.pivot) * body.scale
    offset = max(float(np.linalg.norm(k.offset)) for k in keys)
    return float(np.linalg.norm(v, axis=1).max()) * 1.6 + offset


def small_mesh(shape: str, color):
    """A little glowing polychoron of reach 1 (shots, weak spots, hidden crystals)."""
    m = make_shape(shape).with_color(color)
    r = float(np.linalg.norm(m.vertices.astype(np.float64), axis=1).max())
    return m, r


# ------------------------------------------------------------------ state
@dataclass
class Foe:
    """An enemy's state (``Entity.data`` of an ``"enemy"`` entity).

    ``centre (4,) float64`` is where the state machine has it; the body is drawn
    round it. Times are ticks.
    """

    spec: EnemySpec = fixed()
    body: Body = fixed()
    keys: list = fixed()
    index: int = fixed()
    centre: np.ndarray
    side: int = fixed()  # +1: it hides ana of the player, -1 kata
    health: int
    state: str = "hidden"
    since: int = 0
    next_shot: int = 0
    shots_left: int = 0
    leave_at: int = -1
    back_at: int = 0
    drift: np.ndarray = field(default_factory=lambda: np.zeros(4))
    next_drift: int = 0
    hurt_tick: int = -(10**9)
    pull: tuple[float, float, int, int] | None = None  # (from_w, to_w, start, end) while the blast drags it
    pulled_by: str = "blast"  # what started the last pull: "blast", or "camera" (the frustum switch)
    loot: int | None = None  # entity id of the crystal inside it, until released
    weak: int | None = None  # entity id of its weak spot's marker
    phase: float = fixed(default=0.0)  # seconds its animation runs ahead of the clock (enemies do not move in step)
    eid: int = fixed(default=-1)  # its entity id
    track: Track | None = fixed(default=None)  # ``keys`` as arrays, for body_models

    @property
    def alive(self) -> bool:
        return self.state != "dying"

    def weak_point(self) -> np.ndarray | None:
        """Where its weak spot is now, ``(4,) float64``, or None."""
        return None if self.spec.weak_spot is None else self.centre + self.spec.weak_spot

    def loot_point(self) -> np.ndarray:
        """Where its hidden crystal is now, ``(4,) float64``."""
        off = self.spec.loot_offset
        if off is None:  # between it and the player when it hides: a pull drags the crystal through the slice
            off = np.array([0.0, 0.0, 0.0, -0.45 * self.side])
        return self.centre + off


@dataclass
class Shot:
    """An enemy's shot (``Entity.data`` of an ``"enemy_shot"``): it flies straight at
    ``velocity (4,)`` (no w part) from ``origin (4,)``; ``source`` is the enemy's id."""

    origin: np.ndarray
    velocity: np.ndarray
    born: int
    damage: float
    source: int

    def at(self, ticks: int, dt: float) -> np.ndarray:
        return self.origin + self.velocity * (ticks * dt)


@dataclass
class Hive:
    """The level's enemies and their shots (``game.states.enemies``)."""

    foes: list[int] = field(default_factory=list)  # enemy entity ids, in the level's order
    shots: list[int] = field(default_factory=list)  # live shot entity ids
    bodies: dict = fixed(default_factory=dict)  # built bodies by kind and look
    shot_mesh: object = fixed(default=None)
    shot_reach: float = fixed(default=1.0)
    armour_tick: int = -(10**9)  # last bullet that struck armour (the HUD says where to aim)
    defeated: int = 0
