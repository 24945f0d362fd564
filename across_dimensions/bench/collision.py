"""The walker's collision per tick with solid 4D objects turning every tick, against true sections
and, in the same run, against the sections' bounding boxes (what it used before).

The scene is the Bridge level with a solid 120-cell (3240 tetrahedra) turning beside the
player and the level's slab turning too: both change every tick, so every tick slices them
again (the worst case for the section caches). Each tick times one walker step
(:func:`~across_dimensions.game.player.step_player`), once against the sections' triangles
(the game's way) and once against the sections' bounding boxes, slicing included in both.
"""

from __future__ import annotations

import time

import numpy as np

from ..core.shapes import make_shape
from ..core.transform import pose
from ..game.actions import Actions
from ..game.entities import Placed, reach
from ..game.player import Surroundings, step_player
from ..game.sim import Game
from ..game.systems import manipulation
from ..world.level import load_level
from ..world.resources import levels_dir

START = (-1.0, 0.0, 1.5, 0.0)


def _collision_scene() -> tuple[Game, list]:
    game = Game(load_level(levels_dir() / "06_bridge.toml"))
    mesh = make_shape("120-cell")
    turning = Placed(pose((1.2, 1.0, 1.8, 0.0), {}, np.full(4, 0.8)))
    game.entities.spawn("object", "cell", mesh, turning, solid=True, radius=reach(mesh, 0.8))
    game.place_player(START)
    return game, [turning]


def _turn_solids(game: Game, movers: list, k: int) -> None:
    """Turn everything a little: the 120-cell in xw and yz, the slab in zw back and forth."""
    movers[0].move(pose((1.2, 1.0, 1.8, 0.0), {"xw": 0.03 * k, "yz": 0.017 * k}, np.full(4, 0.8)))
    manipulation.set_offset(game, game.entities.named("slab"), "zw", int(45000 + 40000 * np.sin(0.05 * k)))
    game.solids_moved()  # the 120-cell too: the walker's per-tick caches see the new poses


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
        if mode == "section":  # the solids' true sections, as the game walks
            around = Surroundings(game.level.w_range, game.colliders_at, sections_at=game.sections_at)
        else:  # the sections' bounding boxes, as boxes
            around = Surroundings(game.level.w_range, boxes)
        _turn_solids(game, movers, 0)
        game.sections_at(0.0)  # warm-up: the slicing kernels' first call
        for k in range(ticks):
            _turn_solids(game, movers, k)
            # Walk back and forth across the platform's edge, beside the turning solids.
            a = Actions(right=1.0 if (k // 60) % 2 == 0 else -1.0, forward=0.3)
            c0 = time.process_time()
            t0 = time.perf_counter()
            step_player(game.player, a, game.dt, g, around)
            times[k] = time.perf_counter() - t0
            cpu[k] = time.process_time() - c0
            tris[k] = sum(len(t) for t in game.sections_at(float(game.player.position[3])))
            if game.player.position[1] < -2.0:  # fell off: back onto the platform
                game.place_player(START)
        out[f"{mode}_median_ms"] = 1e3 * float(np.median(times))
        out[f"{mode}_p95_ms"] = 1e3 * float(np.percentile(times, 95))
        out[f"{mode}_cpu_median_ms"] = 1e3 * float(np.median(cpu))  # less sensitive to other load
        if mode == "section":
            out["triangles"] = float(tris.mean())
    out["ticks"] = ticks
    out["tick_budget_ms"] = 1000.0 / 60.0
    return out
