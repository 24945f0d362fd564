"""Drawing frames with OpenGL (moderngl).

The only package that imports moderngl; it never imports pyglet and never
changes game state: it reads a :class:`~across_dimensions.game.frame.Frame`.

Typical offscreen use::

    ctx = create_offscreen_context()
    renderer = Renderer(ctx)
    target = Offscreen(ctx, 1280, 720)
    target.use()
    renderer.draw(frame)
    target.save_png("shot.png")

On screen, the app wraps its window's context with :func:`wrap_current_context`,
calls ``ctx.screen.use()`` and then ``renderer.draw(frame)`` every frame.
"""

from ..core.edges import feature_edges
from .context import Offscreen, RenderError, create_offscreen_context, wrap_current_context
from .hud import HudRenderer, hud_quads
from .png import read_png, write_png
from .renderer import STYLES, Renderer, RenderStats

__all__ = [
    "Offscreen",
    "RenderError",
    "create_offscreen_context",
    "wrap_current_context",
    "Renderer",
    "RenderStats",
    "STYLES",
    "feature_edges",
    "HudRenderer",
    "hud_quads",
    "read_png",
    "write_png",
]
