"""Text laid out in pixels: lines wrapped to a width, a line cut to fit.

Shared by everything that draws words with the bitmap font (:mod:`.hud`, :mod:`.cards`,
:mod:`.menu`), so a panel's text is broken the same way wherever it is drawn. Widths are
pixels at a font ``scale`` (see :func:`~.font.text_width`).

The player's text size (settings ``text_size``, 1 to 1.5) is applied here too: each of those
picks its scale from the viewport and passes it through :func:`scaled`, so hints, menus, cards
and the HUD grow together (the font is drawn at whole scales: 125 % of 2 is 3, of 4 is 5).
"""

from __future__ import annotations

import functools

from .font import text_width


def wrap(message: str, max_width: int, scale: int) -> list[str]:
    """``message`` broken into lines at most ``max_width`` pixels wide at ``scale``.

    Newlines start new lines; words are kept whole unless one alone is too wide, which is then
    broken where it stops fitting. Cached: HUD lines repeat from frame to frame.
    """
    return list(_wrap_cached(message, int(max_width), int(scale)))


@functools.lru_cache(maxsize=256)
def _wrap_cached(message: str, max_width: int, scale: int) -> tuple[str, ...]:
    lines: list[str] = []
    fits = lambda t: text_width(t, scale) <= max_width  # noqa: E731
    for para in message.split("\n"):
        line = ""
        for word in para.split(" "):
            while not fits(word) and len(word) > 1:  # a word longer than a line: hard break
                if line:
                    lines.append(line)
                    line = ""
                cut = len(word) - 1
                while cut > 1 and not fits(word[:cut]):
                    cut -= 1
                lines.append(word[:cut])
                word = word[cut:]
            cand = f"{line} {word}" if line else word
            if fits(cand):
                line = cand
            else:
                lines.append(line)
                line = word
        lines.append(line)
    return tuple(lines)


def ellipsized(text: str, max_width: int, scale: int, mark: str = "\u2026") -> str:
    """``text`` cut to fit ``max_width`` pixels, ending in ``mark`` when cut."""
    if text_width(text, scale) <= max_width:
        return text
    while text and text_width(text + mark, scale) > max_width:
        text = text[:-1]
    return text.rstrip() + mark


_text_size = [1.0]


def set_text_size(factor: float) -> None:
    """Draw text ``factor`` times its own size from now on (the settings' ``text_size``)."""
    _text_size[0] = float(factor)


def scaled(scale: int) -> int:
    """A text scale chosen for the viewport, times the player's text size, rounded half up to a
    whole scale and never below ``scale``."""
    return max(int(scale), int(scale * _text_size[0] + 0.5))
