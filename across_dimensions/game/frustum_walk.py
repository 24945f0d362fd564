"""Walking on frustum images: objects a level marks ``walkable_in_frustum``.

The paper's 4D camera can turn "a barrier into a building that the user can enter". While the
frustum view holds (the rig's mode is ``"frustum"``: switched on and not yet gliding back), each
marked object collides with the walker as its projected 3D image, the very triangles the frustum
view draws (:func:`~..core.frustum.frustum_project` from the rig's 4D camera, placed in slice
space), instead of its cross-section. The image stays where it is while the player walks round
it (the detached camera does not follow the player), and changes as the camera orbits.

On the way back (the glide back starts, by the key or an empty bar) the objects are their
cross-sections again at once; :func:`safe_spot` finds where to put a player who would then be
inside geometry. The rules per tick live in :mod:`.systems.frustum_walk`.

Arrays: triangles ``(t, 3, 3) float64`` (see :mod:`.section_collision`).
"""

from __future__ import annotations

import numpy as np

from ..core.frustum import frustum_project
from .camera import FRUSTUM_NEAR
from .entities import Scripted
from .player import overlapping, player_box
from .section_collision import box_blocked, inside, triangles_of

#: Distances (metres) and directions tried, nearest first, when the player must be moved out of
#: geometry at the end of the frustum view: rings every 0.25 m out to 6 m, 16 directions each,
#: each at the player's height and one ledge (0.4 m) higher. Past that, the place the view was
#: switched on from.
RINGS = np.arange(0.25, 6.01, 0.25)
DIRECTIONS = 16
LIFTS = (0.0, 0.4)


def walkable(e) -> bool:
    """Is entity ``e`` a level object marked ``walkable_in_frustum``?"""
    return isinstance(e.motion, Scripted) and e.motion.obj.walkable_in_frustum


def images_hold(game) -> bool:
    """Do marked objects collide as their images this tick (the frustum view holds)?"""
    return game.level.camera.frustum and game.camera.mode == "frustum"


def image_triangles(game, e, cache: dict) -> np.ndarray:
    """The frustum image of entity ``e`` in slice space, ``(t, 3, 3) float64``; ``cache`` keeps
    one entry per entity, recomputed only when the camera's pose or the object's model changed."""
    rig, p = game.camera, game.player
    pose, place = rig.frustum_pose(p.eye(), float(p.position[3]))
    model = e.model(game)
    hit = cache.get(e.id)
    if hit is not None and np.array_equal(hit[0], pose) and np.array_equal(hit[1], model):
        return hit[2]
    tri = frustum_project(e.mesh, pose, fov_deg=rig.fov_deg, near=FRUSTUM_NEAR, model=model)
    tris = triangles_of(tri) + place[:3, 3]
    cache[e.id] = (pose.copy(), model.copy(), tris)
    return tris


def overlaps(game, position) -> bool:
    """Would the player's box at ``position (4,)`` overlap a box, a solid's section (or stand
    inside one), a mesh part or a rigid body, as the walker meets them this tick?"""
    w = float(position[3])
    lo, hi = player_box(position)
    if overlapping(lo, hi, game.colliders_at(w)).any():
        return True
    middle = (lo + hi) / 2.0
    for tris in game.sections_at(w):
        if len(tris) and (box_blocked(lo, hi, tris) or inside(middle, tris)):
            return True
    return game.physics is not None and game.bodies_block_w(position, w)


def safe_spot(game, anchor) -> np.ndarray | None:
    """Where to put a player who stands inside geometry: the nearest free spot on the rings
    round them (:data:`RINGS`, :data:`DIRECTIONS`, :data:`LIFTS`), else ``anchor (4,)`` (where
    the frustum view was switched on) if it is free, else None (the caller respawns)."""
    here = np.asarray(game.player.position, dtype=np.float64)
    angles = 2.0 * np.pi * np.arange(DIRECTIONS) / DIRECTIONS
    for r in RINGS:
        for a in angles:
            for lift in LIFTS:
                spot = here + np.array([r * np.sin(a), lift, r * np.cos(a), 0.0])
                if not overlaps(game, spot):
                    return spot
    anchor = np.asarray(anchor, dtype=np.float64)
    return anchor if not overlaps(game, anchor) else None
