"""What a player can bind: the actions, the key names, and the base key layouts.

Key names are plain strings, pyglet's key symbol names (``"W"``, ``"SPACE"``, ``"LSHIFT"``,
``"F3"``, ``"_1"`` for the digit 1, ...) plus the mouse buttons and wheel
(:data:`MOUSE_BUTTONS`). This module does not import pyglet: the window maps names to pyglet
codes (:mod:`.input`), so bindings can be checked and tested without a display.
"""

from __future__ import annotations

import difflib
import string
from typing import Any

#: Every bindable action, in menu order, with a one-line description. Adding an
#: action is one line here (plus, optionally, a default key in the presets; an
#: action missing from a preset simply starts unbound).
ACTION_DESCRIPTIONS: dict[str, str] = {
    "move_forward": "Walk forward",
    "move_back": "Walk backward",
    "strafe_left": "Step left",
    "strafe_right": "Step right",
    "jump": "Jump",
    "w_ana": "Move along the fourth axis towards +w (ana)",
    "w_kata": "Move along the fourth axis towards -w (kata)",
    "fire": "Fire the current weapon",
    "alt_fire": "Alternate fire of the current weapon",
    "next_weapon": "Switch to the next weapon",
    "previous_weapon": "Switch to the previous weapon",
    "weapon_1": "Take the first weapon",
    "weapon_2": "Take the second weapon",
    "weapon_3": "Take the third weapon",
    "switch_camera": "Switch between the 3D and 4D cameras",
    "manipulate": "Grab, rotate or release the object in front of you",
    "record": "Start or stop recording a replay",
    "screenshot": "Save a screenshot",
    "toggle_fps": "Show or hide the frame-rate counter",
    "debug_draw": "Show or hide the physics debug overlay (colliders, contacts, sleeping bodies)",
    "toggle_fullscreen": "Switch between windowed and fullscreen",
    "pause": "Pause the game and open the menu",
    "editor": "Open the level editor, or return from it to the game",
    "editor_play_here": "In the level editor: play from the editor's camera and w",
    "seek": "Move along w to the nearest thing of interest; press again for the next one",
    "seek_jump": "Seek without the glide: jump straight to the thing's w",
    "toggle_ghosts": "Show or hide the ghosts of what lies just off the slice along w",
    "hints": "Dismiss the hint on screen, or show the level's hints again",
    "toggle_mute": "Mute or unmute the sound",
    "restart_checkpoint": "Once the level can no longer be won: restart from the last checkpoint",
    "turn_xw_pos": "Hold: turn the slice in the xw plane (x towards +w)",
    "turn_xw_neg": "Hold: turn the slice in the xw plane (x towards -w)",
    "turn_yw_pos": "Hold: turn the slice in the yw plane (y towards +w)",
    "turn_yw_neg": "Hold: turn the slice in the yw plane (y towards -w)",
    "turn_zw_pos": "Hold: turn the slice in the zw plane (z towards +w)",
    "turn_zw_neg": "Hold: turn the slice in the zw plane (z towards -w)",
    "snap_slice": "Turn the slice back to the nearest 90-degree step",
    "step_xw_pos": "Turn the slice 90 degrees in the xw plane",
    "step_xw_neg": "Turn the slice 90 degrees back in the xw plane",
    "step_yw_pos": "Turn the slice 90 degrees in the yw plane",
    "step_yw_neg": "Turn the slice 90 degrees back in the yw plane",
    "step_zw_pos": "Turn the slice 90 degrees in the zw plane",
    "step_zw_neg": "Turn the slice 90 degrees back in the zw plane",
    "orbit_left": "Hold, in frustum view: move the 4D camera one way round the focus point",
    "orbit_right": "Hold, in frustum view: move the 4D camera the other way round the focus point",
    "toggle_pip": "Show or hide the inset with the other projection (picture in picture)",
}

#: The bindable action names, in menu order.
ACTIONS: tuple[str, ...] = tuple(ACTION_DESCRIPTIONS)
#: Held actions that pairs of opposites (one on lets go of the other when they toggle).
TOGGLE_PAIRS: tuple[tuple[str, str], ...] = (
    ("w_ana", "w_kata"),
    ("turn_xw_pos", "turn_xw_neg"),
    ("turn_yw_pos", "turn_yw_neg"),
    ("turn_zw_pos", "turn_zw_neg"),
    ("orbit_left", "orbit_right"),
)
#: The held actions a press may toggle instead (the settings' ``toggle_actions``), in menu order.
TOGGLEABLE_ACTIONS: tuple[str, ...] = tuple(
    a for a in ACTIONS if a == "manipulate" or any(a in pair for pair in TOGGLE_PAIRS)
)

#: Mouse buttons and the wheel, named like keys so one binding can mix both. A
#: wheel notch is a press of a one-shot action (next weapon), or holds any
#: other action for one tick.
MOUSE_BUTTONS: tuple[str, ...] = (
    "MOUSE_LEFT",
    "MOUSE_MIDDLE",
    "MOUSE_RIGHT",
    "MOUSE_4",
    "MOUSE_5",
    "MOUSE_WHEEL_UP",
    "MOUSE_WHEEL_DOWN",
)

#: Every accepted key name: a subset of pyglet's ``pyglet.window.key`` symbol
#: names (a test checks that) plus :data:`MOUSE_BUTTONS`. A closed list lets a
#: typo in the file be reported instead of silently binding nothing.
KEY_NAMES: frozenset[str] = frozenset(
    [*string.ascii_uppercase]
    + [f"_{d}" for d in range(10)]  # pyglet's names for the digit row
    + [f"F{n}" for n in range(1, 13)]
    + [f"NUM_{d}" for d in range(10)]
    + ["NUM_ADD", "NUM_SUBTRACT", "NUM_MULTIPLY", "NUM_DIVIDE", "NUM_DECIMAL", "NUM_ENTER"]
    + [
        "SPACE",
        "TAB",
        "ESCAPE",
        "RETURN",
        "BACKSPACE",
        "DELETE",
        "INSERT",
        "HOME",
        "END",
        "PAGEUP",
        "PAGEDOWN",
        "UP",
        "DOWN",
        "LEFT",
        "RIGHT",
        "LSHIFT",
        "RSHIFT",
        "LCTRL",
        "RCTRL",
        "LALT",
        "RALT",
        "CAPSLOCK",
    ]
    + [
        "MINUS",
        "EQUAL",
        "BRACKETLEFT",
        "BRACKETRIGHT",
        "BACKSLASH",
        "SEMICOLON",
        "APOSTROPHE",
        "GRAVE",
        "COMMA",
        "PERIOD",
        "SLASH",
    ]
    + list(MOUSE_BUTTONS)
)

_COMMON = {
    "jump": ("SPACE",),
    "fire": ("MOUSE_LEFT",),
    "alt_fire": ("MOUSE_RIGHT",),
    "next_weapon": ("R", "MOUSE_WHEEL_DOWN"),
    "previous_weapon": ("MOUSE_WHEEL_UP",),
    "weapon_1": ("_1",),
    "weapon_2": ("_2",),
    "weapon_3": ("_3",),
    "switch_camera": ("TAB",),
    "manipulate": ("F",),
    "record": ("F9",),
    "screenshot": ("F12",),
    "toggle_fps": ("F3",),
    "debug_draw": ("F4",),
    "toggle_fullscreen": ("F11",),
    "pause": ("ESCAPE",),
    "editor": ("F2",),
    "editor_play_here": ("F5",),
    "seek": ("T",),
    "seek_jump": ("Y",),
    "toggle_ghosts": ("V",),
    "hints": ("H",),
    "toggle_mute": ("M",),
    "restart_checkpoint": ("BACKSPACE",),
    "turn_xw_pos": ("L",),
    "turn_xw_neg": ("J",),
    "turn_yw_pos": ("O",),
    "turn_yw_neg": ("U",),
    "turn_zw_pos": ("I",),
    "turn_zw_neg": ("K",),
    "snap_slice": ("N",),
    "step_xw_pos": ("_4",),
    "step_xw_neg": ("_5",),
    "step_yw_pos": ("_6",),
    "step_yw_neg": ("_7",),
    "step_zw_pos": ("_9",),
    "step_zw_neg": ("_0",),
    "orbit_left": ("COMMA",),
    "orbit_right": ("PERIOD",),
    "toggle_pip": ("P",),
}

#: Base key layouts. pyglet reports key *symbols*, which follow the keyboard
#: layout, so an AZERTY keyboard needs ZQSD/A to get WASD/Q's physical keys.
PRESETS: dict[str, dict[str, tuple[str, ...]]] = {
    "qwerty": {
        "move_forward": ("W", "UP"),
        "move_back": ("S", "DOWN"),
        "strafe_left": ("A", "LEFT"),
        "strafe_right": ("D", "RIGHT"),
        "w_ana": ("E",),
        "w_kata": ("Q",),
        **_COMMON,
    },
    "azerty": {
        "move_forward": ("Z", "UP"),
        "move_back": ("S", "DOWN"),
        "strafe_left": ("Q", "LEFT"),
        "strafe_right": ("D", "RIGHT"),
        "w_ana": ("E",),
        "w_kata": ("A",),
        **_COMMON,
    },
}
del _COMMON

#: What a binding may be, in words (for messages about a bad one).
KEYS_EXPECTED = (
    'a list of key names such as ["SPACE"] (pyglet symbol names: '
    "'A'..'Z', '_0'..'_9', 'F1'..'F12', 'SPACE', 'LSHIFT', 'UP', ..., "
    "or 'MOUSE_LEFT', 'MOUSE_MIDDLE', 'MOUSE_RIGHT', 'MOUSE_4', 'MOUSE_5', "
    "'MOUSE_WHEEL_UP', 'MOUSE_WHEEL_DOWN')"
)


def normalise_key(name: str) -> str:
    """Canonical spelling of a key name: upper case, and a bare digit ``"1"``
    becomes pyglet's ``"_1"`` (an easy slip when editing the file by hand)."""
    name = name.strip().upper()
    if len(name) == 1 and name.isdigit():
        name = "_" + name
    return name


def parse_keys(value: Any) -> tuple[str, ...]:
    """Turn a binding value into a tuple of canonical key names.

    Accepts a list of strings (or a single string, the obvious meaning).
    Duplicates are dropped, keeping the first. Raises ``TypeError`` for a wrong
    type and ``ValueError`` naming the unknown keys.
    """
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, (list, tuple)):
        raise TypeError("not a list of key names")
    keys: list[str] = []
    unknown: list[str] = []
    for item in value:
        if not isinstance(item, str):
            raise TypeError(f"{item!r} is not a key name (a string)")
        key = normalise_key(item)
        if key not in KEY_NAMES:
            unknown.append(item)
        elif key not in keys:
            keys.append(key)
    if unknown:
        parts = []
        for item in unknown:
            close = difflib.get_close_matches(normalise_key(item), KEY_NAMES, n=1)
            parts.append(f"{item!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
        raise ValueError("unknown key name " + ", ".join(parts))
    return tuple(keys)
