"""Cost of the game's entity and system machinery, next to the same game without entities.

A generated format-2 level holds a floor and ``n`` entities: crystals and
spinning 5-cells spread over the hall and along w, as a busy level would. The
player walks and moves along w on a fixed script. Timed: ``Game.step`` (all
systems, no physics bodies) and ``Game.frame`` (what to draw, without the GPU),
as medians over many ticks, and the same two for the level without entities in
the same run, so the difference is what the entities cost.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from ..world.level import load_level
from .actions import Actions
from .sim import Game

_HEADER = """
[level]
format = 2
name = "bench"
w_range = [-2.0, 2.0]
[spawn]
position = [0.0, 0.0, -20.0, 0.0]
[goal]
center = [0.0, 1.0, 100.0]
size = [1.0, 1.0, 1.0]
[energy]
start = 100.0
max = 100.0
w_cost = 0.5
[[box]]
center = [0.0, -0.5, 0.0]
size = [60.0, 1.0, 60.0]
"""


def bench_level_text(n: int, seed: int = 0) -> str:
    """TOML of the benchmark level with ``n`` entities (half crystals, half spinning 5-cells)."""
    rng = np.random.default_rng(seed)
    parts = [_HEADER]
    for i in range(n):
        x, z = rng.uniform(-25, 25, 2)
        w = rng.uniform(-2, 2)
        if i % 2 == 0:
            parts.append(f"[[crystal]]\nposition = [{x:.3f}, 1.0, {z:.3f}, {w:.3f}]\nenergy = 1.0\n")
        else:
            parts.append(
                f'[[object]]\nshape = "5-cell"\nposition = [{x:.3f}, 1.5, {z:.3f}, {w:.3f}]\n'
                f"scale = 0.5\nspin = {{ xw = 30.0, yz = 20.0 }}\nsolid = false\n"
            )
    return "\n".join(parts)


def _script(t: int) -> Actions:
    return Actions(forward=1.0 if (t // 120) % 2 == 0 else -1.0, yaw=0.01, w=float(np.sin(t / 40.0)))


def _time_game(game: Game, ticks: int) -> tuple[float, float]:
    step, frame = [], []
    for t in range(ticks):
        a = _script(t)
        t0 = time.perf_counter()
        game.step(a)
        t1 = time.perf_counter()
        game.frame(0.5)
        t2 = time.perf_counter()
        step.append(t1 - t0)
        frame.append(t2 - t1)
    return 1e3 * float(np.median(step)), 1e3 * float(np.median(frame))


def bench_entities(n: int = 200, ticks: int = 600) -> dict:
    """Median ms per ``Game.step`` and per ``Game.frame`` with ``n`` entities and with none."""
    out = {}
    with tempfile.TemporaryDirectory() as d:
        for label, count in (("entities", n), ("baseline", 0)):
            path = Path(d) / f"bench_{count}.toml"
            path.write_text(bench_level_text(count), encoding="utf-8")
            game = Game(load_level(path))
            _time_game(game, 60)  # warm-up: kernels and caches
            out[f"{label}_step_ms"], out[f"{label}_frame_ms"] = _time_game(game, ticks)
    out["entities"] = n
    return out
