"""The game-facing 4D rigid-body world.

>>> from across_dimensions.physics import BodyDef, PhysicsWorld, WorldDef
>>> world = PhysicsWorld(WorldDef(gravity=(0, -9.81, 0, 0)))  # ground plane y = 0
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

import numpy as np

from . import pipeline as pl
from .body_def import vec4
from .collide import SCRATCH_POINTS
from .debug_draw import DebugDrawer, DebugDrawOptions, debug_draw
from .events import ContactEvent, manifold_events, touching_keys
from .queries import box_push_out_kernel, raycast_kernel
from .state import (
    DYNAMIC,
    STATIC_KEY,
    Bodies,
    Scratch,
    new_contacts,
    new_manifolds,
    new_params,
    new_solver_rows,
    new_warm_start,
)
from .tet_mesh import CANDIDATES
from .world_bodies import WorldBodies
from .world_def import WorldDef
from .world_static import TetMeshes, WorldStatic, empty_static

#: Pairs closer than this (metres) count as touching for events.
_TOUCH_TOL = 1e-3


def _pair_involves(keys: np.ndarray, i: int) -> np.ndarray:
    """Which pair keys ``(k,) int64`` (``a << 32 | b``, see :mod:`.pipeline`) name body ``i``."""
    a = keys >> 32
    b = keys & 0xFFFFFFFF
    return (a == i) | ((b == i) & (b < STATIC_KEY))


class PhysicsWorld(WorldBodies, WorldStatic):
    """4D rigid bodies (hyperspheres, boxes) against each other and a 3D world.

    The methods on bodies are those of :class:`~.world_bodies.WorldBodies`, the
    ones on the static world those of :class:`~.world_static.WorldStatic`.

    Parameters
    ----------
    definition : WorldDef, optional
        The world's settings (see :class:`~.world_def.WorldDef` for each and its
        default); ``WorldDef()`` when not given.

    Attributes
    ----------
    definition : WorldDef
        The settings the world was made with (gravity, ``inverse_cube_G`` and
        ``allow_sleep`` may change since: read them from the world).
    bodies : Bodies
        Every body slot (see :mod:`.state`); read it, change bodies through the methods.
    static : StaticWorld
        Half-spaces and 3D world boxes.
    params : (1,) PARAMS_DTYPE record array
        The tuning values of the definition, by name (``params["max_push"]``).
    contacts : Contacts
        The last tick's contacts; the first :attr:`last_contact_count` are valid.
    warm : WarmStart
        The impulses the next tick starts from.
    """

    def __init__(self, definition: WorldDef | None = None):
        d = WorldDef() if definition is None else definition
        if not isinstance(d, WorldDef):
            raise TypeError(f"PhysicsWorld takes a WorldDef, got {type(d).__name__}")
        self.definition = d
        self.params = new_params()
        d.write_params(self.params)
        self.tick_dt = float(d.tick_dt)
        self.substeps = int(d.substeps)
        self.gravity = d.gravity
        self.inverse_cube_G = d.inverse_cube_G
        self.allow_sleep = d.allow_sleep
        self.max_ticks = int(d.max_ticks)
        self.time = 0.0
        self._acc = 0.0
        self._alloc_bodies(16)
        self.static = empty_static()
        self._tets = TetMeshes()
        if d.ground:
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
        self.params["gravity"] = vec4(value, "gravity")
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
            return  # (the ground is added before the buffers exist)
        kept = self._kept[0]
        self._forget_manifolds((kept.key[: int(kept.pairs[0])] & 0xFFFFFFFF) >= STATIC_KEY)

    def _wake_all(self) -> None:
        if hasattr(self, "bodies"):
            n = self._n
            dyn = self.bodies.alive[:n] & (self.bodies.kind[:n] == DYNAMIC)
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
            nc = pl.tick(
                self.bodies, self.static, params, self.contacts, self.warm, self._rows, self._scratch, self._kept
            )
            if nc == -1:
                self._alloc_contacts(2 * int(self._scratch.needed[0]), self.contacts.key.shape[0])
            elif nc == -2:
                self._alloc_contacts(self._scratch.pairs.shape[0], 2 * int(self._scratch.needed[0]))
            else:
                break
        self._kept = self._kept[::-1]
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
        o = vec4(origin, "origin")
        d = vec4(direction, "direction")
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
        c = vec4(center, "center")
        h = vec4(half_extents, "half_extents")
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
