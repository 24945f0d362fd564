"""Render the desktop icon, ``packaging/across-dimensions.png``: a tesseract
seen through a 4D camera's frustum, drawn by the game's own renderer.

``python packaging/make_icon.py [OUT.png] [--size 256]`` (needs EGL, like
``across-dimensions demo --screenshots``). The PNG is committed; run this again
only to change the picture.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from across_dimensions.core import frustum_project, shapes
from across_dimensions.core.mesh import TriMesh3
from across_dimensions.core.transform import compose, rotation, translation
from across_dimensions.game.frame import Camera3, Drawable, Frame, Hud
from across_dimensions.render.context import Offscreen, create_offscreen_context
from across_dimensions.render.renderer import Renderer

HERE = Path(__file__).resolve().parent


def _tinted(mesh: TriMesh3, near, far) -> TriMesh3:
    """Colour each vertex by its 4D depth: near cyan, far violet (the game's
    cue for distance along w)."""
    d = mesh.depth if mesh.depth is not None else np.zeros(len(mesh.vertices), np.float32)
    t = np.clip((d - d.min()) / max(float(np.ptp(d)), 1e-6), 0.0, 1.0)[:, None]
    c = (1 - t) * np.float32(near) + t * np.float32(far)
    colors = np.concatenate([c, np.ones((len(c), 1))], 1).astype(np.float32)
    return TriMesh3(mesh.vertices, mesh.faces, mesh.normals, colors, mesh.depth)


def icon_frame() -> Frame:
    """The icon's scene: the tesseract turned in four planes, 3 units
    in front of the 4D camera along w."""
    turns = (rotation("xw", 0.5), rotation("yw", 0.35), rotation("xz", 0.6), rotation("yz", 0.3))
    model = compose(translation((0.0, 0.0, 0.0, 3.2)), *turns)
    projected = frustum_project(shapes.tesseract(), model=model, fov_deg=80.0)
    mesh = _tinted(projected, (0.35, 0.95, 1.0), (0.75, 0.35, 1.0))
    # Frame the projection: look along +z at its bounding box's centre, from
    # where the box's larger side fills about 85% of the picture.
    used = mesh.vertices[np.unique(mesh.faces)].astype(np.float64)
    lo, hi = used.min(0), used.max(0)
    centre, extent = 0.5 * (lo + hi), float(np.max((hi - lo)[:2]))
    fov = 50.0
    distance = 0.5 * extent / 0.85 / np.tan(np.radians(fov / 2)) + 0.5 * (hi - lo)[2]
    cam = Camera3(position=centre - np.array([0.0, 0.0, distance]), fov_y_deg=fov)
    return Frame(
        camera=cam,
        drawables=[
            Drawable("tesseract", 0, mesh, style="ghost"),
            Drawable("tesseract-edges", 0, mesh, style="wire"),
        ],
        hud=Hud(),
        sky_color=(0.04, 0.05, 0.09),
    )


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", default=str(HERE / "across-dimensions.png"))
    ap.add_argument("--size", type=int, default=256)
    args = ap.parse_args(argv)
    ctx = create_offscreen_context()
    target = Offscreen(ctx, args.size, args.size, samples=4)
    target.use()
    Renderer(ctx).draw(icon_frame(), hud=False)
    target.save_png(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
