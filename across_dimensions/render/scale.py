"""Render scale: draw the scene at a fraction of the window, then upscale it.

A software rasterizer (Mesa llvmpipe on 2 cores) spends most of a frame
shading pixels; at scale 0.5 it shades a quarter as many. The scene is drawn into
an offscreen framebuffer of the scaled size and stretched over the window by one
full-screen triangle (each pixel doubled at 0.5, bilinear at other scales); the
HUD is then drawn at full resolution on top, so text stays sharp.
"""

from __future__ import annotations

import moderngl

from .context import Offscreen

#: Accepted range of the setting (fraction of the window's width and height).
SCALE_RANGE = (0.5, 1.0)
#: Renderers that rasterize on the CPU, and the scale used for them by default.
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast", "software rasterizer")
SOFTWARE_SCALE = 0.5

_BLIT_VERTEX = """
#version 330
out vec2 v_uv;
void main() {
    // One triangle covering the screen: (-1,-1), (3,-1), (-1,3).
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    v_uv = 0.5 * p + 0.5;
    gl_Position = vec4(p, 0.0, 1.0);
}
"""
_BLIT_FRAGMENT = """
#version 330
uniform sampler2D u_image;
in vec2 v_uv;
out vec4 f_color;
void main() { f_color = vec4(texture(u_image, v_uv).rgb, 1.0); }
"""


def default_render_scale(gl_renderer: str) -> float:
    """The render scale to use when the setting is ``"auto"``: lower on a software rasterizer.

    Parameters
    ----------
    gl_renderer : str
        ``GL_RENDERER`` (``ctx.info["GL_RENDERER"]``), e.g. ``"llvmpipe (LLVM 15.0.6, 256 bits)"``.
    """
    name = gl_renderer.lower()
    return SOFTWARE_SCALE if any(s in name for s in SOFTWARE_RENDERERS) else 1.0


def resolve_render_scale(setting, ctx: moderngl.Context) -> float:
    """A settings value (``"auto"`` or a number) as the scale to draw at."""
    if setting == "auto" or setting is None:
        return default_render_scale(str(ctx.info.get("GL_RENDERER", "")))
    return min(max(float(setting), SCALE_RANGE[0]), SCALE_RANGE[1])


def scaled_size(size: tuple[int, int], scale: float) -> tuple[int, int]:
    """Pixel size of the scene drawn at ``scale`` of ``size`` (at least 1x1)."""
    return max(1, round(size[0] * scale)), max(1, round(size[1] * scale))


class ScaledTarget:
    """An offscreen framebuffer at ``scale`` of a destination size, and its upscale.

    Usage per frame::

        target.begin(window_size)   # binds the small framebuffer
        renderer.draw(frame, target.viewport, hud=False)
        target.present(ctx.screen, viewport)  # stretch onto the window

    At scale 1 :meth:`begin` returns False and nothing is redirected.
    """

    def __init__(self, ctx: moderngl.Context, scale: float):
        self.ctx = ctx
        self.scale = float(scale)
        self._off: Offscreen | None = None
        self._prog = ctx.program(vertex_shader=_BLIT_VERTEX, fragment_shader=_BLIT_FRAGMENT)
        self._vao = ctx.vertex_array(self._prog, [])

    @property
    def active(self) -> bool:
        return self.scale < 1.0

    @property
    def viewport(self) -> tuple[int, int, int, int]:
        return self._off.viewport

    def begin(self, size: tuple[int, int]) -> bool:
        """Bind the scaled framebuffer for a destination of ``size``; False at scale 1."""
        if not self.active:
            return False
        want = scaled_size(size, self.scale)
        if self._off is None or self._off.size != want:
            if self._off is not None:
                self._off.release()
            self._off = Offscreen(self.ctx, *want)
            # At a whole factor (2x at scale 0.5) every source pixel becomes an equal block, so
            # nearest sampling is exact and crisp, and costs half what bilinear does on a
            # software rasterizer; any other factor needs bilinear to spread pixels evenly.
            whole = all(size[i] == want[i] * round(size[i] / want[i]) for i in (0, 1))
            f = moderngl.NEAREST if whole else moderngl.LINEAR
            self._off.texture.filter = (f, f)
        self._off.use()
        return True

    def present(self, fbo, viewport: tuple[int, int, int, int]) -> None:
        """Stretch the scaled image over ``viewport`` of ``fbo`` (binds ``fbo``)."""
        fbo.use()
        ctx = self.ctx
        ctx.viewport = viewport
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        self._off.texture.use(0)
        self._prog["u_image"].value = 0
        self._vao.render(moderngl.TRIANGLES, vertices=3)

    def release(self) -> None:
        if self._off is not None:
            self._off.release()
            self._off = None
        self._vao.release()
        self._prog.release()
