"""OpenGL contexts and offscreen framebuffers.

This is the one module that creates OpenGL contexts. Two kinds exist:

* :func:`create_offscreen_context` - a standalone EGL context with no window,
  for tests, screenshots and benchmarks (works on Mesa llvmpipe without a GPU
  or display).
* :func:`wrap_current_context` - wraps the context a windowing layer (the app,
  with pyglet) has already made current, so the app never imports moderngl.

Both raise :class:`RenderError` with a readable reason instead of moderngl's
low-level exceptions.
"""

from __future__ import annotations

import moderngl
import numpy as np

from .png import write_png

#: OpenGL version the shaders are written for (GLSL 330 core).
REQUIRED_GL = 330


class RenderError(RuntimeError):
    """Rendering cannot happen: no usable OpenGL, bad input, or a GL failure."""


def color_writes(fbo: moderngl.Framebuffer, on: bool) -> None:
    """Turn the colour writes of ``fbo``, the bound framebuffer, on or off at once.

    moderngl (5.13) only stores the colour mask of a framebuffer with one colour attachment
    when it is set, and applies it at the framebuffer's next ``clear`` or ``use``: a depth-only
    pass that only sets the mask writes its colour all the same, and once a masked clear has
    applied it, setting it back does not turn colour writes on again. ``use`` applies it now,
    with the framebuffer's viewport, scissor and depth mask, which are the current ones.
    """
    fbo.color_mask = (on,) * 4
    fbo.use()


def create_offscreen_context(require: int = REQUIRED_GL) -> moderngl.Context:
    """Create a standalone (windowless) OpenGL context through EGL.

    Parameters
    ----------
    require : int
        Minimum OpenGL version as ``major * 100 + minor * 10``.

    Returns
    -------
    moderngl.Context
        Not bound to any framebuffer; draw into an :class:`Offscreen`.

    Raises
    ------
    RenderError
        EGL or a GL driver is missing (e.g. no ``libEGL``/Mesa installed), or the
        driver offers an older GL than ``require``.
    """
    try:
        ctx = moderngl.create_standalone_context(backend="egl", require=require)
    except Exception as e:  # moderngl raises plain Exception / ValueError / ImportError here
        raise RenderError(
            f"cannot create an offscreen OpenGL {require // 100}.{require // 10 % 10} core context through EGL: {e}. "
            "Either EGL/a GL driver is missing (Debian: apt-get install libegl1 libgl1-mesa-dri gives software "
            "rendering with llvmpipe) or the driver offers an older OpenGL."
        ) from e
    return ctx


def wrap_current_context(require: int = REQUIRED_GL) -> moderngl.Context:
    """Wrap the OpenGL context that is current on this thread (e.g. a pyglet window's).

    The window's default framebuffer is ``ctx.screen``; bind it with
    ``ctx.screen.use()`` before :meth:`Renderer.draw`.

    Raises
    ------
    RenderError
        No context is current, or it is older than ``require``.
    """
    try:
        return moderngl.create_context(require=require)
    except Exception as e:
        raise RenderError(
            f"cannot use the current OpenGL context (need GL {require // 100}.{require // 10 % 10} core): {e}"
        ) from e


class Offscreen:
    """A framebuffer to render into without a window.

    Parameters
    ----------
    ctx : moderngl.Context
    width, height : int
        Pixels.
    samples : int
        0 for no multisampling, or 2/4/8 for MSAA. With MSAA the scene is drawn
        into multisampled renderbuffers and resolved into a plain RGBA8 texture
        when read. MSAA costs ~2x on llvmpipe, so it is off by default.

    Attributes
    ----------
    fbo : moderngl.Framebuffer
        Where to draw (the multisampled one when ``samples > 0``).
    texture : moderngl.Texture
        The single-sampled RGBA8 colour result (after :meth:`resolve`).
    """

    def __init__(self, ctx: moderngl.Context, width: int, height: int, samples: int = 0):
        width, height, samples = int(width), int(height), int(samples)
        if width <= 0 or height <= 0:
            raise RenderError(f"offscreen size must be positive, got {width}x{height}")
        if samples and samples > ctx.max_samples:
            raise RenderError(f"{samples}x MSAA requested, the driver allows at most {ctx.max_samples}")
        self.ctx = ctx
        self.width, self.height, self.samples = width, height, samples
        self.texture = ctx.texture((width, height), 4)
        self._depth = ctx.depth_renderbuffer((width, height))
        self._resolve_fbo = ctx.framebuffer(color_attachments=[self.texture], depth_attachment=self._depth)
        if samples:
            self._ms_color = ctx.renderbuffer((width, height), 4, samples=samples)
            self._ms_depth = ctx.depth_renderbuffer((width, height), samples=samples)
            self.fbo = ctx.framebuffer(color_attachments=[self._ms_color], depth_attachment=self._ms_depth)
        else:
            self._ms_color = self._ms_depth = None
            self.fbo = self._resolve_fbo

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` in pixels."""
        return self.width, self.height

    @property
    def viewport(self) -> tuple[int, int, int, int]:
        """The whole framebuffer as ``(x, y, w, h)``."""
        return 0, 0, self.width, self.height

    def use(self) -> Offscreen:
        """Bind for drawing and set the viewport to the whole framebuffer."""
        self.fbo.use()
        self.fbo.viewport = self.viewport
        return self

    def resolve(self) -> None:
        """Resolve MSAA samples into :attr:`texture` (no-op without MSAA)."""
        if self.samples:
            self.ctx.copy_framebuffer(self._resolve_fbo, self.fbo)

    def read_rgba(self) -> np.ndarray:
        """The image as ``(h, w, 4) uint8``, top row first."""
        self.resolve()
        data = self._resolve_fbo.read(components=4, alignment=1)
        # OpenGL rows start at the bottom; images start at the top.
        return np.frombuffer(data, np.uint8).reshape(self.height, self.width, 4)[::-1].copy()

    def read_rgb(self) -> np.ndarray:
        """The image as ``(h, w, 3) uint8``, top row first."""
        self.resolve()
        data = self._resolve_fbo.read(components=3, alignment=1)
        return np.frombuffer(data, np.uint8).reshape(self.height, self.width, 3)[::-1].copy()

    def save_png(self, path) -> np.ndarray:
        """Write the image as an RGB PNG; returns the ``(h, w, 3) uint8`` pixels written."""
        rgb = self.read_rgb()
        write_png(path, rgb)
        return rgb

    def release(self) -> None:
        """Free the GPU objects (safe to call twice).

        If this framebuffer is still bound, framebuffer 0 is bound instead:
        moderngl re-binds "the current framebuffer" after creating a new one,
        and re-binding a deleted one raises GL_INVALID_OPERATION.
        """
        ctx = getattr(self, "ctx", None)
        if ctx is not None and self.fbo is not None and ctx.fbo in (self.fbo, self._resolve_fbo):
            ctx.detect_framebuffer(0).use()
        for name in ("fbo", "_resolve_fbo", "_ms_color", "_ms_depth", "texture", "_depth"):
            obj = getattr(self, name, None)
            if obj is not None:
                obj.release()
                setattr(self, name, None)

    def __enter__(self) -> Offscreen:
        return self

    def __exit__(self, *exc) -> None:
        self.release()
