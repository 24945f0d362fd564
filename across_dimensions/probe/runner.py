"""Running the library against levels: one headless game per (level, strategy), in
worker processes, and the per-level rows the command prints.

A run steps the simulation (no rendering) with the strategy's bot until the level is won,
the bot gives up, its time is out, or nothing has changed for :data:`STALL_TICKS` (no step
nearer the goal, no new place visited, no event that matters). A won run of a strategy that avoided a mechanic the
level needs is a bypass; a run that ends unwon in a state some proof of :mod:`.proofs`
condemns is a soft-lock.
"""

from __future__ import annotations

import importlib
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from ..game.sim import Game
from ..world.level import load_level
from ..world.resources import is_prologue_file
from ..world.scene import build_scene
from . import read
from .flat import flat_library, plan_flat, run_flat
from .pilot import Ctx
from .proofs import softlocks
from .route import load_route
from .strategies import library

#: Ticks with no progress after which a run stops (12 simulated seconds).
STALL_TICKS = 12 * 60
#: Events whose count going up is progress, even far from the goal.
PROGRESS = (
    "crystal_collected",
    "target_hit",
    "enemy_hit",
    "enemy_defeated",
    "manipulated",
    "slice_aligned",
    "camera_switched",
    "blast",
    "field",
)

_cache: dict = {}  # per process: level path -> (level, scene, route)


def _prepared(path: str):
    if path not in _cache:
        level = load_level(path)
        scene = build_scene(level)
        _cache[path] = (level, scene, load_route(level, scene=scene))
    return _cache[path]


def strategies_for(level, route) -> list:
    """The strategies that mean something in ``level``."""
    return [s for s in library() if s.applies(level, route)]


def _progress(game, seen: set) -> tuple:
    """What counts as getting somewhere: the nearest the goal has been, the places visited
    (metre cells, half units of w) and the events of :data:`PROGRESS`."""
    centre, _, _ = read.goal(game)
    p = read.feet(game)
    seen.add((round(p[0]), round(p[1]), round(p[2]), round(2 * p[3])))
    d = round(float(np.hypot(centre[0] - p[0], centre[2] - p[2])), 1)
    return d, (len(seen), *(read.count(game, k) for k in PROGRESS))


def run_one(path: str, name: str, seed: int = 0) -> dict:
    """Run the strategy ``name`` on the level at ``path``; a dict of what happened."""
    if is_prologue_file(path):
        return run_flat(path, name)
    t0 = time.perf_counter()
    level, scene, route = _prepared(path)
    strategy = next(s for s in library() if s.name == name)
    game = Game(level, seed=seed, scene=scene)
    limit = max(strategy.ticks, int(1.5 * route.ticks))  # half as long again as the designer took
    ctx = Ctx(game, strategy.allow, route, give_up=limit)
    bot = strategy.bot(ctx)
    seen: set = set()
    best, since = _progress(game, seen), 0
    while game.tick < limit and not read.won(game):
        try:
            actions = next(bot)
        except StopIteration:
            break
        game.step(actions)
        now = _progress(game, seen)
        if now[0] < best[0] or now[1] != best[1]:
            best, since = (min(now[0], best[0]), now[1]), game.tick
        elif game.tick - since > STALL_TICKS:
            break
    won = read.won(game)
    return {
        "level": path,
        "strategy": name,
        "won": won,
        "tick": game.completed_tick if won else game.tick,
        "softlocks": [] if won else softlocks(game, route),
        "seconds": time.perf_counter() - t0,
    }


def _plan(path: str) -> dict:
    """The strategies that apply to a level, and what it needs (worker side)."""
    if is_prologue_file(path):
        return plan_flat(path)
    t0 = time.perf_counter()
    level, _, route = _prepared(path)
    names = [s.name for s in strategies_for(level, route)]
    return {"level": path, "needs": list(level.needs), "strategies": names, "seconds": time.perf_counter() - t0}


def _row(plan: dict, runs: list[dict]) -> dict:
    """One level's row: its bypasses and soft-locks, each naming the strategy."""
    by_name = {s.name: s for s in (flat_library() if is_prologue_file(plan["level"]) else library())}
    needs = set(plan["needs"])
    bypasses, locks = [], []
    for r in sorted(runs, key=lambda r: plan["strategies"].index(r["strategy"])):
        s = by_name[r["strategy"]]
        avoided = sorted(s.avoids & needs)
        if r["won"] and avoided and not s.disruption:
            bypasses.append(
                {"strategy": s.name, "avoided": avoided, "won_tick": r["tick"], "seconds": round(r["tick"] / 60, 2)}
            )
        for why in r["softlocks"]:
            locks.append({"strategy": s.name, "tick": r["tick"], "proof": why})
    return {
        "level": Path(plan["level"]).stem,
        "needs": plan["needs"],
        "strategies_run": plan["strategies"],
        "bypasses": bypasses,
        "softlocks": locks,
        "seconds": round(plan["seconds"] + sum(r["seconds"] for r in runs), 1),
    }


def probe(paths: list, workers: int = 2) -> list[dict]:
    """Probe the levels at ``paths`` with ``workers`` processes; one row per level, in order.

    Each row is ``{level, needs, strategies_run, bypasses, softlocks, seconds}`` where
    ``seconds`` is the processor time spent on the level (its runs added up).
    """
    paths = [str(p) for p in paths]
    try:  # worker processes need named semaphores, which some Python builds lack
        importlib.import_module("multiprocessing.synchronize")
    except (ImportError, NotImplementedError):
        workers = 1
    if workers <= 1:
        plans = [_plan(p) for p in paths]
        runs = [run_one(p["level"], n) for p in plans for n in p["strategies"]]
    else:
        ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
        with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
            plans = list(pool.map(_plan, paths))
            tasks = [(p["level"], n) for p in plans for n in p["strategies"]]
            # The slowest levels first, so the workers finish together.
            weight = {p: _weight(p) for p in paths}
            tasks.sort(key=lambda t: -weight[t[0]])
            runs = list(pool.map(run_one, *zip(*tasks))) if tasks else []
    return [_row(p, [r for r in runs if r["level"] == p["level"]]) for p in plans]


def _weight(path: str) -> float:
    """A guess at how long a level's runs take: enemies and bodies cost the most."""
    if is_prologue_file(path):
        return 1.0
    level = load_level(path)
    return 3.0 * len(level.enemies) + level.bodies + len(level.targets)
