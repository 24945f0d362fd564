"""What the window shows a new player: hints, the flat-being card, and the settings warning line.

* Hints (:class:`~across_dimensions.game.hints.HintBook`) stay on screen, in their own panel,
  until the player does what each asks (the level state a hint's ``until`` names, or the action it
  names) or dismisses it with the ``hints`` key; the same key shows
  them again. The window's notices and the game's prompts never replace them.
* Before the first move along w in a session, the ``"flatland"`` card (drawn by
  :mod:`across_dimensions.render.cards`) stops the game and teaches the idea with the
  lower-dimensional analogy; any key or click closes it, and the move then goes ahead.
  A window recording to a file given on the command line skips the card, so a scripted
  recording starts as the level does.
* Settings warnings are one line at the bottom for :data:`WARNING_SECONDS`; their details are in
  the log file (:func:`~.settings_log.report_warnings`).
"""

from __future__ import annotations

import string

from ..game.frame import Card, Hud
from ..game.hints import HintBook

#: Seconds the settings warning line stays.
WARNING_SECONDS = 15.0
#: Seconds a hint stays ticked off (with a check mark) after the player did what it asked.
DONE_SECONDS = 0.8
#: Keys that close the card besides a click (the ``hints`` and ``jump`` actions close it too).
CARD_KEYS = ("RETURN", "SPACE", "ESCAPE")

FLATLAND_LINES = (
    "You are the flat being of a 4D world",
    "What is there: a ball passes through the plane",
    "What the flat being sees: only a circle",
    "A flat being lives in a plane and sees only what lies in it. A ball passing through its plane"
    " looks to it like a circle that appears, grows, shrinks and vanishes; the rest of the ball is"
    " out of its world.",
    "Your world is a 3D slice of a 4D one. {w_ana} and {w_kata} slide your slice along w: 4D things"
    " change shape, walls appear and fade, and whatever is off your slice is out of sight (the radar"
    " and the ghosts show where).",
    "Press {jump} or Enter, or click, to start",
)


#: How key names read in hints (anything else: letters and F-keys as they are, others capitalized).
KEY_LABELS = {
    "MOUSE_LEFT": "left click",
    "MOUSE_RIGHT": "right click",
    "MOUSE_MIDDLE": "middle click",
    "MOUSE_4": "mouse button 4",
    "MOUSE_5": "mouse button 5",
    "MOUSE_WHEEL_UP": "wheel up",
    "MOUSE_WHEEL_DOWN": "wheel down",
    "SPACE": "Space",
    "RETURN": "Enter",
    "ESCAPE": "Esc",
    "TAB": "Tab",
    "BACKSPACE": "Backspace",
    "LSHIFT": "Left Shift",
    "RSHIFT": "Right Shift",
    "LCTRL": "Left Ctrl",
    "RCTRL": "Right Ctrl",
    "LALT": "Left Alt",
    "RALT": "Right Alt",
    "UP": "Up",
    "DOWN": "Down",
    "LEFT": "Left",
    "RIGHT": "Right",
}


def key_label(name: str) -> str:
    """A settings key name as a player reads it: ``"_1"`` -> ``"1"``, ``"MOUSE_LEFT"`` -> ``"left click"``."""
    if name in KEY_LABELS:
        return KEY_LABELS[name]
    if name.startswith("_") and name[1:].isdigit():
        return name[1:]
    if name.startswith("NUM_"):
        return "keypad " + name[4:].lower()
    if len(name) == 1 or (name[0] == "F" and name[1:].isdigit()):
        return name
    return name.capitalize()


def fill_keys(text: str, settings) -> str:
    """A hint with each ``{action}`` replaced by the player's keys for it, in words: ``"E"``,
    ``"R or wheel down"``; an action with no key reads ``"(unbound)"``, an unknown name stays as
    written, and a malformed hint is shown as it is."""

    class _Keys(dict):
        def __missing__(self, key):
            return "{" + key + "}"

    keys = _Keys({a: " or ".join(key_label(k) for k in settings.keys_for(a)) or "(unbound)" for a in settings.bindings})
    try:
        return string.Formatter().vformat(text, (), keys)
    except (ValueError, IndexError, KeyError):
        return text


def with_keys(text: str, settings) -> str:
    """``text`` with each ``{action}`` replaced by the keys bound to it, short (``"W/UP"``): the
    game's prompts and the labels beside things, where room is scarce (hints use :func:`fill_keys`'s
    words). Unknown names and stray braces stay as written."""

    class _Keys(dict):
        def __missing__(self, key):
            return "{" + key + "}"

    keys = {
        a: "/".join(
            k.replace("MOUSE_", "mouse ").lower() if k.startswith("MOUSE_") else k.lstrip("_")
            for k in settings.keys_for(a)
        )
        or "(unbound)"
        for a in settings.bindings
    }
    try:
        return text.format_map(_Keys(keys))
    except (ValueError, IndexError):  # a stray brace in a game prompt: show it as written
        return text


class Onboarding:
    """Hints, the card and the warning line of one window.

    Parameters
    ----------
    warning : str
        The settings warning line, or ``""``.
    card : bool
        Whether the flat-being card may be shown this session.
    """

    def __init__(self, warning: str = "", card: bool = True):
        self.warning = warning
        self.warning_left = WARNING_SECONDS if warning else 0.0
        self.card_allowed = card
        self.card_time: float | None = None  # seconds the card has been open, None when closed
        self.book = HintBook([])
        self.hints_on = True  # False in the editor's play-from-here
        self.done_flash: tuple[str, float] | None = None  # (hint text, seconds left) just done by the player
        self.ui_cues: list[str] = []  # menu sounds to play (app.sound effect names), taken by the window

    # ----------------------------------------------------------------- events
    def level_started(self, hints) -> None:
        self.book = HintBook(list(hints))

    @property
    def blocking(self) -> bool:
        """The card is open: the game waits."""
        return self.card_time is not None

    def before_tick(self, moving_along_w: bool) -> bool:
        """Called before each tick; opens the card on the session's first push along w.

        Returns True when the game must not step (the card is open).
        """
        if moving_along_w and self.card_allowed:
            self.card_allowed = False
            self.card_time = 0.0
            self.ui_cues.append("menu_select")
        return self.blocking

    def ticked(self, actions, dt: float, game=None) -> None:
        """A tick was simulated with ``actions``; ``game`` is the state after it (the hints that
        wait for an outcome read it)."""
        if self.hints_on:
            before = self.book.current()
            self.book.tick(actions, dt, game)
            finished = game is not None and game.event_counts.get("level_complete", 0) > 0
            if finished:
                self.done_flash = None  # the level's end closes the hints: no tick mark over "Level complete"
            elif before is not None and before.done and (before.asks or before.until) and not self.book.reviewing:
                self.done_flash = (before.text, DONE_SECONDS)  # done by doing it: tick it off visibly

    def wall(self, dt: float) -> None:
        """``dt`` seconds of wall time passed (animations, the warning's time)."""
        if self.card_time is not None:
            self.card_time += dt
        if self.done_flash is not None:
            text, left = self.done_flash
            self.done_flash = (text, left - dt) if left > dt else None
        self.warning_left = max(0.0, self.warning_left - dt)

    def key(self, action: str | None, key_name: str = "") -> bool:
        """A key went down (``action`` it is bound to, if any). True when it was used here."""
        if action in ("screenshot", "toggle_fullscreen", "toggle_mute"):
            return False  # these work over the card too
        if self.card_time is not None:
            if action in ("hints", "jump", "pause") or key_name in CARD_KEYS or action is None:
                self.card_time = None
                self.ui_cues.append("menu_select")
            return True  # the card swallows every key while open
        if action == "hints":
            self.done_flash = None
            self.book.toggle()
            self.ui_cues.append("menu_move")
            return True
        if action is not None:
            self.book.note(action)
        return False

    def click(self) -> bool:
        """A mouse button went down; True when it closed the card."""
        if self.card_time is not None:
            self.card_time = None
            self.ui_cues.append("menu_select")
            return True
        return False

    def take_ui_cues(self) -> list[str]:
        """The menu sounds asked for since the last call."""
        cues, self.ui_cues = self.ui_cues, []
        return cues

    # ---------------------------------------------------------------- drawing
    def decorate(self, hud: Hud, with_keys) -> None:
        """Fill ``hud``'s hint, warning and card fields; ``with_keys(text)`` fills in the player's keys."""
        h = self.book.current() if self.hints_on else None
        if self.done_flash is not None and self.hints_on:
            hud.hint = "\u2713 " + with_keys(self.done_flash[0])
            hud.hint_label = "Done"
        elif h is not None:
            hud.hint = with_keys(h.text)
            i, n = self.book.current_index() + 1, len(self.book.hints)
            hud.hint_label = f"Hint {i}/{n} \u00b7 {with_keys('{hints}')} hides"
        if self.warning and self.warning_left > 0:
            hud.warning = self.warning
        if self.card_time is not None:
            hud.card = Card("flatland", self.card_time, tuple(with_keys(t) for t in FLATLAND_LINES))
