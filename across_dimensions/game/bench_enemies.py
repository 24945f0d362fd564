"""Cost of animated enemies: ten of them in the player's slice, each re-sliced every tick.

The Hive's hall with ten enemies in front of the player, five of each body kind
(the swarm's ten hyperspheres, 6,000 tetrahedra; the lifted tree, about 10,000),
held in the player's slice by a blast's pull that never ends, so every tick
their animation poses change and every frame cuts all ten again (the worst case:
nothing can come from the section cache). Timed: ``Game.step`` and
``Game.frame`` (sections included, no GPU), medians over many ticks, next to
the same hall without enemies in the same run.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from ..world.level import load_level
from .actions import Actions
from .sim import Game

_HALL = """
[level]
format = 2
name = "enemy bench"
w_range = [-1.0, 1.0]
[spawn]
position = [0.0, 0.0, -10.0, 0.0]
[goal]
center = [0.0, 1.0, 100.0]
size = [1.0, 1.0, 1.0]
[health]
max = 10000.0
[[box]]
center = [0.0, -0.5, 0.0]
size = [30.0, 1.0, 40.0]
"""


def bench_level_text(n: int) -> str:
    """The hall with ``n`` enemies on two rows ahead of the player, kinds alternating."""
    parts = [_HALL]
    for i in range(n):
        x, z = -6.0 + 3.0 * (i % 5), -2.0 + 4.0 * (i // 5)
        kind = "swarm" if i % 2 == 0 else "morph"
        parts.append(f'[[enemy]]\nkind = "{kind}"\nposition = [{x:.1f}, 1.6, {z:.1f}, 0.0]\nsight = 0.1\n')
    return "\n".join(parts)


def _hold_in_slice(game: Game) -> None:
    """Every enemy dragged to w = 0 by a pull that never ends: in view, animated, not shooting."""
    for e in game.entities.of_kind("enemy"):
        e.data.state = "dragged"
        e.data.centre[3] = 0.0
        e.data.pull = (0.0, 0.0, game.tick, 10**9)


def _time(game: Game, ticks: int) -> tuple[float, float, int]:
    step, frame, cut = [], [], 0
    for t in range(ticks):
        a = Actions(yaw=0.002 * np.sin(t / 30.0))
        t0 = time.perf_counter()
        game.step(a)
        t1 = time.perf_counter()
        before = game.sections.computed
        game.frame(0.5)
        t2 = time.perf_counter()
        cut += game.sections.computed - before
        step.append(t1 - t0)
        frame.append(t2 - t1)
    return 1e3 * float(np.median(step)), 1e3 * float(np.median(frame)), cut


def bench_enemies(n: int = 10, ticks: int = 300) -> dict:
    """Median ms per ``Game.step`` and ``Game.frame`` with ``n`` enemies in view and with none.

    Returns
    -------
    dict
        ``enemies_step_ms``, ``enemies_frame_ms``, ``baseline_step_ms``, ``baseline_frame_ms``,
        ``sections_per_frame`` (enemy sections cut per frame), ``tets`` (their tetrahedra), ``enemies``.
    """
    out = {"enemies": n}
    with tempfile.TemporaryDirectory() as d:
        for label, count in (("enemies", n), ("baseline", 0)):
            path = Path(d) / f"enemies_{count}.toml"
            path.write_text(bench_level_text(count), encoding="utf-8")
            game = Game(load_level(path))
            game.step(Actions())
            _hold_in_slice(game)
            _time(game, 30)  # warm-up: kernels and caches
            step, frame, cut = _time(game, ticks)
            out[f"{label}_step_ms"], out[f"{label}_frame_ms"] = step, frame
            if count:
                out["sections_per_frame"] = cut / ticks
                out["tets"] = sum(len(e.mesh.tets) for e in game.entities.of_kind("enemy"))
    return out
