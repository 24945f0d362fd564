"""The body methods of :class:`~.world.PhysicsWorld`: add, remove, read, move, push and wake bodies.

A part of the world class, kept apart by job: it works on the world's
``bodies`` (:class:`~.state.Bodies`), ``params`` and the previous poses kept for
drawing, and calls the world's ``_check``, ``_alloc_bodies`` and
``_forget_pairs``.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core import transform

from .bivector import world_inverse_inertia
from .body_def import KINDS, BodyDef, bivector, resolve, rotation_matrix, vec4
from .collide import BOX
from .state import DYNAMIC, STATIC


class WorldBodies:
    """Methods on the bodies of a :class:`~.world.PhysicsWorld` (see there for its state)."""

    def add_body(self, body_def: BodyDef) -> int:
        """Add a body and return its id.

        Parameters
        ----------
        body_def : BodyDef
            Shape, pose, motion and material (see :class:`BodyDef` for the defaults).

        Returns
        -------
        int
            The body id, stable until :meth:`remove_body`.

        Raises
        ------
        ValueError
            Unknown shape or kind, a non-positive size, radius or mass.
        """
        if not isinstance(body_def, BodyDef):
            raise TypeError(f"add_body takes a BodyDef, got {type(body_def).__name__}")
        r = resolve(body_def)
        free = np.flatnonzero(~self.bodies.alive[: self._n])
        if free.size:
            # The lowest free slot, so the same calls always give the same ids and a
            # game that fires for ten minutes keeps its arrays as long as its busiest moment.
            i = int(free[0])
        else:
            if self._n == self.bodies.alive.shape[0]:
                self._alloc_bodies(2 * self.bodies.alive.shape[0])
                self._scratch = self._scratch._replace(margin=np.zeros(self.bodies.alive.shape[0]))
            i = self._n
            self.bodies = self.bodies._replace(count=i + 1)
        b = self.bodies
        b.alive[i] = True
        b.kind[i] = r.kind
        b.shape[i] = r.shape
        b.half_extents[i] = r.half_extents
        b.bound[i] = r.bound
        b.position[i] = r.position
        b.rotation[i] = r.rotation
        b.velocity[i] = r.velocity
        b.angular_velocity[i] = r.angular_velocity
        b.mass[i] = r.mass
        b.inv_mass[i] = r.inv_mass
        b.inv_inertia[i] = r.inv_inertia
        b.friction[i] = body_def.friction
        b.restitution[i] = body_def.restitution
        b.awake[i] = True
        b.sleep_timer[i] = 0.0
        b.island[i] = i
        self._prev_position[i] = self.bodies.position[i]
        self._prev_rotation[i] = self.bodies.rotation[i]
        return i

    def remove_body(self, body_id: int) -> None:
        """Delete a body; sleeping bodies near it wake (they may have rested on it).

        Its slot is free for the next :meth:`add_body` (the lowest free slot is
        taken first), so the warm-start impulses and touching pairs that name
        it are dropped here: a newcomer in the slot must not inherit them.
        """
        i = self._check(body_id)
        self._wake_near(i)
        n = self._n
        # Sleepers whose island was rooted at this body wake too: the root id is about to
        # name a different body.
        rooted = self.bodies.alive[:n] & ~self.bodies.awake[:n] & (self.bodies.island[:n] == i)
        rooted[i] = False
        for j in np.flatnonzero(rooted):
            self.wake(int(j))
        self.bodies.alive[i] = False
        self.bodies.awake[i] = False
        self.bodies.velocity[i] = 0.0
        self.bodies.angular_velocity[i] = 0.0
        self._forget_pairs(i)

    def _wake_near(self, i: int) -> None:
        n = self._n
        d = np.linalg.norm(self.bodies.position[:n] - self.bodies.position[i], axis=1)
        near = d <= self.bodies.bound[:n] + self.bodies.bound[i] + 4 * self.params["margin"][0]
        for j in np.flatnonzero(near & self.bodies.alive[:n] & ~self.bodies.awake[:n]):
            self.wake(int(j))

    @property
    def body_ids(self) -> list[int]:
        """Ids of the bodies that exist."""
        return [int(i) for i in np.flatnonzero(self.bodies.alive[: self._n])]

    def body_pose(self, body_id: int, alpha: float | None = None) -> np.ndarray:
        """Model matrix of a body: ``(5, 5) float64`` homogeneous ``[[R, x], [0, 1]]``.

        Parameters
        ----------
        body_id : int
        alpha : float, optional
            Blend from the pose at the start of the last tick (0) to the
            current one (1), for drawing frames between ticks; pass
            :attr:`tick_fraction` to draw where the accumulated time is. The
            simulation itself is unaffected.
        """
        i = self._check(body_id)
        m = np.eye(5)
        if alpha is None or alpha >= 1.0:
            m[:4, :4] = self.bodies.rotation[i]
            m[:4, 4] = self.bodies.position[i]
        else:
            a = max(0.0, float(alpha))
            m[:4, :4] = transform.orthonormalize((1 - a) * self._prev_rotation[i] + a * self.bodies.rotation[i])
            m[:4, 4] = (1 - a) * self._prev_position[i] + a * self.bodies.position[i]
        return m

    @property
    def tick_fraction(self) -> float:
        """Time accumulated towards the next tick, as a fraction of ``tick_dt`` in [0, 1)."""
        return min(self._acc / self.tick_dt, 1.0)

    def body_position(self, body_id: int) -> np.ndarray:
        """Centre ``(4,) float64`` (a copy)."""
        return self.bodies.position[self._check(body_id)].copy()

    def body_rotation(self, body_id: int) -> np.ndarray:
        """Rotation ``(4, 4) float64`` (a copy)."""
        return self.bodies.rotation[self._check(body_id)].copy()

    def body_velocity(self, body_id: int) -> tuple[np.ndarray, np.ndarray]:
        """Linear ``(4,)`` and angular ``(6,)`` velocity (copies)."""
        i = self._check(body_id)
        return self.bodies.velocity[i].copy(), self.bodies.angular_velocity[i].copy()

    def body_half_extents(self, body_id: int) -> np.ndarray | None:
        """Half extents ``(4,)`` of a box body in its own frame (a copy); None for a sphere."""
        i = self._check(body_id)
        return self.bodies.half_extents[i].copy() if self.bodies.shape[i] == BOX else None

    def body_mass(self, body_id: int) -> float:
        return float(self.bodies.mass[self._check(body_id)])

    def body_inertia(self, body_id: int) -> np.ndarray:
        """World-frame inertia ``(6, 6) float64`` on bivectors (dynamic bodies)."""
        i = self._check(body_id)
        inv = np.zeros((6, 6))
        world_inverse_inertia(self.bodies.rotation[i], self.bodies.inv_inertia[i], inv)
        return np.linalg.inv(inv)

    def set_velocity(self, body_id: int, velocity=None, angular_velocity=None) -> None:
        """Set linear ``(4,)`` and/or angular ``(6,)`` velocity and wake the body."""
        i = self._check(body_id)
        if self.bodies.kind[i] == STATIC:
            raise ValueError("static bodies cannot move; use kind='kinematic'")
        if velocity is not None:
            self.bodies.velocity[i] = vec4(velocity, "velocity")
        if angular_velocity is not None:
            self.bodies.angular_velocity[i] = bivector(angular_velocity)
        self.wake(i)

    def set_pose(self, body_id: int, position=None, rotation=None) -> None:
        """Teleport a body (typically a kinematic one) and wake whatever it now touches."""
        i = self._check(body_id)
        if position is not None:
            self.bodies.position[i] = vec4(position, "position")
        if rotation is not None:
            self.bodies.rotation[i] = rotation_matrix(rotation)
        self._wake_near(i)
        if self.bodies.kind[i] == DYNAMIC:
            self.wake(i)

    def push(self, body_id: int, impulse, point=None) -> None:
        """Apply an impulse ``(4,)`` (N s) to a dynamic body, at its centre or at ``point``.

        Off-centre pushes also spin the body: ``dw = I^-1 (r ^ impulse)``.
        Static and kinematic bodies ignore pushes.
        """
        i = self._check(body_id)
        if self.bodies.kind[i] != DYNAMIC:
            return
        p = vec4(impulse, "impulse")
        self.wake(i)
        self.bodies.velocity[i] += p * self.bodies.inv_mass[i]
        if point is not None:
            r = vec4(point, "point") - self.bodies.position[i]
            tau = np.array([r[a] * p[b] - r[b] * p[a] for a, b in ((0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3))])
            inv = np.zeros((6, 6))
            world_inverse_inertia(self.bodies.rotation[i], self.bodies.inv_inertia[i], inv)
            self.bodies.angular_velocity[i] += inv @ tau

    def wake(self, body_id: int) -> None:
        """Wake a body and the sleeping island it belongs to."""
        i = self._check(body_id)
        if self.bodies.kind[i] != DYNAMIC:
            return
        if not self.bodies.awake[i]:
            n = self._n
            group = self.bodies.alive[:n] & ~self.bodies.awake[:n] & (self.bodies.island[:n] == self.bodies.island[i])
            group &= self.bodies.kind[:n] == DYNAMIC
            self.bodies.awake[:n][group] = True
            self.bodies.sleep_timer[:n][group] = 0.0
        self.bodies.awake[i] = True
        self.bodies.sleep_timer[i] = 0.0

    def body_kind(self, body_id: int) -> str:
        """``"dynamic"``, ``"kinematic"`` or ``"static"``."""
        k = self.bodies.kind[self._check(body_id)]
        return next(name for name, code in KINDS.items() if code == k)

    def is_sleeping(self, body_id: int) -> bool:
        i = self._check(body_id)
        return bool(self.bodies.kind[i] == DYNAMIC and not self.bodies.awake[i])
