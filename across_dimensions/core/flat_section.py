"""Sections one dimension down: the plane ``z = z0`` through 3D solids gives 2D polygons.

The Flatland analogy of :mod:`.section`: there a 4D mesh cut by a hyperplane gives the 3D world
the player walks in; here a 3D solid cut by a plane gives the flat world of a flat being, in the
plane's own coordinates ``(x, y)``. A 3D ball meets the plane as a circle of radius
``sqrt(r^2 - (z0 - c)^2)`` (:func:`sphere_circle_radius`), a box only while ``z0`` lies in its z
extent, a staircase as a different profile at each ``z0``.

Rules
-----
A solid is a closed triangle mesh (:class:`Solid3`), triangles counter-clockwise seen from
outside. Each vertex is classified by the sign of ``z - z0``: ``> 0`` is *above*; on the plane
counts as below, the tie-break of :mod:`.section`, which keeps every section closed. A triangle
with one or two vertices above is cut along the two edges whose ends differ, into one segment.
A solid spanning ``a <= z <= b`` therefore has a section for ``a <= z0 < b``.

* Each cut point is computed from its edge with the lower vertex index first (a corner on the
  plane is its own cut point, exactly), so the two triangles sharing an edge give bit-identical
  points, and segments join into loops by the mesh
  edges they were cut from (:func:`section_loops`), with no distance tolerance.
* A segment runs from the point where the triangle's vertex cycle ``a -> b -> c`` leaves the
  above side to the point where it enters it. For triangles wound counter-clockwise from outside
  that makes outer loops run counter-clockwise in ``(x, y)`` (positive area) and holes clockwise,
  decided by the vertex order alone, so even a segment of zero length (a cut through a vertex)
  chains in its place.

Two implementations share these rules: :func:`section_segments` (numba) and
:func:`section_segments_reference` (plain numpy, the oracle the tests compare against).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ._jit import njit


class Solid3(NamedTuple):
    """A closed 3D triangle mesh.

    Attributes
    ----------
    vertices : (n, 3) float64
    triangles : (m, 3) uint32
        Counter-clockwise seen from outside; every edge shared by exactly two triangles.
    """

    vertices: np.ndarray
    triangles: np.ndarray

    def z_extent(self) -> tuple[float, float]:
        """``(low, high)`` z of the solid: it has a section for ``low <= z0 < high``."""
        z = self.vertices[:, 2]
        return float(z.min()), float(z.max())


class Segments(NamedTuple):
    """The cut of a solid by a plane, as unordered directed segments.

    Attributes
    ----------
    points : (k, 2, 2) float64
        Start and end ``(x, y)`` of each segment.
    keys : (k, 2) int64
        The mesh edge each end was cut from, as ``low * n + high`` (vertex indices, ``n``
        vertices): an end's key is the start key of the segment that follows it in its loop.
    """

    points: np.ndarray
    keys: np.ndarray


# size: one loop over triangles with the three edges unrolled
@njit(cache=True)
def _cut(v, tri, z0, points, keys):
    """Fill ``points (m, 2, 2)`` and ``keys (m, 2)`` with the segments of ``tri``; return their number."""
    n = v.shape[0]
    k = 0
    for t in range(tri.shape[0]):
        above = 0
        for j in range(3):
            if v[tri[t, j], 2] > z0:
                above += 1
        if above == 0 or above == 3:
            continue
        for j in range(3):  # edge j runs from corner j to corner j + 1
            i0 = tri[t, j]
            i1 = tri[t, (j + 1) % 3]
            up0 = v[i0, 2] > z0
            up1 = v[i1, 2] > z0
            if up0 == up1:
                continue
            lo = min(i0, i1)
            hi = max(i0, i1)
            # A corner on the plane is its own cut point exactly (lo + 1 * (hi - lo) need not be hi).
            s = 1.0 if v[hi, 2] == z0 else (z0 - v[lo, 2]) / (v[hi, 2] - v[lo, 2])
            end = 0 if up0 else 1  # leaving the above side starts the segment, entering ends it
            if s == 1.0:
                points[k, end, 0] = v[hi, 0]
                points[k, end, 1] = v[hi, 1]
            else:
                points[k, end, 0] = v[lo, 0] + s * (v[hi, 0] - v[lo, 0])
                points[k, end, 1] = v[lo, 1] + s * (v[hi, 1] - v[lo, 1])
            keys[k, end] = np.int64(lo) * n + np.int64(hi)
        k += 1
    return k


def section_segments(solid: Solid3, z0: float) -> Segments:
    """The segments where the plane ``z = z0`` cuts ``solid`` (numba kernel).

    Parameters
    ----------
    solid : Solid3
    z0 : float

    Returns
    -------
    Segments
        ``points (k, 2, 2) float64`` and ``keys (k, 2) int64``, in triangle order.
    """
    v = np.ascontiguousarray(solid.vertices, dtype=np.float64)
    tri = np.ascontiguousarray(solid.triangles, dtype=np.int64)
    points = np.empty((len(tri), 2, 2), np.float64)
    keys = np.empty((len(tri), 2), np.int64)
    k = _cut(v, tri, float(z0), points, keys)
    return Segments(points[:k].copy(), keys[:k].copy())


def section_segments_reference(solid: Solid3, z0: float) -> Segments:
    """:func:`section_segments` in plain numpy, one triangle at a time (the tests' oracle)."""
    v = np.asarray(solid.vertices, dtype=np.float64)
    n = len(v)
    points, keys = [], []
    for a, b, c in np.asarray(solid.triangles, dtype=np.int64):
        up = [bool(v[i, 2] > z0) for i in (a, b, c)]
        if all(up) or not any(up):
            continue
        seg, key = [None, None], [0, 0]
        for (i0, u0), (i1, u1) in zip(zip((a, b, c), up), zip((b, c, a), up[1:] + up[:1])):
            if u0 == u1:
                continue
            lo, hi = min(i0, i1), max(i0, i1)
            end = 0 if u0 else 1
            if v[hi, 2] == z0:
                seg[end] = v[hi, :2]
            else:
                seg[end] = v[lo, :2] + (z0 - v[lo, 2]) / (v[hi, 2] - v[lo, 2]) * (v[hi, :2] - v[lo, :2])
            key[end] = lo * n + hi
        points.append(seg)
        keys.append(key)
    return Segments(np.asarray(points, np.float64).reshape(-1, 2, 2), np.asarray(keys, np.int64).reshape(-1, 2))


def section_loops(solid: Solid3, z0: float) -> list[np.ndarray]:
    """The closed polygons where the plane ``z = z0`` cuts ``solid``.

    Returns
    -------
    list of (p, 2) float64
        One array of ``(x, y)`` corners per loop, without the closing repeat and without
        consecutive duplicates; outer boundaries counter-clockwise, holes clockwise. Loops with
        fewer than three distinct corners (a plane grazing an edge) are left out, and so is any
        chain that does not close (the solid was not closed).
    """
    seg = section_segments(solid, z0)
    follow = {int(k): i for i, k in enumerate(seg.keys[:, 0])}
    used = np.zeros(len(seg.keys), bool)
    loops = []
    for first in range(len(used)):
        if used[first]:
            continue
        corners, i, closed = [], first, False
        while not used[i]:
            used[i] = True
            corners.append(seg.points[i, 0])
            nxt = follow.get(int(seg.keys[i, 1]))
            if nxt is None:
                break
            closed = nxt == first
            i = nxt
        if closed:
            loop = _distinct(np.asarray(corners))
            if len(loop) >= 3:
                loops.append(loop)
    return loops


def _distinct(loop: np.ndarray) -> np.ndarray:
    """``loop`` without corners equal to the one before them (cyclically)."""
    keep = np.any(loop != np.roll(loop, 1, axis=0), axis=1)
    return loop[keep] if keep.any() else loop[:1]


def signed_area(loop: np.ndarray) -> float:
    """Area of a polygon ``(p, 2)``: positive when its corners run counter-clockwise."""
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def sphere_circle_radius(center_z: float, radius: float, z0: float) -> float:
    """Radius of the circle where the plane ``z = z0`` cuts a ball: ``sqrt(r^2 - (z0 - c)^2)``,
    0 where it misses (the circle's centre is the ball's ``(x, y)``)."""
    d = z0 - center_z
    return math.sqrt(radius * radius - d * d) if abs(d) < radius else 0.0
