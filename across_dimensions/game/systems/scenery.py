"""The level's fixed geometry: the 3D world present at every w, its floors, and the
3D worlds extended along w (sliced at the player's w)."""

from __future__ import annotations

import numpy as np

from ..frame import Drawable


def draw(game, frame, alpha) -> None:
    scene, w = game.scene, float(game.player.position[3])
    frame.sky = "dome"  # the renderer's sky dome (a flat sky_color where it has none)
    frame.time = game.time + alpha * _dt()
    frame.drawables.append(Drawable("static", 0, scene.static_mesh))
    frame.drawables.append(Drawable("floor", 0, scene.floor_mesh, style="floor"))
    for i, world in enumerate(scene.worlds):
        tri, rev = game.sections.section(f"world:{i}", world.mesh, np.eye(5), w)
        frame.drawables.append(Drawable(f"world:{i}", rev, tri, w_offset=_w_offset(world.layers_w, w)))


def _w_offset(layers_w, w: float) -> float:
    """Where the slice cuts a world along w: 0 at its centre, -1 or 1 where it ends (the w cue)."""
    lo, hi = float(layers_w[0]), float(layers_w[-1])
    half = 0.5 * (hi - lo)
    return (0.5 * (lo + hi) - w) / half if half > 0.0 else 0.0


def _dt() -> float:
    from ..sim import DT  # imported late: the simulation imports this module

    return DT
