"""The time trial's ghost as a figure: a translucent player-sized body where the best run was.

The figure is a 3D surface of revolution the player's size (:data:`~..game.player.HEIGHT` tall,
twice :data:`~..game.player.HALF_WIDTH` wide) with a visor on the side it looks to, drawn as a
``"ghost"`` drawable (translucent, no depth writes: it never hides what stands behind it). It
stands at the ghost's feet in the slice's 3D space and is seen only while its w is near the
slice's: fully on the slice, fading to nothing :data:`W_REACH` away along w, as a 4D figure
cut by the slice would.
"""

from __future__ import annotations

import functools

import numpy as np

from ..core.mesh import TriMesh3
from ..game.frame import Drawable
from ..game.player import HALF_WIDTH, HEIGHT

KEY = "time_trial_ghost"
#: Along w, how far from the slice the figure is still seen (fading linearly to it).
W_REACH = 0.5
#: The figure's colour and the tint its ghost shading is pulled towards (a pale gold, unlike the
#: blue and orange of the w ghosts).
COLOR = (1.0, 0.85, 0.45, 1.0)
TINT = (1.0, 0.8, 0.35, 0.6)
#: Its profile: (radius, height) as fractions of the half width and the height, feet to crown.
_PROFILE = (
    (0.0, 0.0),
    (0.7, 0.0),
    (0.85, 0.35),
    (1.0, 0.62),
    (0.75, 0.76),
    (0.35, 0.8),
    (0.6, 0.86),
    (0.65, 0.94),
    (0.4, 0.99),
    (0.0, 1.0),
)
_SIDES = 12


@functools.cache
def figure_mesh() -> TriMesh3:
    """The figure, feet at the origin, looking along +z: closed and wound counter-clockwise
    seen from outside."""
    r = np.array([p[0] for p in _PROFILE]) * HALF_WIDTH
    y = np.array([p[1] for p in _PROFILE]) * HEIGHT
    a = np.arange(_SIDES) * 2 * np.pi / _SIDES
    verts = np.stack([np.outer(r, np.sin(a)).ravel(), np.repeat(y, _SIDES), np.outer(r, np.cos(a)).ravel()], axis=1)
    faces = []
    for i in range(len(_PROFILE) - 1):
        for j in range(_SIDES):
            k = (j + 1) % _SIDES
            v00, v01, v10, v11 = i * _SIDES + j, i * _SIDES + k, (i + 1) * _SIDES + j, (i + 1) * _SIDES + k
            faces += [(v00, v01, v10), (v01, v11, v10)]
    body = (verts, np.array(faces))
    visor = _box(np.array([0.0, 0.9 * HEIGHT, 0.55 * HALF_WIDTH]), np.array([0.55, 0.05, 0.2]) * HALF_WIDTH * 2)
    return _mesh([body, visor])


def _box(center: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64)
    quads = ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3))
    faces = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return center + corners * half, np.array(faces)


def _mesh(parts) -> TriMesh3:
    """One mesh of ``parts`` ((k, 3) vertices, (f, 3) faces), flat-shaded: each face its own
    three vertices and normal, so the figure reads as facets through its translucency."""
    tris = np.concatenate([v[f] for v, f in parts])  # (t, 3, 3)
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    keep = length[:, 0] > 1e-12  # the profile's ends meet in a point: those triangles are empty
    tris, n = tris[keep], n[keep] / length[keep]
    count = len(tris) * 3
    return TriMesh3(
        tris.reshape(-1, 3).astype(np.float32),
        np.arange(count, dtype=np.uint32).reshape(-1, 3),
        np.repeat(n, 3, axis=0).astype(np.float32),
        np.tile(np.array(COLOR, np.float32), (count, 1)),
    )


def ghost_drawable(feet: np.ndarray, yaw: float, slice_w: float) -> Drawable | None:
    """The figure standing at ``feet`` ``(4,)`` (slice space: x, y, z and w) looking along ``yaw``,
    for a slice at ``slice_w``; None when it is :data:`W_REACH` or more away along w."""
    away = abs(float(feet[3]) - float(slice_w))
    if away >= W_REACH:
        return None
    c, s = np.cos(yaw), np.sin(yaw)
    model = np.eye(4)
    model[:3, :3] = ((c, 0.0, s), (0.0, 1.0, 0.0), (-s, 0.0, c))
    model[:3, 3] = feet[:3]
    return Drawable(
        KEY, 0, figure_mesh(), model, style="ghost", tint=TINT, opacity=1.0 - away / W_REACH, outside_only=True
    )
