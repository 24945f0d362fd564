"""Keys, mouse buttons and the wheel to actions: the bindings, and what play reads at each tick.

Settings name keys as strings (``"SPACE"``, ``"MOUSE_4"``, ``"MOUSE_WHEEL_UP"``); pyglet has codes.
:class:`Bindings` maps one to the other for every action. :class:`PlayInput` gathers what happens
between two ticks and turns it into the next tick's :class:`~across_dimensions.game.actions.Actions`:

- held actions (walking, jump, w, the slice turns, the orbit, manipulation) are read from the keys
  and buttons down at the tick, and a press that began and ended between two ticks counts as held
  for that one tick: a tap shorter than a frame still jumps, steps or grabs, even at 5 FPS;
- one-shot actions (:data:`~across_dimensions.game.actions.PRESSES`) are counted, so two taps
  between two ticks are two;
- an action the player set to toggle (settings ``toggle_actions``: w moves, manipulation, the
  orbit, the slice turns) is held from one press to the next instead of while its key is down;
- the player's "reduce motion" setting is a flag of every tick's actions (replays record it);
- the mouse's motion since the last tick is that tick's look.
"""

from __future__ import annotations

import functools

import pyglet

from ..game.actions import CAMERA_BUTTONS, MAX_PRESSES, PRESSES, Actions
from ..game.frame import ScreenLabel
from .keymap import KEY_NAMES, TOGGLE_PAIRS, TOGGLEABLE_ACTIONS
from .settings import Settings

_MOUSE = {
    "MOUSE_LEFT": "LEFT",
    "MOUSE_MIDDLE": "MIDDLE",
    "MOUSE_RIGHT": "RIGHT",
    "MOUSE_4": "MOUSE4",
    "MOUSE_5": "MOUSE5",
}
#: One-shot actions read only as counts: a tap of one reaches the game as its press, never as
#: held. ``manipulate`` is not among them: it is counted, and held it grabs, so a tap grabs for a tick.
COUNTED_ONLY = frozenset(PRESSES) - {"manipulate"}
#: Each action a press may toggle instead of holding (settings ``toggle_actions``) with
#: its opposite, which switching it on lets go of.
OPPOSITE = {a: b for a, b in TOGGLE_PAIRS} | {b: a for a, b in TOGGLE_PAIRS}


def key_name(kind: str, code) -> str | None:
    """The settings name of a pyglet key (``kind`` ``"key"``), mouse button (``"mouse"``) or wheel
    direction (``"wheel"``, code +1 or -1); None when it has none."""
    if kind == "wheel":
        return "MOUSE_WHEEL_UP" if code > 0 else "MOUSE_WHEEL_DOWN"
    if kind == "mouse":
        return next((n for n, attr in _MOUSE.items() if getattr(pyglet.window.mouse, attr) == code), None)
    return _key_names_by_code().get(code)


@functools.cache
def _key_names_by_code() -> dict[int, str]:
    """pyglet key code -> the settings' name for it (pyglet has aliases: RETURN is ENTER, GRAVE is
    QUOTELEFT). Built on first use: ``pyglet.window`` needs a display the moment it is imported."""
    return {getattr(pyglet.window.key, n): n for n in sorted(KEY_NAMES) if not n.startswith("MOUSE_")}


def key_code(name: str) -> tuple[str, int]:
    """pyglet code for a settings key name: ``("key", code)``, ``("mouse", button)`` or ``("wheel", +1 | -1)``."""
    if name in ("MOUSE_WHEEL_UP", "MOUSE_WHEEL_DOWN"):
        return "wheel", 1 if name.endswith("UP") else -1
    if name.startswith("MOUSE_"):
        return "mouse", getattr(pyglet.window.mouse, _MOUSE[name])
    return "key", getattr(pyglet.window.key, name)


def with_keys(text: str, settings: Settings) -> str:
    """``text`` with each ``{action}`` replaced by the keys bound to it (``"W/UP"``); unknown names
    and stray braces stay as written."""
    keys = {
        a: "/".join(
            k.replace("MOUSE_", "mouse ").lower() if k.startswith("MOUSE_") else k.lstrip("_")
            for k in settings.keys_for(a)
        )
        or "(unbound)"
        for a in settings.bindings
    }
    try:
        return text.format_map(_Missing(keys))
    except (ValueError, IndexError):  # a stray brace in a game prompt: show it as written
        return text


class _Missing(dict):
    """format_map helper: unknown ``{names}`` stay as written."""

    def __missing__(self, key):
        return "{" + key + "}"


class Bindings:
    """Each action's pyglet codes, from the settings; :meth:`update` after the settings change."""

    def __init__(self, settings: Settings):
        self.codes: dict[str, list[tuple[str, int]]] = {}
        self.update(settings)

    def update(self, settings: Settings) -> None:
        self.codes = {a: [key_code(k) for k in settings.keys_for(a)] for a in settings.bindings}

    def actions_of(self, kind: str, code) -> list[str]:
        """Every action bound to the key, button or wheel direction."""
        return [a for a, codes in self.codes.items() if (kind, code) in codes]

    def action_of(self, kind: str, code) -> str | None:
        """The first action bound to it, or None."""
        return next(iter(self.actions_of(kind, code)), None)

    def keys_of(self, action: str) -> list[int]:
        """The key codes (no buttons, no wheel) bound to ``action``."""
        return [code for kind, code in self.codes.get(action, ()) if kind == "key"]


class PlayInput:
    """What the player did since the last tick, read as that tick's actions.

    Parameters
    ----------
    bindings : Bindings
    keys : pyglet.window.key.KeyStateHandler
        The window's keyboard state (which keys are down now).
    """

    def __init__(self, bindings: Bindings, keys, settings: Settings | None = None):
        self.bindings = bindings
        self.keys = keys
        self.mouse_buttons: set = set()
        self.presses: dict[str, int] = {}  # one-shot actions pressed since the last tick, and how often
        self.tapped: set[str] = set()  # held actions pressed since the last tick (a key, button or wheel notch)
        self.look = [0.0, 0.0]  # radians of yaw and pitch since the last tick
        self.latched: set[str] = set()  # toggle actions switched on
        self.reduce_motion = False
        self.toggle_actions: frozenset[str] = frozenset()
        if settings is not None:
            self.use(settings)

    def use(self, settings: Settings) -> None:
        """Take the settings that change what a tick reads: reduce motion, and the actions a press
        toggles instead of holding (an action no longer toggled lets go)."""
        self.reduce_motion = settings.reduce_motion
        self.toggle_actions = frozenset(settings.toggle_actions)
        self.latched &= self.toggle_actions

    def press(self, kind: str, code, times: int = 1) -> None:
        """A key, mouse button or wheel notch went down: count it for the one-shot actions bound to
        it, and hold the others for at least the next tick (or, for a toggled action, switch it
        on or off; switching one on lets go of its opposite)."""
        for action in self.bindings.actions_of(kind, code):
            if action in PRESSES:
                self.presses[action] = min(self.presses.get(action, 0) + times, MAX_PRESSES)
            if action in self.toggle_actions:
                if times % 2:
                    self.latched ^= {action}
                    self.latched.discard(OPPOSITE.get(action))
            elif action not in COUNTED_ONLY:
                self.tapped.add(action)

    def latched_label(self) -> ScreenLabel:
        """A label at the left of the view naming the toggled actions that are on, and their keys."""
        names = ", ".join(f"{{{a}}} {a.replace('_', ' ')}" for a in TOGGLEABLE_ACTIONS if a in self.latched)
        return ScreenLabel(f"ON: {names}", -10.0, 0.45)

    def mouse_down(self, button) -> None:
        self.mouse_buttons.add(button)
        self.press("mouse", button)

    def mouse_up(self, button) -> None:
        self.mouse_buttons.discard(button)

    def turn(self, dyaw: float, dpitch: float) -> None:
        """The mouse moved: ``dyaw`` and ``dpitch`` radians more for the next tick."""
        self.look[0] += dyaw
        self.look[1] += dpitch

    def held(self, action: str) -> bool:
        """Down now, or pressed since the last tick; for a toggled action, switched on."""
        if action in self.toggle_actions:
            return action in self.latched
        if action in self.tapped:
            return True
        for kind, code in self.bindings.codes.get(action, ()):
            if (kind == "key" and self.keys[code]) or (kind == "mouse" and code in self.mouse_buttons):
                return True
        return False

    def read(self) -> Actions:
        """This tick's actions; what was gathered for it is used up."""
        axis = lambda pos, neg: float(self.held(pos)) - float(self.held(neg))  # noqa: E731
        # clamped(): a replay stores exactly these frames, and Replay.load
        # refuses non-finite or out-of-bound rows (a huge mouse jump, a driver's NaN).
        actions = Actions(
            forward=axis("move_forward", "move_back"),
            right=axis("strafe_right", "strafe_left"),
            yaw=self.look[0],
            pitch=self.look[1],
            w=axis("w_ana", "w_kata"),
            jump=self.held("jump"),
            fire=self.held("fire"),
            alt_fire=self.held("alt_fire"),
            switch_camera=self.held("switch_camera"),
            manipulate=self.held("manipulate"),
            next_weapon=self.held("next_weapon"),
            **{b: self.held(b) for b in CAMERA_BUTTONS},
            reduced_motion=self.reduce_motion,
            presses=Actions.count_presses(self.presses),
        ).clamped()
        self.drop_pending()
        return actions

    def drop_pending(self) -> None:
        """Forget the presses, taps and look gathered for the next tick."""
        self.presses.clear()
        self.tapped.clear()
        self.look = [0.0, 0.0]

    def forget(self) -> None:
        """Forget everything, the buttons down and the toggles on too (play resumes, or another
        view had the input)."""
        self.drop_pending()
        self.mouse_buttons.clear()
        self.latched.clear()
