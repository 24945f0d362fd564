"""Events of the player and the level: crystals and energy, moves along w, contacts and
respawns, checkpoints, secrets, the camera and the slice."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from .base import Event


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
class CheckpointReached(Event):
    """The player touched a checkpoint: dying now brings them back there."""

    kind: ClassVar[str] = "checkpoint_reached"
    name: str


@dataclass(frozen=True)
class SecretFound(Event):
    """The player stepped into a ``[[secret]]``'s volume for the first time.

    Attributes
    ----------
    name : str
        The secret's name in the level.
    found, total : int
        How many of the level's secrets are found now (this one included), and how many it has.
    """

    kind: ClassVar[str] = "secret_found"
    name: str
    found: int
    total: int


@dataclass(frozen=True)
class CameraSwitched(Event):
    """The 4D camera changed mode.

    Attributes
    ----------
    mode : str
        The new mode: ``"frustum"`` (detached), ``"returning"`` (gliding back) or
        ``"synced"`` (cross-section again).
    reason : str
        ``"key"`` (the switch key), ``"energy"`` (the bar ran dry) or ``"arrived"``
        (the glide back ended).
    """

    kind: ClassVar[str] = "camera_switched"
    mode: str
    reason: str


@dataclass(frozen=True)
class EnteredFrustumObject(Event):
    """While the frustum view holds, the player's box came to touch the bounds of the image of an
    object the level marks ``walkable_in_frustum`` (stepped onto or into it, :mod:`..frustum_walk`).
    Fires once per entry: again only after the player left its bounds or the view ended.

    Attributes
    ----------
    entity : int
        The object's entity id.
    name : str
        Its name in the level.
    """

    kind: ClassVar[str] = "entered_frustum_object"
    entity: int
    name: str


@dataclass(frozen=True)
class MovedToSafety(Event):
    """The frustum view ended with the player inside geometry (they stood in an image where the
    cross-section has a wall): they were put at the nearest free spot (:func:`..frustum_walk.safe_spot`),
    or back at their last checkpoint when none was free.

    Attributes
    ----------
    position : tuple of float
        Where they stand now, ``(x, y, z, w)``.
    """

    kind: ClassVar[str] = "moved_to_safety"
    position: tuple


@dataclass(frozen=True)
class SliceTurnRefused(Event):
    """A turn of the slice towards the world's w axis was refused: the player's eye stands at a
    world w outside the level's w range (walked there along a turned slice). Fires on the first
    tick of a refused turn, not on every tick it is held.

    Attributes
    ----------
    w : float
        The eye's world w.
    low, high : float
        The level's w range.
    """

    kind: ClassVar[str] = "slice_turn_refused"
    w: float
    low: float
    high: float


@dataclass(frozen=True)
class SliceTurnUnpaid(Event):
    """A turn of the slice was refused or stopped short because the energy bar could not pay
    for it (``[energy] slice_cost``). Fires on the first tick of a cut turn, not on every tick.

    Attributes
    ----------
    need : int
        What a 90-degree step costs, thousandths.
    have : int
        What the bar held, thousandths.
    """

    kind: ClassVar[str] = "slice_turn_unpaid"
    need: int
    have: int


@dataclass(frozen=True)
class SliceAligned(Event):
    """A 90-degree step or a snap of the slice landed exactly on the axes.

    Attributes
    ----------
    angles : tuple of float
        The slice's x, y and z axes' angles towards w, degrees (multiples of 90).
    """

    kind: ClassVar[str] = "slice_aligned"
    angles: tuple
