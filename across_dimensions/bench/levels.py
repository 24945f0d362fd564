"""The worst frame of every shipped level, from everywhere a player can stand.

For each level, the player is placed on a ``grid x grid`` lattice of points
over the level's floor (at the spawn's height and w) and turned to eight
directions; points inside walls are kept on purpose: the view then faces a
wall from closer than any player can, the worst case for the rasterizer. At
each pose the game is stepped one tick (so moving things are sliced anew),
then the frame is built (``Game.frame``, ghosts on as in the window) and drawn
at 1280x720 with its HUD and radar, through the render scale, and finished.
Reported per level: the worst and the median frame time over the poses and
where the worst was. Each pose's time is the fastest of its few frames: other
jobs on a shared machine only ever add time, and the worst over a hundred poses
would otherwise measure the worst moment of the other jobs. Every pose is drawn
once, untimed, before any is measured: llvmpipe compiles shader variants the
first time it meets a mix of GL state, a one-off like the kernels' compile.
(Boxes are drawn outside only: inside one, the view sees through its faces to
what lies beyond, about what a player pressed against it sees.)

Beside each worst full-size frame's wall time is its CPU time (the whole
process, llvmpipe's threads included), and under each level where that frame's
time goes, pass by pass (:mod:`..render.passes`: CPU ms, triangles, overdraw),
then the same for the worst frame at the render scale, where the upscale to the
window is a full-size pass of its own.
The targets are printed for full size (with the render scale's figures, same
run, as the baseline) and for the render scale; ``bench levels`` then measures
the peak memory of ``play`` on the largest level (:mod:`.memory`).
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from ..core import heap
from ..game.actions import Actions
from ..game.sim import Game
from ..game.systems.ghosts import GhostView
from ..render.context import Offscreen, create_offscreen_context
from ..render.passes import PassProfile
from ..render.renderer import Renderer
from ..render.scale import ScaledTarget, resolve_render_scale, scaled_size
from ..world.level import load_level
from ..world.resources import level_files, resolve_level
from .memory import TARGET_MB

TARGET_FPS = 60.0
DIRECTIONS = 8


def _poses(game: Game, grid: int) -> list[tuple[float, float, float]]:
    """``(x, z, yaw)`` over the floor's bounds (or the static mesh's when there is no floor)."""
    scene = game.scene
    mesh = scene.floor_mesh if not scene.floor_mesh.is_empty else scene.static_mesh
    if mesh.is_empty:
        lo = hi = game.player.position[[0, 2]]
    else:
        v = mesh.vertices.astype(np.float64)
        lo, hi = v[:, [0, 2]].min(axis=0), v[:, [0, 2]].max(axis=0)
    # Inset half a cell so the outermost points stand on the floor, not on its rim.
    ts = (np.arange(grid) + 0.5) / grid
    out = []
    for tx in ts:
        for tz in ts:
            x, z = lo + np.array([tx, tz]) * (hi - lo)
            for k in range(DIRECTIONS):
                out.append((float(x), float(z), 2 * np.pi * k / DIRECTIONS))
    return out


def _draw_at(game: Game, view: tuple, pose: tuple, feet: tuple, scale: float) -> float:
    """Step the game, stand at ``pose`` ``(x, z, yaw)`` (``feet``: height and w), build the
    frame and draw it at ``scale`` with its HUD, finished; its seconds (the step not counted).
    With a :class:`PassProfile` on the renderer, each pass is charged to it."""
    ctx, renderer, scaled, screen, size = view
    prof = renderer.profile
    x, z, yaw = pose
    game.step(Actions())
    game.place_player((x, feet[0], z, feet[1]), yaw, 0.0)
    if prof is not None:
        prof.start()
    t0 = time.perf_counter()
    frame = game.frame()
    if prof is not None:
        prof.mark("game")
    if scaled[scale].begin(size):
        renderer.draw(frame, scaled[scale].viewport, hud=False)
        renderer.draw_radar(frame, screen.viewport, scale)
        scaled[scale].present(screen.fbo, screen.viewport)
        if prof is not None:
            prof.mark("upscale")
        renderer.draw_overlay(frame, screen.viewport, radar=False)
    else:
        screen.use()
        renderer.draw(frame, screen.viewport)
    ctx.finish()
    if prof is not None:
        prof.mark("hud")
        prof.stop()
    return time.perf_counter() - t0


def _geometry(game: Game) -> int:
    """The level's size: scenery triangles plus the tetrahedra of its 4D worlds and objects."""
    scene = game.scene
    tris = sum(len(m.faces) for m in (scene.static_mesh, scene.floor_mesh, scene.open_mesh))
    return tris + sum(len(w.mesh.tets) for w in scene.worlds) + sum(len(o.mesh.tets) for o in scene.objects)


def _profile(game: Game, view: tuple, pose: tuple, feet: tuple, frames: int, scale: float = 1.0) -> list[dict]:
    """Where the time of the frame at ``pose`` goes at ``scale``, pass by pass (see
    :mod:`..render.passes`): the mean of ``frames`` profiled frames. Overdraw is per pixel of
    the scaled view."""
    renderer, size = view[1], view[4]
    w, h = scaled_size(size, scale)
    renderer.profile = PassProfile(view[0], w * h)
    try:
        for _ in range(frames):
            _draw_at(game, view, pose, feet, scale)
        return renderer.profile.rows(frames)
    finally:
        renderer.profile = None


def _print_passes(rows: list[dict], out, where: str = "full size") -> None:
    """One line of the passes that cost anything: ms, triangles (k) and overdraw (x the view)."""
    parts = []
    for r in rows:
        if r["triangles"]:
            parts.append(f"{r['pass']} {r['ms']:.1f} ({r['triangles'] / 1e3:.1f}k tri, {r['overdraw']:.2f}x)")
        elif r["ms"] >= 0.05:
            parts.append(f"{r['pass']} {r['ms']:.1f}")
    out(f"    {where}, worst pose, CPU ms per pass: " + " | ".join(parts))


def _measure(game: Game, view: tuple, poses: list, feet: tuple, scale: float, frames: int) -> dict:
    """Per scale (the render scale and 1), per pose: ``(fastest wall seconds, pose, its CPU seconds)``."""
    # Warm-up, untimed: llvmpipe compiles a variant of a shader for each new mix of GL
    # state the first time it meets one (tens of ms, once per run, like the kernels'
    # compile); the frames measured are the ones a player sees after that.
    for pose in poses:
        for s in dict.fromkeys((scale, 1.0)):
            _draw_at(game, view, pose, feet, s)
    per_pose = {scale: [], 1.0: []}
    for pose in poses:
        # Each scale's frames in a row, as the game draws them (interleaving the two sizes
        # frame by frame would make each frame start with the other size's buffers in cache);
        # the first frame of a pose uploads its sections and is not counted.
        for s in dict.fromkeys((scale, 1.0)):
            times = []
            for _ in range(frames + 1):
                c0 = time.process_time()
                times.append((_draw_at(game, view, pose, feet, s), time.process_time() - c0))
            wall, cpu = min(times[1:])
            per_pose[s].append((wall, pose, cpu))
    return per_pose


def run(levels=None, grid: int = 6, frames: int = 3, render_scale=None, size=(1280, 720), out=print) -> list[dict]:
    """Measure each level; returns one row per level.

    Every pose is drawn at the render scale and then, right after, at full
    resolution, so both see about the same machine load: the ratio of the two is
    what the render scale buys.

    Parameters
    ----------
    levels : list of str, optional
        Level files or shipped names; default every shipped level.
    render_scale : float, optional
        Default: what the game picks for this GL renderer (``"auto"``).
    """
    paths = [resolve_level(x) for x in levels] if levels else list(level_files())
    ctx = create_offscreen_context()
    rows = []
    try:
        scale = resolve_render_scale("auto" if render_scale is None else render_scale, ctx)
        out(f"Every shipped level, {grid}x{grid} standing points x {DIRECTIONS} directions, 1280x720 at render scale")
        out(f"{scale:g} ({ctx.info.get('GL_RENDERER', '?')}) and at full size; each pose: fastest of {frames} frames")
        out(
            f"{'level':22s} {'poses':>5s} {'median':>7s} {'worst':>7s} {'worst fps':>9s} {'full: worst':>11s} "
            f"{'fps':>6s} {'CPU ms':>7s}  worst at (x, z, yaw)"
        )
        screen = Offscreen(ctx, *size)
        scaled = {scale: ScaledTarget(ctx, scale), 1.0: ScaledTarget(ctx, 1.0)}
        for path in paths:
            game = Game(load_level(path))
            game.ghost_view = GhostView()
            renderer = Renderer(ctx)
            heap.settle()  # as the game does after loading a level
            feet = (float(game.player.position[1]), float(game.player.position[3]))
            view = (ctx, renderer, scaled, screen, size)
            per_pose = _measure(game, view, _poses(game, grid), feet, scale, frames)
            worst, at, _ = max(per_pose[scale])
            worst_full, at_full, cpu_full = max(per_pose[1.0])
            passes = _profile(game, view, at_full, feet, frames)
            # At the render scale the upscale to the window is a pass of its own, at full size.
            passes_scaled = _profile(game, view, at, feet, frames, scale) if scale < 1.0 else []
            renderer.release()
            size_of_level = _geometry(game)
            med = statistics.median(t for t, _, _ in per_pose[scale])
            row = {
                "level": path.stem,
                "poses": len(per_pose[scale]),
                "render_scale": scale,
                "median_ms": round(1e3 * med, 3),
                "worst_ms": round(1e3 * worst, 3),
                "worst_fps": round(1.0 / worst, 2),
                "worst_at": [round(at[0], 2), round(at[1], 2), round(float(np.degrees(at[2])), 1)],
                "full_worst_ms": round(1e3 * worst_full, 3),
                "full_worst_fps": round(1.0 / worst_full, 2),
                # CPU time of the whole process (llvmpipe's threads included) for that frame: the
                # drawing's work, which other jobs on a shared machine disturb far less than wall time.
                "full_worst_cpu_ms": round(1e3 * cpu_full, 3),
                "full_worst_at": [round(at_full[0], 2), round(at_full[1], 2), round(float(np.degrees(at_full[2])), 1)],
                "passes": passes,
                "passes_at_scale": passes_scaled,
                "geometry": size_of_level,
            }
            rows.append(row)
            out(
                f"{row['level']:22s} {row['poses']:5d} {row['median_ms']:7.2f} {row['worst_ms']:7.2f} "
                f"{row['worst_fps']:9.1f} {row['full_worst_ms']:11.2f} {row['full_worst_fps']:6.1f} "
                f"{row['full_worst_cpu_ms']:7.1f}  "
                f"({at[0]:.1f}, {at[1]:.1f}, {np.degrees(at[2]):.0f} deg)"
            )
            _print_passes(passes, out)
            if passes_scaled:
                _print_passes(passes_scaled, out, f"render scale {scale:g}")
        for t in scaled.values():
            t.release()
        screen.release()
    finally:
        ctx.release()
    return rows


def largest(rows: list[dict]) -> dict:
    """The row of the largest level measured (scenery triangles plus 4D tetrahedra)."""
    return max(rows, key=lambda r: r["geometry"])


def print_targets(rows, memory=None, out=print) -> None:
    """The PASS/FAIL lines: each level at full size (its baseline: the same poses at the render
    scale, same run) and at the render scale, and ``memory`` (``(MB, note)`` of ``play`` on the
    largest level; None: not measured)."""
    out("Target (2 cores, llvmpipe): every shipped level >= 60 FPS everywhere a player can stand, at full 1280x720")
    for r in rows:
        mark = "PASS" if r["full_worst_fps"] >= TARGET_FPS else "FAIL"
        out(
            f"  [{mark}] {r['level']:22s} full size: worst {r['full_worst_fps']:.1f} FPS "
            f"(baseline, same poses at render scale {r['render_scale']:g}: worst {r['worst_fps']:.1f}, "
            f"median {1e3 / r['median_ms']:.1f} FPS)"
        )
    out("Target: the same at the default render scale")
    for r in rows:
        mark = "PASS" if r["worst_fps"] >= TARGET_FPS else "FAIL"
        out(f"  [{mark}] {r['level']:22s} worst {r['worst_fps']:.1f} FPS at render scale {r['render_scale']:g}")
    if memory is not None:
        mb, note = memory
        big = largest(rows)["level"]
        line = f"peak memory of play on the largest level ({big}) <= {TARGET_MB:.0f} MB"
        if mb is None:
            out(f"  [n/a ] {line}: not measured ({note})")
        else:
            out(f"  [{'PASS' if mb <= TARGET_MB else 'FAIL'}] {line}: {mb:.0f} MB ({note}, maximum resident set)")
