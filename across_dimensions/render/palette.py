"""The colours of every w cue, in each palette the player can choose.

The scene's own colours are :mod:`.materials`'s palettes; this module holds the colours the
overlays use to say "ana" (+w) or "kata" (-w) and the few others a player must read at a
glance: the ghosts' tints, the HUD's w gauge, its caps and labels, the radar's ``+w`` /
``-w`` labels and pins, the energy bar and the hints' accent. One palette is in use at a
time (:func:`use`, called by the renderer's ``set_palette``); the HUD and the radar ask
:func:`cue` and :func:`pin` for colours as they draw.

Palettes
--------
``"default"``
    Ana warm (orange), kata cool (blue), as the game has always looked.
``"colour_blind"``
    Okabe-Ito hues (orange, sky blue, yellow, bluish green, vermillion, reddish purple):
    pairs stay apart for deuteranopes, protanopes and tritanopes, in lightness too.
``"high_contrast"``
    Saturated, light-or-dark colours on darker bands: ana yellow, kata deep blue, pins
    near white or strongly coloured. Colour-blind-safe as well.

Every ana / kata pair stays at least a CIEDE2000 distance of 40 apart under simulated
deuteranopia, protanopia and tritanopia (tests/test_palette.py), and w is never told by
colour alone: ghosts differ by pattern (stripes ana, dots kata), radar pins by height,
the gauge by where its fill lies, and the labels say ``+w`` and ``-w``.

Colours are RGBA (display colours; ghost tints' alpha is how far a ghost is pulled to
them) and pins RGB.
"""

from __future__ import annotations

#: The palettes, in menu order.
NAMES = ("default", "colour_blind", "high_contrast")

_DEFAULT = {
    "ghost_ana": (1.0, 0.4, 0.08, 0.75),
    "ghost_kata": (0.1, 0.5, 1.0, 0.75),
    "gauge_ana": (1.0, 0.55, 0.25, 0.45),
    "gauge_kata": (0.3, 0.6, 1.0, 0.45),
    "blocked_ana": (1.0, 0.55, 0.2, 0.95),
    "blocked_kata": (0.35, 0.7, 1.0, 0.95),
    "label_ana": (1.0, 0.6, 0.3, 0.9),
    "label_kata": (0.35, 0.65, 1.0, 0.9),
    "marker": (1.0, 0.75, 0.15, 1.0),
    "marker_out": (1.0, 0.25, 0.2, 1.0),
    "energy": (0.25, 0.9, 1.0, 0.9),
    "energy_flash": (0.85, 1.0, 1.0, 1.0),
    "energy_empty": (1.0, 0.18, 0.15, 1.0),
    "hint_band": (0.02, 0.04, 0.08, 0.72),
    "hint_accent": (0.3, 0.85, 1.0, 0.95),
}

_CUES: dict[str, dict[str, tuple[float, float, float, float]]] = {
    "default": _DEFAULT,
    "colour_blind": {
        **_DEFAULT,
        "ghost_ana": (0.9, 0.6, 0.0, 0.75),  # Okabe-Ito orange
        "ghost_kata": (0.0, 0.45, 0.7, 0.75),  # Okabe-Ito blue
        "gauge_ana": (0.95, 0.65, 0.1, 0.5),
        "gauge_kata": (0.25, 0.55, 0.95, 0.5),
        "blocked_ana": (0.95, 0.65, 0.1, 0.95),
        "blocked_kata": (0.35, 0.65, 1.0, 0.95),
        "label_ana": (0.95, 0.7, 0.2, 0.95),
        "label_kata": (0.35, 0.65, 1.0, 0.95),
        "marker": (0.95, 0.9, 0.25, 1.0),  # Okabe-Ito yellow
        "marker_out": (0.8, 0.4, 0.0, 1.0),  # vermillion
        "energy": (0.35, 0.7, 0.9, 0.9),  # sky blue
        "energy_empty": (0.8, 0.4, 0.0, 1.0),
        "hint_accent": (0.35, 0.7, 0.9, 0.95),
    },
    "high_contrast": {
        **_DEFAULT,
        "ghost_ana": (1.0, 0.85, 0.0, 0.85),
        "ghost_kata": (0.05, 0.25, 1.0, 0.85),
        "gauge_ana": (1.0, 0.85, 0.0, 0.75),
        "gauge_kata": (0.2, 0.4, 1.0, 0.75),
        "blocked_ana": (1.0, 0.85, 0.0, 1.0),
        "blocked_kata": (0.2, 0.4, 1.0, 1.0),
        "label_ana": (1.0, 0.9, 0.2, 1.0),
        "label_kata": (0.3, 0.45, 1.0, 1.0),
        "marker": (1.0, 1.0, 1.0, 1.0),
        "marker_out": (1.0, 0.2, 0.6, 1.0),
        "energy": (1.0, 1.0, 1.0, 1.0),
        "energy_flash": (1.0, 1.0, 0.4, 1.0),
        "energy_empty": (1.0, 0.2, 0.6, 1.0),
        "hint_band": (0.0, 0.0, 0.0, 0.92),
        "hint_accent": (1.0, 0.9, 0.2, 1.0),
    },
}

#: The pairs that tell ana from kata, in every palette.
PAIRS = (
    ("ghost_ana", "ghost_kata"),
    ("gauge_ana", "gauge_kata"),
    ("blocked_ana", "blocked_kata"),
    ("label_ana", "label_kata"),
)

_PINS_DEFAULT = {
    "crystal": (0.25, 0.95, 1.0),
    "body": (1.0, 0.58, 0.18),
    "enemy": (1.0, 0.18, 0.22),
    "bullet": (1.0, 0.95, 0.3),
    "target": (1.0, 0.35, 0.9),
    "camera_focus": (0.5, 1.0, 0.35),
    "camera_eye": (0.55, 0.6, 1.0),
    "object": (0.86, 0.86, 0.92),
}
_PINS: dict[str, dict[str, tuple[float, float, float]]] = {
    "default": _PINS_DEFAULT,
    "colour_blind": {
        **_PINS_DEFAULT,
        "crystal": (0.35, 0.7, 0.9),  # sky blue
        "body": (0.9, 0.6, 0.0),  # orange
        "enemy": (0.8, 0.4, 0.0),  # vermillion
        "bullet": (0.95, 0.9, 0.25),  # yellow
        "target": (0.8, 0.6, 0.7),  # reddish purple
        "camera_focus": (0.0, 0.6, 0.5),  # bluish green
        "camera_eye": (0.0, 0.45, 0.7),  # blue
    },
    "high_contrast": {
        **_PINS_DEFAULT,
        "crystal": (0.4, 1.0, 1.0),
        "body": (1.0, 0.75, 0.0),
        "enemy": (1.0, 0.1, 0.5),
        "bullet": (1.0, 1.0, 1.0),
        "target": (1.0, 0.4, 1.0),
        "camera_focus": (0.6, 1.0, 0.2),
        "camera_eye": (0.5, 0.6, 1.0),
        "object": (1.0, 1.0, 1.0),
    },
}

_current = ["default"]


def use(name: str) -> None:
    """Draw the w cues in palette ``name`` (one of :data:`NAMES`) from now on.

    Raises
    ------
    ValueError
        For an unknown name.
    """
    if name not in _CUES:
        raise ValueError(f"palette {name!r}: unknown; expected one of {', '.join(NAMES)}")
    _current[0] = name


def current() -> str:
    """The palette in use."""
    return _current[0]


def cue(key: str, palette: str | None = None) -> tuple[float, float, float, float]:
    """The RGBA colour ``key`` (``"gauge_ana"``, ``"energy"``...) of ``palette`` (the one in use)."""
    return _CUES[palette or _current[0]][key]


def pin(kind: str, palette: str | None = None) -> tuple[float, float, float]:
    """A radar pin's RGB for entity ``kind`` in ``palette`` (the one in use)."""
    return _PINS[palette or _current[0]][kind]


def ghost_tint(tint, pattern: str):
    """A ghost's tint in the palette in use: the game tints ana ghosts (``"stripes"``) and kata
    ghosts (``"dots"``) with the default palette's colours; anything else keeps its own."""
    if tint is None or _current[0] == "default":
        return tint
    key = {"stripes": "ghost_ana", "dots": "ghost_kata"}.get(pattern)
    return tint if key is None else cue(key)


def settings_palette(colour_blind: bool, high_contrast: bool) -> str:
    """The palette the settings ask for: high contrast wins over colour blind."""
    return "high_contrast" if high_contrast else ("colour_blind" if colour_blind else "default")


__all__ = ["NAMES", "PAIRS", "cue", "current", "ghost_tint", "pin", "settings_palette", "use"]
