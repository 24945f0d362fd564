"""The library of naive strategies the probe runs against a level.

Two sorts:

- *Shortcuts* try to finish the level while avoiding some mechanics (``avoids``). One that
  wins although the level's ``[design] needs`` names a mechanic it avoided is a bypass.
- *Disruptions* do what a careless player might (waste the energy, push a crate into a
  corner, turn the slice back half way) and then play on as well as the bot can. They
  look for soft-locks (:mod:`.proofs`); their wins are no bypass.

Every strategy is a bot (:mod:`.pilot`, :mod:`.skills`): it reads the goal, the crystals,
the switches, the crates and the enemies from the game and steers, jumps and aims at them.
The full bot, :func:`play`, follows the shipped replay's steps (:mod:`.route`) with its
own hands, skipping those its :class:`~.pilot.Allow` forbids, and walks to the goal.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..game.actions import Actions
from ..world.design import NEEDS
from . import read
from .pilot import Allow, Ctx, Progress, distance_xz, drive, goto, idle, look, move_w, wait, yaw_to
from .skills import (
    camera_loot,
    fetch,
    fight,
    frustum_walk,
    gather,
    hit_target,
    push_body,
    sidestep,
    turn_handle,
    turn_slice,
    use,
    walk_to_goal,
    weapon_slot,
)

EVERYTHING = frozenset(NEEDS)
NO_WEAPONS: frozenset = frozenset()


@dataclass(frozen=True)
class Strategy:
    """One entry of the library.

    ``avoids``: mechanics (words of :data:`~across_dimensions.world.design.NEEDS`) the
    strategy never uses; empty for a disruption. ``applies(level, route)`` says whether it
    means anything in a level; ``bot(ctx)`` is its generator of actions.
    """

    name: str
    avoids: frozenset
    applies: Callable
    bot: Callable
    allow: Allow = Allow()
    disruption: bool = False
    ticks: int = 45 * 60


# ------------------------------------------------------------------ the full bot
def play(ctx: Ctx):
    """Follow the route's steps with the bot's own hands (those its allowances permit), then
    walk to the goal."""
    game, allow, route = ctx.game, ctx.allow, ctx.route
    yield idle(game)  # the first tick sets the systems up (switches, enemies)
    seen = {c.name for c in read.crystals(game) if abs(c.center[3] - read.feet(game)[3]) <= c.radius}
    yield from gather(ctx, seen)
    for step in route.steps:
        if read.won(game) or (ctx.give_up and game.tick >= ctx.give_up):
            return
        if step.kind == "target":
            yield from hit_target(ctx, step.name, step)
        elif step.kind == "pickup":
            yield from fetch(ctx, step.name)
        elif step.kind == "enemy" and step.info.get("opens"):
            yield from fight(ctx, step.name)
        elif step.kind == "manipulate" and allow.manipulation != "none":
            for plane, angle in step.info["angles"].items():
                yield from turn_handle(ctx, step.name, plane, _short_of(game, step.name, plane, angle, allow))
        elif step.kind == "body" and allow.bodies:
            yield from push_body(ctx, step.name, step.info["rest"][[0, 2]])
        elif step.kind == "turn" and allow.slice_turn != "none":
            yield from turn_slice(ctx, step)
        elif step.kind == "camera_loot" and allow.frustum != "none" and allow.camera_loot:
            yield from camera_loot(ctx, step)
        elif step.kind == "frustum_walk" and allow.frustum != "none" and allow.frustum_walk:
            yield from frustum_walk(ctx, step)
    yield from walk_to_goal(ctx)


def _short_of(game, name: str, plane: str, angle: float, allow: Allow) -> float:
    """The angle a strategy turns to: the route's, or one step short of it (``partial``)."""
    if allow.manipulation != "partial":
        return angle
    h = next(h for h in read.handles(game) if h.name == name)
    return angle - math.copysign(h.step or 15.0, angle)


# ------------------------------------------------------------------ plain walkers
def straight(ctx: Ctx):
    """Walk straight at the goal (at its w, when it has one), jumping at ledges and drops."""
    yield from walk_to_goal(ctx, tricks=False)


def wall_hug(ctx: Ctx):
    """Head for the goal; when stopped, follow the obstacle sideways (the bug algorithm),
    one side then the other, jumping where the ground asks for it."""
    game = ctx.game
    centre, _, _ = read.goal(game)
    side = 1
    while not read.won(game):
        if (yield from goto(ctx, centre[[0, 2]], tol=0.2, ticks=1200)):
            yield from wait(ctx, 5)
            return
        yield from sidestep(ctx, side)
        side = -side


def jump_spam(ctx: Ctx):
    """Run at the goal jumping at every chance, weaving left and right."""
    game = ctx.game
    centre, _, _ = read.goal(game)
    while not read.won(game):
        a = drive(game, centre[[0, 2]])
        weave = math.sin(game.tick * 0.08)
        yield Actions(forward=a.forward, right=weave, yaw=a.yaw, pitch=a.pitch, jump=True)


def unaimed_fire(ctx: Ctx):
    """Walk at the goal firing the gun straight ahead whenever it is ready, standing a few
    seconds at a third, a half and two thirds of the way, and backing off to fire again
    when stopped."""
    game = ctx.game
    yield from fetch(ctx, "gun")
    centre, _, _ = read.goal(game)
    start = read.feet(game)[[0, 2]]
    stops = [start + f * (centre[[0, 2]] - start) for f in (1 / 3, 1 / 2, 2 / 3)]
    for where in [*stops, centre[[0, 2]], None, None, None]:
        if where is None:  # stopped short of the goal: back off and fire again
            p = read.feet(game)[[0, 2]]
            where = p - 4.0 * (centre[[0, 2]] - p) / max(np.linalg.norm(centre[[0, 2]] - p), 1e-6)
        progress = None
        for _ in range(900):
            if read.won(game):
                return
            if progress is None:
                progress = Progress(game, where)
            if distance_xz(game, where) < 0.4 or progress.stuck(game, where):
                break
            yield _firing(ctx, drive(game, where))
        for _ in range(240):
            if read.won(game):
                return
            dy, dp = look(game, yaw_to(game, centre[[0, 2]]), 0.0)
            yield _firing(ctx, Actions(yaw=dy, pitch=dp))
    for _ in range(3):
        if (yield from walk_to_goal(ctx, tricks=False)):
            return


def _firing(ctx: Ctx, a: Actions) -> Actions:
    """``a`` with the gun in hand and fired when it is ready (level, straight ahead)."""
    game = ctx.game
    k = weapon_slot(ctx, "gun")
    if k is None:
        return a
    if read.slot(game) != k:
        return Actions(forward=a.forward, yaw=a.yaw, pitch=a.pitch, jump=a.jump, presses=(("weapon_1", 1),))
    fire = read.weapon_ready(game)
    return Actions(forward=a.forward, yaw=a.yaw, pitch=a.pitch, jump=a.jump, presses=(("fire", 1),) if fire else ())


# ------------------------------------------------------------------ disruptions
def waste(ctx: Ctx):
    """Empty the bar at the start: every weapon at the floor from the dearest, the frustum
    camera held, a manipulable turned to and fro, the slice turned short of a step and back,
    walking along w; then play on."""
    game = ctx.game
    yield idle(game)
    centre, _, _ = read.goal(game)
    away = yaw_to(game, centre[[0, 2]]) + math.pi  # shots go the other way, so none throws a switch
    for spec in read.weapons(game):  # a careless player takes every weapon lying about...
        yield from fetch(ctx, spec.kind)
    for spec in sorted(read.weapons(game), key=lambda s: -s.cost_milli):  # ...and fires it at the floor
        while read.energy(game) is not None and read.energy(game) * 1000 >= spec.cost_milli > 0:
            if not (yield from use(ctx, spec.kind, away, pitch=-0.6)):
                break
    if game.level.camera.frustum and read.energy(game):
        yield Actions(presses=(("switch_camera", 1),))
        while read.camera_mode(game) == "frustum":
            yield idle(game)
        yield from wait(ctx, 80)
    yield from _waste_turning(ctx)
    yield from _waste_slice(ctx)
    lo, hi = read.w_range(game)
    for _ in range(20):
        if not read.energy(game) or read.w_cost(game) <= 0 or hi <= lo:
            break
        yield from move_w(ctx, hi if read.feet(game)[3] < 0.5 * (lo + hi) else lo, ticks=240)
    if game.level.camera.turn and read.slice_cost(game) > 0:  # the turn is paid in one go: refill first
        for _ in range(50 * 60):  # long enough for a crystal to grow back, short of the bot's time
            if not read.regrowing(game):
                break
            yield idle(game)
    yield from play(ctx)


def _waste_turning(ctx: Ctx):
    game = ctx.game
    for h in read.handles(game):
        for plane, (lo, hi) in h.limits.items():
            for angle in (hi, lo, hi, lo, 0.0):
                if not read.energy(game):
                    break
                yield from turn_handle(ctx, h.name, plane, angle)


def _waste_slice(ctx: Ctx):
    """Where turning the slice costs energy: take every crystal lying about, then spend the bar
    on turns short of a step (held to 80 degrees, turned back, snapped home) until it is empty."""
    game = ctx.game
    if not (game.level.camera.turn and read.slice_cost(game) > 0):
        return
    yield from gather(ctx, {c.name for c in read.crystals(game)})
    for _ in range(10):
        if not read.energy(game):
            break
        for _ in range(120):
            if read.slice_away_deg(game) >= 80.0 or not read.energy(game):
                break
            yield idle(game, turn_zw_pos=True)
        while read.slice_away_deg(game) > 20.0:
            yield idle(game, turn_zw_neg=True)
        yield idle(game, presses=(("snap_slice", 1),))
        yield from wait(ctx, 30)


def push_to_end(direction):
    """Push every body the route uses as far as it goes along ``direction`` (x or z, + or -),
    then play on."""

    def bot(ctx: Ctx):
        game = ctx.game
        yield idle(game)
        for step in ctx.route.steps:  # what the route does before it uses the bodies (doors)
            if step.kind == "target" and step.tick < ctx.route.of_kind("body")[0].tick:
                yield from hit_target(ctx, step.name, step)
        for step in ctx.route.of_kind("body"):
            b = read.body_named(game, step.name)
            if b is not None:
                yield from push_body(ctx, step.name, b.center[[0, 2]] + 40.0 * np.asarray(direction), ticks=900)
        yield from play(ctx)

    return bot


def blast_to_ends(ctx: Ctx):
    """Blast every switch and body within reach to each end of the w range in turn, then play."""
    game = ctx.game
    lo, hi = read.w_range(game)
    things = read.targets(game) + read.bodies(game)
    for t in things:
        for w in (lo, hi):
            yield from goto(ctx, t.center[[0, 2]] + np.array([0.0, -2.0]), w, ticks=600)
            yield from use(ctx, "blast")
            yield from wait(ctx, 45)
    yield from play(ctx)


def turn_back_midway(ctx: Ctx):
    """Turn the slice as the route does, walk half way to the goal, turn it back; then play."""
    game = ctx.game
    steps = ctx.route.of_kind("turn")
    centre, _, _ = read.goal(game)
    yield idle(game)
    yield from gather(ctx, set())  # what the route takes before it turns (a turn may cost energy)
    yield from turn_slice(ctx, steps[0], back_after=0.5 * np.linalg.norm(centre[[0, 2]] - steps[0].at[[0, 2]]))
    yield from play(ctx)


# ------------------------------------------------------------------ the library
def _kinds(level) -> set:
    return {w.kind for w in level.weapons}


def _has_w(level, route) -> bool:
    return level.w_range[1] > level.w_range[0]


def _always(level, route) -> bool:
    return True


def _route_has(kind: str):
    return lambda level, route: route.uses(kind)


def library() -> list[Strategy]:
    """Every strategy, in the order the probe reports them."""
    return _walkers() + _without_weapons() + _without_tools() + _disruptions()


def _walkers() -> list[Strategy]:
    full = Allow()
    return [
        Strategy("straight", EVERYTHING - {"w_move"}, _always, straight),
        Strategy("wall_hug", EVERYTHING, _always, wall_hug, Allow(w=False)),
        Strategy("jump_spam", EVERYTHING, _always, jump_spam, Allow(w=False)),
        Strategy("no_w_move", frozenset({"w_move", "crystals", "radar"}), _has_w, play, full.but(w=False, radar=False)),
        Strategy(
            "visible_crystals_only",
            frozenset({"crystals", "radar"}),
            lambda lv, r: bool(lv.crystals),
            play,
            full.but(crystals="visible", radar=False),
        ),
        Strategy(
            "no_radar",
            frozenset({"radar"}),
            lambda lv, r: _has_w(lv, r) and lv.radar is not None,
            play,
            full.but(radar=False, crystals="visible"),
        ),
    ]


def _without_weapons() -> list[Strategy]:
    full = Allow()
    out = [
        Strategy(
            "no_weapons",
            frozenset({"gun", "blast", "field"}),
            lambda lv, r: bool(lv.weapons),
            play,
            full.but(weapons=NO_WEAPONS),
        )
    ]
    for kind in ("gun", "blast", "field"):
        others = frozenset({"gun", "blast", "field"} - {kind})
        several = lambda lv, r, k=kind: k in _kinds(lv) and len(_kinds(lv)) > 1  # noqa: E731
        out.append(Strategy(f"only_{kind}", others, several, play, full.but(weapons=frozenset({kind}))))
        out.append(Strategy(f"no_{kind}", frozenset({kind}), several, play, full.but(weapons=full.weapons - {kind})))
    out.append(
        Strategy(
            "unaimed_fire",
            EVERYTHING - {"gun"},
            lambda lv, r: "gun" in _kinds(lv),
            unaimed_fire,
            Allow(w=False, aim=False),
        )
    )
    return out


def _without_tools() -> list[Strategy]:
    full = Allow()
    manip = lambda lv, r: bool(lv.manipulables)  # noqa: E731
    return [
        Strategy("no_enemies", frozenset({"enemies"}), lambda lv, r: bool(lv.enemies), play, full.but(enemies=False)),
        Strategy("no_bodies", frozenset({"rigid_bodies"}), lambda lv, r: lv.bodies > 0, play, full.but(bodies=False)),
        Strategy("no_manipulation", frozenset({"manipulation"}), manip, play, full.but(manipulation="none")),
        Strategy("partial_turns", frozenset({"manipulation"}), manip, play, full.but(manipulation="partial")),
        Strategy(
            "no_slice_turn", frozenset({"slice_turn"}), lambda lv, r: lv.camera.turn, play, full.but(slice_turn="none")
        ),
        Strategy(
            "no_frustum",
            frozenset({"frustum", "orbit", "frustum_walk", "camera_loot"}),
            lambda lv, r: lv.camera.frustum,
            play,
            full.but(frustum="none"),
        ),
        Strategy(
            "frustum_no_orbit",
            frozenset({"orbit"}),
            lambda lv, r: lv.camera.frustum and (bool(lv.targets) or r.uses("frustum_walk")),
            play,
            full.but(frustum="fixed"),
        ),
        # Walking to the goal without stepping onto the image the route climbs.
        Strategy(
            "no_frustum_walk",
            frozenset({"frustum_walk"}),
            _route_has("frustum_walk"),
            play,
            full.but(frustum_walk=False),
        ),
        # Leaving the enemy's crystal to the kill or the blast: never freeing it with the camera's hold.
        Strategy(
            "no_camera_loot", frozenset({"camera_loot"}), _route_has("camera_loot"), play, full.but(camera_loot=False)
        ),
    ]


def _disruptions() -> list[Strategy]:
    out = [Strategy("waste_energy", frozenset(), lambda lv, r: lv.energy.enabled, waste, disruption=True)]
    for label, d in (("+x", (1.0, 0.0)), ("-x", (-1.0, 0.0)), ("+z", (0.0, 1.0)), ("-z", (0.0, -1.0))):
        out.append(Strategy(f"push_bodies_{label}", frozenset(), _route_has("body"), push_to_end(d), disruption=True))
    out += [
        Strategy(
            "blast_to_w_ends",
            frozenset(),
            lambda lv, r: "blast" in _kinds(lv) and bool(lv.targets),
            blast_to_ends,
            disruption=True,
        ),
        Strategy("turn_back_midway", frozenset(), _route_has("turn"), turn_back_midway, disruption=True),
    ]
    return out
