"""The design probe on Flatland prologue levels: the same questions, one dimension down.

The prologue's being walks, jumps and slides its plane along z; its puzzles are a wall passed
along z, a key found by its pin on the z bar, and a ball ridden across a pit. The strategies:

- *Shortcuts* (a win is a bypass when the level's ``[design] needs`` names what they avoid):
  ``straight`` walks at the goal jumping, never moving its plane; ``no_radar`` follows the
  shipped replay to the room where it first takes an item, then looks for the way on blind
  (sweeping z at what blocks it), never steering by the z bar; ``no_bodies`` follows the
  replay to where it first rides a ball, then jumps the gap at a z the ball has left.
- *Disruptions* (their wins are no bypass; failing to win after them is a soft-lock):
  ``fall_in_pit`` drops into the gap the replay crosses on a ball, ``z_to_ends`` takes its
  plane to both ends of the z range where it waits, ``crate_to_wall`` pushes the first crate
  as far as it goes. Each then gets back on the route (climbs out, walks to the place the
  replay waited, sets its z, waits until every ball is where it was then) and plays the rest
  of the replay.

The prologue spends nothing that cannot come back (no energy, items never leave, balls roll
forever), so no cheap argument shows a soft-lock the way :mod:`.proofs` does for 4D levels:
a disruption's finding here is empirical, the sentence says the bot could not get back on
the route, and the strategy that found it is named so a designer can replay what it did.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from ..game.actions import Actions
from ..game.flatland import FlatGame
from ..game.flatland.sim import COYOTE_TICKS
from ..game.replay import Replay, ReplayError
from ..world.flat_level import FlatLevel, load_flat_level
from .route import replay_for

REST_SPEED = 0.05  # m/s: the being counts as standing still below this
STALL_TICKS = 45  # ticks without 5 cm of progress: something is in the way
SWEEP_SECONDS = 20.0  # how long the blind search pushes at what blocks it


@dataclass
class FlatRoute:
    """The shipped replay of a prologue level, played once: its actions and, per tick before
    each action, where the being stood, its plane, whether it stood still and the balls'
    places (what getting back on the route must match)."""

    actions: list
    x: np.ndarray  # (t,) float64
    y: np.ndarray  # (t,) float64
    z: np.ndarray  # (t,) float64
    resting: np.ndarray  # (t,) bool: on the ground and still
    ball_z: np.ndarray  # (t, b) float64
    ball_dir: np.ndarray  # (t, b) float64
    on_ball: np.ndarray  # (t,) bool: standing on a ball's circle
    events: list  # (tick, kind, name)
    ticks: int
    won: bool

    def rest_before(self, tick: int) -> int:
        """The last tick at or before ``tick`` when the being stood still (0 when none)."""
        still = np.flatnonzero(self.resting[: tick + 1])
        return int(still[-1]) if still.size else 0

    def first(self, kind: str) -> int | None:
        """The tick of the route's first event of ``kind``."""
        return next((t for t, k, _ in self.events if k == kind), None)


def _standing_on_ball(game: FlatGame) -> bool:
    x, y = game.position[:2]
    for i, ball in enumerate(game.level.balls):
        r = game.world.ball_radius(i, game.z)
        if (
            r > 0.0
            and abs(x - ball.center[0]) <= r
            and abs(y - (ball.center[1] + np.sqrt(max(r * r - (x - ball.center[0]) ** 2, 0.0)))) < 0.1
        ):
            return True
    return False


def flat_route(level: FlatLevel, replay_path=None) -> FlatRoute | None:
    """Play ``level``'s shipped replay headless; None when it has none (or one of another file).
    ``replay_path`` plays that replay instead, whatever file it was recorded on (for a variant
    of a level whose route is the same up to the part that changed)."""
    path = replay_path or replay_for(level.path)
    try:
        rep = Replay.load(path) if path is not None else None
    except ReplayError:
        rep = None
    if rep is None or (replay_path is None and rep.level_hash != level.source_hash):
        return None
    game = FlatGame(level, seed=rep.seed)
    rows, events, actions = [], [], []
    for a in rep.actions:
        v = game.space.being.velocity
        still = game.grounded and abs(v.x) < REST_SPEED and abs(v.y) < REST_SPEED
        p = game.position
        rows.append(
            (p[0], p[1], p[2], still, game.world.ball_z.copy(), game.world.ball_dir.copy(), _standing_on_ball(game))
        )
        actions.append(a)
        game.step(a)
        events += [(game.tick, e.kind, e.name) for e in game.events]
        if game.outcome == "complete":
            break
    x, y, z, still, bz, bd, on = zip(*rows)
    return FlatRoute(
        actions,
        np.array(x),
        np.array(y),
        np.array(z),
        np.array(still),
        np.array(bz),
        np.array(bd),
        np.array(on),
        events,
        game.tick,
        game.outcome == "complete",
    )


# ------------------------------------------------------------------ hands
Bot = Iterator[Actions]


def _replay(route: FlatRoute, start: int, stop: int | None = None) -> Bot:
    yield from route.actions[start:stop]


def _walk_to(game: FlatGame, x: float, within: float = 0.05, limit: int = 1800) -> Bot:
    """Walk (jumping when stuck) until the feet are within ``within`` of ``x`` and still."""
    best, since = abs(game.position[0] - x), game.tick
    for _ in range(limit):
        dx = x - game.position[0]
        if abs(dx) < within and abs(game.space.being.velocity.x) < REST_SPEED and game.grounded:
            return
        if abs(dx) < best - 0.05:
            best, since = abs(dx), game.tick
        stuck = game.tick - since > STALL_TICKS
        yield Actions(right=float(np.clip(dx * 2.0, -1.0, 1.0)), jump=stuck and game.tick % 30 < 15)


def _set_z(game: FlatGame, z: float, limit: int = 900) -> Bot:
    """Slide the plane to ``z`` and let it settle there."""
    for _ in range(limit):
        dz = z - game.z
        if abs(dz) < 0.004 and abs(game.vz) < 0.01:
            return
        yield Actions(w=float(np.clip(dz * 4.0, -1.0, 1.0)))


def _wait_for_balls(game: FlatGame, route: FlatRoute, tick: int, limit: int = 3600) -> Bot:
    """Stand still until every ball is where (and going the way) it was at the route's ``tick``."""
    want_z, want_dir = route.ball_z[tick], route.ball_dir[tick]
    for _ in range(limit):
        w = game.world
        if np.all(np.abs(w.ball_z - want_z) < 0.007) and np.all(w.ball_dir == want_dir):
            return
        yield Actions()


def back_on_route(game: FlatGame, route: FlatRoute, tick: int) -> Bot:
    """Get back to where the route stood still at ``tick`` (climbing out of anything first),
    wait for the balls, and play the rest of the route."""
    for _ in range(900):  # climb: walk back towards the place, jumping, until at its height
        if game.position[1] > route.y[tick] - 0.3 and game.grounded:
            break
        yield Actions(right=float(np.sign(route.x[tick] - game.position[0]) or -1.0), jump=game.tick % 30 < 15)
    yield from _walk_to(game, float(route.x[tick]))
    yield from _set_z(game, float(route.z[tick]))
    yield from _walk_to(game, float(route.x[tick]), within=0.02)
    yield from _wait_for_balls(game, route, tick)
    yield from _replay(route, tick)


# ------------------------------------------------------------------ the strategies
def straight(game: FlatGame, route: FlatRoute) -> Bot:
    goal = float(game.level.goal_center[0])
    while True:
        yield Actions(right=float(np.sign(goal - game.position[0])), jump=game.tick % 20 < 10)


def no_radar(game: FlatGame, route: FlatRoute) -> Bot:
    """To the last checkpoint before the first item is taken, then blind: walk on, and where
    something blocks, sweep the plane across the whole z range pushing and jumping."""
    taken = route.first("item_taken")
    if taken is None:
        return
    before = [t for t, k, _ in route.events if k == "checkpoint" and t < taken]
    start = before[-1] if before else 0
    yield from _replay(route, 0, start)
    lo, hi = game.level.z_range
    goal = float(game.level.goal_center[0])
    best, since = game.position[0], game.tick
    end = game.tick + int(SWEEP_SECONDS * 60) + 1800
    target = hi
    while game.tick < end:
        if game.position[0] > best + 0.05:
            best, since = game.position[0], game.tick
        if game.tick - since < STALL_TICKS:
            yield Actions(right=float(np.sign(goal - game.position[0])), jump=game.tick % 30 < 15)
            continue
        if abs(game.z - target) < 0.02:
            target = lo if target == hi else hi
        yield Actions(right=1.0, jump=game.tick % 30 < 15, w=float(np.sign(target - game.z)))


def _before_ride(route: FlatRoute) -> int | None:
    """The last tick the route stood still before it first stood on a ball."""
    ride = np.flatnonzero(route.on_ball)
    return None if not ride.size else route.rest_before(int(ride[0]))


def no_bodies(game: FlatGame, route: FlatRoute) -> Bot:
    """To where the route waited for the ball, then jump the gap with a run-up, only while no
    ball cuts the plane (the plane taken to the z range's end the balls visit least)."""
    rest = _before_ride(route)
    if rest is None:
        return
    yield from _replay(route, 0, rest)
    edge = float(route.x[rest])
    lo, hi = game.level.z_range
    yield from _set_z(game, hi if abs(hi) >= abs(lo) else lo)
    for _ in range(4):  # a few tries, climbing back out of the gap between them
        if game.position[0] > edge + 2.0 and game.grounded and game.position[1] > route.y[rest] - 0.3:
            break  # across
        yield from back_to(game, edge, float(route.y[rest]))
        yield from _walk_to(game, edge - 5.0)
        for _ in range(3600):  # until no ball will be in the plane during the run and the jump
            if _clear_for(game, 240):
                break
            yield Actions()
        for _ in range(240):  # the latest jump there is: off the edge, in the last tick of grace
            yield Actions(right=1.0, jump=game.position[0] > edge and game.air_ticks == COYOTE_TICKS - 1)
    yield from straight(game, route)


def _clear_for(game: FlatGame, ticks: int) -> bool:
    """Whether no ball cuts the plane for the next ``ticks`` ticks (the balls' own roll, forecast)."""
    world = copy.copy(game.world)
    world.ball_z, world.ball_dir = game.world.ball_z.copy(), game.world.ball_dir.copy()
    for _ in range(ticks):
        if any(world.ball_radius(i, game.z) > 0.0 for i in range(len(game.level.balls))):
            return False
        world.advance(game.dt)
    return True


def back_to(game: FlatGame, x: float, y: float) -> Bot:
    for _ in range(900):
        if game.position[1] > y - 0.3 and game.grounded:
            return
        yield Actions(right=float(np.sign(x - game.position[0]) or -1.0), jump=game.tick % 30 < 15)


def fall_in_pit(game: FlatGame, route: FlatRoute) -> Bot:
    rest = _before_ride(route)
    if rest is None:
        return
    yield from _replay(route, 0, rest)
    for _ in range(120):
        yield Actions(right=1.0)
    yield from (Actions() for _ in range(60))
    yield from back_on_route(game, route, rest)


def z_to_ends(game: FlatGame, route: FlatRoute) -> Bot:
    """At the first place the route waits after taking an item, the plane to both ends and back."""
    taken = route.first("item_taken")
    rest = route.rest_before(min(taken + 120, route.ticks - 1)) if taken is not None else 0
    yield from _replay(route, 0, rest)
    lo, hi = game.level.z_range
    yield from _set_z(game, lo)
    yield from _set_z(game, hi)
    yield from back_on_route(game, route, rest)


def crate_to_wall(game: FlatGame, route: FlatRoute) -> Bot:
    """Push the first crate the way it lies from the spawn for ten seconds, then play the route."""
    if not game.level.crates:
        return
    side = float(np.sign(game.level.crates[0].center[0] - game.position[0]) or 1.0)
    for _ in range(600):
        yield Actions(right=side)
    yield from back_on_route(game, route, 0)


@dataclass(frozen=True)
class FlatStrategy:
    """One strategy against a prologue level (see :class:`.strategies.Strategy`)."""

    name: str
    avoids: frozenset
    bot: Callable
    disruption: bool = False


def flat_library() -> list[FlatStrategy]:
    return [
        FlatStrategy("straight", frozenset({"w_move", "radar", "rigid_bodies"}), straight),
        FlatStrategy("no_radar", frozenset({"radar"}), no_radar),
        FlatStrategy("no_bodies", frozenset({"rigid_bodies"}), no_bodies),
        FlatStrategy("fall_in_pit", frozenset(), fall_in_pit, disruption=True),
        FlatStrategy("z_to_ends", frozenset(), z_to_ends, disruption=True),
        FlatStrategy("crate_to_wall", frozenset(), crate_to_wall, disruption=True),
    ]


_cache: dict = {}


def _prepared(path: str):
    if path not in _cache:
        level = load_flat_level(path)
        _cache[path] = (level, flat_route(level))
    return _cache[path]


def plan_flat(path: str) -> dict:
    t0 = time.perf_counter()
    level, route = _prepared(path)
    names = [s.name for s in flat_library()] if route is not None and route.won else ["straight"]
    return {"level": path, "needs": list(level.needs), "strategies": names, "seconds": time.perf_counter() - t0}


def run_flat(path: str, name: str) -> dict:
    """Run strategy ``name`` on the prologue level at ``path`` (the shape of ``runner.run_one``)."""
    t0 = time.perf_counter()
    level, route = _prepared(path)
    strategy = next(s for s in flat_library() if s.name == name)
    game = FlatGame(level)
    limit = 2 * (route.ticks if route else 3600) + 3600
    bot = strategy.bot(game, route)
    while game.tick < limit and game.outcome != "complete":
        try:
            actions = next(bot)
        except StopIteration:
            break
        game.step(actions)
    won = game.outcome == "complete"
    locks = []
    if strategy.disruption and not won:
        x, y, z = game.position
        locks.append(
            f"after {name} the bot could not get back on the route and finish "
            f"(it ended at x = {x:.1f}, y = {y:.1f}, z = {z:.2f} after {game.tick / 60:.0f} s)"
        )
    return {
        "level": path,
        "strategy": name,
        "won": won,
        "tick": game.completed_tick if won else game.tick,
        "softlocks": locks,
        "seconds": time.perf_counter() - t0,
    }
