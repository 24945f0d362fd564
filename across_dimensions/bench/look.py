"""What the sci-fi look costs: frame time of every shipped level in both looks, in the same run.

``python -m across_dimensions.bench.look [--frames N]`` plays each shipped level from its
spawn (walking slowly forward, turning, and drifting along w so 4D cross-sections change) and
draws every frame twice into a 1280x720 offscreen target, once with the ``flat`` look and once
with the ``scifi`` look (:mod:`..render.materials`), alternating so both see the same machine load. It
reports, per look, the median milliseconds of ``Renderer.draw`` plus ``ctx.finish``: wall time,
and CPU time of the whole process (llvmpipe's rasterizer threads included), which a machine
shared with other work disturbs far less than wall time. That is the GPU side of a frame (on
llvmpipe, mostly fragment shading); the game's own frame (``Game.frame``) is the same for both
looks and is not counted.
"""

from __future__ import annotations

import argparse
import statistics
import time

from ..game.actions import Actions
from ..game.sim import Game
from ..render.context import Offscreen, create_offscreen_context
from ..render.renderer import Renderer
from ..world.level import load_level
from ..world.resources import level_files

LOOKS = ("flat", "scifi")


def bench_look(frames: int = 60, size=(1280, 720), levels=None) -> list[dict]:
    """Median ms per frame for each look on each level.

    Returns
    -------
    list of dict
        One per level: ``{"level": file name, "flat": ms, "scifi": ms, "flat_cpu": ms, "scifi_cpu": ms}``.
    """
    paths = list(levels) if levels is not None else list(level_files())
    ctx = create_offscreen_context()
    rows = []
    try:
        target = Offscreen(ctx, *size)
        renderers = {look: Renderer(ctx, look=look) for look in LOOKS}
        for path in paths:
            game = Game(load_level(path))
            times = {key: [] for look in LOOKS for key in (look, f"{look}_cpu")}
            for r in renderers.values():
                r.forget_meshes()
            for i in range(frames + 3):
                w = 0.6 if (i // 40) % 2 == 0 else -0.6
                game.step(Actions(forward=0.3, yaw=0.004, w=w))
                frame = game.frame()
                for look in LOOKS if i % 2 == 0 else LOOKS[::-1]:
                    target.use()
                    t0, c0 = time.perf_counter(), time.process_time()
                    renderers[look].draw(frame, target.viewport)
                    ctx.finish()
                    if i >= 3:  # the first frames upload every mesh and build programs
                        times[look].append(1e3 * (time.perf_counter() - t0))
                        times[f"{look}_cpu"].append(1e3 * (time.process_time() - c0))
            rows.append({"level": path.name, **{k: statistics.median(v) for k, v in times.items()}})
        for r in renderers.values():
            r.release()
        target.release()
    finally:
        ctx.release()
    return rows


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m across_dimensions.bench.look", description=__doc__)
    p.add_argument("--frames", type=int, default=60)
    args = p.parse_args(argv)
    for row in bench_look(max(5, args.frames)):
        print(
            f"{row['level']:28s} flat {row['flat']:6.2f} ms (CPU {row['flat_cpu']:6.2f})   "
            f"scifi {row['scifi']:6.2f} ms (CPU {row['scifi_cpu']:6.2f})"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
