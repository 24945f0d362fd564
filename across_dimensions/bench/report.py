"""``across-dimensions bench``: the CPU report, each figure next to its baseline from the same run.

Kernels (cross-section and frustum against a copy of the same bytes), physics (against an
empty step), then the game's own machinery: entities, crystals and enemies per tick and per
frame (against the same level without them), walker collision, the 4D camera, and with an
OpenGL context the HUD and radar, ghosts and the scene look. The CPU targets end the report,
one PASS or FAIL line each.
"""

from __future__ import annotations

from .. import _shipped_kernels as shipped
from ..core import bench as core_bench
from . import systems


def kernels_in_use() -> str:
    """Which compiled code the kernels' figures time: the shipped kernels, built for a baseline
    processor every x86-64 machine of the last decade runs, or kernels compiled here for this one
    (faster where its wider vectors pay, and so not the figure a player's first start gets)."""
    if shipped.active():
        return f"the shipped kernels, compiled for {shipped.CPU}"
    from numba.core import config

    if config.CPU_NAME:  # NUMBA_CPU_NAME
        return f"kernels compiled for {config.CPU_NAME}"
    import llvmlite.binding as ll

    return f"kernels compiled for this processor ({ll.get_host_cpu_name()})"


def run(out=print, quick: bool = False, physics: bool = True) -> list[tuple[bool, str]]:
    """Print the whole report through ``out``; returns the CPU targets as ``(met, line)``."""
    out(f"Kernels: {kernels_in_use()}.")
    out("Cross-section and frustum projection, one thread (median of runs):")
    sizes = (100_000, 300_000) if quick else (100_000, 1_000_000, 4_000_000)
    core_bench.run(sizes=sizes, repeat=3 if quick else 7, out=out)
    if physics:
        from ..physics.bench import report

        out("")
        out("Physics, piles of mixed dynamic bodies in contact (hyperspheres and hypercubes), one core:")
        report(out, sizes=(200,) if quick else (200, 1000), ticks=100 if quick else 200)
    rows = _systems(out, quick)
    _walker_and_camera(out, quick)
    hud = _gpu_side(out, quick)
    met = systems.targets(*rows)
    if hud is not None:
        met.append(_hud_target(hud))
    out("")
    out("CPU targets (median per tick or frame, this machine, this run):")
    for ok, line in met:
        out(f"  [{'PASS' if ok else 'FAIL'}] {line}")
    return met


def _systems(out, quick: bool) -> tuple[dict, dict, dict, dict]:
    ticks = 240 if quick else 600
    out("")
    out("Game systems, 200 entities (100 crystals, 100 spinning 5-cells) vs the same level empty:")
    res = systems.bench_entities(200, ticks=ticks)
    out(
        f"  Game.step:  {res['entities_step_ms']:.3f} ms per tick   (baseline, no entities: "
        f"{res['baseline_step_ms']:.3f} ms; target: entities add < 0.5 ms)"
    )
    out(
        f"  Game.frame: {res['entities_frame_ms']:.3f} ms per frame  (baseline: {res['baseline_frame_ms']:.3f} ms; "
        "sections of what reaches the slice included)"
    )
    cry = systems.bench_crystals(1000, ticks=ticks)
    out(
        f"  1000 crystals along the player's path (growing back; {cry['taken']} taken): Game.step "
        f"{cry['crystals_step_ms']:.3f} ms per tick   (baseline, the path without them: "
        f"{cry['baseline_step_ms']:.3f} ms)"
    )
    foes = systems.bench_enemies(10, ticks=120 if quick else 300)
    out("")
    out(
        f"Enemies: {foes['enemies']} animated in view ({foes['tets']:,} tetrahedra), each re-sliced every tick, "
        f"its ghosts every other frame ({foes['sections_per_frame']:.1f} sections, "
        f"{foes['triangles_per_frame']:,} triangles per frame):"
    )
    out(
        f"  Game.step {foes['enemies_step_ms']:.2f} ms, Game.frame {foes['enemies_frame_ms']:.2f} ms   "
        f"(baseline, the hall without them: {foes['baseline_step_ms']:.2f} ms, {foes['baseline_frame_ms']:.2f} ms; "
        "a 60 Hz frame is 16.7 ms)"
    )
    many = systems.bench_enemies(64, ticks=120 if quick else 300, held=False)
    out(
        f"  {many['enemies']} enemies on their own (steering, shooting, fleeing along w): Game.step "
        f"{many['enemies_step_ms']:.2f} ms   (baseline, the hall without them: {many['baseline_step_ms']:.2f} ms)"
    )
    return res, cry, foes, many


def _walker_and_camera(out, quick: bool) -> None:
    from .camera import bench_camera
    from .collision import bench_collision

    col = bench_collision(120 if quick else 300)
    out("")
    out(f"Walker collision per tick, solid 4D objects turning every tick (~{col['triangles']:.0f} section triangles):")
    out(
        f"  true sections {col['section_median_ms']:.3f} ms median, {col['section_p95_ms']:.3f} ms p95   "
        f"(baseline, their bounding boxes: {col['box_median_ms']:.3f} ms median; a tick is "
        f"{col['tick_budget_ms']:.1f} ms)"
    )
    cam = bench_camera(cycles=2 if quick else 4)
    out("")
    out(f"The 4D camera on {cam['level']}, Game.step + Game.frame per tick, median (no GPU):")
    out(
        f"  cross-section {cam['synced_ms']:.2f} ms   frustum, camera still {cam['frustum_still_ms']:.2f} ms   "
        f"frustum, orbiting {cam['frustum_orbit_ms']:.2f} ms   returning {cam['returning_ms']:.2f} ms"
    )
    out(
        f"  switch tick {cam['switch_ms']:.2f} ms, hand-over tick {cam['handover_ms']:.2f} ms (slowest); "
        f"picture in picture on: cross-section {cam['synced_pip_ms']:.2f} ms, frustum {cam['frustum_pip_ms']:.2f} ms"
    )


def _gpu_side(out, quick: bool) -> dict | None:
    """HUD and radar, ghosts and the look (they need an OpenGL context); the 200-pin HUD row."""
    try:
        from ..render.context import RenderError, create_offscreen_context
        from .ghosts import bench_ghosts
        from .hud import bench_hud

        ctx = create_offscreen_context()
    except (ImportError, RenderError) as e:
        out(f"HUD, radar and ghosts: skipped (no OpenGL context: {e})")
        return None
    out("")
    out("HUD and radar at 1280x720, CPU time per frame (target < 1 ms for the geometry):")
    try:
        for pins in (20, 200):
            hud = bench_hud(ctx, n_pins=pins, frames=100 if quick else 300)
            out(
                f"  {pins:3d} radar pins: HUD with energy bar and radar {hud['hud_energy_radar_ms']:.3f} ms   "
                f"(baseline, HUD alone: {hud['hud_ms']:.3f} ms); geometry {hud['layout_ms']:.3f} ms "
                f"(HUD alone {hud['hud_layout_ms']:.3f} ms), inside the radar's {hud['radar_draw_calls']} draw calls "
                f"{hud['radar_driver_ms']:.3f} ms"
            )
    finally:
        ctx.release()
    g = bench_ghosts(frames=60 if quick else 120)
    out("")
    out(f"Ghosts along w on {g['level']}, moving along w, 1280x720, median per frame (budget: 2x the slice's cost):")
    out(
        f"  ghosts on: sections {g['on']['sections']:.2f} ms, frame {g['on']['frame']:.1f} ms   (baseline, ghosts off: "
        f"sections {g['off']['sections']:.2f} ms, frame {g['off']['frame']:.1f} ms); ghosts cost "
        f"{g['ghost_section_ratio']:.2f}x the slice's own projection"
    )
    from .look import bench_look

    out("")
    out("Scene look, every shipped level at 1280x720, draw + finish, median per frame (wall, and CPU of all threads):")
    for row in bench_look(frames=20 if quick else 60):
        out(
            f"  {row['level']:24s} sci-fi {row['scifi']:6.1f} ms (CPU {row['scifi_cpu']:5.1f})   "
            f"(baseline, flat look: {row['flat']:6.1f} ms (CPU {row['flat_cpu']:5.1f}))"
        )
    return hud


def _hud_target(hud: dict) -> tuple[bool, str]:
    from .hud import GEOMETRY_MS

    return hud["layout_ms"] <= GEOMETRY_MS, (
        f"HUD and radar geometry, {hud['pins']} pins <= {GEOMETRY_MS:g} ms: {hud['layout_ms']:.2f} ms "
        f"(baseline, HUD alone {hud['hud_layout_ms']:.2f} ms)"
    )
