"""Player settings: key bindings, mouse look, display options, and their file.

Settings live in one TOML file, ``settings.toml`` in the per-user config folder
(see :func:`settings_path`)::

    preset = "qwerty"            # or "azerty": the base key layout
    mouse_sensitivity = 0.0025   # radians per pixel
    invert_x = false
    invert_y = false
    fov_deg = 75.0
    fullscreen = false
    vsync = true
    show_fps = false
    width = 1280
    height = 720
    radar = true                 # the radar, in levels that have one
    radar_range_scale = 1.0      # times the level's radar range
    radar_height_scale = 1.0     # times the level's pin heights
    ghosts = true                # ghosts: of what lies just off the slice along w, and manipulation previews
    ghost_distance = 1.0         # times the level's ghost distance
    ghost_strength = 1.0         # times the ghosts' opacity
    ghost_layers = 1             # 1 or 2 per side
    reduce_motion = false        # seek jumps instead of gliding
    volume = 0.8                 # sound effects, 0 (silent) to 1
    mute = false                 # the mute key toggles it while playing
    colour_blind = false         # a palette that never tells things apart by red and green alone
    render_scale = "auto"        # 0.5 to 1.0: draw at this fraction of the window, upscaled; "auto" from the GPU
    pip = false                  # the inset with the other projection (a key toggles it)
    pip_size = 0.3               # its height, a fraction of the window's

    [bindings]                   # only the actions that differ from the preset
    jump = ["SPACE", "MOUSE_RIGHT"]

Key names are plain strings, pyglet's key symbol names (``"W"``, ``"SPACE"``,
``"LSHIFT"``, ``"F3"``, ``"_1"`` for the digit 1, ...) plus ``"MOUSE_LEFT"``,
``"MOUSE_MIDDLE"`` and ``"MOUSE_RIGHT"``. This module deliberately does not
import pyglet: the window maps names to pyglet codes, so settings can be loaded,
checked and tested without a display.

Loading never raises: the game must start even with a hand-edited, broken file.
Each problem becomes a warning naming the file, the entry and what was
expected, and only that entry falls back to its default.

>>> s = default_settings("azerty")
>>> s.action_for_key("Z"), s.keys_for("strafe_left")
('move_forward', ('Q', 'LEFT'))
"""

from __future__ import annotations

import difflib
import math
import os
import string
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import platformdirs
import tomli_w

from ..core.fileio import FileProblem, atomic_writer, read_text

#: Largest settings file read, in bytes: a real one is about 1 kB.
SETTINGS_MAX_BYTES = 64 * 1024

__all__ = [
    "ACTIONS",
    "ACTION_DESCRIPTIONS",
    "CONFIG_DIR_ENV",
    "KEY_NAMES",
    "MOUSE_BUTTONS",
    "PRESETS",
    "Settings",
    "default_settings",
    "load_settings",
    "look_delta",
    "save_settings",
    "settings_path",
]

# --------------------------------------------------------------------------
# Actions and key names
# --------------------------------------------------------------------------

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

#: Environment variable that replaces the config folder (tests, portable installs).
CONFIG_DIR_ENV = "ACROSS_DIMENSIONS_CONFIG_DIR"

_APP_NAME = "across-dimensions"
_FILE_NAME = "settings.toml"

_KEYS_EXPECTED = (
    'a list of key names such as ["SPACE"] (pyglet symbol names: '
    "'A'..'Z', '_0'..'_9', 'F1'..'F12', 'SPACE', 'LSHIFT', 'UP', ..., "
    "or 'MOUSE_LEFT', 'MOUSE_MIDDLE', 'MOUSE_RIGHT', 'MOUSE_4', 'MOUSE_5', "
    "'MOUSE_WHEEL_UP', 'MOUSE_WHEEL_DOWN')"
)

# --------------------------------------------------------------------------
# Validation rules for the scalar settings
# --------------------------------------------------------------------------


class _Rule:
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

_RULES: dict[str, _Rule] = {
    "preset": _Rule(" or ".join(repr(p) for p in PRESETS), _preset),
    "mouse_sensitivity": _Rule(
        "a number of radians per pixel, > 0 and < 0.1", _number(0.0, 0.1, open_lo=True, open_hi=True)
    ),
    "invert_x": _Rule("true or false", _boolean),
    "invert_y": _Rule("true or false", _boolean),
    "fov_deg": _Rule("a number of degrees from 50 to 120", _number(50.0, 120.0)),
    "fullscreen": _Rule("true or false", _boolean),
    "vsync": _Rule("true or false", _boolean),
    "show_fps": _Rule("true or false", _boolean),
    "ghosts": _Rule("true or false", _boolean),
    "width": _Rule(f"a whole number of pixels from 320 to {_MAX_SIZE}", _integer(320, _MAX_SIZE)),
    "height": _Rule(f"a whole number of pixels from 240 to {_MAX_SIZE}", _integer(240, _MAX_SIZE)),
    "radar": _Rule("true or false", _boolean),
    "radar_range_scale": _Rule("a number from 0.25 to 4", _number(0.25, 4.0)),
    "radar_height_scale": _Rule("a number from 0.25 to 4", _number(0.25, 4.0)),
    "ghost_distance": _Rule("a factor of the level's ghost distance from 0.25 to 4", _number(0.25, 4.0)),
    "ghost_strength": _Rule("a factor of the ghosts' opacity from 0 to 3", _number(0.0, 3.0)),
    "ghost_layers": _Rule("1 or 2 (ghost layers on each side)", _integer(1, 2)),
    "reduce_motion": _Rule("true or false", _boolean),
    "volume": _Rule("a number from 0 (silent) to 1", _number(0.0, 1.0)),
    "mute": _Rule("true or false", _boolean),
    "colour_blind": _Rule("true or false", _boolean),
    "render_scale": _Rule('"auto" or a number from 0.5 to 1.0 (fraction of the window drawn, then upscaled)', None),
    "pip": _Rule("true or false", _boolean),
    "pip_size": _Rule("a fraction of the window's height from 0.1 to 0.5", _number(0.1, 0.5)),
}


def _render_scale(value: Any) -> float | str:
    if isinstance(value, str) and value.strip().lower() == "auto":
        return "auto"
    return _number(0.5, 1.0)(value)


_RULES["render_scale"].convert = _render_scale


def _normalise_key(name: str) -> str:
    """Canonical spelling of a key name: upper case, and a bare digit ``"1"``
    becomes pyglet's ``"_1"`` (an easy slip when editing the file by hand)."""
    name = name.strip().upper()
    if len(name) == 1 and name.isdigit():
        name = "_" + name
    return name


def _parse_keys(value: Any) -> tuple[str, ...]:
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
        key = _normalise_key(item)
        if key not in KEY_NAMES:
            unknown.append(item)
        elif key not in keys:
            keys.append(key)
    if unknown:
        parts = []
        for item in unknown:
            close = difflib.get_close_matches(_normalise_key(item), KEY_NAMES, n=1)
            parts.append(f"{item!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
        raise ValueError("unknown key name " + ", ".join(parts))
    return tuple(keys)


# --------------------------------------------------------------------------
# Settings
# --------------------------------------------------------------------------


@dataclass
class Settings:
    """Everything the player can configure.

    Parameters
    ----------
    bindings : dict of str to tuple of str, optional
        Action name -> key names. Actions left out take the preset's keys, so
        ``Settings(preset="azerty", bindings={"jump": ("X",)})`` is AZERTY with
        jump moved; an empty tuple unbinds. After construction it holds every
        action of :data:`ACTIONS`, in that order.
    preset : str
        Base layout, a key of :data:`PRESETS`.
    mouse_sensitivity : float
        Radians of turn per pixel of mouse motion, in (0, 0.1).
    invert_x, invert_y : bool
        Reverse horizontal / vertical mouse look.
    fov_deg : float
        Vertical field of view, degrees, in [50, 120].
    fullscreen, vsync, show_fps : bool
        Display options.
    width, height : int
        Window size in pixels, at least 320 x 240.
    radar : bool
        Show the radar in levels that have one.
    radar_range_scale, radar_height_scale : float
        Multiply the level's radar range and pin heights (0.25 to 4): a player
        who wants to see farther, or read small w offsets more easily.
    ghosts : bool
        Draw ghosts: of what lies just off the slice along w (a key toggles
        them), and the previews while manipulating a 4D object.
    ghost_distance : float
        Factor on the level's ghost distance along w, in [0.25, 4].
    ghost_strength : float
        Factor on the ghosts' opacity, in [0, 3].
    ghost_layers : int
        Ghost layers on each side of the slice, 1 or 2.
    reduce_motion : bool
        Seek jumps to its w instead of gliding there.
    volume : float
        Loudness of the sound effects, 0 (silent) to 1.
    mute : bool
        No sound at all (the ``toggle_mute`` key flips it while playing).
    colour_blind : bool
        A colour-blind-safe palette.
    render_scale : float or "auto"
        Fraction of the window's width and height the scene is drawn at (0.5 to
        1.0), then upscaled: a software rasterizer trades resolution for frame
        rate. ``"auto"`` picks from the GL renderer (lower for llvmpipe and
        softpipe; see :func:`across_dimensions.render.scale.default_render_scale`).
    pip : bool
        Start with the picture-in-picture on: a small inset showing the other projection
        (frustum while the game shows the cross-section, and the other way round).
    pip_size : float
        The inset's height as a fraction of the window's, in [0.1, 0.5].

    Raises
    ------
    ValueError
        If a value is of the wrong type or out of range, or a binding names an
        unknown action or key. (Files never raise: see :func:`load_settings`.)
    """

    bindings: dict[str, tuple[str, ...]] | None = None
    preset: str = "qwerty"
    mouse_sensitivity: float = 0.0025
    invert_x: bool = False
    invert_y: bool = False
    fov_deg: float = 75.0
    fullscreen: bool = False
    vsync: bool = True
    show_fps: bool = False
    width: int = 1280
    height: int = 720
    radar: bool = True
    radar_range_scale: float = 1.0
    radar_height_scale: float = 1.0
    ghosts: bool = True
    ghost_distance: float = 1.0
    ghost_strength: float = 1.0
    ghost_layers: int = 1
    reduce_motion: bool = False
    volume: float = 0.8
    mute: bool = False
    colour_blind: bool = False
    render_scale: float | str = "auto"
    pip: bool = False
    pip_size: float = 0.3

    def __post_init__(self) -> None:
        for name, rule in _RULES.items():
            value = getattr(self, name)
            try:
                setattr(self, name, rule.convert(value))
            except (TypeError, ValueError):
                raise ValueError(f"Settings.{name}: got {value!r}, expected {rule.expected}") from None

        overrides = dict(self.bindings or {})
        for action in overrides:
            if action not in ACTION_DESCRIPTIONS:
                raise ValueError(f"Settings.bindings: unknown action {action!r}, expected one of {ACTIONS}")
        base = PRESETS[self.preset]
        merged = {}
        for action in ACTIONS:  # a fresh dict: never alias the caller's or the preset's
            raw = overrides.get(action, base.get(action, ()))
            try:
                merged[action] = _parse_keys(raw)
            except (TypeError, ValueError) as exc:
                raise ValueError(f"Settings.bindings[{action!r}]: {exc}; expected {_KEYS_EXPECTED}") from None
        self.bindings = merged

    def keys_for(self, action: str) -> tuple[str, ...]:
        """Key names bound to ``action`` (empty if unbound).

        Raises
        ------
        KeyError
            If ``action`` is not in :data:`ACTIONS` (a typo in code should fail
            loudly, not leave a control dead).
        """
        if action not in ACTION_DESCRIPTIONS:
            raise KeyError(f"unknown action {action!r}; known actions: {', '.join(ACTIONS)}")
        return self.bindings.get(action, ())

    def conflicts(self) -> dict[str, tuple[str, ...]]:
        """Keys bound to more than one action: key -> actions in :data:`ACTIONS` order."""
        owners: dict[str, list[str]] = {}
        for action in ACTIONS:
            for key in self.bindings.get(action, ()):
                owners.setdefault(key, []).append(action)
        return {key: tuple(acts) for key, acts in owners.items() if len(acts) > 1}

    def key_map(self) -> dict[str, str]:
        """Reverse map key name -> action, for the window to build once.

        A key bound to several actions maps to the first of them in
        :data:`ACTIONS` order; :meth:`problems` reports such keys.
        """
        result: dict[str, str] = {}
        for action in ACTIONS:
            for key in self.bindings.get(action, ()):
                result.setdefault(key, action)
        return result

    def action_for_key(self, key: str) -> str | None:
        """The action ``key`` triggers, or ``None`` if it is unbound.

        ``key`` is matched case-insensitively. A key bound to several actions
        triggers only the first in :data:`ACTIONS` order (deterministic, and
        reported by :meth:`problems`).
        """
        return self.key_map().get(_normalise_key(key))

    def problems(self) -> list[str]:
        """Human-readable descriptions of keys bound to more than one action."""
        return [
            f"key {key!r} is bound to {' and '.join(repr(a) for a in acts)}; it will only trigger {acts[0]!r}"
            for key, acts in self.conflicts().items()
        ]


def default_settings(preset: str = "qwerty") -> Settings:
    """Default settings on the given key layout (``"qwerty"`` or ``"azerty"``).

    Raises
    ------
    ValueError
        For an unknown preset.
    """
    return Settings(preset=preset)


def look_delta(settings: Settings, dx_pixels: float, dy_pixels: float) -> tuple[float, float]:
    """Turn mouse motion into a look change.

    Parameters
    ----------
    settings : Settings
    dx_pixels, dy_pixels : float
        Mouse motion as pyglet reports it: ``dx > 0`` is rightwards, ``dy > 0``
        upwards.

    Returns
    -------
    dyaw, dpitch : float
        Radians. Positive yaw turns right and positive pitch looks up (the
        convention of :class:`across_dimensions.game.actions.Actions`), each
        reversed by ``invert_x`` / ``invert_y``. Pitch is not clamped here.
    """
    s = settings.mouse_sensitivity
    dyaw = float(dx_pixels) * s * (-1.0 if settings.invert_x else 1.0)
    dpitch = float(dy_pixels) * s * (-1.0 if settings.invert_y else 1.0)
    return dyaw, dpitch


# --------------------------------------------------------------------------
# File
# --------------------------------------------------------------------------


def settings_path() -> Path:
    """Where the settings file lives.

    ``$ACROSS_DIMENSIONS_CONFIG_DIR/settings.toml`` when that variable is set
    and non-empty (tests use it to stay out of the real config folder),
    otherwise ``settings.toml`` in platformdirs' per-user config folder for
    ``"across-dimensions"``.
    """
    override = os.environ.get(CONFIG_DIR_ENV, "").strip()
    folder = Path(override).expanduser() if override else Path(platformdirs.user_config_dir(_APP_NAME))
    return folder / _FILE_NAME


def _defaults() -> dict[str, Any]:
    return {f.name: f.default for f in fields(Settings) if f.name != "bindings"}


def load_settings(path: str | os.PathLike | None = None) -> tuple[Settings, list[str]]:
    """Read settings from a TOML file, never raising.

    Parameters
    ----------
    path : path-like, optional
        Defaults to :func:`settings_path`.

    Returns
    -------
    settings : Settings
    warnings : list of str
        One message per problem, each naming the file, the entry and what was
        expected. A missing file gives the defaults and no warning; a file that
        cannot be read or is not valid TOML gives one warning and all defaults;
        a bad entry (wrong type, out of range, unknown preset, action or key
        name) gives a warning and that entry's default while the valid entries
        are kept. Keys bound to more than one action are reported too.
    """
    path = Path(path) if path is not None else settings_path()
    defaults = _defaults()
    try:
        # Regular files of at most SETTINGS_MAX_BYTES only: a FIFO or a link to
        # /dev/zero must not hang or exhaust memory. A byte-order mark is skipped.
        data = tomllib.loads(read_text(path, limit=SETTINGS_MAX_BYTES, what="settings"))
    except FileProblem as exc:
        if not os.path.lexists(path):
            return default_settings(), []
        return default_settings(), [f"{exc}; using the default settings"]
    except RecursionError:  # deeply nested arrays: tomllib recurses per level
        return default_settings(), [f"{path}: not valid TOML (nested too deeply); using the default settings"]
    except (tomllib.TOMLDecodeError, ValueError) as exc:  # ValueError: an integer of over 4300 digits
        return default_settings(), [f"{path}: not valid TOML ({exc}); using the default settings"]

    warnings: list[str] = []

    def bad(entry: str, value: Any, expected: str, default: Any, why: str = "") -> None:
        shown = list(default) if isinstance(default, tuple) else default
        detail = f" ({why})" if why else ""
        warnings.append(f"{path}: {entry} = {value!r}{detail}: expected {expected}; using the default {shown!r}")

    values: dict[str, Any] = {}
    for name, rule in _RULES.items():
        if name in data:
            try:
                values[name] = rule.convert(data[name])
            except (TypeError, ValueError):
                bad(name, data[name], rule.expected, defaults[name])

    for name in data:
        if name not in _RULES and name != "bindings":
            # Ignored rather than fatal: it may come from a newer version.
            warnings.append(
                f"{path}: unknown setting {name!r}, ignored; expected one of {', '.join(list(_RULES) + ['[bindings]'])}"
            )

    preset = PRESETS[values.get("preset", defaults["preset"])]
    overrides: dict[str, tuple[str, ...]] = {}
    raw_bindings = data.get("bindings", {})
    if not isinstance(raw_bindings, dict):
        warnings.append(
            f"{path}: bindings = {raw_bindings!r}: expected a [bindings] table of "
            f'action = ["KEY", ...]; using the preset\'s bindings'
        )
        raw_bindings = {}
    for action, raw in raw_bindings.items():
        if action not in ACTION_DESCRIPTIONS:
            close = difflib.get_close_matches(action, ACTIONS, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            warnings.append(
                f"{path}: [bindings] unknown action {action!r}{hint}, ignored; expected one of {', '.join(ACTIONS)}"
            )
            continue
        try:
            overrides[action] = _parse_keys(raw)
        except (TypeError, ValueError) as exc:
            bad(f"[bindings] {action}", raw, _KEYS_EXPECTED, preset.get(action, ()), str(exc))

    # Every value was checked above, so construction cannot fail.
    settings = Settings(bindings=overrides, **values)
    warnings.extend(f"{path}: [bindings] {problem}" for problem in settings.problems())
    return settings, warnings


def _to_toml(settings: Settings) -> dict[str, Any]:
    doc: dict[str, Any] = {name: getattr(settings, name) for name in _RULES}
    # Only the differences from the preset, so the file stays short and a
    # changed ``preset`` line still moves every action the player left alone.
    base = PRESETS[settings.preset]
    doc["bindings"] = {action: list(keys) for action, keys in settings.bindings.items() if keys != base.get(action, ())}
    return doc


_HEADER = b"""\
# Across Dimensions settings, rewritten by the game: edit while it is closed.
# [bindings] lists only actions whose keys differ from the preset, e.g.
#   jump = ["SPACE", "MOUSE_RIGHT"]     (an empty list [] unbinds an action)

"""


def save_settings(settings: Settings, path: str | os.PathLike | None = None) -> Path:
    """Write settings as TOML, atomically (:func:`~across_dimensions.core.fileio.atomic_writer`).

    The text goes to a uniquely named temporary file in the same folder, is
    flushed to disk, then renamed over the target, so a crash or a full disk
    leaves either the old file or the new one, never a truncated mix, and no
    temporary file.

    Parameters
    ----------
    settings : Settings
    path : path-like, optional
        Defaults to :func:`settings_path`, whose config folder is created if
        missing. A folder given explicitly must already exist.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ValueError
        If ``settings`` was modified into an invalid state after construction
        (checked before anything is written).
    FileProblem
        If ``path``'s folder is missing (a ``ValueError`` naming it).
    OSError
        If the file cannot be written; the old file, if any, is untouched and
        no temporary file is left behind.
    """
    own_folder = path is None
    path = Path(path) if path is not None else settings_path()
    checked = replace(settings)  # re-runs __post_init__ validation on fields set since construction
    payload = _HEADER + tomli_w.dumps(_to_toml(checked)).encode("utf-8")
    if own_folder:
        path.parent.mkdir(parents=True, exist_ok=True)  # the game's own config folder, not a user's typo
    with atomic_writer(path, "wb") as f:
        f.write(payload)
    return path


# --------------------------------------------------------------------------
# Warnings: one line on screen, every detail in a log file
# --------------------------------------------------------------------------

#: Environment variable that replaces the log folder (tests, portable installs).
LOG_DIR_ENV = "ACROSS_DIMENSIONS_LOG_DIR"


def log_path() -> Path:
    """The settings log: ``settings.log`` in platformdirs' per-user log folder (or ``$ACROSS_DIMENSIONS_LOG_DIR``)."""
    override = os.environ.get(LOG_DIR_ENV, "").strip()
    folder = Path(override).expanduser() if override else Path(platformdirs.user_log_dir(_APP_NAME))
    return folder / "settings.log"


def report_warnings(warnings: list[str], path: str | os.PathLike | None = None) -> str:
    """Write every settings warning to the log file and return the one line a player sees.

    Parameters
    ----------
    warnings : list of str
        From :func:`load_settings`.
    path : path-like, optional
        The settings file they are about (named in the line); defaults to :func:`settings_path`.

    Returns
    -------
    str
        ``""`` when there is nothing to report; otherwise one line naming the settings file, how
        many problems it has and where the details are (or that the log could not be written).
        The log file is replaced on each start: it describes the settings this run uses.
    """
    if not warnings:
        return ""
    source = Path(path) if path is not None else settings_path()
    log = log_path()
    n = len(warnings)
    what = "a problem" if n == 1 else f"{n} problems"
    line = f"Settings: {what} in {source}; defaults used for those entries"
    try:
        log.parent.mkdir(parents=True, exist_ok=True)  # the game's own log folder
        with atomic_writer(log, "w") as f:
            f.write("".join(w + "\n" for w in warnings))
    except (OSError, FileProblem) as e:
        return f"{line} (log not written: {e}); first: {warnings[0]}"
    return f"{line}; details in {log}"


def warning_screen_line(warnings: list[str], path: str | os.PathLike | None = None) -> str:
    """The short form of :func:`report_warnings`' line for the screen: file and log by name only."""
    if not warnings:
        return ""
    source = Path(path) if path is not None else settings_path()
    n = len(warnings)
    what = "a problem" if n == 1 else f"{n} problems"
    return f"{what.capitalize()} in {source.name}: see {log_path().name}"
