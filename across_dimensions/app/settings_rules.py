"""How each setting of :mod:`.settings` is checked: what it accepts, in words, and how it is read.

A rule's ``convert`` returns the normalised value or raises ``TypeError``/``ValueError``;
its ``expected`` says what is accepted, for the messages that name a bad entry.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from .keymap import ACTION_DESCRIPTIONS, PRESETS, TOGGLEABLE_ACTIONS

#: Text sizes the menu steps through (times the game's own size); the file accepts any in between.
TEXT_SIZES = (1.0, 1.25, 1.5)


class Rule:
    """How one scalar setting is checked: ``convert`` returns the normalised
    value or raises ``TypeError``/``ValueError``; ``expected`` says in words
    what is accepted, for messages."""

    def __init__(self, expected: str, convert: Callable[[Any], Any]):
        self.expected = expected
        self.convert = convert


def _boolean(value: Any) -> bool:
    # TOML has real booleans; 0/1 or "yes" are rejected rather than guessed.
    if not isinstance(value, bool):
        raise TypeError("not a boolean")
    return value


def _number(lo: float, hi: float, *, open_lo: bool = False, open_hi: bool = False) -> Callable[[Any], float]:
    def convert(value: Any) -> float:
        # bool is an int subclass in Python; ``fov_deg = true`` must not mean 1.
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError("not a number")
        x = float(value)
        above = x > lo if open_lo else x >= lo
        below = x < hi if open_hi else x <= hi
        if not (math.isfinite(x) and above and below):  # NaN fails both comparisons
            raise ValueError("out of range")
        return x

    return convert


def _integer(lo: int, hi: int) -> Callable[[Any], int]:
    def convert(value: Any) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError("not an integer")
        if not lo <= value <= hi:
            raise ValueError("out of range")
        return value

    return convert


def _preset(value: Any) -> str:
    if not isinstance(value, str):
        raise TypeError("not a string")
    name = value.strip().lower()
    if name not in PRESETS:
        raise ValueError("unknown preset")
    return name


# Window sizes: at least 320x240 so the HUD fits; the upper bound only stops
# absurd values (a typo like 12800000) from reaching the GL driver.
_MAX_SIZE = 16384

RULES: dict[str, Rule] = {
    "preset": Rule(" or ".join(repr(p) for p in PRESETS), _preset),
    "mouse_sensitivity": Rule(
        "a number of radians per pixel, > 0 and < 0.1", _number(0.0, 0.1, open_lo=True, open_hi=True)
    ),
    "invert_x": Rule("true or false", _boolean),
    "invert_y": Rule("true or false", _boolean),
    "fov_deg": Rule("a number of degrees from 50 to 120", _number(50.0, 120.0)),
    "fullscreen": Rule("true or false", _boolean),
    "vsync": Rule("true or false", _boolean),
    "show_fps": Rule("true or false", _boolean),
    "ghosts": Rule("true or false", _boolean),
    "width": Rule(f"a whole number of pixels from 320 to {_MAX_SIZE}", _integer(320, _MAX_SIZE)),
    "height": Rule(f"a whole number of pixels from 240 to {_MAX_SIZE}", _integer(240, _MAX_SIZE)),
    "radar": Rule("true or false", _boolean),
    "radar_range_scale": Rule("a number from 0.25 to 4", _number(0.25, 4.0)),
    "radar_height_scale": Rule("a number from 0.25 to 4", _number(0.25, 4.0)),
    "ghost_distance": Rule("a factor of the level's ghost distance from 0.25 to 4", _number(0.25, 4.0)),
    "ghost_strength": Rule("a factor of the ghosts' opacity from 0 to 3", _number(0.0, 3.0)),
    "ghost_layers": Rule("1 or 2 (ghost layers on each side)", _integer(1, 2)),
    "reduce_motion": Rule("true or false", _boolean),
    "volume": Rule("a number from 0 (silent) to 1", _number(0.0, 1.0)),
    "mute": Rule("true or false", _boolean),
    "colour_blind": Rule("true or false", _boolean),
    "render_scale": Rule('"auto" or a number from 0.5 to 1.0 (fraction of the window drawn, then upscaled)', None),
    "pip": Rule("true or false", _boolean),
    "pip_size": Rule("a fraction of the window's height from 0.1 to 0.5", _number(0.1, 0.5)),
    "high_contrast": Rule("true or false", _boolean),
    "text_size": Rule(f"a factor of the text's size from {TEXT_SIZES[0]} to {TEXT_SIZES[-1]}", _number(1.0, 1.5)),
    "captions": Rule("true or false", _boolean),
    "toggle_actions": Rule(f"a list of action names among {', '.join(TOGGLEABLE_ACTIONS)}", None),
}


def _render_scale(value: Any) -> float | str:
    if isinstance(value, str) and value.strip().lower() == "auto":
        return "auto"
    return _number(0.5, 1.0)(value)


def _toggle_actions(value: Any) -> tuple[str, ...]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list | tuple) or not all(isinstance(v, str) for v in value):
        raise TypeError("not a list of action names")
    names = tuple(dict.fromkeys(v.strip().lower() for v in value))  # in order, each once
    if any(n not in TOGGLEABLE_ACTIONS for n in names):
        raise ValueError("not an action that can toggle")
    return names


RULES["render_scale"].convert = _render_scale
RULES["toggle_actions"].convert = _toggle_actions
assert all(a in ACTION_DESCRIPTIONS for a in TOGGLEABLE_ACTIONS)
