"""The prologue's hints, each done when the level state it names holds.

A hint of a prologue level says what it waits for (``[[hint]] until``, ``world/flat_level.py``):
the being past an x (``x_min``, ``x_max``), its plane past a z (``z_min``, ``z_max``), or an event
(``event = "item_taken"``); all the conditions given must hold. Pressing a key is never enough:
"hold {w_kata} until the line meets the pin" is done when the key is taken, not when the key is
pressed. A hint whose state already holds when its turn comes is done at once, so the hints
follow a player who runs ahead. A hint without ``until`` stays for its reading time
(:func:`..hints.reading_seconds`).

Like :class:`..hints.HintBook` this is presentation: it reads the game and never changes it, so
replays and state hashes do not depend on it; the ``hints`` key dismisses the hint on screen, or
with none left shows them all again, each for its reading time.
"""

from __future__ import annotations

from ...world.flat_level import HintSpec
from ..hints import reading_seconds


def holds(until: dict, game) -> bool:
    """Whether ``game`` (a :class:`~.sim.FlatGame`) is in the state ``until`` names."""
    x, z = float(game.position[0]), float(game.z)
    checks = {
        "x_min": lambda v: x >= v,
        "x_max": lambda v: x <= v,
        "z_min": lambda v: z >= v,
        "z_max": lambda v: z <= v,
        "event": lambda v: game.event_counts.get(v, 0) > 0,
    }
    return all(checks[k](v) for k, v in until.items())


class StateHints:
    """A prologue level's hints as the player works through them.

    Parameters
    ----------
    specs : list of HintSpec
    """

    def __init__(self, specs: list[HintSpec]):
        self.specs = list(specs)
        self.done = [False] * len(self.specs)
        self.shown = [0.0] * len(self.specs)
        self.reviewing = False

    def current_index(self) -> int:
        """Index of the hint on screen, -1 when none."""
        return next((i for i, d in enumerate(self.done) if not d), -1)

    def current(self) -> HintSpec | None:
        """The hint on screen, or None."""
        i = self.current_index()
        return None if i < 0 else self.specs[i]

    def tick(self, game, dt: float) -> None:
        """One tick of ``dt`` seconds passed; ``game`` is the state after it."""
        i = self.current_index()
        while i >= 0:
            h = self.specs[i]
            self.shown[i] += dt
            read = self.shown[i] >= reading_seconds(h.text)
            if (h.until and not self.reviewing and holds(h.until, game)) or ((self.reviewing or not h.until) and read):
                self.done[i] = True
                i = self.current_index()
                dt = 0.0  # the next hint starts now: a state that already holds ends it too, this tick
                continue
            break

    def toggle(self) -> None:
        """The ``hints`` key: dismiss the hint on screen, or with none, show them all again."""
        i = self.current_index()
        if i >= 0:
            self.done[i] = True
        elif self.specs:
            self.done = [False] * len(self.specs)
            self.shown = [0.0] * len(self.specs)
            self.reviewing = True

    def remaining(self) -> int:
        """Hints not done yet, the one on screen included."""
        return self.done.count(False)
