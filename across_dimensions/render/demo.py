"""Small scenes for screenshots, tests and the renderer benchmark.

``python -m across_dimensions.render.demo out.png [--size 1280x720] [--bench N] [--tris 100000] [--msaa 4]``
renders a demo frame offscreen, saves it, and with ``--bench`` times N frames.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from ..core.mesh import TriMesh3
from ..game.frame import Camera3, Drawable, Frame, Hud

# Per face: outward normal, and two in-plane axes (u, v) with u x v = normal in
# a right-handed basis, so the quad below winds counter-clockwise seen from outside.
_BOX_FACES = [
    ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
    ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
]


def box_mesh(center=(0.0, 0.0, 0.0), size=(1.0, 1.0, 1.0), color=(0.8, 0.3, 0.2, 1.0)) -> TriMesh3:
    """An axis-aligned box with flat normals.

    Parameters
    ----------
    center, size : (3,) floats
    color : 3 or 4 floats, linear RGB(A); or a (6, 4) array, one colour per face
        in the order +x, -x, +y, -y, +z, -z.

    Returns
    -------
    TriMesh3
        24 vertices, 12 triangles.
    """
    c = np.asarray(center, np.float64)
    h = 0.5 * np.asarray(size, np.float64)
    cols = np.asarray(color, np.float32)
    if cols.ndim == 1:
        cols = np.broadcast_to(np.r_[cols, [1.0] * (4 - len(cols))], (6, 4))
    verts, norms, colors, faces = [], [], [], []
    for i, (n, u, v) in enumerate(_BOX_FACES):
        n, u, v = (np.asarray(a, np.float64) for a in (n, u, v))
        base = len(verts)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            verts.append(c + h * (n + su * u + sv * v))
            norms.append(n)
            colors.append(cols[i])
        faces += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return TriMesh3(
        np.asarray(verts, np.float32),
        np.asarray(faces, np.uint32),
        np.asarray(norms, np.float32),
        np.asarray(colors, np.float32),
    )


def plane_mesh(half_size: float = 50.0, y: float = 0.0, color=(0.07, 0.075, 0.09, 1.0)) -> TriMesh3:
    """A horizontal square at height ``y`` (normal +y), two triangles."""
    s = float(half_size)
    v = np.array([[-s, y, -s], [s, y, -s], [s, y, s], [-s, y, s]], np.float32)
    return TriMesh3(
        v,
        np.array([[0, 2, 1], [0, 3, 2]], np.uint32),
        np.tile(np.float32([0, 1, 0]), (4, 1)),
        np.tile(np.asarray(color, np.float32), (4, 1)),
    )


def terrain_mesh(n_triangles: int = 100_000, extent: float = 60.0) -> TriMesh3:
    """A wavy heightfield of about ``n_triangles`` triangles (for benchmarks).

    Vertices are shared between triangles and normals are smooth.
    """
    n = max(2, int(np.sqrt(n_triangles / 2)) + 1)
    xs = np.linspace(-extent, extent, n)
    X, Z = np.meshgrid(xs, xs, indexing="xy")
    Y = 1.2 * np.sin(X * 0.35) * np.cos(Z * 0.27) + 0.4 * np.sin(X * 1.3 + Z * 0.7)
    # Normal of y = f(x, z): (-df/dx, 1, -df/dz), from central differences.
    dYdx = np.gradient(Y, xs, axis=1)
    dYdz = np.gradient(Y, xs, axis=0)
    N = np.stack([-dYdx, np.ones_like(Y), -dYdz], -1)
    N /= np.linalg.norm(N, axis=-1, keepdims=True)
    V = np.stack([X, Y - 1.2, Z], -1).reshape(-1, 3)
    t = (Y.reshape(-1) + 1.6) / 3.2
    C = np.stack([0.15 + 0.35 * t, 0.35 + 0.25 * t, 0.25 + 0.1 * (1 - t), np.ones_like(t)], -1)
    i = np.arange(n - 1)
    a = (i[:, None] * n + i[None, :]).reshape(-1)
    b, c, d = a + 1, a + n, a + n + 1
    faces = np.concatenate([np.stack([a, c, b], -1), np.stack([b, c, d], -1)])
    return TriMesh3(
        V.astype(np.float32), faces.astype(np.uint32), N.reshape(-1, 3).astype(np.float32), C.astype(np.float32)
    )


def demo_frame(n_terrain_triangles: int = 0, w: float = 0.35) -> Frame:
    """A small game-like scene: floor grid, lit boxes, a ghost, a wire box, HUD."""
    cam = Camera3(position=np.array([3.2, 2.4, -5.5]), yaw=-0.5, pitch=-0.25)
    # With a benchmark terrain, the terrain is the ground (a floor above it
    # would hide it and flatter the timings through early depth rejection).
    ground = (
        Drawable("terrain", 0, terrain_mesh(n_terrain_triangles))
        if n_terrain_triangles
        else Drawable("floor", 0, plane_mesh(200.0, 0.0), style="floor")
    )
    drawables = [
        ground,
        Drawable("cube", 0, box_mesh((0, 0.75, 0), (1.5, 1.5, 1.5), (0.85, 0.32, 0.2, 1.0))),
        Drawable("pillar", 0, box_mesh((-2.5, 1.5, 3.0), (0.8, 3.0, 0.8), (0.25, 0.55, 0.85, 1.0))),
        Drawable("ghost", 0, box_mesh((1.8, 0.6, 1.2), (1.2, 1.2, 1.2), (0.4, 0.95, 0.8, 1.0)), style="ghost"),
        Drawable("wire", 0, box_mesh((-1.2, 0.5, -1.0), (1.0, 1.0, 1.0), (1.0, 0.95, 0.4, 1.0)), style="wire"),
    ]
    return Frame(
        camera=cam, drawables=drawables, hud=Hud(w=w, w_min=-1.0, w_max=1.0, fps=60.0, message="Reach the exit")
    )


def main(argv=None) -> None:
    from .context import Offscreen, create_offscreen_context
    from .renderer import Renderer

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", default="demo.png")
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--msaa", type=int, default=0)
    ap.add_argument("--tris", type=int, default=0, help="add a terrain of about this many triangles")
    ap.add_argument("--bench", type=int, default=0, help="time this many frames")
    args = ap.parse_args(argv)
    width, height = (int(x) for x in args.size.lower().split("x"))
    ctx = create_offscreen_context()
    renderer = Renderer(ctx)
    target = Offscreen(ctx, width, height, samples=args.msaa)
    frame = demo_frame(args.tris)
    target.use()
    renderer.draw(frame)
    target.save_png(args.out)
    print(f"wrote {args.out} ({width}x{height}, {ctx.info['GL_RENDERER']})")
    if args.bench:
        # Warm up (first frame uploads and JIT-compiles the shaders in llvmpipe).
        for _ in range(2):
            renderer.draw(frame)
            ctx.finish()
        times = []
        for _ in range(args.bench):
            frame.camera.yaw += 0.01  # move so nothing can be cached between frames
            t0 = time.perf_counter()
            renderer.draw(frame)
            target.resolve()
            ctx.finish()
            times.append(time.perf_counter() - t0)
        t = np.array(times) * 1e3
        print(
            f"{args.bench} frames, {renderer.stats.triangles} triangles, {renderer.stats.draw_calls} draw calls, "
            f"msaa={args.msaa}: median {np.median(t):.1f} ms, min {t.min():.1f} ms, max {t.max():.1f} ms"
        )


if __name__ == "__main__":
    main()
