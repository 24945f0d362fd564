"""The drawn entities' poses as arrays: every model of a frame in one pass.

Most 4D things in a level turn by a script (spinning objects, crystals): their pose is a
function of time alone. :class:`EntityModels` keeps their positions, angles, spins and
scales as arrays (rebuilt only when entities come or go) and poses them all at once with
:func:`.poses.poses`, the same bits as :meth:`~across_dimensions.world.scene.Object4.model_at`
gives one by one. Entities placed by a system or by physics (enemies, bullets, bodies) are
asked one by one: there are few of them.
"""

from __future__ import annotations

import numpy as np

from .entities import Placed, Scripted
from .poses import angle_rows, poses

#: Kinds never drawn as 4D matter: the camera's own indicators stand in slice space.
INDICATOR_KINDS = ("camera_focus", "camera_eye")


class EntityModels:
    """Models of the entities with a mesh, in spawn order, for a frame's ``alpha``.

    Attributes
    ----------
    entities : list of Entity
        The drawn entities (a mesh, not a camera indicator), as of the last :meth:`update`.
    centers : (n, 4) float64
    radii : (n,) float64
    """

    def __init__(self):
        self._version = None
        self.entities: list = []
        self.centers = np.zeros((0, 4))
        self.radii = np.zeros(0)
        self._scripted = np.zeros(0, np.int64)  # rows of the scripted entities
        self._others: list[int] = []
        self._arrays: tuple = ()
        self._memo: tuple = (None, None)
        self._centers_of = None  # (tick, pose version, entities' version) the centres are of
        self._columns: dict = {}  # name -> array of a per-entity value, until entities come or go
        self.hidden_memo: tuple = (None, None)  # the frame's occlusion (see occlusion.hidden_rows)
        self.occluder_memo: tuple = (None, None)  # the frame's occluders (occlusion._frame_occluders)

    def update(self, game) -> None:
        """Take the game's entities again if any came or went; the centres, once a tick (or pose change)."""
        if self._version != game.entities.version:
            self._version = game.entities.version
            self.entities = [e for e in game.entities if e.mesh is not None and e.kind not in INDICATOR_KINDS]
            scripted = [i for i, e in enumerate(self.entities) if isinstance(e.motion, Scripted)]
            objs = [self.entities[i].motion.obj for i in scripted]
            self._scripted = np.array(scripted, np.int64)
            self._others = [i for i, e in enumerate(self.entities) if not isinstance(e.motion, Scripted)]
            self._arrays = (
                np.array([o.position for o in objs], np.float64).reshape(-1, 4),
                angle_rows([o.rotation_deg for o in objs]),
                angle_rows([o.spin_deg for o in objs]),
                np.array([o.scale for o in objs], np.float64).reshape(-1, 4),
            )
            self.radii = np.array([e.radius for e in self.entities], np.float64)
            self.centers = np.zeros((len(self.entities), 4))
            self.centers[self._scripted] = self._arrays[0]  # spin never moves an object
            self._columns = {}
        key = (game.tick, game.pose_version, self._version)
        if self._centers_of != key:  # nothing moves between the systems drawing one frame
            self._centers_of = key
            for i in self._others:
                self.centers[i] = self.entities[i].center(game)

    def column(self, name: str, value) -> np.ndarray:
        """``value(entity)`` of every entity as one array (``(n, ...)``), made again only when
        entities come or go: for what does not change in an entity's life (its mesh, its kind)."""
        got = self._columns.get(name)
        if got is None:
            got = self._columns[name] = np.array([value(e) for e in self.entities], np.float64)
        return got

    def models(self, game, alpha: float | None) -> np.ndarray:
        """``(n, 5, 5) float64``: each entity's model ``alpha`` of the way from the previous tick
        (None: now), as :meth:`~.entities.Entity.model` gives it."""
        key = (game.tick, alpha, self._version, game.pose_version)
        if self._memo[0] == key:
            return self._memo[1]  # the frame's systems ask in turn: nothing moves between them
        out = np.empty((len(self.entities), 5, 5))
        if len(self._scripted):
            position, rotation, spin, scale = self._arrays
            t = game.time if alpha is None else game.time - (1.0 - alpha) * game.dt
            out[self._scripted] = poses(position, np.radians(rotation + spin * t), scale)
        if alpha is None:
            for i in self._others:
                out[i] = self.entities[i].model(game, alpha)
        else:
            self._blend_placed(game, alpha, out)
        self._memo = (key, out)
        return out

    def _blend_placed(self, game, alpha: float, out: np.ndarray) -> None:
        """Into ``out``, the models of the entities not scripted: those a system places
        (:class:`~.entities.Placed`, blended between ticks) in one pass, the same bits as
        :meth:`~.entities.Placed.model` one by one; the rest (rigid bodies) one by one."""
        blend, rest = [], []
        for i in self._others:
            m = self.entities[i].motion
            if isinstance(m, Placed) and m.previous is not None:
                blend.append(i)
            else:
                rest.append(i)
        if blend:
            pose = np.array([self.entities[i].motion.pose for i in blend])
            prev = np.array([self.entities[i].motion.previous for i in blend])
            out[blend] = prev + alpha * (pose - prev)
        for i in rest:
            out[i] = self.entities[i].model(game, alpha)


__all__ = ["EntityModels", "INDICATOR_KINDS"]
