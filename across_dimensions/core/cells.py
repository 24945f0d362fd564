"""A tet mesh's flat convex cells, found from its tets, for slicing cell by cell.

A polychoron's boundary is made of convex 3D cells (a 120-cell's 120
dodecahedra), each split into tets only because the mesh format is tets (27 per
dodecahedron). A hyperplane cuts a convex cell in one convex polygon, but
slicing tet by tet draws it as the 9-15 triangles its cut tets make. Slicing the
cell instead gives the same polygon as ``k - 2`` triangles for its ``k`` corners,
which are the cut points of the cell's real edges: about three times fewer
triangles for a software rasterizer to set up, and less work for the kernel.

The cells are found from the tets alone, so any mesh qualifies (a loaded file
as well as a built polychoron): tets that share a face and a hyperplane belong
to one cell; a cell's real edges are the edges of its boundary triangles where
those triangles crease (not the diagonals that split a pentagon into
triangles). A mesh is sliced by cells only when every cell is closed and convex
and cells hold several tets on average; otherwise :func:`mesh_cells` returns
``None`` and the tet slicer is used.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .mesh import TetMesh4, cross4

#: Fewest tets per cell, on average, for slicing by cells to pay: a prism lifted
#: from a 3D triangle is 3 tets, whose section is at most 5 triangles anyway.
MIN_TETS_PER_CELL = 4.0
#: Angle (radians) under which two normals count as parallel: coplanar tets, flat edges.
ANGLE_TOL = 1e-4


class Cells(NamedTuple):
    """A mesh's convex cells (vertex indices of the mesh).

    Attributes
    ----------
    edge_start : (c + 1,) int64
        Cell ``i``'s real edges are ``edges[edge_start[i]:edge_start[i + 1]]``.
    edges : (e, 2) int64
        Vertex pairs, lower index first (cut points are interpolated from it,
        as the tet slicer does, so both agree to the bit on a shared edge).
    tets_of : (c, 4) int64
        One tet of each cell (its vertices, in the mesh's orientation): the
        slicer takes the cell's outward normal from it, as from any tet.
    centers : (c, 4) float64
        Bounding sphere of each cell.
    radii : (c,) float64
    """

    edge_start: np.ndarray
    edges: np.ndarray
    tets_of: np.ndarray
    centers: np.ndarray
    radii: np.ndarray


def mesh_cells(mesh: TetMesh4) -> Cells | None:
    """The mesh's convex cells, or ``None`` when slicing by cells does not apply.

    Cached on the mesh.
    """
    if "cells" not in mesh._cache:
        mesh._cache["cells"] = _find_cells(mesh)
    return mesh._cache["cells"]


def _find_cells(mesh: TetMesh4) -> Cells | None:
    faces, owners = mesh.unique_faces()
    if (owners[:, 1] < 0).any():
        return None  # an open mesh: cells may be open too
    n = mesh.tet_normals()
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    a, b = owners[:, 0], owners[:, 1]
    inside = np.einsum("ij,ij->i", n[a], n[b]) >= np.cos(ANGLE_TOL)
    cell = _components(len(mesh.tets), a[inside], b[inside])
    count = int(cell.max()) + 1
    if len(mesh.tets) < MIN_TETS_PER_CELL * count:
        return None
    # Boundary triangles of each cell: the faces between two cells, once per side.
    bface = np.flatnonzero(~inside)
    tri_cell = np.concatenate([cell[a[bface]], cell[b[bface]]])
    tri = np.concatenate([faces[bface], faces[bface]]).astype(np.int64)
    v = mesh.vertices.astype(np.float64)
    # Each cell's normal: that of its first tet (all its tets share the hyperplane).
    first_tet = np.full(count, len(mesh.tets))
    np.minimum.at(first_tet, cell, np.arange(len(mesh.tets)))
    normals = n[first_tet]
    # In-hyperplane normal of each boundary triangle (orientation fixed below).
    p = v[tri]
    tn = cross4(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], normals[tri_cell])
    tn /= np.maximum(np.linalg.norm(tn, axis=1, keepdims=True), 1e-300)
    # Every triangle edge, keyed by (cell, lower vertex, higher vertex).
    e = np.sort(tri[:, [[0, 1], [1, 2], [2, 0]]], axis=2).reshape(-1, 2)
    e_cell = np.repeat(tri_cell, 3)
    e_tri = np.repeat(np.arange(len(tri)), 3)
    nv = len(v)
    key = (e_cell * nv + e[:, 0]) * nv + e[:, 1]
    order = np.argsort(key, kind="stable")
    key, e, e_cell, e_tri = key[order], e[order], e_cell[order], e_tri[order]
    # A closed cell's surface has every edge in exactly two of its triangles.
    if len(key) % 2 or (key[0::2] != key[1::2]).any():
        return None
    e, e_cell = e[0::2], e_cell[0::2]
    t0, t1 = e_tri[0::2], e_tri[1::2]
    real = np.abs(np.einsum("ij,ij->i", tn[t0], tn[t1])) < np.cos(ANGLE_TOL)
    e, e_cell = e[real], e_cell[real]  # sorted by cell already
    edge_start = np.searchsorted(e_cell, np.arange(count + 1))
    centers, radii = _spheres(v, e, e_cell, count)
    if not _convex(v, tri, tri_cell, tn, e, e_cell, radii):
        return None
    return Cells(edge_start.astype(np.int64), e, mesh.tets[first_tet].astype(np.int64), centers, radii)


def _components(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Connected components of ``n`` nodes joined by the pairs ``(a, b)``: labels ``0..k-1``."""
    label = np.arange(n)
    while True:
        low = np.minimum(label[a], label[b])
        new = label.copy()
        np.minimum.at(new, a, low)
        np.minimum.at(new, b, low)
        new = new[new]  # pointer jumping: labels point at labels
        if (new == label).all():
            break
        label = new
    return np.unique(label, return_inverse=True)[1].reshape(-1)


def _spheres(v, e, e_cell, count):
    """Bounding spheres ``(count, 4), (count,)`` of each cell's vertices (its edges' ends)."""
    ends = np.concatenate([e[:, 0], e[:, 1]])
    owner = np.concatenate([e_cell, e_cell])
    lo = np.full((count, 4), np.inf)
    hi = np.full((count, 4), -np.inf)
    np.minimum.at(lo, owner, v[ends])
    np.maximum.at(hi, owner, v[ends])
    centers = 0.5 * (lo + hi)
    r2 = np.zeros(count)
    np.maximum.at(r2, owner, ((v[ends] - centers[owner]) ** 2).sum(axis=1))
    return centers, np.sqrt(r2)


def _convex(v, tri, tri_cell, tn, e, e_cell, radii) -> bool:
    """Does every cell lie on one side of the plane of each of its boundary triangles?

    A closed polyhedron is convex exactly when every face's plane has all its
    vertices on one side. Each triangle's normal is turned away from the mean of
    the cell's vertices (inside a convex cell) and the vertices are tested against it.
    """
    count = len(radii)
    ends = np.concatenate([e[:, 0], e[:, 1]])
    owner = np.concatenate([e_cell, e_cell])
    order = np.argsort(owner, kind="stable")
    ends, owner = ends[order], owner[order]
    v_start = np.searchsorted(owner, np.arange(count + 1))
    t_order = np.argsort(tri_cell, kind="stable")
    t_start = np.searchsorted(tri_cell[t_order], np.arange(count + 1))
    for c in range(count):
        verts = v[np.unique(ends[v_start[c] : v_start[c + 1]])]
        ts = t_order[t_start[c] : t_start[c + 1]]
        corner = v[tri[ts, 0]]
        outward = np.einsum("tj,tj->t", corner - verts.mean(axis=0), tn[ts]) >= 0
        normal = tn[ts] * np.where(outward, 1.0, -1.0)[:, None]
        side = np.einsum("tvj,tj->tv", verts[None, :, :] - corner[:, None, :], normal)
        if (side > 1e-6 * max(radii[c], 1e-12)).any():
            return False
    return True
