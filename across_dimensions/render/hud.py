"""The heads-up display, drawn over the 3D scene in pixel coordinates.

Everything on the HUD is an axis-aligned textured quad: text samples glyphs
from the font atlas (:mod:`.font`: DejaVu Sans rasterized by FreeType), and solid
rectangles sample a fully lit block of the same atlas. So the whole HUD is one instanced draw call with one
shader, and the layout (:func:`hud_quads`) is plain numpy that can be tested
without OpenGL.

Layout (pixels, origin top-left, ``W x H`` the viewport):

* crosshair: a plus with a dark outline at ``(W // 2, H // 2)``; hidden while
  paused;
* w indicator: a vertical track on the right, ``w_max`` at the top, with a tick
  at ``w = 0``, a fill from 0 to ``w``, a marker at ``w`` (red when ``w`` is
  outside the range), the label ``w`` above and the value below;
* energy bar (when ``hud.energy`` is not None): bottom-left, a horizontal track whose fill is
  ``value / maximum`` of its inner width, ``ENERGY`` above its left end and the value (``73/100``)
  above its right end; a crystal's ``flash`` brightens the fill and puts a fading glow round the
  bar; when ``empty`` the outline, track and label turn red and the label reads ``NO ENERGY``;
* weapon panel (when ``hud.weapon`` is not None): above the energy bar, the weapon's number,
  name, cost (and bullets in flight), a cooldown bar that fills as the weapon gets ready, and a red
  ``NOT ENOUGH ENERGY`` line above when the last try failed; ``hit_marker`` puts four fading marks
  round the crosshair;
* radar (drawn by :mod:`.radar`, not here): the rectangle :meth:`HudMetrics.radar_rect`,
  bottom-right but left of the w indicator;
* slice gauges (when ``hud.slice`` is not None): top centre, three small tracks
  ``XW YW ZW``, each with ticks at -90, 0 and +90 degrees and a marker at the slice
  axis's angle towards w (green on a 90-degree step), and under them the 4D
  camera's mode (``FRUSTUM 25`` with the orbit angle, ``RETURNING``) when detached;
* FPS (when not None): top-left;
* message: centred horizontally, a third of the way down, on a dark band
  (wrapped to fit);
* paused: the whole view dimmed, then ``PAUSED`` in large text in the middle;
* hint (when ``hud.hint``): its own panel at the top centre, wrapped to 60% of the width, with an
  accent bar on its left and ``hud.hint_label`` in small dim text under it; notices and prompts
  (``message``) never cover it;
* warning (when ``hud.warning``): one line at the bottom centre, between the energy bar and the
  radar, shortened with an ellipsis to fit;
* labels (``hud.labels``): small text on a dark band just right of a point of the world
  (:func:`label_rect`), such as the manipulation keys beside the held object;
* card (when ``hud.card``): drawn over everything by :mod:`.cards`.
* health (when ``hud.health`` is not None): top-left, a bar green when full turning red when low,
  ``HEALTH`` (``SAFE`` just after a death) above its left end and the value above its right end;
  ``damage_flash`` frames the view in red for a moment after a hit, and ``damage_dir`` puts a
  red arc of marks round the crosshair on the side the hit came from (up is ahead).

Colours are display-space RGBA (no gamma applied).
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..game.frame import Hud, Radar
from .captions import draw_captions
from .cards import draw_card
from .font import GLYPH_H, default_font, font_px
from .font import text_width as text_width
from .hud_gauges import (
    BLOCKED_ANA_COLOR as BLOCKED_ANA_COLOR,
)
from .hud_gauges import (
    BLOCKED_KATA_COLOR as BLOCKED_KATA_COLOR,
)
from .hud_gauges import (
    DAMAGE_FLASH_COLOR as DAMAGE_FLASH_COLOR,
)
from .hud_gauges import (
    ENERGY_EMPTY_COLOR as ENERGY_EMPTY_COLOR,
)
from .hud_gauges import (
    ENERGY_FILL_COLOR as ENERGY_FILL_COLOR,
)
from .hud_gauges import (
    ENERGY_FLASH_COLOR as ENERGY_FLASH_COLOR,
)
from .hud_gauges import (
    MARKER_COLOR as MARKER_COLOR,
)
from .hud_gauges import (
    MARKER_OUT_OF_RANGE_COLOR as MARKER_OUT_OF_RANGE_COLOR,
)
from .hud_gauges import (
    draw_damage_cue,
    draw_damage_vignette,
    draw_energy_bar,
    draw_health_bar,
    draw_slice_gauges,
    draw_w_indicator,
    draw_weapon_panel,
)
from .hud_gauges import energy_text as energy_text
from .hud_layout import HudMetrics as HudMetrics
from .hud_layout import damage_cue_points as damage_cue_points
from .hud_layout import health_bar_rect as health_bar_rect
from .hud_layout import hint_lines, hint_rect, label_rect, left_lines, message_layout, message_scale, warning_rect
from .palette import cue
from .quads import QUAD_FLOATS, QuadList
from .quads import quads_text as quads_text
from .radar_yield import give_way
from .text_layout import ellipsized

CROSSHAIR_COLOR = (0.95, 0.95, 0.95, 1.0)
OUTLINE_COLOR = (0.0, 0.0, 0.0, 0.55)
TEXT_COLOR = (0.92, 0.94, 1.0, 1.0)
FPS_COLOR = (0.7, 1.0, 0.7, 0.9)
PAUSE_DIM_COLOR = (0.0, 0.0, 0.0, 0.55)
BAND_COLOR = (0.0, 0.0, 0.0, 0.45)
RADAR_LABEL_COLOR = (0.6, 0.9, 1.0, 0.85)
HIT_COLOR = (1.0, 0.35, 0.25, 1.0)
HINT_BAND_COLOR = cue("hint_band", "default")
HINT_ACCENT_COLOR = cue("hint_accent", "default")
HINT_TEXT_COLOR = (0.95, 0.97, 1.0, 1.0)
HINT_LABEL_COLOR = (0.6, 0.8, 0.95, 0.8)
WARNING_COLOR = (1.0, 0.8, 0.35, 0.95)


def hud_quads(
    hud: Hud, width: int, height: int, radar: Radar | None = None, interest: np.ndarray | None = None
) -> np.ndarray:
    """Lay out the HUD for a ``width x height`` viewport.

    With ``radar``, also the radar's labels round its rectangle (the radar itself is drawn by
    :class:`~across_dimensions.render.radar.RadarRenderer`): ``+w`` at the top left, ``-w`` at the
    bottom left (pins stand above for ana, hang below for kata) and the range at the bottom right.
    ``interest`` (``(n, 3)``: screen centre ``x, y`` and radius in pixels, see
    :func:`~.radar_yield.interest_on_screen`) are things the player may be after: a gauge over
    one of them gives way (:func:`~.radar_yield.give_way`), as the radar does.

    Returns
    -------
    (n, 12) float32
        One row per quad in draw order (later rows on top): rect ``x, y, w, h``
        in pixels (origin top-left, y down), atlas rect ``u0, v0, u1, v1`` in
        texels, colour ``r, g, b, a``.
    """
    m = HudMetrics(int(width), int(height))
    q = QuadList()
    # A hit: the view flashes red (first, so everything else stays readable on top).
    if hud.damage_flash > 0:
        draw_damage_vignette(q, min(float(hud.damage_flash), 1.0), m.width, m.height)
    for block in _gauges(hud, m):
        q.quads(give_way(block, interest))
    if radar is not None:
        _radar_labels(q, radar, m)
    if hud.fps is not None:  # top-left
        q.text(f"{hud.fps:.0f} FPS", m.margin // 2, m.margin // 2, m.text_scale, FPS_COLOR)
    if hud.crosshair and not hud.paused:
        _crosshair(q, hud, m)
    if hud.paused:
        big = message_scale(m)
        q.rect(0, 0, m.width, m.height, PAUSE_DIM_COLOR)
        label = "PAUSED"
        q.text(label, (m.width - text_width(label, big)) // 2, m.height // 2 - (GLYPH_H * big) // 2, big, TEXT_COLOR)
    if hud.hint:  # top centre
        _hint_panel(q, hud, m)
    if hud.warning:  # bottom centre
        _warning_line(q, hud.warning, m)
    if hud.message:
        _message(q, hud, m)
    if not hud.paused:  # labels next to things on screen (the manipulation keys beside the held object)
        for label in hud.labels:
            _screen_label(q, label, m, hint_rect(hud, m.width, m.height))
        draw_captions(q, hud.captions, m)  # sounds made visible (a setting)
    if hud.card is not None:  # the teaching card, over everything
        draw_card(q, hud.card, m.width, m.height)
    return q.array()


def _gauges(hud: Hud, m: HudMetrics) -> list[np.ndarray]:
    """The gauges, each a block of quads that gives way as a whole: the w indicator (none in a 3D
    level: nowhere to go along w), the energy bar with the weapon panel above it, the health bar
    and the hit's direction, the slice gauges."""
    blocks = []

    def block(*draws) -> None:
        g = QuadList()
        for draw in draws:
            draw(g)
        blocks.append(g.array())

    if hud.w_max > hud.w_min:
        block(lambda g: draw_w_indicator(g, hud, m))
    costs = hud.energy.costs if hud.energy is not None else ""  # two lines of costs lift the panel
    block(
        lambda g: hud.energy is not None and draw_energy_bar(g, hud.energy, m),
        lambda g: (
            hud.weapon is not None
            and draw_weapon_panel(g, hud.weapon, m, max(0, len(left_lines(costs, m, gauges=True)) - 1))
        ),
    )
    block(
        lambda g: hud.health is not None and draw_health_bar(g, hud.health, m),
        lambda g: hud.damage_dir is not None and draw_damage_cue(g, float(hud.damage_dir), m),
    )
    if hud.slice is not None:
        block(lambda g: draw_slice_gauges(g, hud.slice, m))
    return blocks


def _radar_labels(q: QuadList, radar: Radar, m: HudMetrics) -> None:
    s = m.text_scale
    rx, ry, rw, rh = m.radar_rect()
    q.text("+w", rx + s, ry + s, s, cue("label_ana"))
    q.text("-w", rx + s, ry + rh - GLYPH_H * s - s, s, cue("label_kata"))
    rng = f"{radar.range:.0f} m"
    q.text(rng, rx + rw - text_width(rng, s) - s, ry + rh - GLYPH_H * s - s, s, RADAR_LABEL_COLOR)


def _crosshair(q: QuadList, hud: Hud, m: HudMetrics) -> None:
    """A plus with a dark outline in the middle; four short marks at its corners after a hit."""
    cx, cy, a, t = m.width // 2, m.height // 2, m.arm, m.thickness
    left, top = cx - t // 2, cy - t // 2
    for grow, color in ((1, OUTLINE_COLOR), (0, CROSSHAIR_COLOR)):
        q.rect(left - a - grow, top - grow, 2 * a + t + 2 * grow, t + 2 * grow, color)
        q.rect(left - grow, top - a - grow, t + 2 * grow, 2 * a + t + 2 * grow, color)
    if hud.hit_marker > 0:
        k = min(float(hud.hit_marker), 1.0)
        for dx, dy in ((-1, -1), (1, -1), (-1, 1), (1, 1)):
            q.rect(cx + dx * (a + t) - t, cy + dy * (a + t) - t, 2 * t, 2 * t, HIT_COLOR[:3] + (k,))


def _message(q: QuadList, hud: Hud, m: HudMetrics) -> None:
    """The message on its band (:func:`~.hud_layout.message_layout`: a third of the way down,
    below PAUSED when paused, below the hint panel when it reaches that far)."""
    lines, scale, (x, y, w, h), line_h = message_layout(hud, m.width, m.height)
    pad = 2 * scale
    q.rect(x, y, w, h, BAND_COLOR)
    for i, ln in enumerate(lines):
        q.text(ln, (m.width - text_width(ln, scale)) // 2, y + pad + i * line_h, scale, TEXT_COLOR)


def _hint_panel(q: QuadList, hud: Hud, m: HudMetrics) -> None:
    s = m.text_scale
    x, y, w, h = hint_rect(hud, m.width, m.height)
    lines, scale, _ = hint_lines(hud.hint, m)
    pad = 3 * s
    q.rect(x, y, w, h, cue("hint_band"))
    q.rect(x, y, max(2, s), h, cue("hint_accent"))  # the accent: a hint, not a notice
    line_h = (GLYPH_H + 4) * scale
    for i, ln in enumerate(lines):
        q.text(ln, x + pad + 2 * s, y + pad + i * line_h, scale, HINT_TEXT_COLOR)
    if hud.hint_label:
        label = hud.hint_label
        q.text(label, x + w - pad - text_width(label, s), y + pad + len(lines) * line_h, s, HINT_LABEL_COLOR)


def _warning_line(q: QuadList, text: str, m: HudMetrics) -> None:
    s = m.text_scale
    x, y, w, h = warning_rect(text, m.width, m.height)
    ex, _, ew, _ = m.energy_bar()
    right = m.radar_rect()[0] - m.margin
    line = ellipsized(text, max(10, right - (ex + ew + m.margin) - 4 * s), s)
    q.rect(x, y, w, h, BAND_COLOR)
    q.text(line, x + 2 * s, y + 2 * s, s, WARNING_COLOR)


def _screen_label(q: QuadList, label, m: HudMetrics, avoid=(0, 0, 0, 0)) -> None:
    s = m.text_scale
    x, y, bw, bh = label_rect(label, m.width, m.height, avoid)
    q.rect(x, y, bw, bh, BAND_COLOR)
    for i, ln in enumerate(label.text.split("\n")):
        q.text(ln, x + 4 * s, y + s + i * (GLYPH_H + 3) * s, s, TEXT_COLOR)


_HUD_VS = """
#version 330
uniform vec2 u_screen;
in vec2 in_corner;
in vec4 in_rect;
in vec4 in_uv;
in vec4 in_color;
out vec2 v_uv;
out vec4 v_color;
void main() {
    vec2 p = in_rect.xy + in_corner * in_rect.zw;
    v_uv = mix(in_uv.xy, in_uv.zw, in_corner);
    v_color = in_color;
    // Pixels (origin top-left) to clip space (origin centre, y up).
    gl_Position = vec4(p.x / u_screen.x * 2.0 - 1.0, 1.0 - p.y / u_screen.y * 2.0, 0.0, 1.0);
}
"""

_HUD_FS = """
#version 330
uniform sampler2D u_atlas;
uniform vec2 u_atlas_size;
in vec2 v_uv;
in vec4 v_color;
out vec4 f_color;
void main() {
    float a = texture(u_atlas, v_uv / u_atlas_size).r;
    f_color = vec4(v_color.rgb, v_color.a * a);
}
"""


class HudRenderer:
    """Draws a :class:`Hud` with one instanced draw call.

    Parameters
    ----------
    ctx : moderngl.Context
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.program = ctx.program(vertex_shader=_HUD_VS, fragment_shader=_HUD_FS)
        self.atlas = None
        self._atlas_revision = -1
        self.program["u_atlas"].value = 0
        corners = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], np.float32)
        self._corner_vbo = ctx.buffer(corners.tobytes())
        self._instances = ctx.buffer(reserve=256 * QUAD_FLOATS * 4, dynamic=True)
        self._vao = self._make_vao()
        self.last_quads = np.zeros((0, QUAD_FLOATS), np.float32)
        self._sizes_ready = (0, 0)  # the view size the font's text sizes were made for

    def _make_vao(self) -> moderngl.VertexArray:
        return self.ctx.vertex_array(
            self.program,
            [
                (self._corner_vbo, "2f", "in_corner"),
                (self._instances, "4f 4f 4f/i", "in_rect", "in_uv", "in_color"),
            ],
        )

    def draw(
        self,
        hud: Hud,
        viewport: tuple[int, int, int, int],
        radar: Radar | None = None,
        interest: np.ndarray | None = None,
    ) -> None:
        """Draw over whatever is in ``viewport`` (``(x, y, w, h)``, GL convention) of the bound framebuffer.

        ``radar`` adds the radar's labels, ``interest`` makes gauges give way (see :func:`hud_quads`).
        """
        _, _, w, h = (int(v) for v in viewport)
        if (w, h) != self._sizes_ready:
            # A text size's first use rasterizes the font's common characters (font.PRELOAD):
            # 20-40 ms, a dropped frame when the first large message shows mid-level. Both the
            # HUD's sizes are made on its first frame at a view size instead.
            m = HudMetrics(w, h)
            for scale in {m.text_scale, message_scale(m)}:
                default_font().prepare(font_px(scale))
            self._sizes_ready = (w, h)
        quads = hud_quads(hud, w, h, radar, interest)
        self.last_quads = quads
        self.draw_quads(quads, viewport)

    def draw_quads(self, quads: np.ndarray, viewport: tuple[int, int, int, int]) -> None:
        """Draw HUD quads (``(n, QUAD_FLOATS)`` float32, see :func:`hud_quads`) over ``viewport``.

        The menus share it: one instanced call with the font atlas, uploaded when glyphs were added.
        """
        if len(quads) == 0:
            return
        _, _, w, h = (int(v) for v in viewport)
        data = quads.tobytes()
        if len(data) > self._instances.size:
            self._instances.orphan(len(data) * 2)
        self._instances.write(data)
        ctx = self.ctx
        ctx.viewport = viewport
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
        self.program["u_screen"].value = (float(w), float(h))
        self._upload_atlas()
        self.atlas.use(0)
        self._vao.render(moderngl.TRIANGLE_STRIP, vertices=4, instances=len(quads))
        ctx.disable(moderngl.BLEND)

    def _upload_atlas(self) -> None:
        """Send the font atlas to the GPU when glyphs were added since the last upload."""
        font = default_font()
        if font.revision == self._atlas_revision:
            return
        image = font.image
        size = (image.shape[1], image.shape[0])
        if self.atlas is None or self.atlas.size != size:
            if self.atlas is not None:
                self.atlas.release()
            self.atlas = self.ctx.texture(size, 1, alignment=1)
            self.atlas.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self.atlas.repeat_x = self.atlas.repeat_y = False
        # Row 0 of the array is uploaded first, so texel row r is array row r:
        # atlas v coordinates count down from the top like the layout's y.
        self.atlas.write(np.ascontiguousarray(image).tobytes())
        self.program["u_atlas_size"].value = (float(size[0]), float(size[1]))
        self._atlas_revision = font.revision

    def release(self) -> None:
        for obj in (self._vao, self._instances, self._corner_vbo, self.atlas, self.program):
            if obj is not None:
                obj.release()
