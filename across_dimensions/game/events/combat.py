"""Events of weapons and enemies: shots, hits, blasts and fields, weapons taken, enemies hit
and defeated, loot released, slabs knocked."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from .base import Event


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
class WeaponAcquired(Event):
    """The player walked into a ``[[pickup]]`` and owns its weapon from now on (and in every later
    level of the campaign); it is taken in hand.

    Attributes
    ----------
    entity : int
        The pickup's entity id (removed in the same tick).
    weapon : str
        The weapon's kind.
    """

    kind: ClassVar[str] = "weapon_acquired"
    entity: int
    weapon: str


@dataclass(frozen=True)
class WeaponSelected(Event):
    """The player switched weapons; ``slot`` counts from 0 among the weapons a run of the level can
    have (``level.weapons``)."""

    kind: ClassVar[str] = "weapon_selected"
    slot: int
    weapon: str


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
