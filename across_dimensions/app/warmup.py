"""Compile the numba kernels before play starts, and say so when it is slow.

The first run after an install compiles every kernel (about a minute on a
2-core machine; later runs load them from the on-disk cache in well under a
second). Doing it up front, with a notice, beats a window that freezes on its
first frame or on entering the first level with rigid bodies.
"""

from __future__ import annotations

import sys
import threading

NOTICE_AFTER = 1.5  # seconds: a cache hit finishes well before this


def warm_up() -> None:
    """Run each kernel the game uses once on a tiny input."""
    from ..core import cross_section, frustum_project, shapes
    from ..core.transform import translation
    from ..physics import BodyDef, PhysicsWorld

    notice = threading.Timer(
        NOTICE_AFTER,
        lambda: print("Compiling the 4D kernels (first run only, about a minute)...", file=sys.stderr, flush=True),
    )
    notice.daemon = True
    notice.start()
    try:
        mesh = shapes.tesseract()
        cross_section(mesh)
        frustum_project(mesh, translation((0.0, 0.0, 0.0, -3.0)))
        world = PhysicsWorld(ground=False)
        world.set_static_boxes([((0.0, -0.5, 0.0), (5.0, 0.5, 5.0))])
        world.add_body(BodyDef("hypersphere", radius=0.5, position=(0.0, 0.5, 0.0, 0.0)))
        world.add_body(BodyDef("hypercube", size=1.0, position=(0.2, 1.6, 0.0, 0.0)))
        world.tick()
        world.push_box_out((0.0, 0.875, 0.0, 0.0), (0.3, 0.875, 0.3, 0.05))
        world.raycast((0.0, 3.0, 0.0, 0.0), (0.0, -1.0, 0.0, 0.0))
    finally:
        notice.cancel()
