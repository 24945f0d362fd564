"""Steering: the probe's bots as a player's hands on the keys.

A bot is a generator that yields one :class:`~across_dimensions.game.actions.Actions` per
tick and reads the game afresh each time it resumes (the runner steps the game between
yields). This module holds what every bot does: turn towards a point at mouse speed, walk
there, jump at a ledge or at the edge of a drop, move along w towards a wanted w, and notice
when it is stuck. :class:`Ctx` carries the game, what the strategy allows
(:class:`Allow`) and a few counters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..game.actions import Actions
from ..game.player import JUMP_SPEED, STEP_HEIGHT, WALK_SPEED
from . import read

#: Largest look change a bot makes in a tick, radians: 9 degrees, a brisk mouse flick.
TURN_RATE = math.radians(9.0)
#: Facing within this of the wanted direction walks at full speed (radians).
WALK_CONE = math.radians(35.0)
#: Ticks without a centimetre of progress before a walk counts as stuck.
STUCK_TICKS = 40
#: How high a jump lifts the feet (m), less a margin: what a ledge may be to be jumped.
JUMP_CLEAR = JUMP_SPEED**2 / (2 * 9.81) - 0.08


@dataclass(frozen=True)
class Allow:
    """What a strategy may do. The defaults allow everything a player can.

    ``crystals``: ``"all"`` (found with the radar), ``"visible"`` (those in the starting
    slice) or ``"none"``; ``weapons``: the kinds it may use; ``aim``: aim at what it knows
    (False: fire straight ahead only); ``manipulation``: ``"full"``, ``"partial"`` (a step
    short of the intended angle) or ``"none"``; ``frustum``: ``"orbit"``, ``"fixed"`` (no
    orbit) or ``"none"``; ``slice_turn``: ``"full"`` or ``"none"``; ``frustum_walk``: walk on a
    ``walkable_in_frustum`` image the route walks on; ``camera_loot``: free and take an enemy's
    crystal with the frustum switch as the route does.
    """

    w: bool = True
    radar: bool = True
    crystals: str = "all"
    weapons: frozenset = frozenset({"gun", "blast", "field"})
    aim: bool = True
    enemies: bool = True
    bodies: bool = True
    manipulation: str = "full"
    frustum: str = "orbit"
    slice_turn: str = "full"
    frustum_walk: bool = True
    camera_loot: bool = True

    def but(self, **changes) -> Allow:
        return replace(self, **changes)


@dataclass
class Ctx:
    """A bot's view of one run: the game, its allowances and its notes."""

    game: object
    allow: Allow
    route: object = None  # the shipped replay's plan (probe.route.Route), or None
    notes: list = field(default_factory=list)
    give_up: int = 0  # tick after which skills stop trying

    @property
    def tick(self) -> int:
        return self.game.tick


# ------------------------------------------------------------------ looking
def wrap(angle: float) -> float:
    """An angle in (-pi, pi]."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def yaw_to(game, xz) -> float:
    """The yaw that looks from the player at the point ``(x, z)``."""
    p = read.feet(game)
    return math.atan2(xz[0] - p[0], xz[1] - p[2])


def look(game, yaw: float, pitch: float = 0.0) -> tuple[float, float]:
    """This tick's ``(dyaw, dpitch)`` towards a wanted view, at most :data:`TURN_RATE` each."""
    y, p = read.view(game)
    dy = float(np.clip(wrap(yaw - y), -TURN_RATE, TURN_RATE))
    dp = float(np.clip(pitch - p, -TURN_RATE, TURN_RATE))
    return dy, dp


def aim_at(game, point3) -> tuple[float, float]:
    """Yaw and pitch that put the crosshair on ``point3 (3,)``."""
    eye = read.eye(game)
    d = np.asarray(point3, float) - eye
    return math.atan2(d[0], d[2]), math.atan2(d[1], math.hypot(d[0], d[2]))


def facing(game, yaw: float, pitch: float | None = None, tol: float = 0.02) -> bool:
    y, p = read.view(game)
    return abs(wrap(yaw - y)) <= tol and (pitch is None or abs(pitch - p) <= tol)


# ------------------------------------------------------------------ the ground ahead
def box_at(pos, dx: float, dz: float, dy: float, height: float | None = None):
    """The player's box at feet ``pos`` moved by ``dx, dy, dz`` (and cut to ``height``): ``lo, hi``."""
    lo, hi = read.player_box(pos)
    lo = lo + np.array([dx, dy, dz])
    hi = hi + np.array([dx, dy, dz])
    if height is not None:
        hi[1] = lo[1] + height
    return lo, hi


def wants_jump(game, heading: float, lookahead: float = 0.35) -> bool:
    """Should a walker heading ``heading`` (yaw) jump now? At a ledge it can clear, or at the
    last moment before the ground ends under it (a running jump carries furthest)."""
    if not read.on_ground(game):
        return False
    pos, w = read.feet(game), float(read.feet(game)[3])
    dx, dz = math.sin(heading), math.cos(heading)
    # A ledge: blocked just above a step's height, clear at the top of a jump.
    lo, hi = box_at(pos, dx * lookahead, dz * lookahead, STEP_HEIGHT + 0.02)
    if read.blocked_box(game, lo, hi, w):
        lo, hi = box_at(pos, dx * lookahead, dz * lookahead, JUMP_CLEAR)
        return not read.blocked_box(game, lo, hi, w)
    # A drop: no floor under the box where the next ticks will carry it.
    v = read.velocity(game)
    speed = max(math.hypot(v[0], v[2]), 0.5 * WALK_SPEED)
    step = speed * game.dt * 1.05  # the last tick with ground under the box: a running jump carries furthest
    lo, hi = box_at(pos, dx * step, dz * step, -0.6, height=0.58)
    return not read.blocked_box(game, lo, hi, w)


# ------------------------------------------------------------------ walking
def drive(game, xz, w: float | None = None, jump: bool = True, allow_w: bool = True, **extra) -> Actions:
    """One tick of walking towards ``(x, z)`` (and along w towards ``w``)."""
    yaw = yaw_to(game, xz)
    dy, dp = look(game, yaw, 0.0)
    off = abs(wrap(yaw - read.view(game)[0]))
    forward = 1.0 if off <= WALK_CONE else max(0.0, math.cos(off))
    dw = 0.0
    if w is not None and allow_w:
        gap = w - float(read.feet(game)[3])
        dw = float(np.clip(gap * 4.0, -1.0, 1.0)) if abs(gap) > 0.01 else 0.0
    leap = jump and forward > 0.5 and wants_jump(game, read.view(game)[0])
    return Actions(forward=forward, yaw=dy, pitch=dp, w=dw, jump=leap, **extra)


def idle(game, **extra) -> Actions:
    """Stand still (and level the view)."""
    _, dp = look(game, read.view(game)[0], 0.0)
    return Actions(pitch=dp, **extra)


def distance_xz(game, xz) -> float:
    p = read.feet(game)
    return math.hypot(xz[0] - p[0], xz[1] - p[2])


class Progress:
    """Notices a walker that stopped getting closer to where it goes."""

    def __init__(self, game, xz):
        self.best = distance_xz(game, xz)
        self.since = game.tick

    def stuck(self, game, xz) -> bool:
        d = distance_xz(game, xz)
        if d < self.best - 0.01:
            self.best, self.since = d, game.tick
        return game.tick - self.since > STUCK_TICKS


def goto(ctx: Ctx, xz, w: float | None = None, tol: float = 0.35, ticks: int = 900):
    """Walk to ``(x, z)`` (and ``w`` when the strategy moves along w). Returns True on arrival,
    False when stuck or out of time."""
    game = ctx.game
    progress = Progress(game, xz)
    end = game.tick + ticks
    allow_w = ctx.allow.w
    while game.tick < end and not read.won(game):
        there = distance_xz(game, xz) <= tol
        w_ok = w is None or not allow_w or abs(float(read.feet(game)[3]) - w) <= 0.03
        if there and w_ok:
            return True
        if there:
            got = yield from move_w(ctx, w, ticks=end - game.tick)
            return abs(got - w) <= 0.03 and distance_xz(game, xz) <= tol
        if progress.stuck(game, xz):
            return False
        yield drive(game, xz, w, allow_w=allow_w)
    return False


def turn_to(ctx: Ctx, yaw: float, pitch: float = 0.0, ticks: int = 90, **extra):
    """Turn on the spot until facing ``yaw, pitch``; ``extra`` are buttons held meanwhile."""
    game = ctx.game
    for _ in range(ticks):
        if facing(game, yaw, pitch, tol=0.004):
            return True
        dy, dp = look(game, yaw, pitch)
        yield Actions(yaw=dy, pitch=dp, **extra)
    return False


def wait(ctx: Ctx, ticks: int, **extra):
    for _ in range(ticks):
        yield idle(ctx.game, **extra)


def move_w(ctx: Ctx, w: float, ticks: int = 600):
    """Stand and move along w to ``w``; returns where it got."""
    game = ctx.game
    last, still = float(read.feet(game)[3]), 0
    for _ in range(ticks):
        now = float(read.feet(game)[3])
        if abs(now - w) <= 0.01:
            break
        still = still + 1 if abs(now - last) < 1e-6 else 0
        if still > 20:  # refused: a wall appears there, the range ends or the bar is empty
            break
        last = now
        yield idle(game, w=float(np.clip((w - now) * 4.0, -1.0, 1.0)))
    return float(read.feet(game)[3])
