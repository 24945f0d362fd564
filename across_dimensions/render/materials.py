"""The game's look as data: named colours (palettes), which become uniforms and shader constants.

A palette is a plain dict of named colours. The sky (:mod:`.sky`) and the scene's fog read
the sky colours from uniforms named ``u_<colour name>``; the scene's fragment shaders have the
light colours compiled in as constants (:func:`.shaders.palette_constants`: on llvmpipe every
input a fragment shader reads costs per triangle or per pixel), so the renderer builds its
programs once per palette it draws with. The renderer keeps one palette (:attr:`Renderer.palette
<across_dimensions.render.renderer.Renderer.palette>`); settings replace it with
:func:`palette`.

Colours are RGB in ``[0, 1]``. Lighting colours are *linear* (they multiply albedo
before tone mapping); sky colours are *display* colours (the sky is drawn as is and
fog mixes toward it after tone mapping), so they look on screen like the numbers say.

Looks
-----
``"scifi"``
    Panel seams and emissive trims on scenery, a metal floor with glowing lines, a
    gradient sky with a nebula band, stars and a sun, fog toward the sky's horizon, and
    4D cross-sections drawn as alien, iridescent matter with bands that encode w.
``"flat"``
    The plain look: flat-shaded materials, a one-colour sky (``Frame.sky_color``) and a
    grid on floors. Cheapest; tests and benchmarks compare against it.
"""

from __future__ import annotations

from collections.abc import Mapping

#: Render looks, cheapest last.
LOOKS = ("scifi", "flat")

#: The default palette: every named colour the sci-fi look uses.
DEFAULT = {
    # sky (display colours)
    "sky_zenith": (0.012, 0.016, 0.045),
    "sky_horizon": (0.11, 0.13, 0.22),
    "sky_ground": (0.035, 0.035, 0.05),
    "nebula_a": (0.42, 0.12, 0.50),  # violet
    "nebula_b": (0.05, 0.34, 0.48),  # teal
    "star": (0.95, 0.97, 1.0),
    "sun": (1.0, 0.86, 0.62),
    "planet": (0.30, 0.42, 0.55),
    # light (linear)
    "key_light": (1.0, 0.93, 0.82),
    "ambient_sky": (0.12, 0.15, 0.21),
    "ambient_ground": (0.035, 0.033, 0.04),
    # scenery emission (linear)
    "trim": (0.10, 0.75, 1.0),
    "floor_line": (0.06, 0.40, 0.62),
    # 4D matter (linear): which side of the slice a thing lies on
    "ana": (1.0, 0.45, 0.10),  # +w: warm, like the ana ghosts
    "kata": (0.15, 0.50, 1.0),  # -w: cool, like the kata ghosts
    "hyper_rim": (0.75, 0.45, 1.0),
}

#: Palettes by name. ``"colorblind"`` keeps every pair a player must tell apart (ana and
#: kata, trim and floor, nebula hues) apart in lightness as well as hue, using the
#: Okabe-Ito orange / sky blue pair that deuteranopes, protanopes and tritanopes all
#: separate; the w cue never depends on colour anyway (band density and pattern).
PALETTES: dict[str, dict[str, tuple[float, float, float]]] = {
    "default": DEFAULT,
    "colorblind": {
        **DEFAULT,
        "nebula_a": (0.45, 0.30, 0.05),
        "nebula_b": (0.10, 0.30, 0.55),
        "trim": (0.85, 0.85, 0.90),
        "floor_line": (0.30, 0.55, 0.85),
        "ana": (0.90, 0.60, 0.0),  # Okabe-Ito orange
        "kata": (0.10, 0.45, 0.95),  # a darker sky blue: also apart in lightness
        "hyper_rim": (0.95, 0.95, 1.0),
    },
    # Strong, light-or-dark pairs (yellow ana, deep blue kata), brighter trims and lines.
    "high_contrast": {
        **DEFAULT,
        "trim": (1.0, 1.0, 1.0),
        "floor_line": (0.55, 0.75, 1.0),
        "ana": (1.0, 0.85, 0.0),
        "kata": (0.05, 0.25, 1.0),
        "hyper_rim": (1.0, 1.0, 1.0),
    },
}


class PaletteError(ValueError):
    """A palette name or colour the look does not know."""


def palette(name: str = "default", **overrides) -> dict[str, tuple[float, float, float]]:
    """A copy of the palette ``name``, with some colours replaced.

    Parameters
    ----------
    name : str
        A key of :data:`PALETTES`.
    **overrides : (3,) float
        Named colours to replace, e.g. ``trim=(1, 0, 0)``.

    Returns
    -------
    dict
        Every name of :data:`DEFAULT`, mapped to an RGB tuple of floats.

    Raises
    ------
    PaletteError
        Unknown palette or colour name, or a colour that is not three numbers in 0-1.
    """
    if name not in PALETTES:
        raise PaletteError(f"palette {name!r}: unknown; expected one of {', '.join(PALETTES)}")
    return merged(PALETTES[name], overrides)


def merged(base: Mapping, changes: Mapping) -> dict[str, tuple[float, float, float]]:
    """``base`` with ``changes`` applied, every colour checked (see :func:`palette`)."""
    out = {k: tuple(float(x) for x in v) for k, v in base.items()}
    for key, value in changes.items():
        if key not in DEFAULT:
            raise PaletteError(f"palette colour {key!r}: unknown; expected one of {', '.join(DEFAULT)}")
        try:
            rgb = tuple(float(x) for x in value)
        except (TypeError, ValueError):
            rgb = ()
        if len(rgb) != 3 or not all(0.0 <= x <= 1.0 for x in rgb):
            raise PaletteError(f"palette colour {key!r}: expected three numbers in 0-1, got {value!r}")
        out[key] = rgb
    return out


def upload(prog, colours: Mapping, set_uniform) -> None:
    """Set ``u_<name>`` in ``prog`` for every named colour (names the program lacks are skipped).

    ``set_uniform(prog, name, value)`` is the renderer's tolerant setter.
    """
    for key, rgb in colours.items():
        set_uniform(prog, f"u_{key}", rgb)


#: How far the w cue's bands are apart, in units of the drawable's size (its bounding
#: radius, clamped to :data:`BAND_SIZE_RANGE` metres): at the centre of a 4D thing along w
#: (``w_offset`` 0) bands are ``BAND_PERIODS[0]`` apart and faint; at the edge of its
#: existence (``|w_offset|`` 1) ``BAND_PERIODS[1]``, dense. Density reads as distance.
BAND_PERIODS = (0.9, 0.14)
BAND_SIZE_RANGE = (0.25, 1.5)


def band_scale(radius: float) -> float:
    """Metres per band unit for a drawable of bounding ``radius`` (see :data:`BAND_PERIODS`)."""
    lo, hi = BAND_SIZE_RANGE
    return min(max(float(radius), lo), hi)


__all__ = ["LOOKS", "DEFAULT", "PALETTES", "PaletteError", "palette", "merged", "upload", "band_scale"]
