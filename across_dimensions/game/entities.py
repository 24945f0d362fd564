"""Entities: everything in a level that lives in 4D and can come and go.

4D objects, rigid bodies, crystals, and later bullets, enemies, targets and the
camera's indicators are all :class:`Entity` records in one
:class:`EntityStore`. An entity has an id, a kind, an optional 4D mesh and a
way to say where it is (its :class:`Motion`), plus kind-specific data. Systems
(``game/systems/``) find the entities they care about by kind and change them;
the drawing and radar systems treat every entity alike.

Ids are integers handed out in increasing order and never reused, so an id
held by a system (a bullet's target, a radar pin) stays valid or becomes
plainly dead when its entity is removed; it can never silently point at a
newcomer. Iteration is in spawn order, so every run visits entities in the same
order and the simulation stays deterministic.

Adding an entity kind: spawn it with a new ``kind`` string and a ``data``
object of your own (a dataclass), give it a radar pin kind from
``game.frame.RADAR_KINDS`` if the player should find it on the radar, and
write the system that gives it behaviour.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.mesh import TetMesh4
from ..core.transform import scaling
from ..world.scene import Object4
from .system import derived, fixed


class Motion:
    """How an entity's object-to-world transform follows time.

    Motions are dataclasses: their fields are state, hashed with the entity, unless marked
    :func:`~.system.fixed` or :func:`~.system.derived` (see :mod:`.system`).
    """

    def model(self, game, alpha: float | None) -> np.ndarray:
        """``(5, 5) float64`` at the current tick, or ``alpha`` of the way from the previous one."""
        raise NotImplementedError

    def center(self, game) -> np.ndarray:
        """Where the entity's origin is now, ``(4,) float64``; cheaper than :meth:`model`."""
        return self.model(game, None)[:4, 4]


@dataclass
class Scripted(Motion):
    """A pose given as a function of simulated time: a level object's pose turned by its spin."""

    obj: Object4 = fixed()

    def model(self, game, alpha=None):
        t = game.time if alpha is None else game.time - (1.0 - alpha) * game.dt
        return self.obj.model_at(t)

    def center(self, game):
        return self.obj.position  # spin turns the object about its origin; it never moves it


@dataclass
class Rigid(Motion):
    """A pose owned by the physics world: a rigid body, drawn scaled by ``scale (4,)``."""

    body: int
    scale: np.ndarray = fixed()

    def model(self, game, alpha=None):
        return game.physics.body_pose(self.body, alpha) @ scaling(self.scale)

    def center(self, game):
        return game.physics.body_position(self.body)


@dataclass
class Placed(Motion):
    """A pose a system sets each tick (bullets, manipulated objects); drawn interpolated.

    ``pose`` and ``previous`` are ``(5, 5) float64``; call :meth:`move` once per tick.
    """

    pose: np.ndarray
    previous: np.ndarray | None = derived(default=None)  # drawing only

    def move(self, pose: np.ndarray) -> None:
        self.previous = self.pose
        self.pose = np.asarray(pose, dtype=np.float64)

    def model(self, game, alpha=None):
        if alpha is None or self.previous is None:
            return self.pose
        # Linear blend of consecutive ticks: close enough for a 1/60 s step, and
        # drawing never feeds back into the simulation.
        return self.previous + alpha * (self.pose - self.previous)

    def center(self, game):
        return self.pose[:4, 4]


@dataclass(eq=False)
class Entity:
    """One thing in the level. Its id, kind, motion, style and data are state (hashed); the
    rest is what it was spawned with and never changes.

    Parameters
    ----------
    id : int
        Unique for the whole game; never reused.
    kind : str
        ``"object"``, ``"body"``, ``"crystal"``, ...
    name : str
    mesh : TetMesh4 or None
        Its 4D shape; None for entities that are not drawn.
    motion : Motion
        Where it is.
    solid : bool
        The walker collides with the bounds of its cross-section (rigid bodies
        collide through physics instead).
    radar : str or None
        Pin kind on the radar (``game.frame.RADAR_KINDS``), or None to stay off it.
    style : str
        Render style of its cross-section (``"solid"``, ``"glow"``, ...).
    data : Any
        Kind-specific state, owned by the kind's system: a dataclass (or a number), hashed
        with the entity field by field unless a field is marked fixed or derived (:mod:`.system`).
    radius : float
        How far the mesh reaches from the centre, scale included (see
        :func:`reach`); used to skip slicing what cannot reach the slice.
    """

    id: int
    kind: str
    name: str = fixed()
    mesh: TetMesh4 | None = fixed()
    motion: Motion
    solid: bool = fixed(default=False)
    radar: str | None = fixed(default=None)
    style: str = "solid"
    data: Any = None
    radius: float = fixed(default=0.0)

    def model(self, game, alpha: float | None = None) -> np.ndarray:
        """Object-to-world ``(5, 5) float64`` now, or ``alpha`` of the way from the previous tick."""
        return self.motion.model(game, alpha)

    def center(self, game) -> np.ndarray:
        """The entity's centre now, ``(4,) float64``."""
        return self.motion.center(game)

    def reaches_slice(self, game, w: float) -> bool:
        """Can the entity's cross-section at ``w`` be non-empty? (False means: skip slicing.)"""
        return abs(float(self.motion.center(game)[3]) - w) <= self.radius


def reach(mesh: TetMesh4, scale=1.0) -> float:
    """How far ``mesh``, scaled by ``scale`` (a number or ``(4,)``), reaches from its origin."""
    if mesh is None or len(mesh.vertices) == 0:
        return 0.0
    return float(np.linalg.norm(mesh.vertices.astype(np.float64), axis=1).max() * np.max(scale))


@dataclass
class EntityTable:
    """The live entities of one tick as arrays, for culling many at once.

    Attributes
    ----------
    entities : list of Entity
        In spawn order.
    centers : (n, 4) float64
        Each entity's centre this tick.
    radii : (n,) float64
        Each entity's reach (:attr:`Entity.radius`).
    """

    entities: list
    centers: np.ndarray
    radii: np.ndarray

    def reaching(self, w: float) -> list:
        """Entities with a mesh whose reach spans the slice at ``w``."""
        near = np.abs(self.centers[:, 3] - w) <= self.radii
        return [e for e, n in zip(self.entities, near) if n and e.mesh is not None]


class EntityStore:
    """The entities of a game, by id, in spawn order.

    Removing an entity frees everything it holds: the game removes its rigid
    body from the physics world (see ``Game.remove``), so a long game does not
    grow the physics arrays.
    """

    def __init__(self):
        self._by_id: dict[int, Entity] = {}
        self._next = 1
        self.version = 0  # bumps on every spawn and removal (for caches of the entity list)

    def spawn(
        self, kind: str, name: str = "", mesh: TetMesh4 | None = None, motion: Motion | None = None, **fields
    ) -> Entity:
        """Add an entity and return it (its ``id`` is new)."""
        if motion is None:
            motion = Placed(np.eye(5))
        e = Entity(self._next, kind, name, mesh, motion, **fields)
        self._by_id[e.id] = e
        self._next += 1
        self.version += 1
        return e

    def remove(self, entity_id: int) -> Entity | None:
        """Forget an entity; returns it, or None if it was already gone."""
        e = self._by_id.pop(entity_id, None)
        if e is not None:
            self.version += 1
        return e

    def get(self, entity_id: int) -> Entity | None:
        """The live entity with this id, or None once it is removed."""
        return self._by_id.get(entity_id)

    def __contains__(self, entity_id: int) -> bool:
        return entity_id in self._by_id

    def __iter__(self) -> Iterator[Entity]:
        return iter(list(self._by_id.values()))  # a copy: systems may remove while iterating

    def __len__(self) -> int:
        return len(self._by_id)

    def of_kind(self, kind: str) -> list[Entity]:
        """Live entities of one kind, in spawn order."""
        return [e for e in self._by_id.values() if e.kind == kind]

    def named(self, name: str) -> Entity | None:
        """The first live entity with this name (levels name their objects)."""
        return next((e for e in self._by_id.values() if e.name == name), None)

    @property
    def next_id(self) -> int:
        return self._next
