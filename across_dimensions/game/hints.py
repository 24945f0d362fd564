"""The level's hints, shown one at a time until the player does what each one asks.

A hint that asks for an outcome says which in the level file (``until``, :mod:`..world.hints`):
the crystal taken, the switch's door gone, the barrier passed. It is done when that level state
holds, never by a key press alone; and when the state of a *later* hint already holds, the hints
before it are done too, so they follow a player who runs ahead. The level's end closes them all.

Any other hint's ``{action}`` placeholders say both which keys to show (the window fills in the
player's own bindings) and what the hint asks for. It is *done* when the player performs any
action it names while it is on screen:

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

from ..world.hints import HintSpec
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


def holds(until: dict, game) -> bool:
    """Whether ``game`` (a :class:`~.sim.Game`) is in the state ``until`` names (all of it)."""
    p = game.player.position
    for key, v in until.items():
        if key == "event":
            ok = game.event_counts.get(v, 0) > 0
        elif key == "gone":
            ok = game.entities.named(v) is None
        elif key == "weapon":
            ars = game.states.weapons
            ok = ars is not None and ars.armed and ars.current.kind == v
        else:
            x = float(p["xyzw".index(key[0])])
            ok = x >= v if key.endswith("_min") else x <= v
        if not ok:
            return False
    return True


def reading_seconds(text: str) -> float:
    """Seconds a hint without an action stays on screen."""
    return READ_BASE_SECONDS + READ_SECONDS_PER_CHAR * len(text)


@dataclass
class Hint:
    """One hint and how far the player is with it."""

    text: str
    asks: tuple[str, ...]
    until: dict = field(default_factory=dict)
    shown: float = 0.0  # seconds on screen so far
    held: float = 0.0  # seconds of holding an asked-for input while on screen
    done: bool = False


@dataclass
class HintBook:
    """A level's hints as the player works through them.

    Parameters
    ----------
    texts : list of HintSpec or str
        The level's hints, with their ``{action}`` placeholders unfilled (a string: no ``until``).

    Notes
    -----
    Call :meth:`tick` once per simulated tick with that tick's actions and the game after it, :meth:`note` when the
    player presses a key for an action that never reaches the simulation (toggle the radar,
    take a screenshot ...), and :meth:`toggle` for the ``hints`` key. :meth:`current` is what to
    show.
    """

    texts: list
    hints: list[Hint] = field(init=False)
    reviewing: bool = False

    def __post_init__(self) -> None:
        self.texts = [HintSpec(t) if isinstance(t, str) else t for t in self.texts]
        self.hints = self._fresh()

    def _fresh(self) -> list[Hint]:
        return [Hint(t.text, placeholders(t.text), dict(t.until)) for t in self.texts]

    def current(self) -> Hint | None:
        """The hint on screen, or None when every hint is done."""
        return next((h for h in self.hints if not h.done), None)

    def current_index(self) -> int:
        """Index of the hint on screen in the level's list, -1 when none."""
        return next((i for i, h in enumerate(self.hints) if not h.done), -1)

    def tick(self, actions: Actions, dt: float, game=None) -> None:
        """One simulated tick of ``dt`` seconds passed with ``actions`` as the player's input;
        ``game`` is the state after it (None: only actions and reading times count)."""
        h = self.current()
        if h is None:
            return
        h.shown += dt
        if game is not None and not self.reviewing and self._state_done(game):
            return
        if not h.asks or self.reviewing or h.until:
            if h.shown >= reading_seconds(h.text) and (self.reviewing or not h.until):
                h.done = True
            if h.asks and self.reviewing and self._performed(h, actions, dt):
                h.done = True
            return
        if self._performed(h, actions, dt):
            h.done = True

    def _state_done(self, game) -> bool:
        """Close the hints up to the last whose ``until`` holds (all at the level's end)."""
        if game.event_counts.get("level_complete", 0):
            for h in self.hints:
                h.done = True
            return True
        last = max((i for i, h in enumerate(self.hints) if not h.done and h.until and holds(h.until, game)), default=-1)
        for h in self.hints[: last + 1]:
            h.done = True
        return last >= 0

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
        if h is not None and action in h.asks and not h.until:
            h.done = True

    def toggle(self) -> None:
        """The ``hints`` key: dismiss the hint on screen, or with none, show them all again."""
        h = self.current()
        if h is not None:
            h.done = True
        elif self.hints:
            self.hints = self._fresh()
            self.reviewing = True

    def remaining(self) -> int:
        """Hints not done yet, the one on screen included."""
        return sum(not h.done for h in self.hints)
