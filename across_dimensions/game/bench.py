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

from ..core.shapes import make_shape
from ..core.transform import pose
from ..world.level import load_level
from ..world.resources import levels_dir
from .actions import Actions
from .entities import Placed, reach
from .player import step_player
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


# ------------------------------------------------------------------ walker collision
# The walker against true sections, next to the bounding boxes it used before, in the
# same run. The scene is the Bridge level with a solid 120-cell (3240 tetrahedra)
# turning beside the player and the level's slab turning too: both change every
# tick, so every tick slices them again (the worst case for the section caches).
# Each tick times one walker step (``game.player.step_player``), once against the
# sections' triangles (the game's way) and once against the sections' bounding
# boxes, slicing included in both.


def _collision_scene() -> tuple[Game, list]:
    game = Game(load_level(levels_dir() / "06_bridge.toml"))
    mesh = make_shape("120-cell")
    turning = Placed(pose((1.2, 1.0, 1.8, 0.0), {}, np.full(4, 0.8)))
    game.entities.spawn("object", "cell", mesh, turning, solid=True, radius=reach(mesh, 0.8))
    game.player.position = np.array([-1.0, 0.0, 1.5, 0.0])
    return game, [turning]


def _turn_solids(game: Game, movers: list, k: int) -> None:
    """Turn everything a little: the 120-cell in xw and yz, the slab in zw back and forth."""
    movers[0].move(pose((1.2, 1.0, 1.8, 0.0), {"xw": 0.03 * k, "yz": 0.017 * k}, np.full(4, 0.8)))
    slab = game.entities.named("slab")
    slab.data.offsets["zw"] = int(45000 + 40000 * np.sin(0.05 * k))
    slab.motion.move(slab.data.model())
    game.pose_version += 1  # the walker's per-tick caches see the new poses


def _section_bounds_colliders(game: Game):
    """The old walker's colliders: the level's boxes plus each solid section's bounds."""

    def colliders(w: float) -> np.ndarray:
        extra = []
        for e in game.entities:
            if e.solid and e.reaches_slice(game, w):
                key = f"bench:{e.id}"
                game.sections.section(key, e.mesh, e.model(game), w)
                extra.append(game.sections.bounds(key)[None])
        return np.concatenate([game.colliders_at(w), *extra]) if extra else game.colliders_at(w)

    return colliders


def bench_collision(ticks: int = 300) -> dict:
    """Time the walker's collision per 60 Hz tick with the level's solid objects turning every tick.

    Returns
    -------
    dict
        ``section_median_ms`` / ``section_p95_ms`` / ``section_cpu_median_ms``: a
        walker step against the sections' triangles (wall clock, and process CPU
        time); ``box_*``: the same against the sections' bounding boxes; ``triangles``: mean section triangles near
        the player per tick; ``tick_budget_ms``: 1000 / 60.
    """
    out = {}
    for mode in ("section", "box"):
        game, movers = _collision_scene()
        boxes = _section_bounds_colliders(game)
        times = np.empty(ticks)
        cpu = np.empty(ticks)
        tris = np.empty(ticks)
        g = float(game.level.gravity[1])
        _turn_solids(game, movers, 0)
        game.sections_at(0.0)  # warm-up: the slicing kernels' first call
        for k in range(ticks):
            _turn_solids(game, movers, k)
            # Walk back and forth across the platform's edge, beside the turning solids.
            a = Actions(right=1.0 if (k // 60) % 2 == 0 else -1.0, forward=0.3)
            c0 = time.process_time()
            t0 = time.perf_counter()
            if mode == "section":
                step_player(game.player, a, game.dt, g, game.level.w_range, game.colliders_at, None, np.inf,
                            game.sections_at)  # fmt: skip
            else:
                step_player(game.player, a, game.dt, g, game.level.w_range, boxes)
            times[k] = time.perf_counter() - t0
            cpu[k] = time.process_time() - c0
            tris[k] = sum(len(t) for t in game.sections_at(float(game.player.position[3])))
            if game.player.position[1] < -2.0:  # fell off: back onto the platform
                game.player.position = np.array([-1.0, 0.0, 1.5, 0.0])
                game.player.velocity[:] = 0.0
        out[f"{mode}_median_ms"] = 1e3 * float(np.median(times))
        out[f"{mode}_p95_ms"] = 1e3 * float(np.percentile(times, 95))
        out[f"{mode}_cpu_median_ms"] = 1e3 * float(np.median(cpu))  # less sensitive to other load
        if mode == "section":
            out["triangles"] = float(tris.mean())
    out["ticks"] = ticks
    out["tick_budget_ms"] = 1000.0 / 60.0
    return out


# ------------------------------------------------------------------ enemies
# Cost of animated enemies: ten of them in the player's slice, each re-sliced every tick.
#
# The Hive's hall with ten enemies in front of the player, five of each body kind
# (the swarm's ten hyperspheres, 6,000 tetrahedra; the lifted tree, about 10,000),
# held in the player's slice by a blast's pull that never ends, so every tick
# their animation poses change and every frame cuts all ten again (the worst case:
# nothing can come from the section cache). Timed: ``Game.step`` and
# ``Game.frame`` (sections included, no GPU), medians over many ticks, next to
# the same hall without enemies in the same run.

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


def enemy_level_text(n: int) -> str:
    """The hall with ``n`` enemies on two rows ahead of the player, kinds alternating."""
    parts = [_ENEMY_HALL]
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


def _time_enemies(game: Game, ticks: int) -> tuple[float, float, int]:
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
            path.write_text(enemy_level_text(count), encoding="utf-8")
            game = Game(load_level(path))
            game.step(Actions())
            _hold_in_slice(game)
            _time_enemies(game, 30)  # warm-up: kernels and caches
            step, frame, cut = _time_enemies(game, ticks)
            out[f"{label}_step_ms"], out[f"{label}_frame_ms"] = step, frame
            if count:
                out["sections_per_frame"] = cut / ticks
                out["tets"] = sum(len(e.mesh.tets) for e in game.entities.of_kind("enemy"))
    return out


# ------------------------------------------------------------------ the 4D camera
CAMERA_LEVEL = "08_around_the_corner.toml"


def bench_camera(cycles: int = 4, ticks: int = 60) -> dict:
    """Frame cost of each 4D camera mode on the camera level, next to cross-section, in one run.

    The player stands at the level's mark looking down the hall; each cycle runs
    ``ticks`` ticks synced (cross-section, the player turning), switches, runs frustum
    with the camera still while the player turns (cached projections), frustum while
    orbiting (every 4D thing re-projected each frame), then the glide back. The bar is
    filled so the frustum never runs dry. Timed per tick: ``Game.step`` plus
    ``Game.frame`` (without the GPU), and the same with the picture-in-picture on.

    Returns
    -------
    dict
        ``<mode>_ms`` median milliseconds per tick for ``synced``, ``frustum_still``,
        ``frustum_orbit``, ``returning``, ``synced_pip``, ``frustum_pip``; ``switch_ms`` and
        ``handover_ms`` the slowest switch tick and first synced tick after a return;
        ``level`` the level's name.
    """
    from .energy import EnergyBar

    game = Game(load_level(levels_dir() / CAMERA_LEVEL))
    game.energy = EnergyBar.of(1e5, 1e5)
    times: dict[str, list] = {k: [] for k in ("synced", "frustum_still", "frustum_orbit", "returning")}
    times |= {"synced_pip": [], "frustum_pip": [], "switch": [], "handover": []}

    def tick(label: str, actions: Actions, pip: bool = False) -> None:
        t0 = time.perf_counter()
        game.step(actions)
        game.frame(0.5, pip=pip)
        times[label].append(time.perf_counter() - t0)

    for _ in range(14):
        game.step(Actions(forward=1.0))
    look = Actions(yaw=0.004)
    switch = Actions(presses=(("switch_camera", 1),))
    for _ in range(ticks):  # warm-up: the kernels' first calls
        game.step(look)
        game.frame(0.5, pip=True)
    return_ticks = max(1, round(game.level.camera.return_time / game.dt))
    for _ in range(cycles):
        for _ in range(ticks):
            tick("synced", look)
        for _ in range(ticks // 4):
            tick("synced_pip", look, pip=True)
        tick("switch", switch)
        for _ in range(ticks):
            tick("frustum_still", look)
        for _ in range(ticks):
            tick("frustum_orbit", Actions(orbit_right=True))
        for _ in range(ticks // 4):
            tick("frustum_pip", Actions(orbit_left=True), pip=True)
        tick("returning", switch)
        for _ in range(return_ticks - 1):
            tick("returning", look)
        tick("handover", look)
    out = {f"{k}_ms": 1e3 * float(np.median(v)) for k, v in times.items() if k not in ("switch", "handover")}
    out["switch_ms"] = 1e3 * float(np.max(times["switch"]))
    out["handover_ms"] = 1e3 * float(np.max(times["handover"]))
    out["level"] = game.level.name
    return out
