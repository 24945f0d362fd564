"""The walker's box against the triangles of 4D objects' cross-sections.

A solid 4D object collides with the player as its true section in the
player's slice: the closed triangle surface :func:`core.section.cross_section`
returns. The player's box (axis-aligned, see :mod:`.player`) moves one axis at
a time; against a triangle that sweep is solved exactly with the separating
axis theorem: a box and a triangle are disjoint exactly when their projections
on one of 13 axes (the box's three face normals, the triangle's normal, and
the nine cross products of box axes with triangle edges) are disjoint. Moving
the box along one axis slides its projection on each test axis linearly, so
each test axis gives an interval of the move's parameter ``s`` in ``[0, 1]``
where the projections overlap, and the shapes overlap where all 13 intervals
do. The first ``s`` of that intersection is where the move stops. No iteration,
no tolerance in the test itself: the same inputs always give the same stop.

Triangles the box already overlaps when a move starts are ignored by that move
(as for boxes in :func:`.player.move_axis`), so the player can always walk out
of something that turned into them.

A section is a closed surface, so a box entirely inside it touches no
triangle; :func:`inside` (a ray-crossing count) catches that case where it
matters: a step along w that would put the player inside a solid.

Arrays: ``tris (t, 3, 3) float64``, each row a triangle's three corners.
"""

from __future__ import annotations

import numpy as np

#: Test axes shorter than this (an edge parallel to a box axis gives a zero
#: cross product) separate nothing and are skipped. Edge vectors are at least
#: the section's welding precision long (about 1e-6 m for float32 vertices), so
#: a cross product of a unit axis with a real edge is far above 1e-12.
AXIS_EPS = 1e-12

_E = np.eye(3)


def triangles_of(mesh) -> np.ndarray:
    """The triangles ``(t, 3, 3) float64`` of a :class:`~across_dimensions.core.mesh.TriMesh3`."""
    if mesh is None or len(mesh.faces) == 0:
        return np.zeros((0, 3, 3))
    return mesh.vertices.astype(np.float64)[mesh.faces.astype(np.int64)]


def _axes(tris: np.ndarray) -> np.ndarray:
    """The 13 separating-axis candidates per triangle, ``(t, 13, 3)`` (some may be zero)."""
    t = len(tris)
    edges = tris[:, [1, 2, 0]] - tris  # (t, 3, 3)
    normal = np.cross(edges[:, 0], edges[:, 1])  # (t, 3)
    # e_i x edge_j for the three box axes and three edges: (t, 3, 3, 3) -> (t, 9, 3)
    cross = np.cross(_E[None, :, None, :], edges[:, None, :, :]).reshape(t, 9, 3)
    return np.concatenate([np.broadcast_to(_E, (t, 3, 3)), normal[:, None, :], cross], axis=1)


class Soup:
    """Triangles prepared for many sweeps in one tick.

    Bounds are computed for all triangles at once (the cheap cull); the test
    axes and projections only for triangles a sweep comes near, once each, so a
    big section far from the player costs little.

    Parameters
    ----------
    tris : (t, 3, 3) float64

    Attributes
    ----------
    lo, hi : (t, 3) float64
        Each triangle's bounds.
    """

    def __init__(self, tris: np.ndarray):
        self.tris = np.asarray(tris, dtype=np.float64).reshape(-1, 3, 3)
        self.lo = self.tris.min(axis=1)
        self.hi = self.tris.max(axis=1)
        t = len(self.tris)
        self._ready = np.zeros(t, bool)
        self._axes = np.zeros((t, 13, 3))
        self._usable = np.zeros((t, 13), bool)
        self._t0 = np.zeros((t, 13))
        self._t1 = np.zeros((t, 13))

    def __len__(self) -> int:
        return len(self.tris)

    def prepared(self, which: np.ndarray) -> tuple:
        """``axes (k, 13, 3)``, ``usable (k, 13)``, ``t0, t1 (k, 13)`` of the triangles ``which (t,) bool``."""
        todo = which & ~self._ready
        if todo.any():
            tris = self.tris[todo]
            axes = _axes(tris)
            proj = np.einsum("tvi,tai->tav", tris, axes)
            self._axes[todo] = axes
            self._usable[todo] = np.einsum("tai,tai->ta", axes, axes) > AXIS_EPS
            self._t0[todo] = proj.min(axis=2)
            self._t1[todo] = proj.max(axis=2)
            self._ready |= todo
        return self._axes[which], self._usable[which], self._t0[which], self._t1[which]


def _soup(tris) -> Soup:
    return tris if isinstance(tris, Soup) else Soup(tris)


def sweep(lo, hi, axis: int, delta: float, tris, which=None) -> tuple[np.ndarray, np.ndarray]:
    """When a box moving along one axis overlaps each triangle.

    Parameters
    ----------
    lo, hi : (3,) float64
        The box at the start of the move.
    axis : int
        0, 1 or 2.
    delta : float
        Signed length of the move along ``axis``.
    tris : (t, 3, 3) float64 or Soup
    which : (t,) bool, optional
        Only these triangles.

    Returns
    -------
    entry, exit : (k,) float64
        The box overlaps triangle ``i`` for ``entry[i] < s < exit[i]``, ``s`` the
        fraction of the move; ``entry >= exit`` means never (the infinite line
        of motion is meant, so callers clip to ``[0, 1]``).
    """
    soup = _soup(tris)
    axes, usable, t0, t1 = soup.prepared(np.ones(len(soup), bool) if which is None else which)
    if len(axes) == 0:
        return np.zeros(0), np.zeros(0)
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    centre = 0.5 * (lo + hi)
    half = 0.5 * (hi - lo)
    c = axes @ centre  # (t, 13)
    r = np.abs(axes) @ half
    v = axes[:, :, axis] * delta  # how far the box's projection slides over the whole move
    # Overlap on an axis: c - r + s v < t1 and c + r + s v > t0.
    a = t0 - c - r  # need s v > a
    b = t1 - c + r  # need s v < b
    with np.errstate(divide="ignore", invalid="ignore"):
        pos, neg = v > 0, v < 0
        enter = np.where(pos, a / v, np.where(neg, b / v, np.where(a < 0, -np.inf, np.inf)))
        leave = np.where(pos, b / v, np.where(neg, a / v, np.where(b > 0, np.inf, -np.inf)))
    enter = np.where(usable, enter, -np.inf)
    leave = np.where(usable, leave, np.inf)
    return enter.max(axis=1), leave.min(axis=1)


def _near(lo, hi, soup: Soup) -> np.ndarray:
    """Triangles whose bounds meet the box ``[lo, hi]`` (closed): a cheap cull before the exact test."""
    return np.all((soup.lo <= hi) & (soup.hi >= lo), axis=1)


def overlapping(lo, hi, tris) -> np.ndarray:
    """Which triangles the open box ``(lo, hi)`` overlaps, ``(t,) bool``."""
    soup = _soup(tris)
    out = np.zeros(len(soup), bool)
    if len(soup) == 0:
        return out
    near = _near(lo, hi, soup)
    if near.any():
        enter, leave = sweep(lo, hi, 0, 0.0, soup, near)
        out[near] = enter < leave
    return out


def first_hit(lo, hi, axis: int, delta: float, tris) -> float | None:
    """The fraction ``s`` of the move at which the box first touches a triangle
    it did not already overlap, or None when the whole move is free.

    ``tris`` is ``(t, 3, 3) float64`` or a :class:`Soup` (prepared once for many moves).
    """
    if len(tris) == 0 or delta == 0.0:
        return None
    soup = _soup(tris)
    lo1, hi1 = np.array(lo, dtype=np.float64), np.array(hi, dtype=np.float64)
    lo1[axis] += min(delta, 0.0)
    hi1[axis] += max(delta, 0.0)
    near = _near(lo1, hi1, soup)
    if not near.any():
        return None
    enter, leave = sweep(lo, hi, axis, delta, soup, near)
    before = (enter < 0.0) & (leave > 0.0)  # already overlapping: ignored, so the box can leave
    hit = (enter < leave) & (enter < 1.0) & (leave > 0.0) & ~before
    if not hit.any():
        return None
    return float(max(enter[hit].min(), 0.0))


def inside(point, tris: np.ndarray) -> bool:
    """Is ``point (3,)`` inside the closed surface ``tris``? Counts crossings of a ray going up (+y).

    A ray through an edge or a corner could count a crossing twice or not at
    all; the ray is tilted by a fixed irrational-looking slope so that this
    needs a point placed exactly on such a line, which a level never does on
    purpose. The count is deterministic either way.
    """
    if len(tris) == 0:
        return False
    d = np.array([1e-3 * np.sqrt(2.0), 1.0, 1e-3 * np.sqrt(3.0)])
    p = np.asarray(point, dtype=np.float64)
    # Möller-Trumbore for all triangles at once.
    e1 = tris[:, 1] - tris[:, 0]
    e2 = tris[:, 2] - tris[:, 0]
    h = np.cross(d, e2)
    det = np.einsum("ti,ti->t", e1, h)
    ok = np.abs(det) > AXIS_EPS
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = p - tris[:, 0]
    u = np.einsum("ti,ti->t", s, h) * inv
    q = np.cross(s, e1)
    v = (q @ d) * inv
    t = np.einsum("ti,ti->t", e2, q) * inv
    hits = ok & (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0)
    return bool(hits.sum() % 2)


def box_blocked(lo, hi, tris: np.ndarray) -> bool:
    """Does the open box ``(lo, hi)`` overlap the solid bounded by ``tris`` (its surface, or lie inside it)?"""
    if len(tris) == 0:
        return False
    return bool(overlapping(lo, hi, tris).any()) or inside(0.5 * (np.asarray(lo) + np.asarray(hi)), tris)


class MeshParts:
    """The level's 3D meshes, ``[[mesh]]`` and ``[[world.mesh]]``, as the walker meets them:
    by their true surfaces (a doorway in an arch asset lets the player through), not their
    bounding boxes.

    A ``[[mesh]]`` is the same at every w: its surface triangles. A world's part
    in the slice at ``w`` is its 3D solid scaled about its bounds' centre by the
    world's profile there (:meth:`..world.scene.ExtendedWorld.scale_at`; the 4D
    mesh is built from the same layer table, and the section of an extruded
    prism between two layers is the solid at the interpolated scale), so its
    section is its solid's boundary triangles, scaled. Boxes are exact as boxes
    and stay boxes.

    Parameters
    ----------
    scene : Scene

    Attributes
    ----------
    rows : (k,) int64
        The parts' rows in ``[scene.static_boxes, scene.world_boxes_at(w)]`` (their
        bounding boxes, which the walker must then ignore).
    """

    def __init__(self, scene):
        from ..world.geometry import placement_matrix

        self._parts = []  # (world or None, centre (3,), triangles (t, 3, 3) at full size, lo, hi)
        rows = []
        level = scene.level
        for i, m in enumerate(level.meshes):
            from ..world.bake import load_surface

            v, f = load_surface(m.asset)
            model = placement_matrix(m.position, m.scale, m.yaw_deg)
            v = np.asarray(v, dtype=np.float64) @ model[:3, :3].T + model[:3, 3]
            self._add(None, v, np.asarray(f, dtype=np.int64))
            rows.append(len(level.boxes) + i)
        row = len(scene.static_boxes)
        for spec, wd in zip(level.worlds, scene.worlds):
            row += len(spec.boxes)
            for m in spec.meshes:
                from ..core.lift import boundary_faces3
                from ..world.bake import bake_solid

                v3, t3 = bake_solid(m.asset)
                model = placement_matrix(m.position, m.scale, m.yaw_deg)
                v3 = np.asarray(v3, dtype=np.float64) @ model[:3, :3].T + model[:3, 3]
                self._add(wd, v3, boundary_faces3(t3))
                rows.append(row)
                row += 1
        self.rows = np.array(rows, dtype=np.int64)

    def _add(self, world, v: np.ndarray, faces: np.ndarray) -> None:
        lo, hi = v.min(axis=0), v.max(axis=0)
        self._parts.append((world, 0.5 * (lo + hi), v[faces], lo, hi))

    def __len__(self) -> int:
        return len(self._parts)

    def triangles_at(self, w: float, feet, margin: float) -> list:
        """Each part's triangles in the slice at ``w``, ``(t, 3, 3) float64``, for parts whose
        (scaled) bounds come within ``margin`` of ``feet (3,)`` (the others are left out)."""
        out = []
        f = np.asarray(feet, dtype=np.float64)[:3]
        for wd, c, tris, lo, hi in self._parts:
            s = 1.0 if wd is None else wd.scale_at(w)
            if s <= 0.0:
                continue
            if np.any(c + s * (lo - c) > f + margin) or np.any(c + s * (hi - c) < f - margin):
                continue
            out.append(tris if s == 1.0 else c + s * (tris - c))
        return out


__all__ = ["Soup", "MeshParts", "triangles_of", "sweep", "overlapping", "first_hit", "inside", "box_blocked"]
