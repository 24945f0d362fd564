"""The energy bar: crystal energy that pays for 4D actions.

Crystals fill it; moving along w (and later firing, manipulating and switching
camera) drains it. Every system pays through :meth:`EnergyBar.spend` or
:meth:`EnergyBar.spend_up_to` and every gain goes through :meth:`EnergyBar.gain`,
so the bar is the one account and each change is an event.

Energy is counted in integer thousandths of a unit ("milli"), not floats: sums
of float amounts depend on their order, and the game promises exact
accounting (start + everything gained - everything spent == the bar, to the
last digit, whatever the run). The value shown to the player is ``milli / 1000``.
"""

from __future__ import annotations

from dataclasses import dataclass

from .events import EnergyEmpty, EnergySpent
from .system import fixed

MILLI = 1000
FLASH_TICKS = 30  # how long the bar flashes after a pickup (half a second at 60 Hz)


def to_milli(amount: float) -> int:
    """Energy units to thousandths, rounded to nearest."""
    return int(round(amount * MILLI))


@dataclass
class EnergyBar:
    """The player's energy (the energy system's state, ``game.energy``).

    Parameters
    ----------
    milli : int
        Current value in thousandths; ``0 <= milli <= maximum_milli``.
    maximum_milli : int
    flash : int
        Ticks of pickup flash left (for the HUD).
    """

    milli: int
    maximum_milli: int = fixed()
    flash: int = 0
    _announced_empty: bool = False
    low_milli: int = -1  # lowest and highest value so far (the replay summary reports them)
    high_milli: int = -1

    def __post_init__(self):
        if self.low_milli < 0:
            self.low_milli = self.high_milli = self.milli

    @classmethod
    def of(cls, start: float, maximum: float) -> EnergyBar:
        m = to_milli(maximum)
        return cls(min(max(to_milli(start), 0), m), m, _announced_empty=to_milli(start) <= 0)

    @property
    def value(self) -> float:
        return self.milli / MILLI

    @property
    def maximum(self) -> float:
        return self.maximum_milli / MILLI

    def tick(self) -> None:
        """Start of a tick: fade the pickup flash."""
        self.flash = max(0, self.flash - 1)

    def gain(self, milli: int) -> int:
        """Add up to ``milli`` (capped at the maximum); returns what was added."""
        added = max(0, min(milli, self.maximum_milli - self.milli))
        self.milli += added
        self.high_milli = max(self.high_milli, self.milli)
        if added > 0:
            self._announced_empty = False
        self.flash = FLASH_TICKS
        return added

    def spend(self, game, milli: int, reason: str) -> bool:
        """Pay ``milli`` in full, or nothing: True when paid."""
        if milli <= 0:
            return True
        if milli > self.milli:
            return False
        self._pay(game, milli, reason)
        return True

    def spend_up_to(self, game, milli: int, reason: str) -> int:
        """Pay as much of ``milli`` as the bar holds; returns what was paid (continuous costs)."""
        paid = max(0, min(milli, self.milli))
        if paid > 0:
            self._pay(game, paid, reason)
        return paid

    def _pay(self, game, milli: int, reason: str) -> None:
        self.milli -= milli
        self.low_milli = min(self.low_milli, self.milli)
        game.emit(EnergySpent(milli, reason))
        if self.milli == 0 and not self._announced_empty:
            self._announced_empty = True
            game.emit(EnergyEmpty())
