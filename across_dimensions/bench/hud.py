"""The HUD and the radar: a demo frame, and the CPU cost of drawing them.

``python -m across_dimensions.bench.hud [--frames N] [--pins P] [--png DIR]`` prints the
median CPU time per frame of laying out and submitting the HUD with the energy bar and a radar of
``P`` pins at 1280x720, next to the same HUD without them (the w indicator and crosshair only).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from ..game.frame import RADAR_KINDS, Drawable, EnergyGauge, Frame, Hud, Radar, RadarPin
from ..render.demo import box_mesh, demo_frame

#: Target: the HUD's and the radar's geometry (numpy, no OpenGL) per frame, milliseconds.
GEOMETRY_MS = 1.0


def demo_pins() -> list[RadarPin]:
    """Sixteen pins: every kind at least once, above, on and below the disc, two beyond the clamp."""
    spec = [
        ("crystal", -0.55, 0.45, 0.45, False),
        ("crystal", 0.30, 0.75, 0.0, True),
        ("crystal", 0.70, -0.20, -0.5, False),
        ("body", -0.25, 0.15, 0.0, True),
        ("body", 0.55, 0.35, 0.3, False),
        ("enemy", -0.15, 0.85, 0.6, False),
        ("enemy", 0.80, 0.45, -0.25, False),
        ("bullet", 0.10, 0.40, 0.15, False),
        ("bullet", 0.20, 0.25, 0.0, True),
        ("target", -0.75, -0.15, -0.35, False),
        ("camera_focus", 0.05, 0.60, 0.0, True),
        ("camera_eye", -0.35, -0.55, 0.35, False),
        ("object", 0.45, -0.65, 0.0, True),
        ("object", -0.80, 0.30, -0.65, False),
        ("crystal", -0.30, -0.25, 1.6, False),
        ("target", 0.15, -0.85, -2.0, False),
    ]
    return [RadarPin(k, x, z, h, v) for k, x, z, h, v in spec]


def random_pins(n: int, seed: int = 0) -> list[RadarPin]:
    """``n`` pins of random kinds spread over the disc, heights in [-1.2, 1.2]."""
    rng = np.random.default_rng(seed)
    r = np.sqrt(rng.random(n)) * 0.98
    a = rng.random(n) * 2 * np.pi
    h = rng.uniform(-1.2, 1.2, n)
    h[rng.random(n) < 0.25] = 0.0
    kinds = rng.integers(0, len(RADAR_KINDS), n)
    x, z = r * np.cos(a), r * np.sin(a)
    return [
        RadarPin(RADAR_KINDS[k], float(x[i]), float(z[i]), float(h[i]), bool(h[i] == 0.0)) for i, k in enumerate(kinds)
    ]


def hud_demo_frame(energy: EnergyGauge | None = None, pins: list[RadarPin] | None = None) -> Frame:
    """A level-like scene with the w indicator, an energy bar and the radar."""
    frame = demo_frame(w=0.35)
    frame.drawables.append(Drawable("crate", 0, box_mesh((3.5, 0.5, 4.0), (1.0, 1.0, 1.0), (0.55, 0.5, 0.42, 1.0))))
    frame.hud = Hud(
        w=0.35,
        w_min=-1.0,
        w_max=1.0,
        fps=None,
        message="",
        energy=energy if energy is not None else EnergyGauge(value=64.0, maximum=100.0, flash=0.0),
    )
    frame.radar = Radar(range=30.0, w_scale=0.5, pins=demo_pins() if pins is None else pins)
    return frame


def bench_hud(ctx, n_pins: int = 200, frames: int = 300, size: tuple[int, int] = (1280, 720)) -> dict:
    """Median CPU time per frame of laying out and submitting the HUD, with and without energy and radar.

    Only the calling thread's CPU time is counted (``time.thread_time``: on a shared machine wall
    time mostly measures the other jobs): each timed call is followed by ``ctx.finish()`` outside
    the timed part, so the GPU's (llvmpipe's rasterizer threads') work does not count.

    Parameters
    ----------
    ctx : moderngl.Context
    n_pins : int
    frames : int
        Frames timed per case (after a few warm-up frames).
    size : (width, height)

    Returns
    -------
    dict
        ``hud_ms`` (the HUD without energy and radar), ``hud_energy_radar_ms`` (with both),
        ``layout_ms`` (the geometry of the latter alone, numpy, no OpenGL calls), ``hud_layout_ms``
        (the same for the HUD without them), ``radar_driver_ms``
        (time inside the radar's draw calls: on llvmpipe, vertex shading and triangle setup run
        there, on the CPU): medians in milliseconds; ``radar_draw_calls`` and ``pins``.
    """
    from ..render.context import Offscreen
    from ..render.renderer import Renderer

    renderer = Renderer(ctx)
    target = Offscreen(ctx, *size)
    try:
        target.use()
        plain = Hud(w=0.35, w_min=-1.0, w_max=1.0, fps=60.0)
        full = Hud(w=0.35, w_min=-1.0, w_max=1.0, fps=60.0, energy=EnergyGauge(64.0, 100.0, 0.4))
        radar = Radar(range=30.0, w_scale=0.5, pins=random_pins(n_pins))
        vp = target.viewport

        driver = []

        def run(hud, with_radar):
            times = []
            for i in range(frames + 5):
                # Nothing may be cached between frames: the value, flash and pins change every frame.
                if hud.energy is not None:
                    hud.energy = EnergyGauge((i * 7) % 100, 100.0, (i % 10) / 10)
                pins = radar.pins[i % 3 :] + radar.pins[: i % 3]
                r = Radar(radar.range, radar.w_scale, pins)
                t0 = time.thread_time()
                if with_radar:
                    renderer.radar.draw(r, vp)
                renderer.hud.draw(hud, vp, r if with_radar else None)
                t1 = time.thread_time()
                ctx.finish()
                if i >= 5:
                    times.append(t1 - t0)
                    if with_radar:
                        driver.append(renderer.radar.driver_seconds)
            return float(np.median(times) * 1e3)

        out = {"hud_ms": run(plain, False), "hud_energy_radar_ms": run(full, True)}
        out |= _time_geometry(plain, full, radar, frames, size)
        out["radar_driver_ms"] = float(np.median(driver) * 1e3)
        out["radar_draw_calls"] = renderer.radar.draw_calls
        out["pins"] = n_pins
        return out
    finally:
        target.release()
        renderer.release()


def _time_geometry(plain: Hud, full: Hud, radar: Radar, frames: int, size) -> dict:
    """Median ms of the geometry alone (numpy, no OpenGL), the HUD with energy and radar
    (``layout_ms``) and without (``hud_layout_ms``, the baseline), alternating so both see
    the same machine load. On llvmpipe each draw call also runs the vertex shaders on the
    calling thread, which a GPU would do: that is not geometry, so it is left out here."""
    from ..render.hud import hud_quads
    from ..render.radar import radar_geometry

    times: dict = {"hud": [], "full": []}
    for i in range(frames):
        r = Radar(radar.range, radar.w_scale, radar.pins[i % 3 :] + radar.pins[: i % 3])
        t0 = time.thread_time()
        hud_quads(plain, *size, None)
        t1 = time.thread_time()
        hud_quads(full, *size, r)
        radar_geometry(r, 100.0)
        t2 = time.thread_time()
        times["hud"].append(t1 - t0)
        times["full"].append(t2 - t1)
    return {"hud_layout_ms": float(np.median(times["hud"]) * 1e3), "layout_ms": float(np.median(times["full"]) * 1e3)}


def main(argv=None) -> None:
    from ..render.context import Offscreen, create_offscreen_context
    from ..render.renderer import Renderer

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--pins", type=int, default=200)
    ap.add_argument("--png", default="", help="also write radar_1280.png and radar_800.png into this folder")
    args = ap.parse_args(argv)
    ctx = create_offscreen_context()
    if args.png:
        from pathlib import Path

        renderer = Renderer(ctx)
        for w, h in ((1280, 720), (800, 450)):
            with Offscreen(ctx, w, h) as t:
                t.use()
                renderer.draw(hud_demo_frame())
                t.save_png(Path(args.png) / f"radar_{w}.png")
        renderer.release()
    r = bench_hud(ctx, args.pins, args.frames)
    print(
        f"HUD at 1280x720, median of {args.frames} frames (CPU, layout + submission): "
        f"{r['hud_ms']:.3f} ms without energy and radar, {r['hud_energy_radar_ms']:.3f} ms with the energy bar "
        f"and a radar of {r['pins']} pins ({r['radar_draw_calls']} radar draw calls), "
        f"of which {r['layout_ms']:.3f} ms is the numpy layout and {r['radar_driver_ms']:.3f} ms is spent inside "
        f"the radar's draw calls (llvmpipe shading vertices and setting up triangles on the CPU)"
    )


if __name__ == "__main__":
    main()
