"""The radar's static disc as one image, laid each frame on one square in the disc's plane.

The disc's layers (:func:`.radar_shapes.disc_vertices`: fills, rings, axes, the view wedge, the
forward notch and the player's chevron, about 700 translucent triangles) never change, and the
radar's camera never turns relative to them. On llvmpipe, which sets up every triangle on the
main thread, drawing them each frame cost more than the radar's pins; so they are drawn once,
seen from above, into an image, and each frame draws one square in the disc's plane with it.

The square stays a surface in the radar's 3D view, depth-tested against the pins (pins below the
disc show through it tinted, pins above stand in front), and the image is premultiplied: one
"over" with it equals drawing its layers one over another (to 8-bit rounding).
"""

from __future__ import annotations

import moderngl
import numpy as np

from .gl_math import mat4_bytes
from .radar_shapes import disc_vertices
from .shaders import FLAT_VERTEX

#: Half the side of the square in the disc's plane that holds all of the static disc (its rim,
#: the forward notch out to 1.17), in disc radii: the image covers it.
DISC_EXTENT = 1.2
#: Texels per disc radius in the image for each pixel per disc radius on screen: two, so the thin
#: rings, sampled bilinearly, stay as crisp as the triangles were and never alias.
DISC_SUPERSAMPLE = 2.0
#: Bounds of the image's side, in texels.
DISC_MIN_TEXELS, DISC_MAX_TEXELS = 128, 2048

_DISC_VS = """
#version 330
uniform mat4 u_view_proj;
out vec2 v_uv;
void main() {
    // A strip over the square: (0, 0), (1, 0), (0, 1), (1, 1) of the image.
    vec2 c = vec2(gl_VertexID == 1 || gl_VertexID == 3 ? 1.0 : 0.0, gl_VertexID >= 2 ? 1.0 : 0.0);
    v_uv = c;
    vec2 xz = (2.0 * c - 1.0) * EXTENT;
    gl_Position = u_view_proj * vec4(xz.x, 0.0, xz.y, 1.0);
}
""".replace("EXTENT", repr(DISC_EXTENT))

_DISC_FS = """
#version 330
uniform sampler2D u_disc;
uniform float u_alpha;
in vec2 v_uv;
out vec4 f_color;
void main() {
    f_color = texture(u_disc, v_uv) * u_alpha;  // premultiplied: colour and coverage alike
}
"""

#: The layers into the image: premultiplied, so the image's alpha is their coverage.
_BAKE_FS = """
#version 330
in vec4 v_color;
out vec4 f_color;
void main() {
    f_color = vec4(v_color.rgb * v_color.a, v_color.a);
}
"""


def disc_image_size(px_per_radius: float) -> int:
    """Texels across the disc's image for a radar of ``px_per_radius`` screen pixels per disc
    radius: a multiple of 64 within :data:`DISC_MIN_TEXELS` and :data:`DISC_MAX_TEXELS`."""
    want = 2.0 * DISC_EXTENT * DISC_SUPERSAMPLE * float(px_per_radius)
    return int(min(max(np.ceil(want / 64.0) * 64, DISC_MIN_TEXELS), DISC_MAX_TEXELS))


def disc_view_proj() -> np.ndarray:
    """``(4, 4) float64``: the disc's square seen from above, x across the image and z up it
    (texel row 0 at ``z = -DISC_EXTENT``, as the square's ``v = 0``)."""
    m = np.zeros((4, 4))
    m[0, 0] = m[1, 2] = 1.0 / DISC_EXTENT
    m[3, 3] = 1.0
    return m


class DiscImage:
    """The disc's image and the square that shows it.

    Parameters
    ----------
    ctx : moderngl.Context

    Attributes
    ----------
    image : moderngl.Texture or None
        RGBA8, premultiplied; None until the first :meth:`prepare`.
    bakes : int
        How many times the layers were drawn into :attr:`image`: once, and again when a larger
        radar needs a finer image.
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.prog = ctx.program(vertex_shader=_DISC_VS, fragment_shader=_DISC_FS)
        self.prog["u_disc"].value = 0
        self.vao = ctx.vertex_array(self.prog, [])
        self.image: moderngl.Texture | None = None
        self.bakes = 0

    def prepare(self, px_per_radius: float) -> None:
        """Draw the layers into :attr:`image` when there is none yet or the radar needs a finer
        one; never a coarser (a small view between two big ones, the picture in picture or a
        benchmark's two scales, must not make it redraw every frame). Leaves the bound
        framebuffer and the viewport as they were; blending is left on."""
        size = disc_image_size(px_per_radius)
        if self.image is not None and self.image.size[0] >= size:
            return
        ctx = self.ctx
        bound, viewport = ctx.fbo, ctx.viewport
        layers = disc_vertices()
        prog = ctx.program(vertex_shader=FLAT_VERTEX, fragment_shader=_BAKE_FS)
        vbo = ctx.buffer(layers.tobytes())
        vao = ctx.vertex_array(prog, [(vbo, "3f 4f", "in_pos", "in_color")])
        image = ctx.texture((size, size), 4)
        image.filter = (moderngl.LINEAR, moderngl.LINEAR)
        image.repeat_x = image.repeat_y = False
        fbo = ctx.framebuffer(color_attachments=[image])
        fbo.use()
        ctx.viewport = (0, 0, size, size)
        ctx.clear(0.0, 0.0, 0.0, 0.0)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.enable(moderngl.BLEND)
        # Premultiplied "over", colour and coverage alike, the layers in their order.
        ctx.blend_func = (moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA)
        prog["u_view_proj"].write(mat4_bytes(disc_view_proj()))
        vao.render(moderngl.TRIANGLES, vertices=len(layers))
        for obj in (fbo, vao, vbo, prog):
            obj.release()
        if self.image is not None:
            self.image.release()
        self.image = image
        self.bakes += 1
        if bound is not None:
            bound.use()
        ctx.viewport = viewport

    def draw(self, vp_bytes: bytes, alpha: float) -> None:
        """Lay the image over the bound framebuffer through the radar's ``vp_bytes`` (its
        view-projection, column-major float32), ``alpha`` its opacity; blending on, premultiplied,
        the destination's alpha kept. Depth test and mask are the caller's."""
        ctx = self.ctx
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = (moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
        self.prog["u_view_proj"].write(vp_bytes)
        self.prog["u_alpha"].value = float(alpha)
        self.image.use(0)
        self.vao.render(moderngl.TRIANGLE_STRIP, vertices=4)

    def release(self) -> None:
        for obj in (self.vao, self.prog, self.image):
            if obj is not None:
                obj.release()
        self.image = None
