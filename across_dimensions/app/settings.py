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
    reduce_motion = false        # what glides snaps; held turns turn in jumps (see the README)
    volume = 0.8                 # sound effects, 0 (silent) to 1
    mute = false                 # the mute key toggles it while playing
    colour_blind = false         # a palette that never tells things apart by red and green alone
    high_contrast = false        # a palette of strong, light-or-dark colours (colour-blind-safe too)
    text_size = 1.0              # 1.0, 1.25 or 1.5 times the text of hints, menus and HUD
    captions = false             # sounds made visible: captions and w-side edge indicators
    toggle_actions = []          # held actions a press switches on and off instead
    render_scale = "auto"        # 0.5 to 1.0: draw at this fraction of the window, upscaled; "auto" from the GPU
    pip = false                  # the inset with the other projection (a key toggles it)
    pip_size = 0.3               # its height, a fraction of the window's

    [bindings]                   # only the actions that differ from the preset
    jump = ["SPACE", "MOUSE_RIGHT"]

The actions and the key names (pyglet's key symbol names, ``"W"``, ``"SPACE"``, ``"_1"``
for the digit 1, plus the mouse buttons and wheel) are :mod:`.keymap`'s. This module
deliberately does not import pyglet: the window maps names to pyglet codes, so settings can
be loaded, checked and tested without a display.

Loading never raises: the game must start even with a hand-edited, broken file.
Each problem becomes a warning naming the file, the entry and what was
expected, and only that entry falls back to its default. The warnings reach the player as
one line, with every detail in a log file (:mod:`.settings_log`).

>>> s = default_settings("azerty")
>>> s.action_for_key("Z"), s.keys_for("strafe_left")
('move_forward', ('Q', 'LEFT'))
"""

from __future__ import annotations

import difflib
import os
import tomllib
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import platformdirs
import tomli_w

from ..core.fileio import FileProblem, atomic_writer, read_text
from .keymap import (
    ACTION_DESCRIPTIONS,
    ACTIONS,
    KEY_NAMES,
    KEYS_EXPECTED,
    MOUSE_BUTTONS,
    PRESETS,
    normalise_key,
    parse_keys,
)
from .settings_rules import RULES

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

#: Environment variable that replaces the config folder (tests, portable installs).
CONFIG_DIR_ENV = "ACROSS_DIMENSIONS_CONFIG_DIR"

APP_NAME = "across-dimensions"
_FILE_NAME = "settings.toml"

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
        What glides snaps (slice steps and snap, seek, the camera's return) and what turns
        while held turns in jumps (:mod:`across_dimensions.game.motion`).
    volume : float
        Loudness of the sound effects, 0 (silent) to 1.
    mute : bool
        No sound at all (the ``toggle_mute`` key flips it while playing).
    colour_blind : bool
        A colour-blind-safe palette, for the scene and every w cue (ghosts, HUD, radar).
    high_contrast : bool
        A high-contrast palette (also colour-blind-safe); wins over ``colour_blind``.
    text_size : float
        Factor on the size of the text of hints, menus and the HUD, 1.0 to 1.5.
    captions : bool
        Sounds made visible: a caption for each important sound with its direction and w side,
        and a mark at the screen's edge for what is heard along w.
    toggle_actions : tuple of str
        Held actions (w moves, manipulation, orbit, slice turns) that a press switches on and
        the next press off, instead of acting while the key is down.
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
    high_contrast: bool = False
    text_size: float = 1.0
    captions: bool = False
    toggle_actions: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for name, rule in RULES.items():
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
                merged[action] = parse_keys(raw)
            except (TypeError, ValueError) as exc:
                raise ValueError(f"Settings.bindings[{action!r}]: {exc}; expected {KEYS_EXPECTED}") from None
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
        return self.key_map().get(normalise_key(key))

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


def window_options(settings: Settings) -> dict:
    """What the window takes from the settings: its size, vsync and fullscreen."""
    return {
        "width": settings.width,
        "height": settings.height,
        "vsync": settings.vsync,
        "fullscreen": settings.fullscreen,
    }


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
    folder = Path(override).expanduser() if override else Path(platformdirs.user_config_dir(APP_NAME))
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
    values = _read_values(path, data, warnings)
    preset = PRESETS[values.get("preset", _defaults()["preset"])]
    overrides = _read_bindings(path, data.get("bindings", {}), preset, warnings)
    # Every value was checked above, so construction cannot fail.
    settings = Settings(bindings=overrides, **values)
    warnings.extend(f"{path}: [bindings] {problem}" for problem in settings.problems())
    return settings, warnings


def _bad(path: Path, entry: str, value: Any, expected: str, default: Any, why: str = "") -> str:
    """The warning for an entry whose value is refused, naming the default used instead."""
    shown = list(default) if isinstance(default, tuple) else default
    detail = f" ({why})" if why else ""
    return f"{path}: {entry} = {value!r}{detail}: expected {expected}; using the default {shown!r}"


def _read_values(path: Path, data: dict, warnings: list[str]) -> dict[str, Any]:
    """The valid settings of ``data`` (all but ``[bindings]``), by name; a warning for each bad or
    unknown one."""
    defaults = _defaults()
    values: dict[str, Any] = {}
    for name, rule in RULES.items():
        if name in data:
            try:
                values[name] = rule.convert(data[name])
            except (TypeError, ValueError):
                warnings.append(_bad(path, name, data[name], rule.expected, defaults[name]))
    for name in data:
        if name not in RULES and name != "bindings":
            # Ignored rather than fatal: it may come from a newer version.
            warnings.append(
                f"{path}: unknown setting {name!r}, ignored; expected one of {', '.join(list(RULES) + ['[bindings]'])}"
            )
    return values


def _read_bindings(path: Path, raw_bindings, preset: dict, warnings: list[str]) -> dict[str, tuple[str, ...]]:
    """The valid key bindings of the ``[bindings]`` table, by action; a warning for each bad one
    (that action keeps the preset's keys)."""
    if not isinstance(raw_bindings, dict):
        warnings.append(
            f"{path}: bindings = {raw_bindings!r}: expected a [bindings] table of "
            f'action = ["KEY", ...]; using the preset\'s bindings'
        )
        return {}
    overrides: dict[str, tuple[str, ...]] = {}
    for action, raw in raw_bindings.items():
        if action not in ACTION_DESCRIPTIONS:
            close = difflib.get_close_matches(action, ACTIONS, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            warnings.append(
                f"{path}: [bindings] unknown action {action!r}{hint}, ignored; expected one of {', '.join(ACTIONS)}"
            )
            continue
        try:
            overrides[action] = parse_keys(raw)
        except (TypeError, ValueError) as exc:
            warnings.append(_bad(path, f"[bindings] {action}", raw, KEYS_EXPECTED, preset.get(action, ()), str(exc)))
    return overrides


def _to_toml(settings: Settings) -> dict[str, Any]:
    doc: dict[str, Any] = {name: getattr(settings, name) for name in RULES}
    doc["toggle_actions"] = list(settings.toggle_actions)
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
