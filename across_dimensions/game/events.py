"""Game events: what happened in a tick, as typed records.

Systems report what happens with ``game.emit(SomeEvent(...))``. ``game.events``
holds the events of the last tick in the order they happened, and
``game.event_counts`` counts every kind since the start (the replay summary
prints it). The HUD, sound, tests and tools read these instead of poking at
system internals, and because systems run in a fixed order on a fixed tick,
the list is the same on every run of a replay.

Adding an event kind: a frozen dataclass deriving from :class:`Event` with a
``kind`` class attribute in snake_case. Kinds are part of the replay summary's
contract (``across-dimensions replay --json``): never rename one.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar


@dataclass(frozen=True)
class Event:
    """Base class of every game event."""

    kind: ClassVar[str] = "event"


def event_kinds() -> list[str]:
    """Every event kind defined so far (subclasses of :class:`Event` anywhere), sorted."""
    found, todo = set(), [Event]
    while todo:
        for sub in todo.pop().__subclasses__():
            found.add(sub.kind)
            todo.append(sub)
    return sorted(found)


@dataclass(frozen=True)
class CrystalCollected(Event):
    """The player touched a crystal's cross-section and took it.

    Attributes
    ----------
    entity : int
        The crystal's entity id (removed in the same tick).
    milli : int
        Energy it held, in thousandths of a unit.
    gained_milli : int
        Energy actually added: less than ``milli`` when the bar was nearly full.
    """

    kind: ClassVar[str] = "crystal_collected"
    entity: int
    milli: int
    gained_milli: int


@dataclass(frozen=True)
class EnergySpent(Event):
    """Energy paid for an action (``reason``: ``"w_move"``, later ``"fire"``, ...).

    Attributes
    ----------
    milli : int
        Thousandths of a unit; always positive.
    reason : str
    """

    kind: ClassVar[str] = "energy_spent"
    milli: int
    reason: str


@dataclass(frozen=True)
class EnergyEmpty(Event):
    """The bar reached zero. Fires once per emptying, not on every tick at zero."""

    kind: ClassVar[str] = "energy_empty"


@dataclass(frozen=True)
class WBlocked(Event):
    """The player pushed along w and could not move.

    Fires on the first tick of a blocked push, not on every tick it is held.

    Attributes
    ----------
    reason : str
        ``"wall"`` (a wall would appear around the player), ``"body"`` (a rigid
        body is there), ``"energy"`` (the bar is empty) or ``"range"`` (the end
        of the level's w range).
    direction : int
        +1 ana, -1 kata.
    """

    kind: ClassVar[str] = "w_blocked"
    reason: str
    direction: int


@dataclass(frozen=True)
class Contact(Event):
    """Two rigid bodies, or a body and the static world, started touching.

    Attributes
    ----------
    entity : int
        Entity of the first body.
    other : int or None
        Entity of the second body, or None for the static world.
    impulse : float
        Normal impulse over the tick, N s.
    """

    kind: ClassVar[str] = "contact"
    entity: int
    other: int | None
    impulse: float


@dataclass(frozen=True)
class Respawned(Event):
    """The player fell out of the level and was put back at the spawn point."""

    kind: ClassVar[str] = "respawned"


@dataclass(frozen=True)
class LevelComplete(Event):
    """The player reached the goal."""

    kind: ClassVar[str] = "level_complete"


@dataclass(frozen=True)
class SeekStarted(Event):
    """A seek press chose a thing to move to along w.

    Attributes
    ----------
    entity : int
        The thing's entity id, or -1 for the goal.
    w : float
        The w the seek heads for (inside the level's w range).
    """

    kind: ClassVar[str] = "seek_started"
    entity: int
    w: float


@dataclass(frozen=True)
class SeekArrived(Event):
    """A seek landed exactly on its thing's w (``entity`` -1: the goal)."""

    kind: ClassVar[str] = "seek_arrived"
    entity: int
    w: float


@dataclass(frozen=True)
class SeekBlocked(Event):
    """A seek stopped short at ``w``, the nearest reachable w; ``reason`` as in :class:`WBlocked`."""

    kind: ClassVar[str] = "seek_blocked"
    reason: str
    w: float
