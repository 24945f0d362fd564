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
    """Base class of every game event. ``causes`` names a field whose value is counted beside
    the kind, as ``"kind:value"`` in ``game.cause_counts`` (the replay summary's ``causes``)."""

    kind: ClassVar[str] = "event"
    causes: ClassVar[str | None] = None


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
class ShotFired(Event):
    """The gun fired a bullet.

    Attributes
    ----------
    entity : int
        The bullet's entity id.
    w : float
        The player's w at firing: the centre of the bullet's w oscillation.
    """

    kind: ClassVar[str] = "shot_fired"
    entity: int
    w: float


@dataclass(frozen=True)
class BulletHit(Event):
    """A bullet touched something: its first contact, and every new touch of a body or target.

    Attributes
    ----------
    entity : int
        The bullet's entity id.
    what : str
        ``"world"`` (floors, walls), ``"body"``, ``"bullet"`` or ``"target"``.
    other : int or None
        The entity hit, None for the world.
    """

    kind: ClassVar[str] = "bullet_hit"
    entity: int
    what: str
    other: int | None


@dataclass(frozen=True)
class Blast(Event):
    """The blast pulled every 4D object within its radius towards the player's w.

    Attributes
    ----------
    w : float
        The player's w: where the objects are brought.
    moved : tuple of int
        Entity ids pulled.
    """

    kind: ClassVar[str] = "blast"
    w: float
    moved: tuple


@dataclass(frozen=True)
class FieldCast(Event):
    """The field turned every 4D object within its radius to a glowing wireframe.

    Attributes
    ----------
    shown : tuple of int
        Entity ids drawn as wireframes.
    ticks : int
        How long, in ticks.
    """

    kind: ClassVar[str] = "field"
    shown: tuple
    ticks: int


@dataclass(frozen=True)
class TargetHit(Event):
    """A bullet hit a target.

    Attributes
    ----------
    entity : int
        The target's entity id.
    bullet : int
        The bullet's entity id.
    opened : str
        Name of the object it removed (its door), or "" when none (or already open).
    """

    kind: ClassVar[str] = "target_hit"
    entity: int
    bullet: int
    opened: str


@dataclass(frozen=True)
class WeaponRefused(Event):
    """The player fired and nothing happened: ``reason`` is ``"energy"``, ``"ammo"`` or ``"cooldown"``.

    Attributes
    ----------
    weapon : str
        The weapon's kind.
    reason : str
    """

    kind: ClassVar[str] = "weapon_refused"
    weapon: str
    reason: str


@dataclass(frozen=True)
class WeaponSelected(Event):
    """The player switched weapons; ``slot`` counts from 0 in the level's order."""

    kind: ClassVar[str] = "weapon_selected"
    slot: int
    weapon: str


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
class EnemyHit(Event):
    """A bullet hit an enemy.

    Attributes
    ----------
    entity : int
        The enemy's entity id.
    bullet : int
        The bullet's entity id (spent by the hit).
    damage : int
        Health it took: 0 when it struck the armoured body of an enemy that can only be
        hurt at its weak spot.
    weak_spot : bool
        The bullet hit the weak spot (at its own w).
    """

    kind: ClassVar[str] = "enemy_hit"
    entity: int
    bullet: int
    damage: int
    weak_spot: bool


@dataclass(frozen=True)
class EnemyDefeated(Event):
    """An enemy's health reached zero (its body bursts and goes).

    Attributes
    ----------
    entity : int
    name : str
    opened : str
        The ``[[object]]`` its defeat removed, or "".
    """

    kind: ClassVar[str] = "enemy_defeated"
    entity: int
    name: str
    opened: str


@dataclass(frozen=True)
class PlayerHit(Event):
    """An enemy's shot hit the player.

    Attributes
    ----------
    damage : float
        Health taken.
    direction : tuple of float
        Unit ``(x, z)`` from the player towards where the shot came from (the HUD's cue).
    source : int
        The enemy's entity id.
    """

    kind: ClassVar[str] = "player_hit"
    damage: float
    direction: tuple
    source: int


@dataclass(frozen=True)
class PlayerDied(Event):
    """The player's health reached zero; they come back at ``checkpoint`` ("" for the spawn point)."""

    kind: ClassVar[str] = "player_died"
    checkpoint: str


@dataclass(frozen=True)
class LootReleased(Event):
    """A crystal hidden in an enemy came out: ``crystal`` is the new crystal's entity id and
    ``reason`` is ``"defeated"``, ``"forced"`` (a blast moved the enemy so the crystal's w crossed the
    slice) or ``"camera"`` (the switch to the frustum view held the enemy, ahead of the player and
    within 12 m, and dragged it so the crystal's w crossed the slice: see
    :func:`..systems.enemies._frustum_holds` for the rule)."""

    kind: ClassVar[str] = "loot_released"
    causes: ClassVar[str | None] = "reason"
    entity: int
    crystal: int
    reason: str


@dataclass(frozen=True)
class SlabKnocked(Event):
    """A bullet knocked a hidden slab so that it turns through the slice (the paper's physics
    figure): a box-shaped rigid body whose w extent did not reach the player's slice when the
    bullet first touched it, left turning in the xw, yw or zw plane faster than
    :data:`..systems.bullets.KNOCK_SPIN`. From then on the bullet is an ordinary body: it falls
    and rolls away.

    Attributes
    ----------
    entity : int
        The slab's entity id.
    bullet : int
        The bullet's entity id.
    spin : tuple of float
        The slab's angular velocity in the t, u, v planes (``xw``, ``yw``, ``zw``), rad/s,
        after the impact.
    """

    kind: ClassVar[str] = "slab_knocked"
    entity: int
    bullet: int
    spin: tuple


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
class CheckpointReached(Event):
    """The player touched a checkpoint: dying now brings them back there."""

    kind: ClassVar[str] = "checkpoint_reached"
    name: str


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
class SliceAligned(Event):
    """A 90-degree step or a snap of the slice landed exactly on the axes.

    Attributes
    ----------
    angles : tuple of float
        The slice's x, y and z axes' angles towards w, degrees (multiples of 90).
    """

    kind: ClassVar[str] = "slice_aligned"
    angles: tuple


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
