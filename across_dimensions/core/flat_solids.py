"""3D solids for the flat world, and the 2D geometry their sections need.

Builders make closed triangle meshes (:class:`~.flat_section.Solid3`, counter-clockwise from
outside) that :mod:`.flat_section` cuts: boxes, prisms of a 2D profile along an axis (a wall that
tapers along z, a staircase), spheres. The sections are polygons; a 2D physics engine wants
convex pieces (:func:`convex_pieces`), and the simulation asks whether a piece overlaps a box
(:func:`convex_overlaps_box`, :func:`circle_overlaps_box`).

Polygons are ``(p, 2) float64`` corner arrays, counter-clockwise, no closing repeat.
"""

from __future__ import annotations

import math

import numpy as np

from .flat_section import Solid3, signed_area

#: Cross products below this (m^2) count as zero: a corner this close to straight is dropped, and
#: a point this close to a triangle's edge counts as on it. Level coordinates are centimetre-scale
#: numbers of at most a few hundred metres, whose rounding errors are ~1e-13.
COLLINEAR = 1e-9
#: How deep (m) a box must reach into a piece to overlap it: touching is not overlapping, so a
#: being standing on a floor does not overlap the floor.
OVERLAP_SLOP = 1e-6

#: Corners of the unit box (bit 0: x, bit 1: y, bit 2: z) and its twelve triangles, outward.
_BOX_TRIANGLES = np.array(
    [
        (0, 2, 3), (0, 3, 1),  # -z
        (4, 5, 7), (4, 7, 6),  # +z
        (0, 4, 6), (0, 6, 2),  # -x
        (1, 3, 7), (1, 7, 5),  # +x
        (0, 1, 5), (0, 5, 4),  # -y
        (2, 6, 7), (2, 7, 3),  # +y
    ],
    np.uint32,
)  # fmt: skip
#: Extrusion axis -> which 3D axes the profile's (u, v) and the extrusion become: cyclic, so the
#: map is a rotation and keeps triangles wound outward.
_AXES = {"z": (0, 1, 2), "x": (1, 2, 0), "y": (2, 0, 1)}


def box_solid(center, size) -> Solid3:
    """An axis-aligned box: 8 corners, 12 triangles.

    Parameters
    ----------
    center, size : (3,) float
    """
    c, h = np.asarray(center, np.float64), 0.5 * np.asarray(size, np.float64)
    bits = np.arange(8)[:, None] >> np.arange(3) & 1
    return Solid3(c + h * (2.0 * bits - 1.0), _BOX_TRIANGLES.copy())


def prism_solid(profile, low: float, high: float, axis: str = "z") -> Solid3:
    """A 2D profile extruded along ``axis`` from ``low`` to ``high``.

    Parameters
    ----------
    profile : (p, 2) float
        A simple polygon, counter-clockwise, in the coordinates of the two other axes taken
        cyclically: ``(x, y)`` for ``axis = "z"``, ``(y, z)`` for ``"x"``, ``(z, x)`` for ``"y"``.
    low, high : float
        The extent along ``axis``, ``low < high``.
    axis : {"x", "y", "z"}
    """
    p = np.asarray(profile, np.float64)
    if signed_area(p) <= 0 or not low < high:
        raise ValueError("expected a counter-clockwise profile and low < high")
    k = len(p)
    uvw = np.concatenate([np.c_[p, np.full(k, low)], np.c_[p, np.full(k, high)]])
    i = np.arange(k)
    j = (i + 1) % k
    sides = np.concatenate([np.c_[i, j, j + k], np.c_[i, j + k, i + k]])
    caps = triangulate(p)
    tri = np.concatenate([sides, caps[:, ::-1], caps + k]).astype(np.uint32)
    v = np.empty_like(uvw)
    v[:, list(_AXES[axis])] = uvw
    return Solid3(v, tri)


def staircase_profile(steps: int, run: float, rise: float) -> np.ndarray:
    """The side of a staircase climbing towards +u: ``(2 * steps + 2, 2) float64``, counter-clockwise
    in ``(u, v)`` (along, up), from ``(0, 0)``; step ``k`` (from 1) has its top at ``v = k * rise``
    over ``(k - 1) * run <= u <= k * run``."""
    pts = [(0.0, 0.0), (steps * run, 0.0)]
    for k in range(steps, 0, -1):
        pts += [(k * run, k * rise), ((k - 1) * run, k * rise)]
    return np.asarray(pts, np.float64)


def sphere_solid(center, radius: float, subdivisions: int = 3) -> Solid3:
    """An icosphere: ``20 * 4**subdivisions`` triangles, every vertex on the sphere."""
    t = (1.0 + 5.0**0.5) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t)]
    v += [(0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4)]
    faces += [(11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8)]
    faces += [(3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.asarray(p, np.float64) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        middle: dict[tuple[int, int], int] = {}
        new = []
        for a, b, c in faces:
            ab, bc, ca = (_midpoint(verts, middle, i, j) for i, j in ((a, b), (b, c), (c, a)))
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return Solid3(np.asarray(center, np.float64) + radius * np.asarray(verts), np.asarray(faces, np.uint32))


def _midpoint(verts: list, middle: dict, a: int, b: int) -> int:
    """Index of the point on the unit sphere over edge ``ab``, added once per edge."""
    key = (min(a, b), max(a, b))
    if key not in middle:
        m = verts[a] + verts[b]
        middle[key] = len(verts)
        verts.append(m / np.linalg.norm(m))
    return middle[key]


# ------------------------------------------------------------------ polygons
def _cross(o, a, b) -> float:
    return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))


def simplified(loop) -> np.ndarray:
    """``loop`` without corners where it runs straight on (or folds straight back)."""
    p = np.asarray(loop, np.float64)
    changed = True
    while changed and len(p) > 3:
        changed = False
        for i in range(len(p)):
            if abs(_cross(p[i - 1], p[i], p[(i + 1) % len(p)])) <= COLLINEAR:
                p = np.delete(p, i, axis=0)
                changed = True
                break
    return p


def triangulate(loop) -> np.ndarray:
    """Ear-clipping triangulation of a simple counter-clockwise polygon: ``(p - 2, 3) int64``
    corner indices, each triangle counter-clockwise."""
    p = np.asarray(loop, np.float64)
    left = list(range(len(p)))
    out = []
    while len(left) > 3:
        for k in range(len(left)):
            a, b, c = left[k - 1], left[k], left[(k + 1) % len(left)]
            if _cross(p[a], p[b], p[c]) <= COLLINEAR:
                continue
            inside = any(
                _in_triangle(p[i], p[a], p[b], p[c])
                for i in left
                if i not in (a, b, c) and not any(np.array_equal(p[i], p[j]) for j in (a, b, c))
            )
            if not inside:
                out.append((a, b, c))
                left.pop(k)
                break
        else:  # no ear: what is left is degenerate (straight); fan it so nothing is lost
            out += [(left[0], left[i], left[i + 1]) for i in range(1, len(left) - 1)]
            left = left[:3]
            break
    out.append(tuple(left))
    return np.asarray(out, np.int64)


def _in_triangle(q, a, b, c) -> bool:
    return _cross(a, b, q) >= -COLLINEAR and _cross(b, c, q) >= -COLLINEAR and _cross(c, a, q) >= -COLLINEAR


def is_convex(loop) -> bool:
    """Whether a counter-clockwise polygon turns left (or runs straight) at every corner."""
    p = np.asarray(loop, np.float64)
    return all(_cross(p[i - 1], p[i], p[(i + 1) % len(p)]) >= -COLLINEAR for i in range(len(p)))


def convex_pieces(loop) -> list[np.ndarray]:
    """A simple counter-clockwise polygon as convex counter-clockwise pieces (Hertel-Mehlhorn:
    triangles from :func:`triangulate`, merged across their shared edges while the union stays
    convex; at most four times the fewest pieces possible). A convex polygon is one piece."""
    p = simplified(loop)
    if is_convex(p):
        return [p]
    pieces = [list(t) for t in triangulate(p)]
    merged = True
    while merged:
        merged = False
        for i in range(len(pieces)):
            for j in range(i + 1, len(pieces)):
                union = _merge(pieces[i], pieces[j])
                if union is not None and is_convex(p[union]):
                    pieces[i] = union
                    del pieces[j]
                    merged = True
                    break
            if merged:
                break
    return [simplified(p[q]) for q in pieces]


def _merge(a: list, b: list) -> list | None:
    """The union of two pieces (corner index lists) sharing an edge, as one index list, or None."""
    for k in range(len(a)):
        s, t = a[k], a[(k + 1) % len(a)]
        for m in range(len(b)):
            if b[m] == t and b[(m + 1) % len(b)] == s:
                rest_a = a[k + 1 :] + a[: k + 1]  # from t round to s
                rest_b = b[m + 1 :] + b[: m + 1]  # from s round to t
                return rest_a + rest_b[1:-1]
    return None


# ------------------------------------------------------------------ overlaps
def convex_overlaps_box(piece, low, high, slop: float = OVERLAP_SLOP) -> bool:
    """Whether a convex piece ``(p, 2)`` and the box ``low (2,) .. high (2,)`` overlap by more than
    ``slop`` along every separating axis (the box's two and the piece's edge normals)."""
    p = np.asarray(piece, np.float64)
    lo, hi = np.asarray(low, np.float64), np.asarray(high, np.float64)
    if np.any(p.max(axis=0) <= lo + slop) or np.any(p.min(axis=0) >= hi - slop):
        return False
    corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    edges = np.roll(p, -1, axis=0) - p
    normals = np.c_[edges[:, 1], -edges[:, 0]]  # outward for a counter-clockwise piece
    for n, a in zip(normals, p):
        if np.dot(corners - a, n).min() >= -slop * _length(n):
            return False
    return True


def circle_overlaps_box(center, radius: float, low, high, slop: float = OVERLAP_SLOP) -> bool:
    """Whether a circle and the box ``low (2,) .. high (2,)`` overlap by more than ``slop``."""
    c = np.asarray(center, np.float64)
    nearest = np.clip(c, np.asarray(low, np.float64), np.asarray(high, np.float64))
    return radius > slop and _length(c - nearest) < radius - slop


def _length(v) -> float:
    """The length of a 2-vector as IEEE arithmetic gives it everywhere (the C library's
    ``hypot``, which numpy calls, rounds differently from one glibc version to the next)."""
    return math.sqrt(float(v[0]) * float(v[0]) + float(v[1]) * float(v[1]))
