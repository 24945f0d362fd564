"""The game-facing 4D rigid-body world.

>>> from across_dimensions.physics import PhysicsWorld
>>> world = PhysicsWorld(gravity=(0, -9.81, 0, 0))          # ground plane y = 0
>>> ball = world.add_body("hypersphere", radius=0.5, position=(0, 2, 0, 0.3))
>>> box = world.add_body("hypercube", size=1.0, position=(2, 0.5, 0, 0),
...                      angles={"xw": 0.3})
>>> world.step(1 / 60)                                      # one fixed tick
1
>>> model = world.body_pose(ball)                           # (5, 5) model matrix

Bodies are kept in flat arrays indexed by id (ids are never reused) so that the
compiled pipeline (:mod:`.pipeline`) can step them without Python overhead.
``step(dt)`` feeds a time accumulator and runs whole ticks of the fixed
``tick_dt`` (each split into fixed substeps); the same sequence of calls
therefore gives bit-identical states (:meth:`PhysicsWorld.state_hash`).
"""

from __future__ import annotations

import hashlib
from typing import Iterable, Mapping, Sequence

import numpy as np

from across_dimensions.core import transform

from . import pipeline as pl
from .bivector import world_inverse_inertia
from .collide import BOX, SCRATCH_POINTS, SPHERE
from .events import ContactEvent, manifold_events, touching_keys
from .mass import box_inertia, box_volume, hypersphere_inertia, hypersphere_volume
from .queries import player_kernel, raycast_kernel

#: Pairs closer than this (metres) count as touching for events.
_TOUCH_TOL = 1e-3

_KINDS = {"static": pl.STATIC, "kinematic": pl.KINEMATIC, "dynamic": pl.DYNAMIC}
_SHAPES = {"hypersphere": SPHERE, "sphere": SPHERE, "ball": SPHERE,
           "hypercube": BOX, "box": BOX, "tesseract": BOX}


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
    """

    def __init__(self, gravity=(0.0, -9.81, 0.0, 0.0), inverse_cube_G: float = 0.0, *,
                 ground: bool = True, tick_dt: float = 1.0 / 60.0, substeps: int = 4,
                 iterations: int = 1, relax_iterations: int = 1, allow_sleep: bool = True,
                 max_ticks: int = 4, world_friction: float = 0.6,
                 world_restitution: float = 0.0, sleep_time: float = 0.5,
                 softening: float = 0.05, contact_hertz: float = 30.0,
                 damping_ratio: float = 10.0, max_push: float = 3.0,
                 spin_friction: float = 0.1, rolling_resistance: float = 0.0):
        self.params = np.zeros(pl.N_PARAMS)
        if not tick_dt > 0 or int(substeps) < 1:
            raise ValueError("tick_dt must be positive and substeps at least 1")
        self.tick_dt = float(tick_dt)
        self.substeps = int(substeps)
        self.gravity = gravity
        self.inverse_cube_G = inverse_cube_G
        p = self.params
        p[pl.P_DT] = self.tick_dt
        p[pl.P_SUBSTEPS] = self.substeps
        p[pl.P_SOFTEN] = softening
        p[pl.P_MARGIN] = 0.02
        p[pl.P_HERTZ] = contact_hertz
        p[pl.P_ZETA] = damping_ratio
        p[pl.P_MAXPUSH] = max_push
        p[pl.P_RESTTHR] = 0.5
        p[pl.P_SPINR] = spin_friction
        p[pl.P_ROLL] = rolling_resistance
        p[pl.P_SLEEPLIN] = 0.05
        p[pl.P_SLEEPANG] = 0.1
        p[pl.P_SLEEPTIME] = sleep_time
        p[pl.P_ITERS] = iterations
        p[pl.P_RELAX] = relax_iterations
        p[pl.P_WORLDMU] = world_friction
        p[pl.P_WORLDE] = world_restitution
        self.allow_sleep = allow_sleep
        self.max_ticks = int(max_ticks)
        self.time = 0.0
        self._acc = 0.0
        self._n = 0
        self._alloc_bodies(16)
        self._half_spaces = np.zeros((0, 5))
        self._boxes = np.zeros((0, 6))
        if ground:
            self.add_half_space((0.0, 1.0, 0.0, 0.0), 0.0)
        self._alloc_contacts(256, 256)
        self._scratch_p = np.zeros((SCRATCH_POINTS, 4))
        self._scratch_d = np.zeros(SCRATCH_POINTS)
        self._touch_keys = np.zeros(0, dtype=np.int64)
        self._touch_prev = np.zeros(0, dtype=np.int64)
        self._events_cache: list[ContactEvent] | None = []
        self._events_earlier: list[ContactEvent] = []
        self.last_contact_count = 0

    # ------------------------------------------------------------------ settings
    @property
    def gravity(self) -> np.ndarray:
        """Gravity ``(4,) float64`` (a copy); assign to change it per level."""
        return self.params[pl.P_G:pl.P_G + 4].copy()

    @gravity.setter
    def gravity(self, value) -> None:
        self.params[pl.P_G:pl.P_G + 4] = _vec4(value, "gravity")
        self._wake_all()  # sleepers must feel the new pull

    @property
    def inverse_cube_G(self) -> float:
        """Strength ``G`` of the mutual ``G m1 m2 / r^3`` attraction (0 = off)."""
        return float(self.params[pl.P_INVCUBE])

    @inverse_cube_G.setter
    def inverse_cube_G(self, value: float) -> None:
        self.params[pl.P_INVCUBE] = float(value)
        self._wake_all()

    @property
    def allow_sleep(self) -> bool:
        return bool(self.params[pl.P_ALLOWSLEEP])

    @allow_sleep.setter
    def allow_sleep(self, value: bool) -> None:
        self.params[pl.P_ALLOWSLEEP] = 1.0 if value else 0.0
        if not value and hasattr(self, "awake"):
            self.awake[: self._n] = True

    # ------------------------------------------------------------------ storage
    def _alloc_bodies(self, cap: int) -> None:
        old = getattr(self, "alive", None)
        fields = {
            "alive": ((), bool), "kind": ((), np.int8), "shape": ((), np.int8),
            "half": ((4,), np.float64), "bound": ((), np.float64),
            "pos": ((4,), np.float64), "rot": ((4, 4), np.float64),
            "vel": ((4,), np.float64), "omg": ((6,), np.float64),
            "mass": ((), np.float64), "inv_mass": ((), np.float64),
            "inv_inertia": ((6,), np.float64), "mu": ((), np.float64),
            "rest": ((), np.float64), "awake": ((), bool), "timer": ((), np.float64),
            "island": ((), np.int64),
            # Poses at the start of the last tick, for render interpolation.
            "prev_pos": ((4,), np.float64), "prev_rot": ((4, 4), np.float64),
        }
        for name, (shape, dtype) in fields.items():
            arr = np.zeros((cap,) + shape, dtype=dtype)
            if old is not None:
                arr[: self._n] = getattr(self, name)[: self._n]
            setattr(self, name, arr)
        self._marg = np.zeros(cap)

    def _alloc_contacts(self, pair_cap: int, contact_cap: int) -> None:
        self._pairs = np.zeros((pair_cap, 2), dtype=np.int64)
        old = getattr(self, "_ok", None)
        cnt = int(self._ocnt[0]) if old is not None else 0
        self._ci = np.zeros((contact_cap, 3), dtype=np.int64)
        self._cp = np.zeros((contact_cap, 4))
        self._cn = np.zeros((contact_cap, 4))
        self._cd = np.zeros(contact_cap)
        self._clam = np.zeros((contact_cap, 4))
        self._ctot = np.zeros(contact_cap)
        self._work = pl.solver_work(contact_cap)
        self._touch_buf = np.zeros(contact_cap, dtype=np.int64)
        ok = np.zeros(contact_cap, dtype=np.int64)
        oloc = np.zeros((contact_cap, 4))
        olam = np.zeros(contact_cap)
        oft = np.zeros((contact_cap, 4))
        if old is not None:
            ok[:cnt] = self._ok[:cnt]
            oloc[:cnt] = self._oloc[:cnt]
            olam[:cnt] = self._olam[:cnt]
            oft[:cnt] = self._oft[:cnt]
        self._ok, self._oloc, self._olam, self._oft = ok, oloc, olam, oft
        self._ocnt = np.array([cnt, 0], dtype=np.int64)

    def _check(self, body_id: int) -> int:
        i = int(body_id)
        if not (0 <= i < self._n) or not self.alive[i]:
            raise KeyError(f"no body with id {body_id}")
        return i

    # ------------------------------------------------------------------ bodies
    def add_body(self, shape: str = "hypersphere", size=None, *, radius: float | None = None,
                 position=(0.0, 0.0, 0.0, 0.0), rotation=None,
                 angles: Mapping[str, float] | None = None, velocity=None,
                 angular_velocity=None, mass: float | None = None, density: float = 1.0,
                 kind: str = "dynamic", restitution: float = 0.1,
                 friction: float = 0.5) -> int:
        """Add a body and return its id.

        Parameters
        ----------
        shape : {"hypersphere", "hypercube"}
            ``"box"`` and ``"tesseract"`` are accepted for "hypercube".
        size : float or (4,) array_like, optional
            Hypercube: edge length, or the four edge lengths of a box (its
            inertia is then anisotropic). Hypersphere: diameter, if ``radius``
            is not given. Default 1.
        radius : float, optional
            Hypersphere radius.
        position : (4,) array_like
            Centre, metres.
        rotation : (4, 4) array_like or mapping of plane to angle, optional
        angles : mapping of plane name to radians, optional
            Alternative to ``rotation`` (see :func:`transform.angles_to_rotation`).
        velocity : (4,) array_like, optional
        angular_velocity : (6,) array_like or mapping of plane to rad/s, optional
            Bivector in ``xy xz yz xw yw zw`` order.
        mass : float, optional
            Overrides ``density * hypervolume``.
        density : float
            kg per m^4.
        kind : {"dynamic", "kinematic", "static"}
            Kinematic bodies move with the velocity you set and push others
            without being pushed; static ones never move.
        restitution : float
            Bounciness in [0, 1]; a pair uses the larger of its two values.
        friction : float
            Coulomb coefficient; a pair uses the geometric mean.

        Returns
        -------
        int
            The body id, stable until :meth:`remove_body`.
        """
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
        m = float(mass) if mass is not None else float(density) * volume
        if not m > 0:
            raise ValueError("mass must be positive")
        inertia = hypersphere_inertia(m, half[0]) if sh == SPHERE else box_inertia(m, half)
        if self._n == self.alive.shape[0]:
            self._alloc_bodies(2 * self.alive.shape[0])
        i = self._n
        self._n += 1
        k = _KINDS[kind]
        self.alive[i] = True
        self.kind[i] = k
        self.shape[i] = sh
        self.half[i] = half
        self.bound[i] = half[0] if sh == SPHERE else float(np.linalg.norm(half))
        self.pos[i] = _vec4(position, "position")
        self.rot[i] = _rotation(rotation, angles)
        self.vel[i] = _vec4(velocity, "velocity") if k != pl.STATIC else 0.0
        self.omg[i] = _bivector(angular_velocity) if k != pl.STATIC else 0.0
        self.mass[i] = m
        self.inv_mass[i] = 1.0 / m if k == pl.DYNAMIC else 0.0
        self.inv_inertia[i] = 1.0 / inertia if k == pl.DYNAMIC else 0.0
        self.mu[i] = friction
        self.rest[i] = restitution
        self.awake[i] = True
        self.timer[i] = 0.0
        self.island[i] = i
        self.prev_pos[i] = self.pos[i]
        self.prev_rot[i] = self.rot[i]
        return i

    def remove_body(self, body_id: int) -> None:
        """Delete a body; sleeping bodies near it wake (they may have rested on it)."""
        i = self._check(body_id)
        self._wake_near(i)
        self.alive[i] = False
        self.awake[i] = False
        self.vel[i] = 0.0
        self.omg[i] = 0.0

    def _wake_near(self, i: int) -> None:
        n = self._n
        d = np.linalg.norm(self.pos[:n] - self.pos[i], axis=1)
        near = d <= self.bound[:n] + self.bound[i] + 4 * self.params[pl.P_MARGIN]
        for j in np.flatnonzero(near & self.alive[:n] & ~self.awake[:n]):
            self.wake(int(j))

    @property
    def body_ids(self) -> list[int]:
        """Ids of the bodies that exist."""
        return [int(i) for i in np.flatnonzero(self.alive[: self._n])]

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
            m[:4, :4] = self.rot[i]
            m[:4, 4] = self.pos[i]
        else:
            a = max(0.0, float(alpha))
            m[:4, :4] = transform.orthonormalize((1 - a) * self.prev_rot[i] + a * self.rot[i])
            m[:4, 4] = (1 - a) * self.prev_pos[i] + a * self.pos[i]
        return m

    @property
    def tick_fraction(self) -> float:
        """Time accumulated towards the next tick, as a fraction of ``tick_dt`` in [0, 1)."""
        return min(self._acc / self.tick_dt, 1.0)

    def body_position(self, body_id: int) -> np.ndarray:
        """Centre ``(4,) float64`` (a copy)."""
        return self.pos[self._check(body_id)].copy()

    def body_rotation(self, body_id: int) -> np.ndarray:
        """Rotation ``(4, 4) float64`` (a copy)."""
        return self.rot[self._check(body_id)].copy()

    def body_velocity(self, body_id: int) -> tuple[np.ndarray, np.ndarray]:
        """Linear ``(4,)`` and angular ``(6,)`` velocity (copies)."""
        i = self._check(body_id)
        return self.vel[i].copy(), self.omg[i].copy()

    def body_mass(self, body_id: int) -> float:
        return float(self.mass[self._check(body_id)])

    def body_inertia(self, body_id: int) -> np.ndarray:
        """World-frame inertia ``(6, 6) float64`` on bivectors (dynamic bodies)."""
        i = self._check(body_id)
        inv = np.zeros((6, 6))
        world_inverse_inertia(self.rot[i], self.inv_inertia[i], inv)
        return np.linalg.inv(inv)

    def set_velocity(self, body_id: int, velocity=None, angular_velocity=None) -> None:
        """Set linear ``(4,)`` and/or angular ``(6,)`` velocity and wake the body."""
        i = self._check(body_id)
        if self.kind[i] == pl.STATIC:
            raise ValueError("static bodies cannot move; use kind='kinematic'")
        if velocity is not None:
            self.vel[i] = _vec4(velocity, "velocity")
        if angular_velocity is not None:
            self.omg[i] = _bivector(angular_velocity)
        self.wake(i)

    def set_pose(self, body_id: int, position=None, rotation=None) -> None:
        """Teleport a body (typically a kinematic one) and wake whatever it now touches."""
        i = self._check(body_id)
        if position is not None:
            self.pos[i] = _vec4(position, "position")
        if rotation is not None:
            self.rot[i] = _rotation(rotation)
        self._wake_near(i)
        if self.kind[i] == pl.DYNAMIC:
            self.wake(i)

    def push(self, body_id: int, impulse, point=None) -> None:
        """Apply an impulse ``(4,)`` (N s) to a dynamic body, at its centre or at ``point``.

        Off-centre pushes also spin the body: ``dw = I^-1 (r ^ impulse)``.
        Static and kinematic bodies ignore pushes.
        """
        i = self._check(body_id)
        if self.kind[i] != pl.DYNAMIC:
            return
        p = _vec4(impulse, "impulse")
        self.wake(i)
        self.vel[i] += p * self.inv_mass[i]
        if point is not None:
            r = _vec4(point, "point") - self.pos[i]
            tau = np.array([r[a] * p[b] - r[b] * p[a]
                            for a, b in ((0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3))])
            inv = np.zeros((6, 6))
            world_inverse_inertia(self.rot[i], self.inv_inertia[i], inv)
            self.omg[i] += inv @ tau

    def wake(self, body_id: int) -> None:
        """Wake a body and the sleeping island it belongs to."""
        i = self._check(body_id)
        if self.kind[i] != pl.DYNAMIC:
            return
        if not self.awake[i]:
            n = self._n
            group = self.alive[:n] & ~self.awake[:n] & (self.island[:n] == self.island[i])
            group &= self.kind[:n] == pl.DYNAMIC
            self.awake[:n][group] = True
            self.timer[:n][group] = 0.0
        self.awake[i] = True
        self.timer[i] = 0.0

    def is_sleeping(self, body_id: int) -> bool:
        i = self._check(body_id)
        return bool(self.kind[i] == pl.DYNAMIC and not self.awake[i])

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
        self._half_spaces = np.vstack([self._half_spaces, row[None]])
        self._wake_all()
        return self._half_spaces.shape[0] - 1

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
        self._boxes = np.array(rows, dtype=np.float64).reshape(-1, 6)
        self._wake_all()

    def _wake_all(self) -> None:
        if hasattr(self, "awake"):
            n = self._n
            dyn = self.alive[:n] & (self.kind[:n] == pl.DYNAMIC)
            self.awake[:n][dyn] = True
            self.timer[:n][dyn] = 0.0

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
        p = self.params
        if self.inverse_cube_G != 0.0:
            p = p.copy()
            p[pl.P_ALLOWSLEEP] = 0.0
        n = self._n
        self.prev_pos[:n] = self.pos[:n]
        self.prev_rot[:n] = self.rot[:n]
        while True:
            nc = pl.tick(self._n, self.alive, self.kind, self.shape, self.half, self.bound,
                         self.pos, self.rot, self.vel, self.omg, self.mass, self.inv_mass,
                         self.inv_inertia, self.mu, self.rest, self.awake, self.timer,
                         self.island, self._half_spaces, self._boxes, p, self._pairs,
                         self._marg, self._scratch_p, self._scratch_d, self._ci, self._cp,
                         self._cn, self._cd, self._clam, self._ctot, self._ok, self._oloc, self._olam,
                         self._oft, self._ocnt, self._work)
            if nc == -1:
                self._alloc_contacts(2 * int(self._ocnt[1]), self._ci.shape[0])
            elif nc == -2:
                self._alloc_contacts(self._pairs.shape[0], 2 * int(self._ocnt[1]))
            else:
                break
        self.last_contact_count = nc
        self.time += self.tick_dt
        nt = touching_keys(nc, self._ci, self._cd, self._ctot, _TOUCH_TOL, self._touch_buf)
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
            keys, ab, pts, nrm, imp = manifold_events(nc, self._ci, self._cp, self._cn,
                                                      self._cd, self._ctot, _TOUCH_TOL)
            began = ~np.isin(keys, self._touch_prev)
            self._events_cache = [
                ContactEvent(int(ab[e, 0]), int(ab[e, 1]) if ab[e, 1] >= 0 else "world",
                             pts[e].copy(), nrm[e].copy(), float(imp[e]), bool(began[e]))
                for e in range(keys.shape[0])
            ]
        return self._events_cache

    # ------------------------------------------------------------------ determinism
    def state_bytes(self) -> bytes:
        """Everything that determines the future: bodies, sleep state, warm-start cache."""
        n = self._n
        parts = [np.array([n, self._ocnt[0]], dtype=np.int64), np.array([self.time, self._acc])]
        for name in ("alive", "kind", "shape", "half", "pos", "rot", "vel", "omg", "mass",
                     "inv_mass", "inv_inertia", "mu", "rest", "awake", "timer", "island"):
            parts.append(getattr(self, name)[:n])
        c = int(self._ocnt[0])
        parts += [self._ok[:c], self._oloc[:c], self._olam[:c], self._oft[:c],
                  self._half_spaces, self._boxes, self.params]
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
        hit, t = raycast_kernel(self._n, self.alive, self.shape, self.half, self.pos, self.rot,
                                self._half_spaces, self._boxes, o, d, float(max_dist),
                                include_world, normal)
        if hit == -(1 << 62):
            return None
        who = int(hit) if hit >= 0 else "world"
        return who, float(t), o + t * d, normal

    def player_collide(self, position, radius: float, height: float, w_half: float = 0.05,
                       velocity=None):
        """Push a player out of the bodies in its w slab.

        The player is the upright box ``[x +- radius] x [y, y + height] x
        [z +- radius] x [w +- w_half]`` with ``position = (x, y, z, w)`` its feet.
        Bodies whose 4D shape does not reach into the slab are ignored.

        Parameters
        ----------
        position : (4,) array_like
        radius, height, w_half : float
        velocity : (3,) or (4,) array_like, optional
            The player's velocity. If given, touched dynamic bodies that the
            player walks into get the impulse that makes them move at least
            as fast as the player along its direction of motion (pushing).

        Returns
        -------
        correction : (3,) float64
            xyz offset to add to the player's position.
        touched : list of int
            Ids of the bodies in contact (push the dynamic ones with :meth:`push`).
        """
        feet = _vec4(position, "position")
        touched = np.zeros(self._n, dtype=bool)
        corr = player_kernel(self._n, self.alive, self.shape, self.half, self.pos, self.rot,
                             feet, float(radius), float(height), float(w_half), 4, touched)
        ids = [int(i) for i in np.flatnonzero(touched)]
        if velocity is not None:
            v = np.zeros(4)
            vv = np.asarray(velocity, dtype=np.float64).reshape(-1)
            v[: vv.shape[0]] = vv
            speed = np.linalg.norm(v)
            if speed > 0:
                d = v / speed
                for i in ids:
                    if self.kind[i] != pl.DYNAMIC:
                        continue
                    # Only bodies ahead of the player: behind ones are not pushed.
                    if (self.pos[i] - feet) @ d <= 0:
                        continue
                    lag = speed - self.vel[i] @ d
                    if lag > 0:
                        self.push(i, self.mass[i] * lag * d)
        return corr, ids
