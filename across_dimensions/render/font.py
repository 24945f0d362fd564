"""Text from a real font: DejaVu Sans rasterized by FreeType (through Pillow) into one atlas.

The font file ships in the package (``render/fonts/DejaVuSans.ttf``, with its licence beside it:
the Bitstream Vera licence, free to use and redistribute). Glyphs are rasterized on first use at
the pixel size the HUD asks for and packed into one growing single-channel atlas, so the whole
HUD stays one texture and one instanced draw call. The atlas keeps a :attr:`FontAtlas.revision`
that changes whenever glyphs are added; the renderer re-uploads the texture when it changes.

Sizes are given as the HUD's whole-number ``scale``: the em size is chosen so capital letters
are :data:`GLYPH_H` pixels tall per unit (so the layout's line heights, ``(GLYPH_H + 3) * scale``,
are kept), and a line's baseline sits ``GLYPH_H * scale`` below the top it is placed at. Glyphs
are placed on whole pixels and sampled with nearest filtering: FreeType's anti-aliasing reaches the screen unblurred.

:func:`missing_glyphs` lists the characters of a text the font cannot draw (read from the font's
own ``cmap`` table); a level's hints are checked with it.
"""

from __future__ import annotations

import functools
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: The shipped font and its licence.
FONT_FILE = Path(__file__).with_name("fonts") / "DejaVuSans.ttf"
FONT_LICENCE = Path(__file__).with_name("fonts") / "LICENSE-DejaVu.txt"

#: DejaVu Sans' capital height as a fraction of its em (1493 of 2048 font units): a scale unit's
#: em size is chosen so capitals are :data:`GLYPH_H` pixels tall per unit.
CAP_EM = 1493 / 2048
#: Layout units kept from the HUD's original grid: a line's capital height and a nominal cell
#: width, per scale unit (real widths come from :func:`text_width`).
GLYPH_H = 7
GLYPH_W = 5
CELL_W, CELL_H = GLYPH_W + 1, GLYPH_H + 1
#: Atlas width in texels; it grows in height as glyphs are added.
ATLAS_W = 1024
#: Empty texels kept round every glyph, so nearest sampling at a quad's edge never picks up a
#: neighbour.
PAD = 1
#: Texels of the fully lit block at the atlas' top-left, for solid rectangles.
SOLID = 4
#: Characters rasterized together the first time a size is used: printable ASCII, Latin-1,
#: Latin Extended-A (French, German, Spanish, Polish, Czech, Turkish, ... letters) and the
#: punctuation and arrows hints use.
PRELOAD = (
    "".join(chr(c) for c in range(32, 127))
    + "".join(chr(c) for c in range(0xA0, 0x180))
    + "\u2013\u2014\u2018\u2019\u201c\u201d\u2026\u2022\u00b7\u2190\u2191\u2192\u2193\u2713\u2717\u2122\u20ac"
)
#: Drawn for a character the font lacks.
REPLACEMENT = "?"


@dataclass(frozen=True)
class Glyph:
    """One rasterized glyph at one size.

    Attributes
    ----------
    u, v : int
        Top-left texel of its bitmap in the atlas (v counts rows from the top).
    w, h : int
        Bitmap size in texels (0 for blank glyphs such as space).
    left, top : int
        Offset of the bitmap's top-left from the pen position on the baseline, pixels (``top``
        is negative above the baseline).
    advance : float
        How far the pen moves after it, pixels.
    """

    u: int
    v: int
    w: int
    h: int
    left: int
    top: int
    advance: float


class FontAtlas:
    """Glyphs of one TTF at any number of pixel sizes, packed into one ``uint8`` image.

    Parameters
    ----------
    path : Path
        A TrueType file.
    """

    def __init__(self, path: Path = FONT_FILE):
        from PIL import ImageFont  # Pillow's FreeType binding; imported only when text is drawn

        self._ImageFont = ImageFont
        self.path = Path(path)
        self._data = self.path.read_bytes()
        self.codepoints = frozenset(cmap_codepoints(self._data))
        self.image = np.zeros((64, ATLAS_W), np.uint8)
        self.image[:SOLID, :SOLID] = 255
        self.revision = 1
        self._glyphs: dict[tuple[str, int], Glyph] = {}
        self._by_uv: dict[tuple[int, int], str] = {}
        self._fonts: dict[int, object] = {}
        self._metrics: dict[int, tuple[int, int]] = {}
        # Shelf packing: glyphs go left to right on a shelf; a new shelf starts below the tallest.
        self._x, self._y, self._shelf_h = SOLID + PAD, 0, SOLID + PAD

    # ------------------------------------------------------------------ sizes
    def _font(self, px: int):
        f = self._fonts.get(px)
        if f is None:
            import io

            f = self._ImageFont.truetype(io.BytesIO(self._data), px)
            self._fonts[px] = f
            ascent, descent = f.getmetrics()
            self._metrics[px] = (ascent, descent)
            for ch in PRELOAD:
                self.glyph(ch, px)
        return f

    def prepare(self, px: int) -> None:
        """Rasterize :data:`PRELOAD` at em size ``px`` now, as the size's first use would."""
        self._font(px)

    # ----------------------------------------------------------------- glyphs
    def glyph(self, ch: str, px: int) -> Glyph:
        """The glyph of ``ch`` at em size ``px``, rasterized on first use (:data:`REPLACEMENT` if missing)."""
        key = (ch, px)
        g = self._glyphs.get(key)
        if g is not None:
            return g
        if ord(ch) not in self.codepoints and not ch.isspace():
            g = self.glyph(REPLACEMENT, px)
            self._glyphs[key] = g
            return g
        font = self._font(px)
        advance = float(font.getlength(ch))
        left, top, right, bottom = font.getbbox(ch, anchor="ls")
        w, h = right - left, bottom - top
        if ch.isspace() or w <= 0 or h <= 0:
            g = Glyph(0, 0, 0, 0, 0, 0, advance)
        else:
            from PIL import Image, ImageDraw

            img = Image.new("L", (w, h), 0)
            ImageDraw.Draw(img).text((-left, -top), ch, font=font, fill=255, anchor="ls")
            u, v = self._place(w, h)
            self.image[v : v + h, u : u + w] = np.asarray(img, np.uint8)
            self.revision += 1
            g = Glyph(u, v, w, h, left, top, advance)
            self._by_uv[(u, v)] = ch
        self._glyphs[key] = g
        return g

    def _place(self, w: int, h: int) -> tuple[int, int]:
        if self._x + w + PAD > ATLAS_W:
            self._x, self._y, self._shelf_h = 0, self._y + self._shelf_h, 0
        u, v = self._x, self._y
        self._x += w + PAD
        self._shelf_h = max(self._shelf_h, h + PAD)
        need = v + h + PAD
        if need > self.image.shape[0]:
            grown = np.zeros((max(need, 2 * self.image.shape[0]), ATLAS_W), np.uint8)
            grown[: self.image.shape[0]] = self.image
            self.image = grown
        return u, v

    def char_at(self, u: float, v: float) -> str | None:
        """The character whose bitmap starts at texel ``(u, v)``, or None (solid block, unknown)."""
        return self._by_uv.get((int(u), int(v)))

    def width(self, text: str, px: int) -> int:
        """Pixel width of one line of ``text`` at em size ``px`` (sum of advances, rounded)."""
        return int(round(sum(self.glyph(ch, px).advance for ch in text)))

    def missing(self, text: str) -> set[str]:
        """Characters of ``text`` (whitespace aside) that the font has no glyph for."""
        return {ch for ch in text if not ch.isspace() and ord(ch) not in self.codepoints}


@functools.lru_cache(maxsize=1)
def default_font() -> FontAtlas:
    """The shipped font's atlas, shared by every HUD in the process."""
    return FontAtlas(FONT_FILE)


def font_px(scale: int) -> int:
    """Em size in pixels for the HUD's text ``scale``."""
    return max(6, int(GLYPH_H * int(scale) / CAP_EM))  # rounded down: capitals never overshoot


@functools.lru_cache(maxsize=4096)
def text_width(text: str, scale: int) -> int:
    """Pixel width of a line of ``text`` drawn at ``scale`` (cached: HUD lines repeat every frame)."""
    return default_font().width(text, font_px(scale))


def missing_glyphs(text: str) -> set[str]:
    """Characters of ``text`` the shipped font cannot draw (they would show as ``?``)."""
    return default_font().missing(text)


def solid_uv() -> tuple[float, float, float, float]:
    """Atlas texels inside the fully lit block, as ``u0, v0, u1, v1`` (for solid rectangles)."""
    c = SOLID / 2
    return (c, c, c, c)


def cmap_codepoints(data: bytes) -> set[int]:
    """Code points a TrueType font maps to glyphs, read from its ``cmap`` table (formats 4 and 12).

    Parameters
    ----------
    data : bytes
        The whole font file.
    """
    num_tables = struct.unpack_from(">H", data, 4)[0]
    cmap = None
    for i in range(num_tables):
        tag, _, offset, _ = struct.unpack_from(">4sIII", data, 12 + 16 * i)
        if tag == b"cmap":
            cmap = offset
    if cmap is None:
        raise ValueError("font has no cmap table")
    n = struct.unpack_from(">H", data, cmap + 2)[0]
    found: set[int] = set()
    for i in range(n):
        platform, encoding, sub = struct.unpack_from(">HHI", data, cmap + 4 + 8 * i)
        if not (platform == 3 and encoding in (1, 10)) and platform != 0:
            continue
        at = cmap + sub
        fmt = struct.unpack_from(">H", data, at)[0]
        if fmt == 4:
            seg2 = struct.unpack_from(">H", data, at + 6)[0]
            segs = seg2 // 2
            ends = struct.unpack_from(f">{segs}H", data, at + 14)
            starts = struct.unpack_from(f">{segs}H", data, at + 16 + seg2)
            deltas = struct.unpack_from(f">{segs}h", data, at + 16 + 2 * seg2)
            ro_at = at + 16 + 3 * seg2
            offsets = struct.unpack_from(f">{segs}H", data, ro_at)
            for s in range(segs):
                for c in range(starts[s], ends[s] + 1):
                    if c == 0xFFFF:
                        continue
                    if offsets[s] == 0:
                        gid = (c + deltas[s]) & 0xFFFF
                    else:
                        addr = ro_at + 2 * s + offsets[s] + 2 * (c - starts[s])
                        gid = struct.unpack_from(">H", data, addr)[0]
                        gid = (gid + deltas[s]) & 0xFFFF if gid else 0
                    if gid:
                        found.add(c)
        elif fmt == 12:
            groups = struct.unpack_from(">I", data, at + 12)[0]
            for g in range(groups):
                start, end, gid = struct.unpack_from(">III", data, at + 16 + 12 * g)
                found.update(c for c in range(start, end + 1) if gid + (c - start))
    return found
