"""CPU cost of the game's systems with many entities, each next to the same level without them.

Every row is a generated format-2 level played on a fixed script and timed per tick
(``Game.step``, all systems, no GPU) and per frame (``Game.frame``: what to draw, sections
included), as medians of the CPU time of the game's thread (``time.thread_time``: the game
steps and draws on one thread, numba kernels included; on a machine shared with other jobs,
wall time mostly measures the other jobs), together with the same level without the entities
in the same run, so the difference is what the entities cost:

- :func:`bench_entities`: a hall of ``n`` entities, half crystals, half spinning 5-cells,
  spread over the hall and along w; the player walks and moves along w.
- :func:`bench_crystals`: a dense field of crystals that grow back, around the player's path:
  every tick tests the near ones for pickup and some are taken.
- :func:`bench_enemies`: ``n`` enemies in front of the player, either held in its slice by a
  pull that never ends (every tick their animation changes and every frame cuts them all
  again: nothing comes from a cache) or left to their own state machine (they approach,
  shoot, flee, drift).

The game is driven only through its public interface: levels, actions, ``Game.step`` and
``Game.frame``, and :func:`~across_dimensions.game.systems.enemies.hold`.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from ..game.actions import Actions
from ..game.sim import Game
from ..game.systems import enemies
from ..world.level import load_level

#: Issue targets, milliseconds (the bench prints PASS or FAIL against each).
ENTITIES_FRAME_MS = 2.0
ENEMIES_STEP_MS = 1.0
ENEMIES_FRAME_MS = 2.0
MANY_ENEMIES_STEP_MS = 4.0
CRYSTALS_STEP_MS = 2.0

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


def crystal_field_text(n: int, seed: int = 0) -> str:
    """TOML of the walk through ``n`` crystals: a 12 m wide lane along the player's path, at
    every w of the range, each growing back 2 s after it is taken."""
    rng = np.random.default_rng(seed)
    parts = [_HEADER]
    for _ in range(n):
        x, z, w = rng.uniform(-6, 6), rng.uniform(-24, 8), rng.uniform(-2, 2)
        parts.append(f"[[crystal]]\nposition = [{x:.3f}, 1.0, {z:.3f}, {w:.3f}]\nenergy = 0.1\nrespawn = 2.0\n")
    return "\n".join(parts)


def _script(t: int) -> Actions:
    return Actions(forward=1.0 if (t // 120) % 2 == 0 else -1.0, yaw=0.01, w=float(np.sin(t / 40.0)))


def _time_game(game: Game, ticks: int, script=_script, frame: bool = True) -> tuple[float, float, int]:
    """Median CPU ms of ``Game.step`` and of ``Game.frame`` over ``ticks``, and the sections cut
    (entities sliced, ghosts included, and sections made one by one)."""
    step, draw, cut = [], [], 0
    revisions: dict = {}
    _batched(game, revisions)  # what the batches hold already is not this run's
    for t in range(ticks):
        a = script(t)
        t0 = time.thread_time()
        game.step(a)
        t1 = time.thread_time()
        before = game.sections.computed
        if frame:
            game.frame(0.5)
        t2 = time.thread_time()
        if frame:
            cut += game.sections.computed - before + _batched(game, revisions)
        step.append(t1 - t0)
        draw.append(t2 - t1)
    return 1e3 * float(np.median(step)), 1e3 * float(np.median(draw)), cut


def _batched(game: Game, revisions: dict) -> int:
    """Entities the last frame's batches sliced again (its own and its ghosts'): those of the
    batches whose revision moved since ``revisions`` (``id(batch) -> revision``, updated here;
    a ghost layer waiting its turn keeps its revision and slices nothing)."""
    es = game.entity_sections
    count = 0
    for b in [*es.batches.values(), *es.ghost_batches.values()]:
        if revisions.get(id(b)) != b.revision:
            count += b.sliced
        revisions[id(b)] = b.revision
    return count


def _triangles(game: Game) -> int:
    """Triangles the last frame's entity batches hold (its own and its ghosts'): what the
    slicing kernel wrote, three rows each."""
    es = game.entity_sections
    return sum(len(b.vertices) for b in [*es.batches.values(), *es.ghost_batches.values()]) // 3


def _games(texts: dict, ready=None):
    """``(label, game)`` for each level text, loaded from a temporary file."""
    with tempfile.TemporaryDirectory() as d:
        for label, text in texts.items():
            path = Path(d) / f"{label}.toml"
            path.write_text(text, encoding="utf-8")
            game = Game(load_level(path))
            if ready is not None:
                ready(game)
            yield label, game


def _rows(texts: dict, ticks: int, script=_script, frame=True, ready=None) -> tuple[dict, dict]:
    """Each level's medians, ``<label>_step_ms`` and ``<label>_frame_ms``, and the games by label.

    The games take turns in slices of 20 ticks, so each sees the same machine load."""
    games = dict(_games(texts, ready))
    for game in games.values():
        _time_game(game, 30, script, frame)  # warm-up: kernels and caches
    samples: dict = {label: ([], []) for label in games}
    for start in range(0, ticks, 20):
        for label, game in games.items():
            for t in range(start, min(start + 20, ticks)):
                s, f, _ = _time_game(game, 1, lambda _, t=t: script(t), frame)
                samples[label][0].append(s)
                samples[label][1].append(f)
    out = {}
    for label, (steps, frames) in samples.items():
        out[f"{label}_step_ms"] = float(np.median(steps))
        out[f"{label}_frame_ms"] = float(np.median(frames))
    return out, games


def bench_entities(n: int = 200, ticks: int = 600) -> dict:
    """Median ms per ``Game.step`` and per ``Game.frame`` with ``n`` entities and with none."""
    out, _ = _rows({"entities": bench_level_text(n), "baseline": bench_level_text(0)}, ticks)
    out["entities"] = n
    return out


def bench_crystals(n: int = 1000, ticks: int = 600) -> dict:
    """Median ms per ``Game.step`` walking through ``n`` crystals, and through none.

    Returns
    -------
    dict
        ``crystals_step_ms``, ``baseline_step_ms``, ``crystals`` and ``taken`` (crystals the
        player took, warm-up included).
    """
    texts = {"crystals": crystal_field_text(n), "baseline": crystal_field_text(0)}
    out, games = _rows(texts, ticks, frame=False)
    out["taken"] = games["crystals"].event_counts["crystal_collected"]
    out["crystals"] = n
    return out


# ------------------------------------------------------------------ enemies
_ENEMY_HALL = """
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


def enemy_level_text(n: int, sight: float = 0.1) -> str:
    """The hall with ``n`` enemies ahead of the player, kinds alternating: two rows of five for
    ten, a square grid over the hall for more. ``sight`` 0.1 keeps them hidden unless held."""
    parts = [_ENEMY_HALL]
    side = 5 if n <= 10 else int(np.ceil(np.sqrt(n)))
    step = 3.0 if n <= 10 else 24.0 / max(side - 1, 1)
    for i in range(n):
        x, z = -0.5 * step * (side - 1) + step * (i % side), -2.0 + (4.0 if n <= 10 else step) * (i // side)
        kind = "swarm" if i % 2 == 0 else "morph"
        parts.append(f'[[enemy]]\nkind = "{kind}"\nposition = [{x:.1f}, 1.6, {z:.1f}, 0.0]\nsight = {sight}\n')
    return "\n".join(parts)


def _hold(game: Game) -> None:
    game.step(Actions())
    enemies.hold(game, 0.0, 10**9)


def _turning(t: int) -> Actions:
    return Actions(yaw=0.002 * np.sin(t / 30.0))


def bench_enemies(n: int = 10, ticks: int = 300, held: bool = True) -> dict:
    """Median ms per ``Game.step`` and ``Game.frame`` with ``n`` enemies and with none.

    ``held``: in the player's slice and animated, every one re-sliced every frame; otherwise
    they see the player from anywhere in the hall and run their state machine (steering,
    shots, fleeing along w), and only the step is timed.

    Returns
    -------
    dict
        ``enemies_step_ms``, ``enemies_frame_ms``, ``baseline_step_ms``, ``baseline_frame_ms``,
        ``sections_per_frame`` (enemy sections cut per frame), ``triangles_per_frame`` (what
        those sections hold: the slicing kernel's output, most of the frame's cost), ``tets``
        (their tetrahedra), ``enemies``.
    """
    sight = 0.1 if held else 40.0
    texts = {"enemies": enemy_level_text(n, sight), "baseline": enemy_level_text(0)}
    out, games = _rows(texts, ticks, _turning, frame=held, ready=_hold if held else None)
    game = games["enemies"]
    out["tets"] = sum(len(e.mesh.tets) for e in game.entities.of_kind("enemy"))
    out["sections_per_frame"] = _time_game(game, 10, _turning, held)[2] / 10
    out["triangles_per_frame"] = _triangles(game) if held else 0
    out["enemies"] = n
    return out


def targets(ent: dict, crystals: dict, few: dict, many: dict) -> list[tuple[bool, str]]:
    """``(met, line)`` for each CPU target of the rows above."""

    def row(value, limit, what, base):
        return value <= limit, f"{what} <= {limit:g} ms: {value:.2f} ms (baseline {base:.2f} ms)"

    return [
        row(ent["entities_frame_ms"], ENTITIES_FRAME_MS, "Game.frame, 200 entities", ent["baseline_frame_ms"]),
        row(few["enemies_step_ms"], ENEMIES_STEP_MS, "Game.step, 10 enemies in view", few["baseline_step_ms"]),
        row(few["enemies_frame_ms"], ENEMIES_FRAME_MS, "Game.frame, 10 enemies in view", few["baseline_frame_ms"]),
        row(many["enemies_step_ms"], MANY_ENEMIES_STEP_MS, "Game.step, 64 enemies", many["baseline_step_ms"]),
        row(crystals["crystals_step_ms"], CRYSTALS_STEP_MS, "Game.step, 1000 crystals", crystals["baseline_step_ms"]),
    ]
