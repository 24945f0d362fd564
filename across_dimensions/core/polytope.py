"""Closed tetrahedral boundaries of convex 4-polytopes, from vertices and facet normals.

One generic builder serves every solid of :mod:`.shapes`: :func:`convex_polytope`
finds the face lattice (cells, polygons, edges) and triangulates it by
*pulling*: each polygon is fanned from its lowest-index vertex and each cell is
coned from its lowest-index vertex over the triangles of the polygons that do
not contain it. Both choices depend only on the face itself, so neighbouring
cells triangulate a shared polygon the same way and the mesh closes with no
added vertices.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .mesh import MeshError, TetMesh4, cross4


# =============================================================== face lattice
class PolytopeLattice(NamedTuple):
    """The faces of a convex 4-polytope down to its edges.

    Attributes
    ----------
    incidence : (f, n) bool
        ``incidence[c, i]``: vertex ``i`` lies on cell (facet) ``c``.
    polygons : list of (k,) int64
        Each 2-face's vertex indices in cyclic order, rotated so the lowest
        index comes first.
    polygon_cells : (F, 2) int64
        The two cells meeting at each 2-face.
    edges : (E, 2) int64
        The polytope's edges, ``edges[:, 0] < edges[:, 1]``, sorted.
    """

    incidence: np.ndarray
    polygons: list
    polygon_cells: np.ndarray
    edges: np.ndarray

    @property
    def counts(self) -> tuple[int, int, int, int]:
        """``(vertices, edges, polygons, cells)``."""
        return self.incidence.shape[1], len(self.edges), len(self.polygons), self.incidence.shape[0]


def polytope_lattice(vertices, facet_normals, tol: float = 1e-6) -> PolytopeLattice:
    """Face lattice of the convex hull of ``vertices`` given its facet normals.

    Parameters
    ----------
    vertices : (n, 4) array_like
        The polytope's vertices (all of them extreme points).
    facet_normals : (f, 4) array_like
        One outward normal per facet, any length.
    tol : float
        Relative tolerance for "lies on the facet's hyperplane".

    Returns
    -------
    PolytopeLattice

    Raises
    ------
    ValueError
        When a normal does not pick out a 3-dimensional facet.
    """
    v = np.asarray(vertices, dtype=np.float64)
    n = np.asarray(facet_normals, dtype=np.float64)
    n = n / np.linalg.norm(n, axis=1, keepdims=True)
    scale = float(np.abs(v).max())
    d = n @ v.T
    incidence = d >= d.max(axis=1, keepdims=True) - tol * scale
    _check_facets(v, incidence)

    # Two facets meet in a 2-face exactly when they share >= 3 vertices: the
    # vertices of a polytope are extreme points, so no three are collinear.
    inc_f = incidence.astype(np.float32)  # float: BLAS matmul, exact for counts this small
    shared = inc_f @ inc_f.T
    counts = np.diag(shared)
    same = np.triu((shared == counts[:, None]) & (shared == counts[None, :]), 1)
    if same.any():
        raise ValueError("two facet normals pick out the same facet; pass each facet once")
    ca, cb = np.nonzero(np.triu(shared >= 3, 1))
    polygon_cells = np.stack([ca, cb], axis=1).astype(np.int64)
    members = _pair_members(incidence, ca, cb)
    polygons, sides = _order_polygons(v, members)
    edges = np.unique(np.sort(sides, axis=1), axis=0)
    return PolytopeLattice(incidence, polygons, polygon_cells, edges)


def _check_facets(v: np.ndarray, incidence: np.ndarray) -> None:
    """Each facet must span a 3-dimensional hyperplane."""
    counts = incidence.sum(axis=1)
    if (counts < 4).any():
        bad = np.flatnonzero(counts < 4)
        raise ValueError(f"facet normals {bad[:5].tolist()} touch fewer than 4 vertices: not facets of this polytope")
    # Third singular value of each facet's centred vertex set, batched by size.
    for k in np.unique(counts):
        which = np.flatnonzero(counts == k)
        p = v[np.nonzero(incidence[which])[1].reshape(len(which), k)]
        s = np.linalg.svd(p - p.mean(axis=1, keepdims=True), compute_uv=False)
        flat = s[:, 2] <= 1e-9 * np.maximum(s[:, 0], 1e-300)
        if flat.any():
            raise ValueError(
                f"facet normals {which[flat][:5].tolist()} touch a flat (rank < 3) set of vertices: not facets"
            )


def _pair_members(incidence: np.ndarray, ca: np.ndarray, cb: np.ndarray) -> list:
    """Vertex indices shared by each pair of cells, in chunks to bound memory."""
    nv = incidence.shape[1]
    chunk = max(1, 4_000_000 // max(nv, 1))
    out = []
    for s in range(0, len(ca), chunk):
        rows, cols = np.nonzero(incidence[ca[s : s + chunk]] & incidence[cb[s : s + chunk]])
        splits = np.cumsum(np.bincount(rows, minlength=min(chunk, len(ca) - s)))[:-1]
        out.extend(np.split(cols.astype(np.int64), splits))
    return out


def _order_polygons(v: np.ndarray, members: list) -> tuple[list, np.ndarray]:
    """Sort each planar convex polygon's vertices by angle about its centroid.

    Polygons are grouped by size so each group is one batched SVD.

    Returns
    -------
    ordered : list of (k,) int64
        Cyclic order starting at the lowest index.
    sides : (s, 2) int64
        Every polygon's boundary edges (each polytope edge several times).
    """
    sizes = np.array([len(m) for m in members])
    ordered: list = [None] * len(members)
    sides = []
    for k in np.unique(sizes):
        which = np.flatnonzero(sizes == k)
        idx = np.stack([members[i] for i in which])  # (g, k)
        p = v[idx]
        x = p - p.mean(axis=1, keepdims=True)
        _, _, vt = np.linalg.svd(x, full_matrices=False)  # plane basis: first two rows
        ang = np.arctan2(np.einsum("gkd,gd->gk", x, vt[:, 1]), np.einsum("gkd,gd->gk", x, vt[:, 0]))
        idx = np.take_along_axis(idx, np.argsort(ang, axis=1), axis=1)
        # Start at the lowest index: the fan centre of the pulling triangulation.
        start = np.argmin(idx, axis=1)
        roll = (np.arange(k)[None, :] + start[:, None]) % k
        idx = np.take_along_axis(idx, roll, axis=1)
        sides.append(np.stack([idx, np.roll(idx, -1, axis=1)], axis=2).reshape(-1, 2))
        for i, row in zip(which, idx):
            ordered[i] = row
    return ordered, np.concatenate(sides)


# ============================================================ triangulation
def pulling_tets(vertices, lattice: PolytopeLattice, facet_normals) -> tuple[np.ndarray, np.ndarray]:
    """Pulling triangulation of every cell, oriented by its outward normal.

    Parameters
    ----------
    vertices : (n, 4) array_like
    lattice : PolytopeLattice
    facet_normals : (f, 4) array_like

    Returns
    -------
    tets : (m, 4) int64
        Positively oriented (``cross4`` along the cell's outward normal).
    cell_of_tet : (m,) int64
    """
    v = np.asarray(vertices, dtype=np.float64)
    normals = np.asarray(facet_normals, dtype=np.float64)
    tris, tri_poly = _fan_triangles(lattice.polygons)
    # Each polygon's triangles belong to both cells meeting there.
    tri_cell = lattice.polygon_cells[tri_poly]  # (t, 2)
    cells = tri_cell.reshape(-1)
    tri_rep = np.repeat(tris, 2, axis=0)
    apex = np.argmax(lattice.incidence, axis=1)  # lowest-index vertex of each cell
    a = apex[cells]
    # A polygon containing the apex is fanned from it (the apex is its lowest
    # index too), so "triangle avoids apex" == "polygon avoids apex".
    keep = (tri_rep != a[:, None]).all(axis=1)
    tets = np.concatenate([a[keep, None], tri_rep[keep]], axis=1)
    cell_of_tet = cells[keep]
    tets = _orient(v, tets, normals[cell_of_tet])
    return tets, cell_of_tet


def _fan_triangles(polygons: list) -> tuple[np.ndarray, np.ndarray]:
    """Fan each polygon from its first vertex: ``(t, 3) int64`` and owner ``(t,)``."""
    tris, owner = [], []
    sizes = np.array([len(p) for p in polygons])
    for k in np.unique(sizes):
        which = np.flatnonzero(sizes == k)
        idx = np.stack([polygons[i] for i in which])
        j = np.arange(1, k - 1)
        t = np.stack([np.repeat(idx[:, :1], k - 2, axis=1), idx[:, j], idx[:, j + 1]], axis=2)
        tris.append(t.reshape(-1, 3))
        owner.append(np.repeat(which, k - 2))
    return np.concatenate(tris), np.concatenate(owner)


def _orient(v: np.ndarray, tets: np.ndarray, outward: np.ndarray) -> np.ndarray:
    """Swap two vertices of each tet whose ``cross4`` opposes ``outward``."""
    p = v[tets]
    s = np.einsum("ij,ij->i", cross4(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]), outward)
    scale = float(np.abs(v).max()) or 1.0
    if (np.abs(s) <= 1e-12 * scale**3 * np.linalg.norm(outward, axis=1)).any():
        raise MeshError("degenerate tet in triangulation: a cell is not 3-dimensional")
    tets = tets.copy()
    flip = s < 0
    tets[flip, 1], tets[flip, 2] = tets[flip, 2], tets[flip, 1].copy()
    return tets


def convex_polytope(vertices, facet_normals, name: str = "polytope", color=None, tol: float = 1e-6) -> TetMesh4:
    """Closed tetrahedral boundary of a convex 4-polytope.

    Parameters
    ----------
    vertices : (n, 4) array_like
        Every vertex must be an extreme point (no points inside faces).
    facet_normals : (f, 4) array_like
        Outward normal of each facet, any length.
    name : str
    color : array_like, optional
        ``(3,)``/``(4,)`` for one colour or ``(n, 3|4)`` per vertex; default
        is a gradient along w in the palette of ``name`` (grey if unknown).
    tol : float
        Relative tolerance for vertex-on-facet tests.

    Returns
    -------
    TetMesh4
        Validated.
    """
    v = np.asarray(vertices, dtype=np.float64)
    lattice = polytope_lattice(v, facet_normals, tol)
    tets, _ = pulling_tets(v, lattice, facet_normals)
    return finish_mesh(v, tets, name, color, PALETTES.get(name))


def finish_mesh(v: np.ndarray, tets: np.ndarray, name: str, color, palette=None) -> TetMesh4:
    colors = _default_colors(v, palette) if color is None else color
    return TetMesh4(v.astype(np.float32), tets.astype(np.uint32), colors, name).validate()


# ==================================================================== colours
# Linear RGB pairs: colour at low w, colour at high w.
PALETTES = {
    "5-cell": ((0.85, 0.30, 0.12), (0.95, 0.75, 0.20)),
    "tesseract": ((0.10, 0.35, 0.85), (0.30, 0.85, 0.80)),
    "16-cell": ((0.55, 0.15, 0.75), (0.95, 0.45, 0.65)),
    "24-cell": ((0.12, 0.55, 0.25), (0.75, 0.90, 0.30)),
    "120-cell": ((0.60, 0.10, 0.20), (0.95, 0.65, 0.35)),
    "600-cell": ((0.15, 0.20, 0.65), (0.70, 0.55, 0.95)),
    "hypersphere": ((0.08, 0.30, 0.60), (0.90, 0.55, 0.35)),
    "duoprism": ((0.20, 0.50, 0.55), (0.95, 0.85, 0.45)),
    "cubinder": ((0.45, 0.20, 0.10), (0.90, 0.60, 0.30)),
    "duocylinder": ((0.25, 0.15, 0.55), (0.40, 0.80, 0.85)),
    "spherinder": ((0.15, 0.45, 0.20), (0.55, 0.80, 0.95)),
}


def _default_colors(v: np.ndarray, palette) -> np.ndarray:
    """Blend between a palette's two colours along w, shaded gently along y.

    The w gradient tells cross-sections at different depths apart; the small
    y term keeps a single section from being one flat colour.

    Returns
    -------
    (n, 4) float32
    """
    low, high = np.asarray(palette or ((0.35, 0.35, 0.40), (0.85, 0.85, 0.80)), dtype=np.float64)
    t = _unit_range(v[:, 3])
    shade = 0.85 + 0.15 * _unit_range(v[:, 1])
    rgb = (low + t[:, None] * (high - low)) * shade[:, None]
    return np.concatenate([rgb, np.ones((len(v), 1))], axis=1).astype(np.float32)


def _unit_range(x: np.ndarray) -> np.ndarray:
    span = float(np.ptp(x))
    return (x - x.min()) / span if span > 0 else np.full_like(x, 0.5)


def positive(value: float, what: str) -> float:
    value = float(value)
    if not value > 0:
        raise ValueError(f"{what} must be positive, got {value}")
    return value
