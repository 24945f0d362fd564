"""The level's hints, shown one at a time until the player does what each one asks.

A level's ``hints`` are plain strings (``levels/README.md``); their ``{action}`` placeholders say
both which keys to show (the window fills in the player's own bindings) and what the hint asks
for. A hint is *done* when the player performs any action it names while it is on screen:

* a held input (walking, moving along w, jumping, holding fire) counts once it has been held for
  :data:`HOLD_SECONDS` in total while the hint shows, so "hold {w_ana}" is done by holding, not by
  brushing the key;
* a one-shot action (fire, switch weapon, seek, manipulate, ...) counts on its first press.

A hint that names no action asks only to be read: it is done after its reading time
(:func:`reading_seconds`). Any hint is also done when dismissed (the ``hints`` key). With no hint
on screen the same key shows the level's hints again, from the first, each for its reading time
or until dismissed.

This is presentation state, like the window's notices: it never touches the simulation, so
replays and state hashes are unaffected. It reads the same :class:`~.actions.Actions` frames the
simulation gets, one per tick, so it is tested headless.
"""

from __future__ import annotations

import string
from dataclasses import dataclass, field

from .actions import PRESSES, Actions

#: Seconds an input must be held (in total, while the hint shows) to count as done: long enough
#: that the player saw what it does, short enough not to feel like a chore.
HOLD_SECONDS = 0.5
#: Reading time of a hint without an action: a base plus a time per character (a slow reader's
#: 15 characters per second).
READ_BASE_SECONDS = 2.5
READ_SECONDS_PER_CHAR = 1.0 / 15.0

#: How each action shows in an :class:`Actions` frame: held inputs as a predicate on the frame.
_HELD = {
    "move_forward": lambda a: a.forward > 0,
    "move_back": lambda a: a.forward < 0,
    "strafe_right": lambda a: a.right > 0,
    "strafe_left": lambda a: a.right < 0,
    "w_ana": lambda a: a.w > 0,
    "w_kata": lambda a: a.w < 0,
    "jump": lambda a: a.jump,
    "fire": lambda a: a.fire,
    "alt_fire": lambda a: a.alt_fire,
    "manipulate": lambda a: a.manipulate,
    "switch_camera": lambda a: a.switch_camera,
}


def placeholders(text: str) -> tuple[str, ...]:
    """The ``{names}`` in a hint, in order (``{{`` and ``}}`` are literal braces, not names)."""
    try:
        return tuple(name for _, name, _, _ in string.Formatter().parse(text) if name)
    except ValueError:  # a stray brace: the level check reports it; here it simply names nothing
        return ()


def reading_seconds(text: str) -> float:
    """Seconds a hint without an action stays on screen."""
    return READ_BASE_SECONDS + READ_SECONDS_PER_CHAR * len(text)


@dataclass
class Hint:
    """One hint and how far the player is with it."""

    text: str
    asks: tuple[str, ...]
    shown: float = 0.0  # seconds on screen so far
    held: float = 0.0  # seconds of holding an asked-for input while on screen
    done: bool = False


@dataclass
class HintBook:
    """A level's hints as the player works through them.

    Parameters
    ----------
    texts : list of str
        The level's hints, with their ``{action}`` placeholders unfilled.

    Notes
    -----
    Call :meth:`tick` once per simulated tick with that tick's actions, :meth:`note` when the
    player presses a key for an action that never reaches the simulation (toggle the radar,
    take a screenshot ...), and :meth:`toggle` for the ``hints`` key. :meth:`current` is what to
    show.
    """

    texts: list[str]
    hints: list[Hint] = field(init=False)
    reviewing: bool = False

    def __post_init__(self) -> None:
        self.texts = list(self.texts)
        self.hints = [Hint(t, placeholders(t)) for t in self.texts]

    def current(self) -> Hint | None:
        """The hint on screen, or None when every hint is done."""
        return next((h for h in self.hints if not h.done), None)

    def current_index(self) -> int:
        """Index of the hint on screen in the level's list, -1 when none."""
        return next((i for i, h in enumerate(self.hints) if not h.done), -1)

    def tick(self, actions: Actions, dt: float) -> None:
        """One simulated tick of ``dt`` seconds passed with ``actions`` as the player's input."""
        h = self.current()
        if h is None:
            return
        h.shown += dt
        if not h.asks or self.reviewing:
            if h.shown >= reading_seconds(h.text):
                h.done = True
            if h.asks and self.reviewing and self._performed(h, actions, dt):
                h.done = True
            return
        if self._performed(h, actions, dt):
            h.done = True

    def _performed(self, h: Hint, actions: Actions, dt: float) -> bool:
        if any(actions.pressed(a) for a in h.asks):
            return True
        if any(_HELD[a](actions) for a in h.asks if a in _HELD):
            h.held += dt
        return h.held >= HOLD_SECONDS - 1e-9  # 1e-9: whole ticks of 1/60 s add up to 0.5 s in floating point

    def note(self, action: str) -> None:
        """The player pressed the key of ``action``; counts only for actions the simulation does not
        see (the others are judged by :meth:`tick`, so a tap is not taken for a hold)."""
        if action in _HELD or action in PRESSES:
            return
        h = self.current()
        if h is not None and action in h.asks:
            h.done = True

    def toggle(self) -> None:
        """The ``hints`` key: dismiss the hint on screen, or with none, show them all again."""
        h = self.current()
        if h is not None:
            h.done = True
        elif self.hints:
            self.hints = [Hint(t, placeholders(t)) for t in self.texts]
            self.reviewing = True

    def remaining(self) -> int:
        """Hints not done yet, the one on screen included."""
        return sum(not h.done for h in self.hints)
