"""The level's fixed geometry: the 3D world present at every w, its floors, and the
3D worlds extended along w (sliced at the player's w)."""

from __future__ import annotations

import numpy as np

from ..frame import Drawable


def draw(game, frame, alpha) -> None:
    scene, w = game.scene, float(game.player.position[3])
    frame.drawables.append(Drawable("static", 0, scene.static_mesh))
    frame.drawables.append(Drawable("floor", 0, scene.floor_mesh, style="floor"))
    for i, world in enumerate(scene.worlds):
        tri, rev = game.sections.section(f"world:{i}", world.mesh, np.eye(5), w)
        frame.drawables.append(Drawable(f"world:{i}", rev, tri))
