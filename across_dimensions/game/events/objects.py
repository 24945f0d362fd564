"""Events of 4D objects: manipulation, seeking a w, and objects returned to their start."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from .base import Event


@dataclass(frozen=True)
class ManipulationStarted(Event):
    """The player grabbed a manipulable 4D object with the manipulation tool.

    Attributes
    ----------
    entity : int
    """

    kind: ClassVar[str] = "manipulation_started"
    entity: int


@dataclass(frozen=True)
class Manipulated(Event):
    """A turn of a held object in one plane settled (the key was let go, a snap finished, a limit was hit).

    Attributes
    ----------
    entity : int
    plane : str
        One of ``xy xz yz xw yw zw``.
    angle_deg : float
        The object's rotation in that plane now, degrees.
    offset_deg : float
        How far it is turned from the level's rotation, degrees.
    """

    kind: ClassVar[str] = "manipulated"
    entity: int
    plane: str
    angle_deg: float
    offset_deg: float


@dataclass(frozen=True)
class ManipulationEnded(Event):
    """The player let go of the held object.

    Attributes
    ----------
    entity : int
    """

    kind: ClassVar[str] = "manipulation_ended"
    entity: int


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


@dataclass(frozen=True)
class ObjectReset(Event):
    """A key object stayed out of its beacon's range and was put back at its start.

    Attributes
    ----------
    name : str
        The object's name in the level.
    """

    kind: ClassVar[str] = "object_reset"
    name: str
