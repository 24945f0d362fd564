"""What the w ghosts cost: frame time with ghosts on and off, in the same run.

``python -m across_dimensions.bench.ghosts [LEVEL] [--frames N] [--layers 1|2]`` plays
``LEVEL`` (Tumbling Hall by default) twice side by side, one game with ghosts and one without,
fed the same actions (walking and sweeping back and forth along w, so every section is recomputed
every frame: the worst case), and prints the median milliseconds per frame of

- ``sections``: ``Game.frame`` (the cross-sections the frame needs: projection cost), and
- ``frame``: that plus ``Renderer.draw`` into a 1280x720 offscreen target, finished (``ctx.finish``),

for each game, and the ratio of the ghost layer's extra section cost to the slice's own (the
issue's budget: at most 2 with one layer per side). The two games alternate frame by frame so
both see the same machine load.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from ..game.actions import Actions
from ..game.sim import Game
from ..game.systems.ghosts import GhostView
from ..render.context import Offscreen, create_offscreen_context
from ..render.renderer import Renderer
from ..world.level import load_level
from ..world.resources import level_files


def bench_ghosts(level_path=None, frames: int = 120, layers: int = 1, size=(1280, 720)) -> dict:
    """Median ms per frame with ghosts on and off.

    Returns
    -------
    dict
        ``{"level", "frames", "layers", "on": {"sections", "frame"}, "off": {...},
        "ghost_section_ratio"}``; ``ghost_section_ratio`` is (sections on - sections off) /
        sections off, i.e. the ghosts' projection cost in units of the slice's own.
    """
    path = Path(level_path) if level_path is not None else next(p for p in level_files() if "03_" in p.name)
    level = load_level(path)
    on, off = Game(level), Game(level, scene=None)
    on.ghost_view = GhostView(layers=layers)
    off.ghost_view = GhostView(enabled=False)
    ctx = create_offscreen_context()
    times = {"on": {"sections": [], "frame": []}, "off": {"sections": [], "frame": []}}
    try:
        target = Offscreen(ctx, *size)
        renderers = {"on": Renderer(ctx), "off": Renderer(ctx)}
        for i in range(frames):
            # Sweep along w (1 s each way) while walking in a slow circle.
            a = Actions(forward=0.6, yaw=0.01, w=1.0 if (i // 60) % 2 == 0 else -1.0)
            for name, game in (("on", on), ("off", off)):
                game.step(a)
                target.use()
                t0 = time.perf_counter()
                frame = game.frame()
                t1 = time.perf_counter()
                renderers[name].draw(frame, target.viewport)
                ctx.finish()
                t2 = time.perf_counter()
                if i >= 5:  # the first frames upload every mesh
                    times[name]["sections"].append(1e3 * (t1 - t0))
                    times[name]["frame"].append(1e3 * (t2 - t0))
        for r in renderers.values():
            r.release()
        target.release()
    finally:
        ctx.release()
    med = {k: {m: statistics.median(v) for m, v in d.items()} for k, d in times.items()}
    base = max(med["off"]["sections"], 1e-9)
    return {
        "level": path.name,
        "frames": frames,
        "layers": layers,
        **med,
        "ghost_section_ratio": (med["on"]["sections"] - med["off"]["sections"]) / base,
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m across_dimensions.bench.ghosts", description=__doc__)
    p.add_argument("level", nargs="?", default=None, help="level file (default: Tumbling Hall)")
    p.add_argument("--frames", type=int, default=120)
    p.add_argument("--layers", type=int, choices=(1, 2), default=1)
    args = p.parse_args(argv)
    r = bench_ghosts(args.level, max(10, args.frames), args.layers)
    print(f"ghosts benchmark: {r['level']}, {r['frames']} frames, {r['layers']} layer(s) per side, moving along w")
    for k in ("off", "on"):
        print(f"  ghosts {k:3s}: sections {r[k]['sections']:7.2f} ms   frame {r[k]['frame']:7.2f} ms (median)")
    print(f"  ghost sections cost {r['ghost_section_ratio']:.2f} x the slice's own (budget: 2)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
