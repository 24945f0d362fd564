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
    # Boxes and the [[mesh]] surfaces are closed and the player never stands inside one: their
    # inner faces, always hidden, are skipped (a quarter of the frame's drawing on llvmpipe,
    # which rasterizes them in the depth pre-pass and depth-tests them in the shading pass; an
    # arch seen from close by, an eighth of the Cloister's frame).
    # Each box and surface is a part the renderer draws nearest first: the walls first, then
    # the floors (mostly in view, so drawn over little), then the surfaces.
    frame.drawables.append(Drawable("static", 0, scene.static_mesh, outside_only=True, parts=scene.static_parts))
    floor = Drawable("floor", 0, scene.floor_mesh, style="floor", outside_only=True, parts=scene.floor_parts)
    frame.drawables.append(floor)
    if not scene.open_mesh.is_empty:
        frame.drawables.append(Drawable("static_open", 0, scene.open_mesh, outside_only=True, parts=scene.open_parts))


SYSTEM = System("scenery", draw=draw)
