"""The frames of a level's shipped replay, drawn as the game draws them: where play stutters.

``bench levels`` times the worst place to stand; this times play itself. Each shipped replay is
played tick by tick and every tick's frame is built and drawn with its HUD at the render scale
in a 1280x720 offscreen view, after what the game does before a level's first frame (the
kernels' warm-up, the meshes made ready, the collector settled, the frustum switch's view drawn
under the first frame). Each frame is timed in wall time (step, frame and draw, finished), and
the longest ones are listed with what was new on them: a kernel loaded, glyphs rasterized, a
program built. A frame far above the level's median is one a player sees as a stutter.

The first frame of a level is reported on its own: it builds the programs and compiles
llvmpipe's shader variants for what the spawn shows (tens of ms, over a hundred for the first
level of a process), and the level appears after it. The median frame of the same run is every
row's baseline.
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from .._shipped_kernels import loaded_kernels
from ..core import heap
from ..game.replay import Replay
from ..game.sim import Game
from ..game.systems.ghosts import GhostView
from ..render.context import Offscreen, create_offscreen_context
from ..render.pip import warm_views
from ..render.renderer import Renderer
from ..render.scale import ScaledTarget, resolve_render_scale
from ..world.level import load_level
from ..world.resources import level_files, levels_dir, resolve_level

#: A frame this many times the level's median, or longer than :data:`LONG_MS`, is a stutter.
STUTTER_RATIO = 2.0
LONG_MS = 33.3
#: The longest frames listed per level.
LISTED = 5


def replays(levels=None) -> list:
    """``(level path, replay path)`` of each shipped 4D level with a shipped replay, of
    ``levels`` (names or files) or of every one.

    Raises
    ------
    FileNotFoundError
        A level of ``levels`` is no file and no shipped level.
    ValueError
        One is not a shipped 4D level with a replay (the Flatland prologue, a level of one's own).
    """
    pairs = []
    for path in level_files():
        replay = levels_dir() / "replays" / f"{path.stem}.json"
        if replay.is_file():
            pairs.append((path, replay))
    if not levels:
        return pairs
    wanted = {resolve_level(x).stem for x in levels}
    missing = sorted(wanted - {lv.stem for lv, _ in pairs})
    if missing:
        raise ValueError(f"not a shipped 4D level with a replay: {', '.join(missing)}")
    return [(lv, rp) for lv, rp in pairs if lv.stem in wanted]


class _News:
    """What was made for the first time since the last :meth:`take`: kernels loaded or compiled
    (numba's dispatchers' signatures), glyphs rasterized, programs built."""

    def __init__(self, renderer: Renderer):
        from ..render.font import default_font

        self._renderer = renderer
        self._font = default_font
        self._kernels = self._kernel_count()
        self._glyphs = default_font().revision
        self._programs = self._program_count()

    @staticmethod
    def _kernel_count() -> int:
        return sum(len(d.signatures) for d in loaded_kernels())

    def _program_count(self) -> int:
        return self._renderer.programs.built

    def take(self) -> list[str]:
        news = []
        kernels, glyphs, programs = self._kernel_count(), self._font().revision, self._program_count()
        if kernels > self._kernels:
            news.append(f"{kernels - self._kernels} kernel(s) loaded")
        if glyphs != self._glyphs:
            news.append("glyphs rasterized")
        if programs > self._programs:
            news.append(f"{programs - self._programs} program(s) built")
        self._kernels, self._glyphs, self._programs = kernels, glyphs, programs
        return news


def play_level(level_path, replay_path, ctx, scale: float, size=(1280, 720)) -> dict:
    """Play one replay, drawing every tick; its row (see :func:`run`)."""
    replay = Replay.load(replay_path)
    game = Game(load_level(level_path, arsenal=replay.arsenal), seed=replay.seed)
    game.ghost_view = GhostView()
    renderer = Renderer(ctx)
    screen, target = Offscreen(ctx, *size), ScaledTarget(ctx, scale)
    game.entity_sections.prepare(game.entities, game.states)  # as the game does at a level's start
    heap.settle()
    news = _News(renderer)
    frames = []  # (ms, tick, what was new)
    warm = game.level.camera.frustum  # as the play view does on a level's first frame
    try:
        for actions in replay.actions:
            t0 = time.perf_counter()
            game.step(actions)
            frame = game.frame()
            views, warm = (game.frame(pip=True) if warm else None), False
            if target.begin(size):
                if views is not None:
                    warm_views(renderer, views, target.viewport)
                renderer.draw(frame, target.viewport, hud=False)
                renderer.draw_radar(frame, screen.viewport, scale)
                target.present(screen.fbo, screen.viewport)
                renderer.draw_overlay(frame, screen.viewport, radar=False)
            else:
                screen.use()
                if views is not None:
                    warm_views(renderer, views, screen.viewport)
                renderer.draw(frame, screen.viewport)
            ctx.finish()
            frames.append((1e3 * (time.perf_counter() - t0), game.tick, news.take()))
    finally:
        renderer.release()
        target.release()
        screen.release()
    first, rest = frames[0], frames[1:]
    med = statistics.median(ms for ms, _, _ in rest)
    ms = np.array([f[0] for f in rest])
    limit = max(STUTTER_RATIO * med, LONG_MS)
    longest = sorted(rest, key=lambda f: -f[0])[:LISTED]
    return {
        "level": level_path.stem,
        "frames": len(frames),
        "outcome": game.outcome,
        "median_ms": round(med, 2),
        "p99_ms": round(float(np.percentile(ms, 99)), 2),
        "first_ms": round(first[0], 1),
        "stutters": int((ms > limit).sum()),
        "longest": [{"tick": t, "ms": round(m, 1), "new": n} for m, t, n in longest],
    }


def _described(frame: dict) -> str:
    """``tick: ms (what was new)`` of one of the longest frames."""
    new = f" ({', '.join(frame['new'])})" if frame["new"] else ""
    return f"{frame['tick']}: {frame['ms']:.1f}{new}"


def run(pairs, render_scale=None, out=print) -> list[dict]:
    """Play each of ``pairs`` (:func:`replays`), one row per level: ``frames``, ``median_ms``,
    ``p99_ms``, ``first_ms``, ``stutters`` (frames over :data:`STUTTER_RATIO` times the median and
    over :data:`LONG_MS`) and the ``longest``. The caller warms the kernels up first, as the title
    screen does before any level (``across_dimensions.app.warmup``)."""
    ctx = create_offscreen_context()
    rows = []
    try:
        scale = resolve_render_scale("auto" if render_scale is None else render_scale, ctx)
        out(
            f"Each level's shipped replay, every tick drawn at 1280x720, render scale {scale:g} "
            f"({ctx.info.get('GL_RENDERER', '?')}); wall ms per frame (step, frame, draw):"
        )
        head = f"{'level':22s} {'frames':>6s} {'median':>7s} {'p99':>7s} {'first':>7s} {'stutters':>8s}"
        out(head + "  longest (tick: ms, new)")
        for level_path, replay_path in pairs:
            row = play_level(level_path, replay_path, ctx, scale)
            rows.append(row)
            longest = "; ".join(_described(f) for f in row["longest"][:3])
            out(
                f"{row['level']:22s} {row['frames']:6d} {row['median_ms']:7.2f} {row['p99_ms']:7.2f} "
                f"{row['first_ms']:7.1f} {row['stutters']:8d}  {longest}"
            )
    finally:
        ctx.release()
    out(
        f"(stutters: frames after the first over {STUTTER_RATIO:g}x the level's median and over {LONG_MS:g} ms; "
        "the median is each row's baseline)"
    )
    return rows
