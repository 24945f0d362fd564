"""How the player and the rigid bodies meet: bodies block the player, the player pushes them.

Game rules, not physics: the physics world only answers "how far must this
upright box move to leave the bodies, and which did it touch"
(:meth:`~across_dimensions.physics.PhysicsWorld.push_box_out`); who gets pushed,
and how hard, is decided here.

The player is the upright box ``[x +- radius] x [y, y + height] x [z +- radius]
x [w +- w_half]`` with ``position = (x, y, z, w)`` its feet.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.mesh import cross4
from ..physics.debug_draw import DebugDrawOptions
from ..world.scene import static_tet_meshes
from .player import HALF_WIDTH, HEIGHT
from .system import derived

#: Half thickness of the player's collider along w, metres: the player lives in
#: one 3D slice, so only bodies reaching into this thin slab touch it.
W_HALF = 0.05


def player_box(position, radius: float, height: float, w_half: float = W_HALF) -> tuple[np.ndarray, np.ndarray]:
    """Centre and half extents ``(4,) float64`` of the player's collider."""
    feet = np.asarray(position, dtype=np.float64).reshape(4)
    center = np.array([feet[0], feet[1] + 0.5 * float(height), feet[2], feet[3]])
    half = np.array([float(radius), 0.5 * float(height), float(radius), float(w_half)])
    return center, half


def player_collide(
    physics, position, radius: float, height: float, w_half: float = W_HALF, velocity=None
) -> tuple[np.ndarray, list[int]]:
    """Push a player out of the bodies in its w slab, and optionally push them.

    Parameters
    ----------
    physics : PhysicsWorld
    position : (4,) array_like
        The player's feet.
    radius, height, w_half : float
    velocity : (3,) or (4,) array_like, optional
        The player's velocity. If given, touched dynamic bodies ahead of the
        player get the impulse that makes them move at least as fast as the
        player along its direction of motion (pushing).

    Returns
    -------
    correction : (3,) float64
        xyz offset to add to the player's position.
    touched : list of int
        Ids of the bodies in contact.
    """
    feet = np.asarray(position, dtype=np.float64).reshape(4)
    center, half = player_box(feet, radius, height, w_half)
    corr, ids = physics.push_box_out(center, half)
    if velocity is not None:
        v = np.zeros(4)
        vv = np.asarray(velocity, dtype=np.float64).reshape(-1)
        v[: vv.shape[0]] = vv
        speed = np.linalg.norm(v)
        if speed > 0:
            d = v / speed
            for i in ids:
                if physics.body_kind(i) != "dynamic":
                    continue
                # Only bodies ahead of the player: behind ones are not pushed.
                if (physics.body_position(i) - feet) @ d <= 0:
                    continue
                lag = speed - physics.body_velocity(i)[0] @ d
                if lag > 0:
                    physics.push(i, physics.body_mass(i) * lag * d)
    return corr, ids


def bodies_block(physics, position, w: float, radius: float, height: float) -> bool:
    """Would stepping the player to ``w`` put it deeper inside a rigid body?"""
    moved = np.array(position, dtype=np.float64)
    moved[3] = w
    here, _ = player_collide(physics, position, radius, height)
    there, _ = player_collide(physics, moved, radius, height)
    return bool(np.linalg.norm(there) > np.linalg.norm(here) + 1e-4)


def debug_draw_game(game, drawer, options=None, w: float | None = None) -> None:
    """Report the physics of ``game`` in the slice at ``w``, and the player's collider, to ``drawer``.

    Parameters
    ----------
    game : Game
        Read only.
    drawer : DebugDrawer
        See :mod:`across_dimensions.physics.debug_draw`.
    options : DebugDrawOptions, optional
    w : float, optional
        The slice drawn: a frame's eye (``frame.camera.w``); the player's w by default.
    """
    opt = options or DebugDrawOptions()
    p = game.player
    box = player_box(p.position, HALF_WIDTH, HEIGHT)
    w = float(p.position[3]) if w is None else float(w)
    if game.physics is not None:
        game.physics.debug_draw(drawer, w, opt, boxes=[box])
    elif opt.boxes:
        drawer.draw_box(box[0][:3], box[1][:3], opt.box_color)


def shape_kind(mesh) -> str:
    """``"box"``, ``"convex"`` or ``"none"``: how the bodies meet a solid mesh (see :func:`_shape_of`)."""
    return _shape_of(mesh)[0]


def _shape_of(mesh) -> tuple:
    """How the bodies meet a solid mesh, in its own frame: ``("box", lo, hi)`` when every
    vertex is a corner of its bounds (a tesseract), ``("convex", planes (k, 5), vertices
    (n, 4))`` when it is a convex polytope (every vertex inside every boundary tet's
    hyperplane: the regular polytopes), else ``("none",)``."""
    v = np.asarray(mesh.vertices, dtype=np.float64)
    if len(v) == 0:
        return ("none",)
    lo, hi = v.min(axis=0), v.max(axis=0)
    size = max(float(np.max(hi - lo)), 1e-12)
    tol = 1e-6 * size
    if bool(((np.abs(v - lo) <= tol) | (np.abs(v - hi) <= tol)).all()):
        return ("box", lo, hi)
    t = v[np.asarray(mesh.tets, dtype=np.int64)]  # (m, 4, 4)
    n = cross4(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0], t[:, 3] - t[:, 0])
    ln = np.linalg.norm(n, axis=1)
    ok = ln > 1e-12 * size**3
    n = n[ok] / ln[ok, None]
    d = np.einsum("ti,ti->t", n, t[ok, 0])
    # One plane per facet: the tets of a facet share it (rounded to far below the mesh's precision).
    _, first = np.unique(np.round(np.c_[n, d / size] * 1e5), axis=0, return_index=True)
    planes = np.c_[n, d][np.sort(first)]
    if len(planes) < 5 or len(planes) > MAX_FACETS:
        return ("none",)
    if bool(np.all(v @ planes[:, :4].T <= planes[:, 4] + 1e-4 * size)):
        return ("convex", planes, v)
    return ("none",)


#: Convex solids with more facets than this do not stop bodies (each contact test reads every facet).
MAX_FACETS = 1024


@dataclass
class Placement:
    """Where a solid object's boundary tets were last handed to the physics world.

    ``pose`` is the object-to-world ``(5, 5)`` it was placed by, as bytes; ``world`` its
    tets placed so ``(T, 4, 4) float64`` (None for a degenerate pose); ``motion (4, 5)``
    the velocity field of its last move (zero when it did not move).
    """

    pose: bytes
    world: np.ndarray | None = derived()
    motion: np.ndarray = field(default_factory=lambda: np.zeros((4, 5)))


@dataclass
class SolidColliders:
    """The solid objects as the rigid bodies meet them (``game.states.solid_bodies``).

    Attributes
    ----------
    shapes : dict
        Entity id to what its mesh is (see :func:`_shape_of`), worked out once.
    local : dict
        Entity id to its boundary tets in its own frame ``(T, 4, 4) float64``.
    placed : dict of int to Placement
        Where each was last placed: a tick's motion is the change since then.
    """

    shapes: dict = derived(default_factory=dict)
    local: dict = derived(default_factory=dict)
    placed: dict[int, Placement] = field(default_factory=dict)


def solid_colliders(game) -> tuple[list, list]:
    """The level's solid 4D objects as the rigid bodies meet them.

    Every ``solid`` entity that is neither a rigid body nor manipulable (those
    have their own colliders) becomes, placed by its pose:

    * a box ``(center (4,), half_extents (4,), rotation (4, 4))``, rotation
      local to world, when its mesh is a box (a ``tesseract``: slabs, doors and
      walls). The box is the object itself, so a bullet stops at a door and a
      body rests on a slab exactly where the player sees it;
    * a convex solid ``(planes (k, 5), lo (4,), hi (4,))`` when its mesh is a
      convex polytope (the regular polytopes, a hypersphere): its facets'
      half-spaces and bounds, in the world;
    * nothing otherwise (an arch, a lifted asset): those meet the bodies as the
      tets of their boundary (:func:`tet_colliders`).

    What each mesh is, is worked out once per entity (:class:`SolidColliders`).

    Returns
    -------
    boxes, convex : list, list
        For :meth:`PhysicsWorld.set_static_solids` and :meth:`PhysicsWorld.set_static_convex`.
    """
    cache = game.states.solid_bodies.shapes
    boxes, convex = [], []
    for e in game.entities:
        if not e.solid or e.kind != "object":
            continue
        if e.id not in cache:
            cache[e.id] = _shape_of(e.mesh)
        shape = cache[e.id]
        if shape[0] == "none":
            continue
        m = e.model(game)
        a = m[:4, :4]
        if shape[0] == "convex":
            if abs(np.linalg.det(a)) < 1e-12:
                continue
            planes, v = shape[1], shape[2]
            # n . p <= d in the object's frame is (A^-T n) . (x - t) <= d in the world.
            nw = np.linalg.solve(a.T, planes[:, :4].T).T
            dw = planes[:, 4] + nw @ m[:4, 4]
            ln = np.linalg.norm(nw, axis=1)
            nw, dw = nw / ln[:, None], dw / ln  # unit normals: offsets are distances
            world_v = v @ a.T + m[:4, 4]
            convex.append((np.c_[nw, dw], world_v.min(axis=0), world_v.max(axis=0)))
            continue
        scale = np.linalg.norm(a, axis=0)
        if not np.all(scale > 0):
            continue
        rot = a / scale
        lo, hi = shape[1], shape[2]
        center = m[:4, 4] + rot @ (0.5 * (lo + hi) * scale)
        half = np.maximum(0.5 * (hi - lo) * scale, 1e-4)
        boxes.append((center, half, rot))
    return boxes, convex


#: A solid object whose surface would move faster than this (m/s) in one tick jumped
#: (it was placed, not turned): bodies near it are pushed out, not carried.
MAX_CARRY_SPEED = 20.0


def tet_colliders(game) -> list[np.ndarray]:
    """The level's solid 4D objects that are neither boxes nor convex, as the tets of their boundary.

    Every ``solid`` object entity whose mesh :func:`solid_colliders` leaves out (an
    arch, a lifted asset) gives its boundary tets placed by its pose, outward
    (a mirroring pose reverses them). The arrays are kept per entity and made
    again only when its pose changes, so the physics world sees the same array
    objects (and does nothing) while nothing moves.

    Returns
    -------
    list of (T, 4, 4) float64
        For :meth:`PhysicsWorld.set_static_tets`, in entity order.
    """
    return _tet_meshes(game)[0]


def _tet_meshes(game) -> tuple[list, list]:
    """:func:`tet_colliders` and each mesh's velocity field ``(4, 5)``: the change of its
    pose since it was last placed, over a tick (zero when it has not moved)."""
    solids = game.states.solid_bodies
    shapes, local, placed = solids.shapes, solids.local, solids.placed
    tets, motions = [], []
    for e in game.entities:
        # Solid objects that are not boxes or convex; manipulable ones that are not boxes
        # (a box-shaped one is its own kinematic hypercube, see systems/manipulation.py).
        if e.kind not in ("object", "manipulable") or (e.kind == "object" and not e.solid):
            continue
        if e.id not in shapes:
            shapes[e.id] = _shape_of(e.mesh)
        if shapes[e.id][0] == "box" or (e.kind == "object" and shapes[e.id][0] != "none"):
            continue
        if e.id not in local:
            local[e.id] = np.asarray(e.mesh.vertices, dtype=np.float64)[np.asarray(e.mesh.tets, dtype=np.int64)]
        m = e.model(game)
        key = m.tobytes()
        hit = placed.get(e.id)
        if hit is None or hit.pose != key:
            placed[e.id] = hit = _placed(game, local[e.id], m, hit)
        elif hit.motion.any():
            hit.motion = np.zeros((4, 5))  # placed again where it was: still
        if hit.world is not None:
            tets.append(hit.world)
            motions.append(hit.motion)
    return tets, motions


def _placed(game, local: np.ndarray, m: np.ndarray, before: Placement | None) -> Placement:
    """Tets ``local (T, 4, 4)`` placed by the pose ``m (5, 5)``, moving from where ``before`` put them."""
    a = m[:4, :4]
    det = np.linalg.det(a)
    hit = Placement(m.tobytes(), None)
    if abs(det) < 1e-12:
        return hit
    world = local @ a.T + m[:4, 4]
    if det < 0:
        world = world[:, [0, 2, 1, 3]]  # a mirror turns tets inside out: swap two corners back
    hit.world = np.ascontiguousarray(world)
    if before is not None and before.world is not None:
        # x_new = M_new M_old^-1 x_old: over one tick, that is the surface's velocity field.
        old = np.frombuffer(before.pose, dtype=np.float64).reshape(5, 5)
        motion = ((m @ np.linalg.inv(old) - np.eye(5)) / game.dt)[:4]
        lo, hi = hit.world.min(axis=(0, 1)), hit.world.max(axis=(0, 1))
        corners = np.array([[(hi if (j >> i) & 1 else lo)[i] for i in range(4)] for j in range(16)])
        speed = np.linalg.norm(corners @ motion[:, :4].T + motion[:, 4], axis=1).max()
        if np.isfinite(speed) and speed <= MAX_CARRY_SPEED:
            hit.motion = motion
    return hit


def sync_solids(game) -> None:
    """Hand :func:`solid_colliders` and :func:`tet_colliders` to the physics world (before its
    tick); a no-op without physics."""
    if game.physics is not None:
        boxes, convex = solid_colliders(game)
        game.physics.set_static_solids(boxes)
        game.physics.set_static_convex(convex)
        tets, motions = _tet_meshes(game)
        fixed = static_tet_meshes(game.scene)  # the [[mesh]] parts and worlds: the same arrays every tick
        game.physics.set_static_tets(fixed + tets, [np.zeros((4, 5))] * len(fixed) + motions)
