"""The game-facing 4D rigid-body world.

>>> from across_dimensions.physics import BodyDef, PhysicsWorld
>>> world = PhysicsWorld(gravity=(0, -9.81, 0, 0))          # ground plane y = 0
>>> ball = world.add_body(BodyDef("hypersphere", radius=0.5, position=(0, 2, 0, 0.3)))
>>> box = world.add_body(BodyDef("hypercube", size=1.0, position=(2, 0.5, 0, 0),
...                               angles={"xw": 0.3}))
>>> world.step(1 / 60)                                      # one fixed tick
1
>>> model = world.body_pose(ball)                           # (5, 5) model matrix

Bodies are kept in flat arrays indexed by id (a removed body's slot is reused,
lowest first, so the arrays stay as long as the most bodies alive at once) so that the
compiled pipeline (:mod:`.pipeline`) can step them without Python overhead.
``step(dt)`` feeds a time accumulator and runs whole ticks of the fixed
``tick_dt`` (each split into fixed substeps); the same sequence of calls
therefore gives bit-identical states (:meth:`PhysicsWorld.state_hash`).
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from across_dimensions.core import transform

from . import pipeline as pl
from .bivector import world_inverse_inertia
from .body_def import BodyDef
from .collide import BOX, SCRATCH_POINTS, SPHERE
from .debug_draw import DebugDrawer, DebugDrawOptions, debug_draw
from .events import ContactEvent, manifold_events, touching_keys
from .mass import box_inertia, box_volume, hypersphere_inertia, hypersphere_volume
from .queries import box_push_out_kernel, raycast_kernel
from .state import (
    Bodies,
    Scratch,
    StaticWorld,
    new_contacts,
    new_manifolds,
    new_params,
    new_solver_rows,
    new_warm_start,
)
from .tet_mesh import CANDIDATES, tet_geometry

#: Pairs closer than this (metres) count as touching for events.
_TOUCH_TOL = 1e-3

_KINDS = {"static": pl.STATIC, "kinematic": pl.KINEMATIC, "dynamic": pl.DYNAMIC}
_SHAPES = {"hypersphere": SPHERE, "sphere": SPHERE, "ball": SPHERE, "hypercube": BOX, "box": BOX, "tesseract": BOX}


def _rotation(rotation=None, angles: Mapping[str, float] | None = None) -> np.ndarray:
    if rotation is None:
        return transform.angles_to_rotation(angles or {})
    if isinstance(rotation, Mapping):
        return transform.angles_to_rotation(rotation)
    r = np.asarray(rotation, dtype=np.float64)
    if r.shape == (5, 5):
        r = r[:4, :4]
    if r.shape != (4, 4):
        raise ValueError(f"rotation must be (4, 4), got {r.shape}")
    if transform.orthonormality_error(r) > 1e-6 or np.linalg.det(r) < 0:
        raise ValueError("rotation is not a proper rotation matrix")
    return transform.orthonormalize(r)


def _bivector(value) -> np.ndarray:
    if value is None:
        return np.zeros(6)
    if isinstance(value, Mapping):
        out = np.zeros(6)
        for plane, rate in value.items():
            if plane not in transform.PLANES:
                raise ValueError(f"unknown plane {plane!r}; use one of {', '.join(transform.PLANES)}")
            out[transform.PLANES.index(plane)] = float(rate)
        return out
    out = np.asarray(value, dtype=np.float64).reshape(6)
    return out.copy()


def _pair_involves(keys: np.ndarray, i: int) -> np.ndarray:
    """Which pair keys ``(k,) int64`` (``a << 32 | b``, see :mod:`.pipeline`) name body ``i``."""
    a = keys >> 32
    b = keys & 0xFFFFFFFF
    return (a == i) | ((b == i) & (b < pl.STATIC_KEY))


def _vec4(value, name: str) -> np.ndarray:
    out = np.asarray(value if value is not None else np.zeros(4), dtype=np.float64).reshape(-1)
    if out.shape != (4,):
        raise ValueError(f"{name} must have 4 components (x, y, z, w), got {out.shape[0]}")
    return out.copy()


class PhysicsWorld:
    """4D rigid bodies (hyperspheres, boxes) against each other and a 3D world.

    Parameters
    ----------
    gravity : (4,) array_like
        Acceleration, m/s^2. Default ``-9.81`` along y and nothing along w.
    inverse_cube_G : float
        When non-zero, every pair of bodies attracts with ``G m1 m2 / r^3``
        (Gauss's law in four dimensions). Sleeping is disabled then, because
        attraction never lets a body rest.
    ground : bool
        Add the ground half-space ``y <= 0``.
    tick_dt : float
        Fixed tick, seconds: contacts are found once per tick.
    substeps : int
        Solver substeps per tick (the integration step is ``tick_dt / substeps``).
    iterations, relax_iterations : int
        Solver sweeps per substep with and without the push-out of overlaps.
    allow_sleep : bool
    max_ticks : int
        Most ticks one :meth:`step` may run (caps the catch-up after a hitch;
        the surplus time is dropped).
    world_friction, world_restitution : float
        Material of the static world.
    sleep_time : float
        Seconds a group of touching bodies must stay calm before it sleeps.
    softening : float
        Length added in quadrature to distances in the inverse-cube law, so
        that touching bodies do not feel a near-infinite pull.
    contact_hertz, damping_ratio, max_push : float
        Stiffness, damping and top speed (m/s) of the push-out of overlaps.
    spin_friction : float
        Contact-patch radius of a hypersphere as a fraction of its radius: it
        brakes spinning in the planes of the contact (which point friction
        cannot), so balls do not twirl in place forever. 0 turns it off.
    rolling_resistance : float
        Hypersphere rolling resistance: the braking torque is at most this
        times the normal force times the radius. 0 (the default) rolls on
        ideally, as the physics tests expect; a level may want about 0.02 so
        balls come to rest and sleep.
    reuse_distance, reuse_angle : float
        A box pair's contact manifold is reused while the pair moves less than
        this (m) and turns less than this (rad) since it was found (see
        :mod:`.reuse`); an angle of 0 finds every manifold every tick.

    Attributes
    ----------
    bodies : Bodies
        Every body slot (see :mod:`.state`); read it, change bodies through the methods.
    static : StaticWorld
        Half-spaces and 3D world boxes.
    params : (1,) PARAMS_DTYPE record array
        The tuning values above, by name (``params["max_push"]``).
    contacts : Contacts
        The last tick's contacts; the first :attr:`last_contact_count` are valid.
    warm : WarmStart
        The impulses the next tick starts from.
    """

    def __init__(
        self,
        gravity=(0.0, -9.81, 0.0, 0.0),
        inverse_cube_G: float = 0.0,
        *,
        ground: bool = True,
        tick_dt: float = 1.0 / 60.0,
        substeps: int = 4,
        iterations: int = 1,
        relax_iterations: int = 1,
        allow_sleep: bool = True,
        max_ticks: int = 4,
        world_friction: float = 0.6,
        world_restitution: float = 0.0,
        sleep_time: float = 0.5,
        softening: float = 0.05,
        contact_hertz: float = 30.0,
        damping_ratio: float = 10.0,
        max_push: float = 3.0,
        spin_friction: float = 0.1,
        rolling_resistance: float = 0.0,
        reuse_distance: float = 1e-3,
        reuse_angle: float = np.radians(2.0),
    ):
        if not tick_dt > 0 or int(substeps) < 1:
            raise ValueError("tick_dt must be positive and substeps at least 1")
        self.params = new_params()
        self.tick_dt = float(tick_dt)
        self.substeps = int(substeps)
        self.gravity = gravity
        self.inverse_cube_G = inverse_cube_G
        p = self.params
        p["tick_dt"] = self.tick_dt
        p["substeps"] = self.substeps
        p["softening"] = softening
        p["margin"] = 0.02
        p["contact_hertz"] = contact_hertz
        p["damping_ratio"] = damping_ratio
        p["max_push"] = max_push
        p["restitution_threshold"] = 0.5
        p["spin_friction"] = spin_friction
        p["rolling_resistance"] = rolling_resistance
        p["reuse_distance"] = reuse_distance
        p["reuse_angle"] = reuse_angle
        p["sleep_linear"] = 0.05
        p["sleep_angular"] = 0.1
        p["sleep_time"] = sleep_time
        p["iterations"] = iterations
        p["relax_iterations"] = relax_iterations
        p["world_friction"] = world_friction
        p["world_restitution"] = world_restitution
        self.allow_sleep = allow_sleep
        self.max_ticks = int(max_ticks)
        self.time = 0.0
        self._acc = 0.0
        self._alloc_bodies(16)
        self.static = StaticWorld(
            np.zeros((0, 5)),
            np.zeros((0, 6)),
            np.zeros((0, 24)),
            np.zeros((0, 5)),
            np.zeros((0, 2), np.int64),
            np.zeros((0, 8)),
            np.zeros((0, 4, 4)),
            np.zeros((0, 5)),
            np.zeros((0, 3, 4)),
            np.zeros((0, 8)),
            np.zeros((0, 2), np.int64),
            np.zeros((0, 8)),
            np.zeros((0, 2)),
            np.zeros((0, 4, 5)),
        )
        self._tet_inputs: list[np.ndarray] = []
        self._tet_parts: list[tuple] = []
        if ground:
            self.add_half_space((0.0, 1.0, 0.0, 0.0), 0.0)
        self.warm = new_warm_start(256)
        self._alloc_contacts(256, 256)
        self._touch_keys = np.zeros(0, dtype=np.int64)
        self._touch_prev = np.zeros(0, dtype=np.int64)
        self._events_cache: list[ContactEvent] | None = []
        self._events_earlier: list[ContactEvent] = []
        self.last_contact_count = 0

    # ------------------------------------------------------------------ settings
    @property
    def gravity(self) -> np.ndarray:
        """Gravity ``(4,) float64`` (a copy); assign to change it per level."""
        return self.params["gravity"][0].copy()

    @gravity.setter
    def gravity(self, value) -> None:
        self.params["gravity"] = _vec4(value, "gravity")
        self._wake_all()  # sleepers must feel the new pull

    @property
    def inverse_cube_G(self) -> float:
        """Strength ``G`` of the mutual ``G m1 m2 / r^3`` attraction (0 = off)."""
        return float(self.params["inverse_cube_G"][0])

    @inverse_cube_G.setter
    def inverse_cube_G(self, value: float) -> None:
        self.params["inverse_cube_G"] = float(value)
        self._wake_all()

    @property
    def allow_sleep(self) -> bool:
        return bool(self.params["allow_sleep"][0])

    @allow_sleep.setter
    def allow_sleep(self, value: bool) -> None:
        self.params["allow_sleep"] = 1.0 if value else 0.0
        if not value and hasattr(self, "bodies"):
            self.bodies.awake[: self._n] = True

    # ------------------------------------------------------------------ storage
    def _alloc_bodies(self, cap: int) -> None:
        old = getattr(self, "bodies", None)
        n = old.count if old is not None else 0
        fields = {
            "alive": ((), bool),
            "kind": ((), np.int8),
            "shape": ((), np.int8),
            "half_extents": ((4,), np.float64),
            "bound": ((), np.float64),
            "position": ((4,), np.float64),
            "rotation": ((4, 4), np.float64),
            "velocity": ((4,), np.float64),
            "angular_velocity": ((6,), np.float64),
            "mass": ((), np.float64),
            "inv_mass": ((), np.float64),
            "inv_inertia": ((6,), np.float64),
            "friction": ((), np.float64),
            "restitution": ((), np.float64),
            "awake": ((), bool),
            "sleep_timer": ((), np.float64),
            "island": ((), np.int64),
        }
        arrays = {}
        for name, (shape, dtype) in fields.items():
            arr = np.zeros((cap,) + shape, dtype=dtype)
            if old is not None:
                arr[:n] = getattr(old, name)[:n]
            arrays[name] = arr
        self.bodies = Bodies(count=n, **arrays)
        # Poses at the start of the last tick, for render interpolation.
        prev = (getattr(self, "_prev_position", None), getattr(self, "_prev_rotation", None))
        self._prev_position = np.zeros((cap, 4))
        self._prev_rotation = np.zeros((cap, 4, 4))
        if old is not None:
            self._prev_position[:n] = prev[0][:n]
            self._prev_rotation[:n] = prev[1][:n]

    @property
    def _n(self) -> int:
        return self.bodies.count

    def _alloc_contacts(self, pair_cap: int, contact_cap: int) -> None:
        """Size the per-tick buffers; the warm-start entries are kept."""
        self._scratch = Scratch(
            np.zeros((pair_cap, 2), dtype=np.int64),
            np.zeros(self.bodies.alive.shape[0]),
            np.zeros((SCRATCH_POINTS, 4)),
            np.zeros(SCRATCH_POINTS),
            np.zeros(1, np.int64),
            np.zeros((CANDIDATES, 4)),
            np.zeros((CANDIDATES, 4)),
            np.zeros(CANDIDATES),
        )
        self.contacts = new_contacts(contact_cap)
        self._rows = new_solver_rows(contact_cap)
        old = getattr(self, "_kept", (None, None))[0]
        self._kept = (new_manifolds(pair_cap, contact_cap, old), new_manifolds(pair_cap, contact_cap))
        self._touch_buf = np.zeros(contact_cap, dtype=np.int64)
        if self.warm.key.shape[0] != contact_cap:
            self.warm = new_warm_start(contact_cap, self.warm)

    def _check(self, body_id: int) -> int:
        i = int(body_id)
        if not (0 <= i < self._n) or not self.bodies.alive[i]:
            raise KeyError(f"no body with id {body_id}")
        return i

    # ------------------------------------------------------------------ bodies
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
        d = body_def
        shape, size, radius, kind = d.shape, d.size, d.radius, d.kind
        if shape not in _SHAPES:
            raise ValueError(f"unknown shape {shape!r}; use 'hypersphere' or 'hypercube'")
        if kind not in _KINDS:
            raise ValueError(f"unknown kind {kind!r}; use dynamic, kinematic or static")
        sh = _SHAPES[shape]
        if sh == SPHERE:
            r = float(radius) if radius is not None else (0.5 * float(size) if size is not None else 0.5)
            if not r > 0:
                raise ValueError("radius must be positive")
            half = np.full(4, r)
            volume = hypersphere_volume(r)
        else:
            s = np.broadcast_to(np.asarray(1.0 if size is None else size, dtype=np.float64), (4,))
            if not np.all(s > 0):
                raise ValueError("size must be positive")
            half = 0.5 * s
            volume = box_volume(half)
        m = float(d.mass) if d.mass is not None else float(d.density) * volume
        if not m > 0:
            raise ValueError("mass must be positive")
        inertia = hypersphere_inertia(m, half[0]) if sh == SPHERE else box_inertia(m, half)
        k = _KINDS[kind]
        # Everything that can fail is checked before the slot is taken.
        position = _vec4(d.position, "position")
        rotation = _rotation(d.rotation, d.angles)
        velocity = _vec4(d.velocity, "velocity") if k != pl.STATIC else 0.0
        angular_velocity = _bivector(d.angular_velocity) if k != pl.STATIC else 0.0
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
        self.bodies.alive[i] = True
        self.bodies.kind[i] = k
        self.bodies.shape[i] = sh
        self.bodies.half_extents[i] = half
        self.bodies.bound[i] = half[0] if sh == SPHERE else float(np.linalg.norm(half))
        self.bodies.position[i] = position
        self.bodies.rotation[i] = rotation
        self.bodies.velocity[i] = velocity
        self.bodies.angular_velocity[i] = angular_velocity
        self.bodies.mass[i] = m
        self.bodies.inv_mass[i] = 1.0 / m if k == pl.DYNAMIC else 0.0
        self.bodies.inv_inertia[i] = 1.0 / inertia if k == pl.DYNAMIC else 0.0
        self.bodies.friction[i] = d.friction
        self.bodies.restitution[i] = d.restitution
        self.bodies.awake[i] = True
        self.bodies.sleep_timer[i] = 0.0
        self.bodies.island[i] = i
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

    def _forget_pairs(self, i: int) -> None:
        """Drop warm-start entries and touching pairs that involve body slot ``i``."""
        warm = self.warm
        c = int(warm.count[0])
        keep = ~_pair_involves(warm.key[:c], i)
        k = int(keep.sum())
        if k != c:
            for name in ("key", "local_point", "normal_impulse", "friction_impulse"):
                arr = getattr(warm, name)
                arr[:k] = arr[:c][keep]
            warm.count[0] = k
        self._touch_keys = self._touch_keys[~_pair_involves(self._touch_keys, i)]
        self._touch_prev = self._touch_prev[~_pair_involves(self._touch_prev, i)]
        self._forget_manifolds(_pair_involves(self._kept[0].key[: int(self._kept[0].pairs[0])], i))

    def _forget_manifolds(self, drop: np.ndarray) -> None:
        """Drop the kept box manifolds of the pairs marked in ``drop``: a newcomer in a
        freed slot, or a changed static collider, must not inherit them."""
        kept = self._kept[0]
        n = int(kept.pairs[0])
        keep = ~drop
        k = int(keep.sum())
        if k != n:
            for name in ("key", "first", "count", "axis", "pose"):
                arr = getattr(kept, name)
                arr[:k] = arr[:n][keep]
            kept.pairs[0] = k

    def _forget_static_manifolds(self) -> None:
        if not hasattr(self, "_kept"):
            return
        kept = self._kept[0]
        self._forget_manifolds((kept.key[: int(kept.pairs[0])] & 0xFFFFFFFF) >= pl.STATIC_KEY)

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
        if self.bodies.kind[i] == pl.STATIC:
            raise ValueError("static bodies cannot move; use kind='kinematic'")
        if velocity is not None:
            self.bodies.velocity[i] = _vec4(velocity, "velocity")
        if angular_velocity is not None:
            self.bodies.angular_velocity[i] = _bivector(angular_velocity)
        self.wake(i)

    def set_pose(self, body_id: int, position=None, rotation=None) -> None:
        """Teleport a body (typically a kinematic one) and wake whatever it now touches."""
        i = self._check(body_id)
        if position is not None:
            self.bodies.position[i] = _vec4(position, "position")
        if rotation is not None:
            self.bodies.rotation[i] = _rotation(rotation)
        self._wake_near(i)
        if self.bodies.kind[i] == pl.DYNAMIC:
            self.wake(i)

    def push(self, body_id: int, impulse, point=None) -> None:
        """Apply an impulse ``(4,)`` (N s) to a dynamic body, at its centre or at ``point``.

        Off-centre pushes also spin the body: ``dw = I^-1 (r ^ impulse)``.
        Static and kinematic bodies ignore pushes.
        """
        i = self._check(body_id)
        if self.bodies.kind[i] != pl.DYNAMIC:
            return
        p = _vec4(impulse, "impulse")
        self.wake(i)
        self.bodies.velocity[i] += p * self.bodies.inv_mass[i]
        if point is not None:
            r = _vec4(point, "point") - self.bodies.position[i]
            tau = np.array([r[a] * p[b] - r[b] * p[a] for a, b in ((0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3))])
            inv = np.zeros((6, 6))
            world_inverse_inertia(self.bodies.rotation[i], self.bodies.inv_inertia[i], inv)
            self.bodies.angular_velocity[i] += inv @ tau

    def wake(self, body_id: int) -> None:
        """Wake a body and the sleeping island it belongs to."""
        i = self._check(body_id)
        if self.bodies.kind[i] != pl.DYNAMIC:
            return
        if not self.bodies.awake[i]:
            n = self._n
            group = self.bodies.alive[:n] & ~self.bodies.awake[:n] & (self.bodies.island[:n] == self.bodies.island[i])
            group &= self.bodies.kind[:n] == pl.DYNAMIC
            self.bodies.awake[:n][group] = True
            self.bodies.sleep_timer[:n][group] = 0.0
        self.bodies.awake[i] = True
        self.bodies.sleep_timer[i] = 0.0

    def body_kind(self, body_id: int) -> str:
        """``"dynamic"``, ``"kinematic"`` or ``"static"``."""
        k = self.bodies.kind[self._check(body_id)]
        return next(name for name, code in _KINDS.items() if code == k)

    def is_sleeping(self, body_id: int) -> bool:
        i = self._check(body_id)
        return bool(self.bodies.kind[i] == pl.DYNAMIC and not self.bodies.awake[i])

    # ------------------------------------------------------------------ static world
    def add_half_space(self, normal, offset: float = 0.0) -> int:
        """Add the static solid ``{x : n . x <= offset}`` (``n`` is normalised).

        A slope is a half-space with a tilted normal; the ground is
        ``normal=(0, 1, 0, 0), offset=0``. Returns its index among half-spaces.
        """
        n = _vec4(normal, "normal")
        ln = np.linalg.norm(n)
        if ln == 0:
            raise ValueError("normal must be non-zero")
        row = np.append(n / ln, float(offset) / ln)
        self.static = self.static._replace(half_spaces=np.vstack([self.static.half_spaces, row[None]]))
        self._forget_static_manifolds()
        self._wake_all()
        return self.static.half_spaces.shape[0] - 1

    def set_static_boxes(self, boxes: Iterable[tuple[Sequence[float], Sequence[float]]]) -> None:
        """Replace the 3D world boxes: ``(center (3,), half_extents (3,))`` each,
        extending over all of w."""
        rows = []
        for center, half in boxes:
            c = np.asarray(center, dtype=np.float64).reshape(3)
            h = np.asarray(half, dtype=np.float64).reshape(3)
            if np.any(h <= 0):
                raise ValueError("world box half extents must be positive")
            rows.append(np.concatenate([c, h]))
        self.static = self.static._replace(boxes=np.array(rows, dtype=np.float64).reshape(-1, 6))
        self._forget_static_manifolds()
        self._wake_all()

    def set_static_solids(self, solids: Iterable[tuple]) -> None:
        """Replace the 4D solid boxes: ``(center (4,), half_extents (4,), rotation (4, 4))``
        each, rotation local to world (as :meth:`body_rotation`).

        They are the level's solid objects as seen by the bodies (the game
        sets them each tick from the objects' poses). Sleeping bodies near a
        box that appeared, vanished or moved wake; nothing else changes, so
        setting the same boxes again is free and leaves the simulation as it
        was. They are not in :meth:`state_bytes`: they are derived from poses
        the game hashes itself.
        """
        rows = []
        for center, half, rot in solids:
            c = _vec4(center, "center")
            h = _vec4(half, "half_extents")
            if np.any(h <= 0):
                raise ValueError("solid half extents must be positive")
            r = np.asarray(rot, dtype=np.float64).reshape(4, 4)
            rows.append(np.concatenate([c, h, r.reshape(16)]))
        new = np.array(rows, dtype=np.float64).reshape(-1, 24)
        old = self.static.solids
        if new.shape == old.shape and np.array_equal(new, old):
            return
        self.static = self.static._replace(solids=new)
        self._forget_static_manifolds()
        changed = [r for r in old if not any(np.array_equal(r, q) for q in new)]
        changed += [r for r in new if not any(np.array_equal(r, q) for q in old)]
        self._wake_near_solids(changed)

    def set_static_convex(self, solids: Iterable[tuple]) -> None:
        """Replace the convex solids: each ``(planes (k, 5), lo (4,), hi (4,))``, its facet
        half-spaces ``(n, offset)`` (the solid is ``{x : n . x <= offset}`` for every
        row, ``n`` pointing out of it; normalised here) and its bounds.

        Bodies meet each solid through its facet of least penetration (the
        separating-axis test over its facets), so a body resting on a face is
        exact; near an edge or a corner the contact comes up to the margin
        early. As for :meth:`set_static_solids`, setting the same solids again
        changes nothing, sleeping bodies near a changed one wake, and they are
        not in :meth:`state_bytes`.
        """
        planes, ranges, bounds = [], [], []
        start = 0
        for rows, lo, hi in solids:
            r = np.asarray(rows, dtype=np.float64).reshape(-1, 5)
            ln = np.linalg.norm(r[:, :4], axis=1)
            if len(r) < 5 or not np.all(ln > 0):
                raise ValueError("a convex solid needs at least 5 facets with non-zero normals")
            r = r / ln[:, None]
            lo, hi = _vec4(lo, "lo"), _vec4(hi, "hi")
            planes.append(r)
            ranges.append((start, start + len(r)))
            bounds.append(np.concatenate([lo, hi]))
            start += len(r)
        new = (
            np.concatenate(planes) if planes else np.zeros((0, 5)),
            np.array(ranges, dtype=np.int64).reshape(-1, 2),
            np.array(bounds, dtype=np.float64).reshape(-1, 8),
        )
        st = self.static
        old = (st.convex_planes, st.convex_ranges, st.convex_bounds)
        if all(a.shape == b.shape and np.array_equal(a, b) for a, b in zip(new, old)):
            return
        self.static = st._replace(convex_planes=new[0], convex_ranges=new[1], convex_bounds=new[2])
        self._forget_static_manifolds()
        # Wake sleepers near every convex solid before and after (changes are rare: a door opens).
        boxes = [np.concatenate([0.5 * (b[:4] + b[4:]), 0.5 * (b[4:] - b[:4]), np.eye(4).ravel()]) for b in old[2]]
        boxes += [np.concatenate([0.5 * (b[:4] + b[4:]), 0.5 * (b[4:] - b[:4]), np.eye(4).ravel()]) for b in new[2]]
        self._wake_near_solids(boxes)

    def set_static_tets(self, meshes: Iterable[np.ndarray], motions: Iterable[np.ndarray] | None = None) -> None:
        """Replace the tet meshes: each the boundary tets ``(T, 4, 4)`` of one solid, in the world.

        For solids that are neither boxes nor convex (an arch, a lifted asset):
        every tet is a 3-simplex of the solid's closed boundary, its corners
        ordered so that ``core.mesh.cross4`` of the edges from corner 0 points
        out of the solid (as :class:`~across_dimensions.core.mesh.TetMesh4` keeps
        them). Bodies meet each tet exactly (see :mod:`.tet_mesh`). As for
        :meth:`set_static_solids`, handing over the same arrays again changes
        nothing, sleeping bodies near a mesh that changed wake, and the meshes are
        not in :meth:`state_bytes` (the game hashes the poses they come from).
        Arrays handed over are kept (not copied): make new ones when a mesh moves.

        Parameters
        ----------
        meshes : iterable of (T, 4, 4) array_like
        motions : iterable of (4, 5) array_like, optional
            Each mesh's velocity field ``v(x) = A x + b`` as ``[A | b]`` (m/s), for a
            mesh that moves: a body resting on it is carried along (its contacts
            see the surface's velocity) rather than pushed out after it sank in.
            ``(M_new M_old^-1 - I)[:4] / dt`` for a pose change ``M_old -> M_new``
            over a tick ``dt``. Zero (a still mesh) when not given.
        """
        inputs = [np.asarray(m, dtype=np.float64).reshape(-1, 4, 4) for m in meshes]
        if motions is None:
            motion = np.zeros((len(inputs), 4, 5))
        else:
            motion = np.array([np.asarray(v, dtype=np.float64).reshape(4, 5) for v in motions]).reshape(-1, 4, 5)
            if len(motion) != len(inputs):
                raise ValueError(f"{len(inputs)} tet meshes but {len(motion)} motions")
        old = self._tet_inputs
        same = len(inputs) == len(old) and all(a is b or np.array_equal(a, b) for a, b in zip(inputs, old))
        if same:
            if not np.array_equal(motion, self.static.tet_motion):
                self.static = self.static._replace(tet_motion=motion)
            return
        parts, ranges, sweep = [], [], []
        start = 0
        for i, m in enumerate(inputs):
            if i < len(old) and (m is old[i] or np.array_equal(m, old[i])):
                geo, sw = self._tet_parts[i]  # this mesh stays: its geometry too
            else:
                geo = tet_geometry(m)
                # Sorted along the mesh's longest axis: a body meets one run of them (see tet_mesh).
                b = geo[3]
                ax = int(np.argmax(b[:, 4:].max(axis=0) - b[:, :4].min(axis=0))) if len(b) else 0
                order = np.argsort(b[:, ax], kind="stable")
                geo = tuple(np.ascontiguousarray(a[order]) for a in geo)
                sw = (ax, float((b[:, 4 + ax] - b[:, ax]).max()) if len(b) else 0.0)
            parts.append(geo)
            sweep.append(sw)
            ranges.append((start, start + len(geo[0])))
            start += len(geo[0])
        self._tet_parts = list(zip(parts, sweep))
        if parts:
            tets, planes, bary, bounds = (np.concatenate(a) for a in zip(*parts))
        else:
            tets, planes, bary, bounds = np.zeros((0, 4, 4)), np.zeros((0, 5)), np.zeros((0, 3, 4)), np.zeros((0, 8))
        mesh_bounds = np.array(
            [
                np.concatenate([bounds[a:b, :4].min(axis=0), bounds[a:b, 4:].max(axis=0)])
                if b > a
                else np.array([np.inf] * 4 + [-np.inf] * 4)
                for a, b in ranges
            ],
            dtype=np.float64,
        ).reshape(-1, 8)
        old_bounds = self.static.tet_mesh_bounds
        changed = []
        for i in range(max(len(inputs), len(old))):
            if i < len(inputs) and i < len(old) and (inputs[i] is old[i] or np.array_equal(inputs[i], old[i])):
                continue
            changed += [old_bounds[i]] if i < len(old) else []
            changed += [mesh_bounds[i]] if i < len(inputs) else []
        self._tet_inputs = inputs
        self.static = self.static._replace(
            tets=tets,
            tet_planes=planes,
            tet_bary=bary,
            tet_bounds=bounds,
            tet_ranges=np.array(ranges, dtype=np.int64).reshape(-1, 2),
            tet_mesh_bounds=mesh_bounds,
            tet_sweep=np.array(sweep, dtype=np.float64).reshape(-1, 2),
            tet_motion=motion,
        )
        # Wake sleepers near each mesh that moved, where it was and where it is now.
        rows = [
            np.concatenate([0.5 * (b[:4] + b[4:]), 0.5 * (b[4:] - b[:4]), np.eye(4).ravel()])
            for b in changed
            if np.all(np.isfinite(b))
        ]
        self._wake_near_solids(rows)

    def _wake_near_solids(self, rows) -> None:
        """Wake sleeping bodies whose bounding ball meets one of the solid boxes ``rows``."""
        n = self._n
        if not rows or n == 0:
            return
        b = self.bodies
        sleeping = np.flatnonzero(b.alive[:n] & ~b.awake[:n] & (b.kind[:n] == pl.DYNAMIC))
        for row in rows:
            ext = np.abs(row[8:].reshape(4, 4)) @ row[4:8]
            reach = b.bound[sleeping, None] + 4 * self.params["margin"][0]
            near = np.all(np.abs(b.position[sleeping] - row[:4]) <= ext + reach, axis=1)
            for j in sleeping[near]:
                self.wake(int(j))

    def _wake_all(self) -> None:
        if hasattr(self, "bodies"):
            n = self._n
            dyn = self.bodies.alive[:n] & (self.bodies.kind[:n] == pl.DYNAMIC)
            self.bodies.awake[:n][dyn] = True
            self.bodies.sleep_timer[:n][dyn] = 0.0

    # ------------------------------------------------------------------ stepping
    def step(self, dt: float) -> int:
        """Advance by ``dt`` seconds of game time in fixed ticks.

        Time is accumulated and whole ticks of ``tick_dt`` are run (at most
        ``max_ticks``); the remainder carries over to the next call. The
        contact events of the ticks run are in :attr:`events` until the next
        call (empty if this call ran no tick).

        Returns
        -------
        int
            Ticks run.
        """
        if not dt >= 0:
            raise ValueError("dt must be non-negative")
        h = self.tick_dt
        self._acc += float(dt)
        # The small tolerance makes 1/60 s run exactly one 1/60 s tick despite
        # rounding in the accumulator.
        n = int(np.floor(self._acc / h + 1e-6))
        self._acc = max(0.0, self._acc - n * h)
        if n > self.max_ticks:
            n = self.max_ticks
            self._acc = 0.0
        earlier: list[ContactEvent] = []
        for k in range(n):
            if k:
                # Catching up: keep the events of every tick of this step.
                earlier += self.events
            self.tick()
        self._events_earlier = earlier
        if n == 0:
            self._events_cache = []
        return n

    def tick(self) -> int:
        """Run exactly one tick of ``tick_dt`` (ignoring the accumulator).

        Returns
        -------
        int
            Number of contact points solved.
        """
        params = self.params
        if self.inverse_cube_G != 0.0:
            params = params.copy()
            params["allow_sleep"] = 0.0
        n = self._n
        self._prev_position[:n] = self.bodies.position[:n]
        self._prev_rotation[:n] = self.bodies.rotation[:n]
        while True:
            kept, kept_out = self._kept
            nc = pl.tick(
                self.bodies, self.static, params, self.contacts, self.warm, self._rows, self._scratch, kept, kept_out
            )
            if nc == -1:
                self._alloc_contacts(2 * int(self._scratch.needed[0]), self.contacts.key.shape[0])
            elif nc == -2:
                self._alloc_contacts(self._scratch.pairs.shape[0], 2 * int(self._scratch.needed[0]))
            else:
                break
        self._kept = (kept_out, kept)
        self.last_contact_count = nc
        self.time += self.tick_dt
        nt = touching_keys(nc, self.contacts, _TOUCH_TOL, self._touch_buf)
        self._touch_prev = self._touch_keys
        self._touch_keys = self._touch_buf[:nt].copy()
        self._events_cache = None
        self._events_earlier = []
        return nc

    @property
    def events(self) -> list[ContactEvent]:
        """Contact events of the ticks run by the last :meth:`step` (see :class:`ContactEvent`).

        One event per touching pair per tick. Built on first access from the
        tick's contacts, which stay untouched until the next tick runs. Pairs
        whose bodies fall asleep stop reporting; a touch after waking is new
        (``began``) again.
        """
        return self._events_earlier + self._last_tick_events()

    def _last_tick_events(self) -> list[ContactEvent]:
        if self._events_cache is None:
            nc = self.last_contact_count
            keys, ab, pts, nrm, imp = manifold_events(nc, self.contacts, _TOUCH_TOL)
            began = ~np.isin(keys, self._touch_prev)
            self._events_cache = [
                ContactEvent(
                    int(ab[e, 0]),
                    int(ab[e, 1]) if ab[e, 1] >= 0 else "world",
                    pts[e].copy(),
                    nrm[e].copy(),
                    float(imp[e]),
                    bool(began[e]),
                )
                for e in range(keys.shape[0])
            ]
        return self._events_cache

    # ------------------------------------------------------------------ determinism
    def state_bytes(self) -> bytes:
        """Everything that determines the future: bodies, sleep state, warm-start impulses, kept manifolds."""
        n = self._n
        warm = self.warm
        c = int(warm.count[0])
        parts = [np.array([n, c], dtype=np.int64), np.array([self.time, self._acc])]
        b = self.bodies
        for name in (
            "alive",
            "kind",
            "shape",
            "half_extents",
            "position",
            "rotation",
            "velocity",
            "angular_velocity",
            "mass",
            "inv_mass",
            "inv_inertia",
            "friction",
            "restitution",
            "awake",
            "sleep_timer",
            "island",
        ):
            parts.append(getattr(b, name)[:n])
        # The params record's bytes are those of its 25 float64 fields in order.
        kept = self._kept[0]
        k = int(kept.pairs[0])
        parts += [
            warm.key[:c],
            warm.local_point[:c],
            warm.normal_impulse[:c],
            warm.friction_impulse[:c],
            kept.key[:k],
            kept.count[:k],
            kept.axis[:k],
            kept.pose[:k],
        ]
        parts += [kept.local[f : f + n] for f, n in zip(kept.first[:k], kept.count[:k])]
        parts += [
            self.static.half_spaces,
            self.static.boxes,  # (the solids are not here: see set_static_solids)
            self.params,
        ]
        return b"".join(np.ascontiguousarray(a).tobytes() for a in parts)

    def state_hash(self) -> str:
        """SHA-256 hex digest of :meth:`state_bytes`."""
        return hashlib.sha256(self.state_bytes()).hexdigest()

    # ------------------------------------------------------------------ queries
    def raycast(self, origin, direction, max_dist: float = np.inf, include_world: bool = True):
        """First thing hit by a ray (bullets, picking).

        Parameters
        ----------
        origin, direction : (4,) array_like
            ``direction`` need not be unit length.
        max_dist : float
        include_world : bool
            Also hit the ground, half-spaces and world boxes (reported as ``"world"``).

        Returns
        -------
        tuple or None
            ``(body_id or "world", t, point (4,), normal (4,))`` with ``t`` the
            distance along the unit direction; bodies containing the origin are
            ignored.
        """
        o = _vec4(origin, "origin")
        d = _vec4(direction, "direction")
        ln = np.linalg.norm(d)
        if ln == 0:
            raise ValueError("direction must be non-zero")
        d /= ln
        normal = np.zeros(4)
        hit, t = raycast_kernel(self.bodies, self.static, o, d, float(max_dist), include_world, normal)
        if hit == -(1 << 62):
            return None
        who = int(hit) if hit >= 0 else "world"
        return who, float(t), o + t * d, normal

    def push_box_out(self, center, half_extents):
        """Shortest xyz move that takes an upright 4D box out of the bodies it overlaps.

        The box is axis-aligned and moves only in x, y and z: a thing that lives
        in the 3D slice at its w (the player, see
        :func:`across_dimensions.game.player_bodies.player_collide`). Bodies whose
        4D shape does not reach into its w slab are ignored.

        Parameters
        ----------
        center, half_extents : (4,) array_like

        Returns
        -------
        correction : (3,) float64
            xyz offset to add to the box's position.
        touched : list of int
            Ids of the bodies it overlapped, in id order.
        """
        c = _vec4(center, "center")
        h = _vec4(half_extents, "half_extents")
        touched = np.zeros(self._n, dtype=bool)
        corr = box_push_out_kernel(self.bodies, c, h, 4, touched)
        return corr, [int(i) for i in np.flatnonzero(touched)]

    # ------------------------------------------------------------------ debug drawing
    def debug_draw(self, drawer: DebugDrawer, w: float, options: DebugDrawOptions | None = None, boxes=()) -> None:
        """Report colliders, contacts and query ``boxes`` in the 3D slice at ``w`` to ``drawer``.

        See :func:`~across_dimensions.physics.debug_draw.debug_draw`; the world
        does not change.
        """
        debug_draw(self, drawer, w, options, boxes)
