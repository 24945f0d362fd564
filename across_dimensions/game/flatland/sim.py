"""The prologue's simulation: a flat being in the slice ``z = z0`` of a 3D world, one fixed tick at a time.

``FlatGame.step(actions)`` takes the game's own :class:`~..actions.Actions`: the walk is ``right``
(and ``forward``: either key pair walks), ``jump`` jumps, and ``w``, the player's w keys, moves the
being's plane along z. It never reads the clock and uses no randomness, so the same actions give
the same :meth:`FlatGame.state_hash` in any run and any process, which is what replays check
(:mod:`..playback` plays a prologue level as it plays a 4D one: ``step``, ``tick``, ``state_hash``,
``outcome``, ``level.source_hash``).

A tick, in order:

1. the 3D world moves on (balls roll along z);
2. the being's plane moves along z as asked, unless the being, or a crate present at the new z,
   would overlap something there (a wall cannot appear around it, as in the 4D game);
3. the physics gets the sections at the being's z (:mod:`.space`) and steps;
4. the rules: items touched are taken (and open what they open), checkpoints passed, a fall below
   the level's ``fall_y`` brings the being back to its last checkpoint, the goal completes the level.
"""

from __future__ import annotations

import hashlib
from collections import Counter
from dataclasses import dataclass

import numpy as np

from ...core.flat_solids import circle_overlaps_box, convex_overlaps_box
from ...world.flat_level import EVENTS, FlatLevel
from ..actions import Actions
from ..player import HALF_WIDTH, HEIGHT, W_ACCEL, W_SPEED
from .space import FlatSpace, drive
from .world3 import World3

TICK_RATE = 60
DT = 1.0 / TICK_RATE
#: Ticks after leaving the ground (running off an edge, or a shrinking circle sinking away under
#: the feet) in which a jump still goes (coyote time), and ticks a jump pressed in the air is kept
#: for the landing: a tap shorter than a frame on a circle that shrinks under the being jumps.
COYOTE_TICKS = 6
JUMP_BUFFER_TICKS = 6
#: How deep (m) something must reach into the being (or a crate) at a new z to refuse the move:
#: more than pymunk's resting overlap (:data:`.space.COLLISION_SLOP`), so standing on a floor that
#: goes on at the new z never blocks.
Z_BLOCK_DEPTH = 0.02


def _same(a: list[np.ndarray], b: list[np.ndarray]) -> bool:
    return len(a) == len(b) and all(np.array_equal(p, q) for p, q in zip(a, b))


def _inside(pieces: list[np.ndarray], lo, hi) -> bool:
    return any(convex_overlaps_box(p, lo, hi, Z_BLOCK_DEPTH) for p in pieces)


@dataclass(frozen=True)
class FlatEvent:
    """Something that happened in a tick: ``kind`` (one of ``world.flat_level.EVENTS``) and what."""

    kind: str
    name: str = ""


class FlatGame:
    """A prologue level being played.

    Parameters
    ----------
    level : FlatLevel
    seed : int
        Kept for the replay header; the prologue draws no random numbers.

    Attributes
    ----------
    z : float
        Where the being's plane cuts the 3D world.
    events : list of FlatEvent
        What happened in the last tick.
    event_counts : collections.Counter
    outcome : str or None
        ``"complete"`` once the being reached the goal.
    """

    dt = DT

    def __init__(self, level: FlatLevel, seed: int = 0):
        self.level = level
        self.seed = seed
        self.world = World3(level)
        self.space = FlatSpace(level, DT)
        self.z = float(level.spawn[2])
        self.vz = 0.0
        self.tick = 0
        self.outcome: str | None = None
        self.completed_tick: int | None = None
        self.events: list[FlatEvent] = []
        self.event_counts: Counter = Counter()
        self.checkpoint = -1
        self.respawns = 0
        self.z_blocked = 0.0  # the sign of the w input a move was refused for, 0 when none
        self.facing = 1.0  # which way the being last walked: drawn, never simulated
        self.grounded, self._ground_v = False, (0.0, 0.0)
        self.air_ticks = 0  # ticks since the being last stood on something
        self.jump_buffer = 0  # ticks a jump press is still waiting for ground
        self.jumped = False  # it jumped since it last stood on something
        self.prev_position = self.position.copy()
        self._sync()

    # ---------------------------------------------------------------- reading
    @property
    def position(self) -> np.ndarray:
        """The being's feet ``(x, y, z)``, ``(3,) float64``."""
        p = self.space.being.position
        return np.array([p.x, p.y, self.z])

    @property
    def time(self) -> float:
        return self.tick * DT

    def being_box(self, xy=None) -> tuple[np.ndarray, np.ndarray]:
        """The being's box ``(low (2,), high (2,))`` with its feet at ``xy`` (default: where it is)."""
        x, y = self.position[:2] if xy is None else xy
        return np.array([x - HALF_WIDTH, y]), np.array([x + HALF_WIDTH, y + HEIGHT])

    def emit(self, event: FlatEvent) -> None:
        self.events.append(event)
        self.event_counts[event.kind] += 1

    # ---------------------------------------------------------------- stepping
    def step(self, actions: Actions) -> None:
        """Advance one tick with the player's ``actions``."""
        self.events = []
        self.prev_position = self.position.copy()
        self.world.advance(DT)
        self._move_z(float(actions.w))
        self._sync()
        walk = max(-1.0, min(1.0, float(actions.right) + float(actions.forward)))
        self.facing = float(np.sign(walk)) if walk else self.facing
        self.jump_buffer = JUMP_BUFFER_TICKS if actions.jump else max(0, self.jump_buffer - 1)
        jump = self.jump_buffer > 0 and self.air_ticks <= COYOTE_TICKS and not self.jumped
        if jump:
            self.jump_buffer, self.jumped = 0, True
        drive(self.space, walk, jump, self.grounded, self._ground_v)
        self.space.step()
        self.grounded, self._ground_v = self.space.ground()
        # Still touching the ground the tick after a jump is not landing: the jump is on its way up.
        landed = self.grounded and not (jump or self.space.being.velocity.y > self._ground_v[1] + 1.0)
        self.air_ticks = 0 if self.grounded else self.air_ticks + 1
        self.jumped = self.jumped and not landed
        self._rules()
        self.tick += 1

    def _move_z(self, w: float) -> None:
        """Move the plane along z as the w input asks, accelerating as the 4D walker does along w.
        ``z_blocked`` holds from a refused move until the input is let go or turned round (one
        ``z_blocked`` event per push, however the plane creeps up to what blocks it)."""
        if w * self.z_blocked <= 0.0:
            self.z_blocked = 0.0
        lo, hi = self.level.z_range
        step = W_ACCEL * DT
        self.vz += min(max(w * W_SPEED - self.vz, -step), step)
        z = min(max(self.z + self.vz * DT, lo), hi)
        if z == self.z:
            self.vz = 0.0 if z in (lo, hi) else self.vz
        elif self.blocked_at(z):
            if not self.z_blocked:
                self.emit(FlatEvent("z_blocked"))
            self.z_blocked, self.vz = float(np.sign(w)) or 1.0, 0.0
        else:
            self.z = z

    def blocked_at(self, z: float) -> bool:
        """Whether moving the plane to ``z`` would put something inside the being, or a crate present
        there inside a solid. Only what the move changes can block it, and only if it was not
        already inside: a floor that goes on at the new z never blocks, however deep the being
        stands in it after a hard landing, and neither does a wall it is pressed against."""
        now, then = self.world.pieces(self.z), self.world.pieces(z)
        pairs = [(a, b) for a, b in zip(now, then) if not _same(a, b)]  # (before, after) of what changes
        lo, hi = self.being_box()
        if any(_inside(b, lo, hi) and not _inside(a, lo, hi) for a, b in pairs):
            return True
        for i, ball in enumerate(self.level.balls):
            c, r0, r1 = ball.center[:2], self.world.ball_radius(i, self.z), self.world.ball_radius(i, z)
            grows_in = not circle_overlaps_box(c, r0, lo, hi, Z_BLOCK_DEPTH)
            if grows_in and circle_overlaps_box(c, r1, lo, hi, Z_BLOCK_DEPTH):
                return True
        for i, (body, shape) in enumerate(self.space.crates):
            if not self.world.crate_present(i, z):
                continue
            corners = np.array([body.local_to_world(v) for v in shape.get_vertices()])
            bounds = corners.min(axis=0), corners.max(axis=0)  # a turned crate counts as its bounds
            if self.world.crate_present(i, self.z):
                if any(_inside(b, *bounds) and not _inside(a, *bounds) for a, b in pairs):
                    return True
            elif convex_overlaps_box(corners, lo, hi, Z_BLOCK_DEPTH) or any(_inside(b, *bounds) for b in then):
                return True  # a crate that rested off the plane would come back inside something
        return False

    def _sync(self) -> None:
        """Give the physics the sections at the being's z."""
        for i, pieces in enumerate(self.world.pieces(self.z)):
            self.space.set_solid(i, pieces)
        for i in range(len(self.level.balls)):
            self.space.set_ball(i, self.world.ball_radius(i, self.z))
        for i in range(len(self.level.crates)):
            self.space.set_crate(i, self.world.crate_present(i, self.z))

    def _rules(self) -> None:
        lo, hi = self.being_box()
        for i, item in enumerate(self.level.items):
            r = self.world.item_radius(i, self.z)
            if r > 0.0 and circle_overlaps_box(item.position[:2], r, lo, hi, 0.0):
                self.world.taken.add(item.name)
                self.emit(FlatEvent("item_taken", item.name))
                if item.opens and item.opens not in self.world.gone:
                    self.world.gone.add(item.opens)
                    self.emit(FlatEvent("door_opened", item.opens))
        x, y = self.position[:2]
        for i, (name, p) in enumerate(self.level.checkpoints):
            if i > self.checkpoint and x >= p[0]:
                self.checkpoint = i
                self.emit(FlatEvent("checkpoint", name))
        if y < self.level.fall_y:
            self.emit(FlatEvent("fell"))
            self._respawn()
        if self.outcome is None and self._at_goal():
            self.outcome, self.completed_tick = "complete", self.tick + 1
            self.emit(FlatEvent("complete"))

    def _at_goal(self) -> bool:
        lvl = self.level
        centre = self.position[:2] + (0.0, HEIGHT / 2)
        inside = np.all(np.abs(centre - lvl.goal_center) <= lvl.goal_size / 2)
        return bool(inside) and (lvl.goal_z is None or lvl.goal_z[0] <= self.z <= lvl.goal_z[1])

    def _respawn(self) -> None:
        p = self.level.spawn if self.checkpoint < 0 else self.level.checkpoints[self.checkpoint][1]
        self.space.being.position = (float(p[0]), float(p[1]))
        self.space.being.velocity = (0.0, 0.0)
        self.z, self.vz = float(p[2]), 0.0
        self.respawns += 1
        self._sync()

    # ---------------------------------------------------------------- hashing
    def state_hash(self) -> str:
        """A short hash of the whole state: the being (and its z), the crates, the contacts pymunk
        carries to the next tick, the 3D world, the counters. Equal states give equal hashes."""
        counters = [self.tick, self.z, self.vz, self.checkpoint, self.respawns, self.air_ticks, self.jump_buffer]
        h = hashlib.sha256(np.array(counters, np.float64).tobytes())
        h.update(self.space.state_bytes())
        h.update(self.world.state_bytes())
        h.update(repr((self.outcome, self.z_blocked, self.grounded, self._ground_v, self.jumped)).encode())
        return h.hexdigest()[:16]


def summary(game: FlatGame, result) -> dict:
    """What ``replay --json`` prints for a prologue level: the keys of the 4D game's summary
    (:func:`..playback.summary`), ``position`` being the being's feet ``[x, y, z]`` and ``energy``
    null (the prologue has no energy bar), ``events`` a count for every prologue event kind."""
    return {
        "level": game.level.name,
        "outcome": result.outcome,
        "ticks": result.ticks,
        "hash": result.final_hash,
        "events": {kind: game.event_counts.get(kind, 0) for kind in EVENTS},
        "energy": None,
        "position": [float(v) for v in game.position],
        "respawns": game.respawns,
        "divergence": result.divergence,
    }
