"""How the player and the rigid bodies meet: bodies block the player, the player pushes them.

Game rules, not physics: the physics world only answers "how far must this
upright box move to leave the bodies, and which did it touch"
(:meth:`~across_dimensions.physics.PhysicsWorld.push_box_out`); who gets pushed,
and how hard, is decided here.

The player is the upright box ``[x +- radius] x [y, y + height] x [z +- radius]
x [w +- w_half]`` with ``position = (x, y, z, w)`` its feet.
"""

from __future__ import annotations

import numpy as np

from ..physics.debug_draw import DebugDrawOptions
from .player import HALF_WIDTH, HEIGHT

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


def debug_draw_game(game, drawer, options=None) -> None:
    """Report the physics of ``game`` in the player's slice, and the player's collider, to ``drawer``.

    Parameters
    ----------
    game : Game
        Read only.
    drawer : DebugDrawer
        See :mod:`across_dimensions.physics.debug_draw`.
    options : DebugDrawOptions, optional
    """
    opt = options or DebugDrawOptions()
    p = game.player
    box = player_box(p.position, HALF_WIDTH, HEIGHT)
    w = float(p.position[3])
    if game.physics is not None:
        game.physics.debug_draw(drawer, w, opt, boxes=[box])
    elif opt.boxes:
        drawer.draw_box(box[0][:3], box[1][:3], opt.box_color)


def solid_boxes(game) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The level's solid 4D objects as the rigid bodies meet them: one oriented 4D box each.

    Every ``solid`` entity that is neither a rigid body nor manipulable (those
    have their own colliders) and whose mesh is a box (every vertex a corner of
    its bounds: a ``tesseract``, which is what slabs, doors and walls are built
    from) gives that box, placed by its pose: ``(center (4,), half_extents
    (4,), rotation (4, 4))``, rotation local to world. The box is the object
    itself, so a bullet stops at a door and a body rests on a slab exactly
    where the player sees it. Other shapes give nothing yet: their bounding
    box would stop bodies in an arch's doorway or far from a 24-cell's faces.

    What each mesh is (its bounds, or None) is worked out once per entity
    (``game._solid_bounds``).
    """
    cache = game.__dict__.setdefault("_solid_bounds", {})
    out = []
    for e in game.entities:
        if not e.solid or e.kind != "object":
            continue
        if e.id not in cache:
            cache[e.id] = _box_bounds(e.mesh.vertices)
        lh = cache[e.id]
        if lh is None:
            continue
        m = e.model(game)
        a = m[:4, :4]
        scale = np.linalg.norm(a, axis=0)
        if not np.all(scale > 0):
            continue
        rot = a / scale
        lo, hi = lh
        center = m[:4, 4] + rot @ (0.5 * (lo + hi) * scale)
        half = np.maximum(0.5 * (hi - lo) * scale, 1e-4)
        out.append((center, half, rot))
    return out


def _box_bounds(vertices) -> tuple[np.ndarray, np.ndarray] | None:
    """``(lo, hi)`` of a mesh whose every vertex is a corner of its bounds (a box), else None."""
    v = np.asarray(vertices, dtype=np.float64)
    if len(v) == 0:
        return None
    lo, hi = v.min(axis=0), v.max(axis=0)
    tol = 1e-6 * max(float(np.max(hi - lo)), 1e-12)
    corner = (np.abs(v - lo) <= tol) | (np.abs(v - hi) <= tol)
    return (lo, hi) if bool(corner.all()) else None


def sync_solids(game) -> None:
    """Hand :func:`solid_boxes` to the physics world (before its tick); a no-op without physics."""
    if game.physics is not None:
        game.physics.set_static_solids(solid_boxes(game))
