"""The data one physics tick works on, as named tuples of arrays (the step context).

Box2D hands its solver one ``b2StepContext`` and plain structs with descriptive
fields; numba cannot take classes, but it takes named tuples of arrays and
record arrays, which read the same. :func:`~across_dimensions.physics.pipeline.tick`
receives

* :class:`Bodies` - every body slot (the world's state, updated in place);
* :class:`StaticWorld` - half-spaces, 3D world boxes, 4D solid boxes, convex solids and tet meshes;
* ``params`` - a ``(1,)`` record array of :data:`PARAMS_DTYPE` (tuning values);
* :class:`Contacts` - this tick's contact points, filled by the narrowphase;
* :class:`WarmStart` - last tick's impulses, keyed by pair, replaced each tick;
* :class:`SolverRows` (with :class:`SpinRows`) - per-contact solver rows;
* :class:`Scratch` - buffers the broadphase and narrowphase reuse;
* :class:`Manifolds` - the last tick's box manifolds in the bodies' frames.

The stages of a tick hand each other smaller bundles: :class:`Points` (what a
narrowphase routine writes), :class:`Inertia` (the bodies' world-frame inverse
inertias, from the contact preparation) and :class:`Softness` (the soft
push-out of one substep, Box2D's ``b2Softness``).

All arrays are indexed by body id (``N`` slots) or contact index (``C``
capacity); only the first ``Bodies.count`` bodies and the first ``n`` contacts
a tick reports are meaningful. A contact's second body ``b`` is ``-1 - s`` for
static world collider ``s`` (half-spaces first, then world boxes, solid boxes, convex solids, tet meshes): those rows
have no second body.

Kernels take the arrays out of the bundles once, before their loops: reading a
bundle's field inside a hot loop costs numba a reference-count update per
iteration (measured: 15% on the contact preparation).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

#: Body kinds (``Bodies.kind``).
STATIC = 0
KINEMATIC = 1
DYNAMIC = 2

#: Pair-key offset for static world colliders (body indices stay below it).
STATIC_KEY = 1 << 30

#: Tuning values of a world, one record. The field order and the float64 type
#: of every field (even the counts) are part of the saved state: the bytes of
#: this record enter :meth:`PhysicsWorld.state_hash`, which the shipped replays check.
PARAMS_DTYPE = np.dtype(
    [
        ("tick_dt", np.float64),  # tick length, s (contacts are found once per tick)
        ("gravity", np.float64, (4,)),  # m/s^2
        ("inverse_cube_G", np.float64),  # strength of the mutual G m1 m2 / r^3 pull; 0 = off
        ("softening", np.float64),  # m, added in quadrature to distances in that pull
        ("margin", np.float64),  # m, speculative contact distance at rest
        ("substeps", np.float64),  # solver substeps per tick (a count)
        ("contact_hertz", np.float64),  # stiffness of the push-out of overlaps
        ("damping_ratio", np.float64),  # its damping ratio
        ("max_push", np.float64),  # m/s, top speed of the push-out
        ("restitution_threshold", np.float64),  # m/s, slower approaches do not bounce
        ("sleep_linear", np.float64),  # m/s, calm below this speed...
        ("sleep_angular", np.float64),  # rad/s, ...and this spin
        ("sleep_time", np.float64),  # s an island must stay calm to sleep
        ("allow_sleep", np.float64),  # 1.0 or 0.0
        ("iterations", np.float64),  # solver sweeps per substep with push-out (a count)
        ("relax_iterations", np.float64),  # sweeps without it (a count)
        ("world_friction", np.float64),  # material of the static world
        ("world_restitution", np.float64),
        ("linear_damping", np.float64),  # 1/s
        ("angular_damping", np.float64),  # 1/s
        ("spin_friction", np.float64),  # contact-patch radius of a ball / its radius
        ("rolling_resistance", np.float64),  # ball rolling-resistance coefficient
        ("reuse_distance", np.float64),  # m, a box manifold is reused while its pair moves less
        ("reuse_angle", np.float64),  # rad, ...and turns less than this (0 turns reuse off)
    ]
)


class Bodies(NamedTuple):
    """Every body slot; ids index the arrays (a removed body's slot is reused, lowest first).

    Attributes
    ----------
    count : int
        Slots in use (the arrays may be longer).
    alive : (N,) bool
    kind : (N,) int8
        :data:`STATIC`, :data:`KINEMATIC` or :data:`DYNAMIC`.
    shape : (N,) int8
        ``SPHERE`` or ``BOX`` (see :mod:`.collide`).
    half_extents : (N, 4) float64
        Box half extents in the body frame; a sphere's radius in column 0.
    bound : (N,) float64
        Bounding radius.
    position : (N, 4) float64
    rotation : (N, 4, 4) float64
        Body to world.
    velocity : (N, 4) float64
    angular_velocity : (N, 6) float64
        World-frame bivector, ``xy xz yz xw yw zw``.
    mass, inv_mass : (N,) float64
        Zero inverse mass for static and kinematic bodies.
    inv_inertia : (N, 6) float64
        Body-frame inverse inertia on the six planes.
    friction, restitution : (N,) float64
    awake : (N,) bool
    sleep_timer : (N,) float64
        Seconds the body has been calm.
    island : (N,) int64
        Island id of a sleeping body (the root body of its island).
    """

    count: int
    alive: np.ndarray
    kind: np.ndarray
    shape: np.ndarray
    half_extents: np.ndarray
    bound: np.ndarray
    position: np.ndarray
    rotation: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray
    mass: np.ndarray
    inv_mass: np.ndarray
    inv_inertia: np.ndarray
    friction: np.ndarray
    restitution: np.ndarray
    awake: np.ndarray
    sleep_timer: np.ndarray
    island: np.ndarray


class StaticWorld(NamedTuple):
    """Colliders that never move.

    Attributes
    ----------
    half_spaces : (K, 5) float64
        Solids ``n . x <= offset`` as rows ``(n, offset)``, ``n`` unit.
    boxes : (M, 6) float64
        3D world boxes ``(center, half)`` spanning all of w.
    solids : (S, 24) float64
        4D boxes of the level's solid objects, as rows ``(center (4), half
        extents (4), rotation (16, row-major, local to world))``: the game sets
        them from its solid objects' poses (``PhysicsWorld.set_static_solids``).
    convex_planes : (P, 5) float64
        Facet half-spaces ``(n, offset)`` (``n`` unit, pointing out of the
        solid) of the level's convex solid objects, one run of rows each.
    convex_ranges : (Q, 2) int64
        Each convex solid's rows ``[start, end)`` in ``convex_planes``.
    convex_bounds : (Q, 8) float64
        Each convex solid's bounds ``(lo (4), hi (4))``.
    tets : (T, 4, 4) float64
        Boundary tets of the level's other solid objects (not boxes, not convex),
        in the world, outward (see :mod:`.tet_mesh`), one run of rows per object.
    tet_planes : (T, 5) float64
        Each tet's hyperplane ``(n, offset)``, ``n`` the unit outward normal.
    tet_bary : (T, 3, 4) float64
        Each tet's barycentric map (:func:`.tet_mesh.tet_geometry`).
    tet_bounds : (T, 8) float64
        Each tet's bounds ``(lo (4), hi (4))``.
    tet_ranges : (R, 2) int64
        Each tet mesh's rows ``[start, end)``.
    tet_mesh_bounds : (R, 8) float64
        Each tet mesh's bounds.
    tet_sweep : (R, 2) float64
        Each tet mesh's sort axis (its longest) and its longest tet along it: the
        mesh's tets are sorted by their low bound along that axis.
    tet_motion : (R, 4, 5) float64
        Each tet mesh's velocity field ``v(x) = A x + b`` as ``[A | b]``: zero for a
        mesh that stays, the last tick's pose change over its length for one that moves.
    """

    half_spaces: np.ndarray
    boxes: np.ndarray
    solids: np.ndarray
    convex_planes: np.ndarray
    convex_ranges: np.ndarray
    convex_bounds: np.ndarray
    tets: np.ndarray
    tet_planes: np.ndarray
    tet_bary: np.ndarray
    tet_bounds: np.ndarray
    tet_ranges: np.ndarray
    tet_mesh_bounds: np.ndarray
    tet_sweep: np.ndarray
    tet_motion: np.ndarray


class Contacts(NamedTuple):
    """One tick's contact points, sorted by pair key.

    Attributes
    ----------
    body_a : (C,) int64
    body_b : (C,) int64
        Other body, or ``-1 - s`` for static world collider ``s``.
    key : (C,) int64
        Pair key ``(a << 32) | b`` (static colliders offset by ``STATIC_KEY``).
    point : (C, 4) float64
    normal : (C, 4) float64
        Unit normal from a to b.
    depth : (C,) float64
        Overlap (negative: a speculative gap).
    normal_impulse : (C,) float64
        Normal impulse summed over the tick's substeps (for events).
    surface_velocity : (C, 4) float64
        Velocity of a static collider's surface at the point: non-zero only for a
        tet mesh that moved since the last tick (a turning object), so a body on it
        is carried instead of sinking in while the push-out catches up.
    """

    body_a: np.ndarray
    body_b: np.ndarray
    key: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    depth: np.ndarray
    normal_impulse: np.ndarray
    surface_velocity: np.ndarray


class Manifolds(NamedTuple):
    """Box contact manifolds kept in the bodies' own frames, sorted by pair key.

    A pair whose relative pose has changed by less than the ``reuse_distance``
    and ``reuse_angle`` parameters since its manifold was found reuses it:
    its points ride along with the two bodies and only their depths are
    measured again (the narrowphase of two 4D boxes costs far more).

    Attributes
    ----------
    key : (P,) int64
        Pair keys, sorted.
    first, count : (P,) int64
        Each pair's rows of ``local``.
    axis : (P,) int64
        For two boxes found apart (``count`` 0): the candidate axis of
        :func:`~.collide.box_box` that separated them, tried first next
        tick; -1 for a manifold.
    pose : (P, 20) float64
        The pair's pose when its manifold was found: b's centre in a's frame
        (4), then ``R_a^T R_b`` (16, row-major). A static collider's frame is
        the world's (a solid box's is its own).
    local : (C, 12) float64
        Per point: its place on a's surface in a's frame, on b's surface in
        b's frame, and the normal in a's frame.
    pairs : (1,) int64
        Number of pairs stored.
    """

    key: np.ndarray
    first: np.ndarray
    count: np.ndarray
    axis: np.ndarray
    pose: np.ndarray
    local: np.ndarray
    pairs: np.ndarray


class WarmStart(NamedTuple):
    """Last tick's contact impulses, to start this tick's solve near the answer.

    Attributes
    ----------
    key : (C,) int64
        Pair keys, sorted.
    local_point : (C, 4) float64
        Contact point in body a's frame (matches the same material point).
    normal_impulse : (C,) float64
    friction_impulse : (C, 4) float64
        Friction impulse as a world vector (tangent frames change between ticks).
    count : (1,) int64
        Contacts stored.
    """

    key: np.ndarray
    local_point: np.ndarray
    normal_impulse: np.ndarray
    friction_impulse: np.ndarray
    count: np.ndarray


class SpinRows(NamedTuple):
    """Spin friction and rolling resistance of contacts with a ball (see :func:`.solver._prepare_spins`).

    Attributes
    ----------
    limits : (C, 2) float64
        Torque limits per unit normal impulse: spin, rolling; 0 turns a group off.
    planes : (C, 6, 6) float64
        Unit bivectors the rows act on: the three contact-hyperplane planes, then
        the three planes containing the normal.
    eff_mass : (C, 6) float64
    impulse : (C, 6) float64
    """

    limits: np.ndarray
    planes: np.ndarray
    eff_mass: np.ndarray
    impulse: np.ndarray


class SolverRows(NamedTuple):
    """Per-contact solver rows: the normal and three tangents (see :mod:`.solver`).

    Attributes
    ----------
    direction : (C, 4, 4) float64
        Row directions: the normal, then three tangents.
    anchor_a, anchor_b : (C, 4) float64
        Contact point relative to each body's centre.
    normal_response : (C, 4) float64
        How the relative velocity of the two contact points changes per unit
        of normal impulse (``K n``, with ``K`` the contact's 4x4 mass matrix).
    eff_mass : (C, 4) float64
        Effective mass of each row.
    impulse : (C, 4) float64
        Accumulated impulse of each row.
    local_point : (C, 4) float64
        Contact point in body a's frame (stored for the next warm start).
    approach_speed : (C,) float64
        Normal relative velocity when prepared (for restitution).
    max_normal_impulse : (C,) float64
        Largest normal impulse while solving.
    friction, restitution : (C,) float64
        Of the pair.
    separation : (C,) float64
        Current separation, updated each substep.
    spin : SpinRows
    """

    direction: np.ndarray
    anchor_a: np.ndarray
    anchor_b: np.ndarray
    normal_response: np.ndarray
    eff_mass: np.ndarray
    impulse: np.ndarray
    local_point: np.ndarray
    approach_speed: np.ndarray
    max_normal_impulse: np.ndarray
    friction: np.ndarray
    restitution: np.ndarray
    separation: np.ndarray
    spin: SpinRows


class Scratch(NamedTuple):
    """Buffers the broadphase and narrowphase reuse every tick.

    Attributes
    ----------
    pairs : (P, 2) int64
        Candidate pairs: body a, body b or ``-1 - s``.
    margin : (N,) float64
        Per-body speculative margin.
    points : (SCRATCH_POINTS, 4) float64
    point_depths : (SCRATCH_POINTS,) float64
        Clipping scratch of the box narrowphase.
    needed : (1,) int64
        After an overflow, the capacity that was needed.
    tet_points, tet_normals : (CANDIDATES, 4) float64
    tet_depths : (CANDIDATES,) float64
        Candidate contacts against a tet mesh, before thinning (:mod:`.tet_mesh`).
    """

    pairs: np.ndarray
    margin: np.ndarray
    points: np.ndarray
    point_depths: np.ndarray
    needed: np.ndarray
    tet_points: np.ndarray
    tet_normals: np.ndarray
    tet_depths: np.ndarray


class Points(NamedTuple):
    """Contact points a narrowphase routine writes, from a row it is given (see :mod:`.collide`).

    Attributes
    ----------
    point : (C, 4) float64
    normal : (C, 4) float64
        Unit normal from the first shape to the second.
    depth : (C,) float64
        Overlap (negative: a speculative gap).
    """

    point: np.ndarray
    normal: np.ndarray
    depth: np.ndarray


class Inertia(NamedTuple):
    """The bodies' world-frame inverse inertias for one tick (see :mod:`.prepare`).

    Attributes
    ----------
    iso : (N,) float64
        The scalar inverse inertia where the operator is a multiple of the
        identity (balls, hypercubes, and 0 for bodies that do not move), else -1.
    full : (N, 6, 6) float64
        The operator on bivectors (read where ``iso`` is -1).
    """

    iso: np.ndarray
    full: np.ndarray


class Softness(NamedTuple):
    """The soft push-out of overlaps in one substep (Box2D's ``b2Softness``).

    Attributes
    ----------
    bias_rate, mass_scale, impulse_scale : float
        From :func:`.solver.soft_params`.
    max_push : float
        m/s, the top speed of the push-out.
    inv_h : float
        One over the substep, s^-1.
    """

    bias_rate: float
    mass_scale: float
    impulse_scale: float
    max_push: float
    inv_h: float


def new_params() -> np.ndarray:
    """A zeroed ``(1,)`` record array of :data:`PARAMS_DTYPE`."""
    return np.zeros(1, dtype=PARAMS_DTYPE)


def new_contacts(cap: int) -> Contacts:
    """Contact arrays for ``cap`` points."""
    i8 = np.int64
    return Contacts(
        np.zeros(cap, i8),
        np.zeros(cap, i8),
        np.zeros(cap, i8),
        np.zeros((cap, 4)),
        np.zeros((cap, 4)),
        np.zeros(cap),
        np.zeros(cap),
        np.zeros((cap, 4)),
    )


def new_manifolds(pair_cap: int, cap: int, old: Manifolds | None = None) -> Manifolds:
    """Manifold store for ``pair_cap`` pairs and ``cap`` points, keeping the entries of ``old``."""
    out = Manifolds(
        np.zeros(pair_cap, np.int64),
        np.zeros(pair_cap, np.int64),
        np.zeros(pair_cap, np.int64),
        np.zeros(pair_cap, np.int64),
        np.zeros((pair_cap, 20)),
        np.zeros((cap, 12)),
        np.zeros(1, np.int64),
    )
    if old is not None:
        n = int(old.pairs[0])
        rows = int(old.first[n - 1] + old.count[n - 1]) if n else 0
        if n <= pair_cap and rows <= cap:
            for name in ("key", "first", "count", "axis", "pose"):
                getattr(out, name)[:n] = getattr(old, name)[:n]
            out.local[:rows] = old.local[:rows]
            out.pairs[0] = n
    return out


def new_warm_start(cap: int, old: WarmStart | None = None) -> WarmStart:
    """Warm-start arrays for ``cap`` points, keeping the stored entries of ``old``."""
    out = WarmStart(
        np.zeros(cap, np.int64), np.zeros((cap, 4)), np.zeros(cap), np.zeros((cap, 4)), np.zeros(1, np.int64)
    )
    if old is not None:
        n = int(old.count[0])
        for name in ("key", "local_point", "normal_impulse", "friction_impulse"):
            getattr(out, name)[:n] = getattr(old, name)[:n]
        out.count[0] = n
    return out


def new_solver_rows(cap: int) -> SolverRows:
    """Solver rows for ``cap`` contacts; kept between ticks so no large array is allocated per tick."""
    f = np.float64
    spin = SpinRows(
        np.zeros((cap, 2), f),
        np.zeros((cap, 6, 6), f),
        np.zeros((cap, 6), f),
        np.zeros((cap, 6), f),
    )
    return SolverRows(
        np.zeros((cap, 4, 4), f),
        np.zeros((cap, 4), f),
        np.zeros((cap, 4), f),
        np.zeros((cap, 4), f),
        np.zeros((cap, 4), f),
        np.zeros((cap, 4), f),
        np.zeros((cap, 4), f),
        np.zeros(cap, f),
        np.zeros(cap, f),
        np.zeros(cap, f),
        np.zeros(cap, f),
        np.zeros(cap, f),
        spin,
    )
