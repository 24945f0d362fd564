"""The level's fixed geometry: the 3D world present at every w and its floors. (The 3D
worlds extended along w are 4D content: the projection stage draws them, see
``systems/sections.py``.)"""

from __future__ import annotations

from ..frame import Drawable
from ..system import System


def draw(game, frame, alpha) -> None:
    scene = game.scene
    frame.sky = "dome"  # the renderer's sky dome (a flat sky_color where it has none)
    frame.time = game.time + alpha * game.dt
    frame.drawables.append(Drawable("static", 0, scene.static_mesh))
    frame.drawables.append(Drawable("floor", 0, scene.floor_mesh, style="floor"))


SYSTEM = System("scenery", draw=draw)
