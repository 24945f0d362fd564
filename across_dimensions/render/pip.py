"""Picture in picture: a small inset showing the other projection of the same moment.

While the game shows the cross-section, the inset shows what the frustum switch
would show (the 4D camera in sync with the eye); while the 4D camera is detached,
it shows the cross-section. The game computes the inset's meshes only when asked
(``Game.frame(pip=True)`` fills ``frame.pip``), so the inset costs nothing when off.

The inset sits in the top-left corner, below the FPS counter, with a thin frame,
its height ``size`` times the window's and the window's aspect ratio. It draws the
3D scenery and the inset's 4D meshes from the player's camera, without HUD or radar,
as its own renderer view (``view="pip"``: its meshes stay cached while it is on).
"""

from __future__ import annotations

from dataclasses import replace

from ..game.frame import Frame, Hud
from .renderer import Renderer

FRAME_COLOR = (0.75, 0.9, 1.0)
#: Drawable keys of the 3D scenery, shared by both projections.
SCENERY_KEYS = ("static", "floor")


def inset_rect(viewport: tuple[int, int, int, int], size: float) -> tuple[int, int, int, int]:
    """The inset's ``(x, y, w, h)`` in pixels, OpenGL convention (origin bottom-left)."""
    x, y, w, h = viewport
    ih = max(16, int(round(h * size)))
    iw = max(16, int(round(ih * w / max(h, 1))))
    margin = max(4, w // 64)
    top = h // 12  # clear of the FPS counter and the slice gauges
    return x + margin, y + h - top - ih, iw, ih


def inset_frame(frame: Frame) -> Frame | None:
    """The frame the inset draws, or None when the game computed no inset meshes."""
    if frame.pip is None:
        return None
    scenery = [d for d in frame.drawables if d.key in SCENERY_KEYS]
    return Frame(
        frame.camera,
        scenery + list(frame.pip),
        hud=Hud(crosshair=False),
        sky_color=frame.sky_color,
        light_dir=frame.light_dir,
    )


def draw_pip(renderer: Renderer, frame: Frame, viewport: tuple[int, int, int, int], size: float) -> bool:
    """Draw the inset of ``frame`` into the bound framebuffer; False when there is none."""
    inset = inset_frame(frame)
    if inset is None:
        return False
    x, y, w, h = inset_rect(viewport, size)
    renderer.ctx.clear(*FRAME_COLOR, 1.0, viewport=(x - 2, y - 2, w + 4, h + 4))
    renderer.draw(inset, (x, y, w, h), hud=False, view="pip")
    return True


def warm_views(renderer: Renderer, frame: Frame, viewport: tuple[int, int, int, int]) -> bool:
    """Draw ``frame``'s inset over the whole of ``viewport``, to be drawn over by the frame.

    llvmpipe compiles a program the first time it draws with it in a given GL state (18-36 ms),
    so the first frames of a level's first frustum switch, and of its first glide back (the
    frustum view fading out as ghosts), each dropped one compiling the frustum view's programs
    (its meshes have no normals: programs of their own). Drawn under a level's first frame, at the
    same render scale into the same target, the inset (the scenery and what the switch would
    show), solid and then faded, compiles them then. False when ``frame`` has no inset
    (``Game.frame(pip=True)`` fills it)."""
    inset = inset_frame(frame)
    if inset is None:
        return False
    renderer.draw(inset, viewport, hud=False, view="pip")
    solid = {id(d) for d in frame.pip}
    fading = [replace(d, style="ghost", opacity=0.5) if id(d) in solid else d for d in inset.drawables]
    renderer.draw(replace(inset, drawables=fading), viewport, hud=False, view="pip")
    return True
