"""Ready-made 4D solids as closed, positively oriented :class:`TetMesh4`.

Every builder returns a validated mesh centred at the origin, with ``float32``
vertices, ``uint32`` tets, a ``name`` and a gentle default per-vertex colour
(pass ``color=`` to override it).

=================  =========================================  =====================
name               solid                                      size parameter
=================  =========================================  =====================
``5-cell``         regular simplex, 5 tetrahedral cells       circumradius
``tesseract``      hypercube ``[-size/2, size/2]^4``          edge ``size``
``16-cell``        cross-polytope, 16 tetrahedral cells       circumradius
``24-cell``        24 octahedral cells                        circumradius (= edge)
``120-cell``       120 dodecahedral cells                     circumradius
``600-cell``       600 tetrahedral cells                      circumradius
``hypersphere``    tessellated 3-sphere (600-cell, split)     radius
``duoprism``       p-gon x q-gon                              circumradii r1, r2
``cubinder``       disc x square                              radius, height
``duocylinder``    disc x disc                                radius
``spherinder``     ball x segment                             radius, height
=================  =========================================  =====================

Method
------
All the solids are convex, so one generic builder serves them all:
:func:`convex_polytope` takes the vertices and the outward facet normals, finds
the face lattice (cells, polygons, edges) and triangulates it by *pulling*:
each polygon is fanned from its lowest-index vertex and each cell is coned
from its lowest-index vertex over the triangles of the polygons that do not
contain it. Both choices depend only on the face itself, so neighbouring cells
triangulate a shared polygon the same way and the mesh closes with no added
vertices. Facet normals of the regular polychora are the vertices of the dual
(5-cell: its own negated vertices; tesseract <-> 16-cell; 24-cell <-> 24-cell;
120-cell <-> 600-cell); a product ``A x B`` has facets ``(facet of A) x B``
with normal ``(n_A, 0)`` and ``A x (facet of B)`` with normal ``(0, n_B)``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from itertools import permutations
from typing import NamedTuple

import numpy as np

from .errors import InputError
from .mesh import MeshError, TetMesh4, cross4

PHI = (1.0 + 5.0**0.5) / 2.0


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
    return _finish(v, tets, name, color, _PALETTES.get(name))


def _finish(v: np.ndarray, tets: np.ndarray, name: str, color, palette=None) -> TetMesh4:
    colors = _default_colors(v, palette) if color is None else color
    return TetMesh4(v.astype(np.float32), tets.astype(np.uint32), colors, name).validate()


# ==================================================================== colours
# Linear RGB pairs: colour at low w, colour at high w.
_PALETTES = {
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


# ======================================================= coordinate helpers
def _signed_permutations(base, even_only: bool = False) -> np.ndarray:
    """All sign changes and (even) permutations of ``base``, duplicates removed.

    Returns
    -------
    (k, 4) float64
    """
    base = np.asarray(base, dtype=np.float64)
    perms = [p for p in permutations(range(4)) if not even_only or _parity(p) == 0]
    signs = np.array(np.meshgrid(*[[1.0, -1.0]] * 4, indexing="ij")).reshape(4, -1).T  # (16, 4)
    pts = np.concatenate([(signs * base)[:, list(p)] for p in perms])
    # "+ 0.0" turns -0.0 into 0.0 so signed zeros are not counted twice.
    return np.unique(np.round(pts, 12) + 0.0, axis=0)


def _parity(p) -> int:
    return sum(p[i] > p[j] for i in range(len(p)) for j in range(i + 1, len(p))) % 2


def _cell600_vertices() -> np.ndarray:
    """The 120 vertices of the 600-cell on the unit 3-sphere, ``(120, 4) float64``."""
    return np.concatenate(
        [
            _signed_permutations([1.0, 0.0, 0.0, 0.0]),
            _signed_permutations([0.5, 0.5, 0.5, 0.5]),
            # (1, phi, 1/phi, 0) rather than (phi, 1, ...): the mirror image, the
            # chirality whose cell directions are the 120-cell vertices below.
            _signed_permutations([0.5, PHI / 2, 0.5 / PHI, 0.0], even_only=True),
        ]
    )


def _cell120_vertices() -> np.ndarray:
    """The 600 vertices of the 120-cell, circumradius ``sqrt(8)``, ``(600, 4) float64``.

    Oriented dually to :func:`_cell600_vertices`: each 600-cell vertex is the
    direction of a dodecahedral cell's centre.
    """
    s5, ip, ip2 = 5.0**0.5, 1.0 / PHI, 1.0 / PHI**2
    return np.concatenate(
        [
            _signed_permutations([0.0, 0.0, 2.0, 2.0]),
            _signed_permutations([1.0, 1.0, 1.0, s5]),
            _signed_permutations([ip2, PHI, PHI, PHI]),
            _signed_permutations([ip, ip, ip, PHI**2]),
            _signed_permutations([0.0, ip2, 1.0, PHI**2], even_only=True),
            _signed_permutations([0.0, ip, PHI, s5], even_only=True),
            _signed_permutations([ip, 1.0, PHI, 2.0], even_only=True),
        ]
    )


def _simplex_vertices() -> np.ndarray:
    """Regular 4-simplex on the unit 3-sphere, ``(5, 4) float64``.

    The corners of the standard simplex in R^5, centred and written in an
    orthonormal basis of the hyperplane ``sum(x) = 0``; the last vertex is put
    on the -w axis so the default slice ``w = 0`` shows a tetrahedron.
    """
    e = np.eye(5) - 0.2
    # Orthonormal basis of sum(x) = 0 with the last basis vector along e[4].
    q, _ = np.linalg.qr(np.column_stack([e[4], e[0] - e[1], e[0] + e[1] - 2 * e[2], e[0] + e[1] + e[2] - 3 * e[3]]))
    coords = e @ q[:, [1, 2, 3, 0]]  # (5, 4): the e[4] direction becomes w
    if coords[4, 3] > 0:
        coords[:, 3] *= -1.0
        coords[:, 0] *= -1.0  # keep a proper rotation of the construction
    return coords / np.linalg.norm(coords, axis=1, keepdims=True)


def _polygon(k: int, radius: float, phase: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Regular k-gon: vertices ``(k, 2)`` and outward edge normals ``(k, 2)``."""
    if k < 3:
        raise ValueError(f"a polygon needs at least 3 sides, got {k}")
    if radius <= 0:
        raise ValueError(f"polygon radius must be positive, got {radius}")
    a = phase + 2 * np.pi * np.arange(k) / k
    b = a + np.pi / k
    return radius * np.stack([np.cos(a), np.sin(a)], axis=1), np.stack([np.cos(b), np.sin(b)], axis=1)


def _product(va, na, vb, nb) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and facet normals of ``A x B`` (A's coordinates first).

    Returns
    -------
    vertices : (len(va) * len(vb), da + db) float64
    normals : (len(na) + len(nb), da + db) float64
    """
    va, na, vb, nb = (np.asarray(x, dtype=np.float64) for x in (va, na, vb, nb))
    da, db = va.shape[1], vb.shape[1]
    verts = np.concatenate([np.repeat(va, len(vb), axis=0), np.tile(vb, (len(va), 1))], axis=1)
    normals = np.concatenate(
        [
            np.concatenate([na, np.zeros((len(na), db))], axis=1),
            np.concatenate([np.zeros((len(nb), da)), nb], axis=1),
        ]
    )
    return verts, normals


def _positive(value: float, what: str) -> float:
    value = float(value)
    if not value > 0:
        raise ValueError(f"{what} must be positive, got {value}")
    return value


# ===================================================== regular polychora
def simplex5(radius: float = 1.0, color=None) -> TetMesh4:
    """The 5-cell (regular 4-simplex): 5 vertices, 5 tetrahedral cells.

    Parameters
    ----------
    radius : float
        Circumradius; the edge is ``radius * sqrt(5/2)``.
    color : array_like, optional

    Returns
    -------
    TetMesh4
        5 tets.
    """
    v = _simplex_vertices() * _positive(radius, "radius")
    # Each cell is opposite one vertex, so its outward normal is minus that vertex.
    return convex_polytope(v, -v, "5-cell", color)


def tesseract(size: float = 1.0, color=None) -> TetMesh4:
    """The hypercube ``[-size/2, size/2]^4``: 16 vertices, 8 cubic cells.

    Vertices are in lexicographic order. Each cube is split into 6 tets by the
    pulling rule: coned from its lowest-index corner over the three squares
    not containing it, every square cut along the diagonal through its own
    lowest-index corner, so both cubes sharing a square cut it the same way
    (like the Kuhn split, a global vertex order decides; no added vertices).

    Parameters
    ----------
    size : float
        Edge length (circumradius ``size``).
    color : array_like, optional

    Returns
    -------
    TetMesh4
        48 tets.
    """
    h = _positive(size, "size") / 2.0
    v = _signed_permutations([h, h, h, h])
    normals = np.concatenate([np.eye(4), -np.eye(4)])
    return convex_polytope(v, normals, "tesseract", color)


def cell16(radius: float = 1.0, color=None) -> TetMesh4:
    """The 16-cell (cross-polytope ``|x|_1 <= radius``): 8 vertices, 16 cells.

    Parameters
    ----------
    radius : float
        Circumradius; the edge is ``radius * sqrt(2)``.
    color : array_like, optional

    Returns
    -------
    TetMesh4
        16 tets.
    """
    v = _signed_permutations([_positive(radius, "radius"), 0.0, 0.0, 0.0])
    return convex_polytope(v, _signed_permutations([1.0, 1.0, 1.0, 1.0]), "16-cell", color)


def cell24(radius: float = 1.0, color=None) -> TetMesh4:
    """The 24-cell: 24 vertices, 24 octahedral cells.

    Vertices are the permutations of ``(+-1, +-1, 0, 0) * radius / sqrt(2)``;
    the edge length equals the circumradius.

    Parameters
    ----------
    radius : float
        Circumradius (= edge length).
    color : array_like, optional

    Returns
    -------
    TetMesh4
        96 tets.
    """
    v = _signed_permutations([1.0, 1.0, 0.0, 0.0]) * (_positive(radius, "radius") / 2**0.5)
    # The dual 24-cell: the tesseract's 8 cell directions and its 16 vertices.
    normals = np.concatenate([_signed_permutations([1.0, 0.0, 0.0, 0.0]), _signed_permutations([0.5] * 4)])
    return convex_polytope(v, normals, "24-cell", color)


def cell120(radius: float = 1.0, color=None) -> TetMesh4:
    """The 120-cell: 600 vertices, 1200 edges, 720 pentagons, 120 dodecahedra.

    Parameters
    ----------
    radius : float
        Circumradius; the edge is ``radius * (3 - sqrt(5)) / sqrt(8)``.
    color : array_like, optional

    Returns
    -------
    TetMesh4
        3240 tets (27 per dodecahedron).
    """
    v = _cell120_vertices() * (_positive(radius, "radius") / 8**0.5)
    return convex_polytope(v, _cell600_vertices(), "120-cell", color)


def cell600(radius: float = 1.0, color=None) -> TetMesh4:
    """The 600-cell: 120 vertices, 720 edges, 1200 triangles, 600 tetrahedra.

    Parameters
    ----------
    radius : float
        Circumradius; the edge is ``radius / phi``.
    color : array_like, optional

    Returns
    -------
    TetMesh4
        600 tets.
    """
    v = _cell600_vertices() * _positive(radius, "radius")
    return convex_polytope(v, _cell120_vertices(), "600-cell", color)


# ================================================================ 3-sphere
# Edges of tet (a, b, c, d) in the order ab ac ad bc bd cd.
_TET_EDGES = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])


def hypersphere(radius: float = 1.0, subdivisions: int = 1, color=None) -> TetMesh4:
    """A tessellated 3-sphere: the 600-cell with each tet split 1 -> 8.

    Each split puts a vertex on every edge's midpoint, pushed out onto the
    sphere, and so scales tet count by 8 and halves edge lengths.

    Parameters
    ----------
    radius : float
    subdivisions : int
        Number of 1 -> 8 splits; 0 is the 600-cell itself.
    color : array_like, optional

    Returns
    -------
    TetMesh4
        ``600 * 8**subdivisions`` tets, every vertex at distance ``radius``.
        The enclosed volume approaches ``pi**2 * radius**4 / 2`` from below.
    """
    radius = _positive(radius, "radius")
    if int(subdivisions) != subdivisions or subdivisions < 0:
        raise ValueError(f"subdivisions must be a whole number >= 0, got {subdivisions}")
    base = cell600()
    v, tets = base.vertices.astype(np.float64), base.tets.astype(np.int64)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    for _ in range(int(subdivisions)):
        v, tets = _split_on_sphere(v, tets)
    return _finish(v * radius, tets, "hypersphere", color, _PALETTES["hypersphere"])


def _split_on_sphere(v: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One 1 -> 8 split of a unit 3-sphere mesh, keeping tets positive.

    Parameters
    ----------
    v : (n, 4) float64
        On the unit sphere.
    tets : (m, 4) int64
        Positively oriented.

    Returns
    -------
    v : (n + e, 4) float64
    tets : (8m, 4) int64
    """
    n = len(v)
    pairs = np.sort(tets[:, _TET_EDGES], axis=2).reshape(-1, 2)  # 6 per tet
    # One int64 key per edge: far faster to unique than rows.
    keys, eid = np.unique(pairs[:, 0] * n + pairs[:, 1], return_inverse=True)
    edges = np.stack([keys // n, keys % n], axis=1)
    flat_mid = 0.5 * (v[edges[:, 0]] + v[edges[:, 1]])
    mid = flat_mid / np.linalg.norm(flat_mid, axis=1, keepdims=True)
    ab, ac, ad, bc, bd, cd = (n + eid.reshape(-1, 6)).T
    a, b, c, d = tets.T
    corners = [(a, ab, ac, ad), (ab, b, bc, bd), (ac, bc, c, cd), (ad, bd, cd, d)]
    v_new = np.concatenate([v, mid])
    # The inner octahedron is cut along its shortest diagonal (measured on the
    # sphere): long diagonals make flat tets that invert when pushed outward.
    diagonals = np.stack([(ab, cd), (ac, bd), (ad, bc)])  # (3, 2, m)
    lengths = np.linalg.norm(v_new[diagonals[:, 0]] - v_new[diagonals[:, 1]], axis=2)  # (3, m)
    choice = np.argmin(lengths, axis=0)
    # For each diagonal (p, q), the four other midpoints in cyclic order round it.
    rings = np.stack(
        [
            np.stack([ac, bc, bd, ad]),
            np.stack([ab, bc, cd, ad]),
            np.stack([ab, bd, cd, ac]),
        ]
    )  # (3, 4, m)
    cols = np.arange(len(tets))
    p, q = diagonals[choice, 0, cols], diagonals[choice, 1, cols]
    ring = rings[choice, :, cols]  # (m, 4)
    # In the flat parent every child is the image of the same child of any
    # other positive tet under an orientation-preserving affine map, so which
    # octahedron tets need a swap depends only on (diagonal, i): see _OCTA_SWAP.
    octa = []
    for i in range(4):
        r0, r1 = ring[:, i], ring[:, (i + 1) % 4]
        swap = _OCTA_SWAP[choice, i]
        octa.append((p, q, np.where(swap, r1, r0), np.where(swap, r0, r1)))
    children = np.stack([np.stack(t, axis=1) for t in corners + octa], axis=1).reshape(-1, 4)
    # Pushing midpoints onto the sphere must not invert anything: for a tet
    # (a, b, c, d) cross4 . centroid = -det[a, b, c, d] must stay positive.
    inverted = np.linalg.det(v_new[children]) >= 0
    if inverted.any():
        raise MeshError(f"hypersphere split inverted {int(inverted.sum())} tets")
    return v_new, children


def _octahedron_swaps() -> np.ndarray:
    """``(3, 4) bool``: which inner-octahedron tets of the 1 -> 8 split need a swap.

    Found once on a reference positive tet in the hyperplane ``w = 1``, with
    the same vertex roles as :func:`_split_on_sphere`.
    """
    ref = np.array([[0, 0, 0, 1], [1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1]], dtype=np.float64)
    if np.linalg.det(ref) > 0:  # make it positive: -det > 0
        ref = ref[[0, 2, 1, 3]]
    mid = {f"{'abcd'[i]}{'abcd'[j]}": 0.5 * (ref[i] + ref[j]) for i, j in _TET_EDGES}
    diagonals = [("ab", "cd"), ("ac", "bd"), ("ad", "bc")]
    rings = [("ac", "bc", "bd", "ad"), ("ab", "bc", "cd", "ad"), ("ab", "bd", "cd", "ac")]
    out = np.zeros((3, 4), dtype=bool)
    for k, ((p, q), ring) in enumerate(zip(diagonals, rings)):
        for i in range(4):
            t = np.stack([mid[p], mid[q], mid[ring[i]], mid[ring[(i + 1) % 4]]])
            out[k, i] = np.linalg.det(t) > 0
    return out


_OCTA_SWAP = _octahedron_swaps()


# ================================================================ products
def duoprism(p: int = 6, q: int = 6, r1: float = 1.0, r2: float = 1.0, color=None) -> TetMesh4:
    """The p-q duoprism: a regular p-gon (xy plane) times a q-gon (zw plane).

    Its cells are p q-gonal prisms and q p-gonal prisms.

    Parameters
    ----------
    p, q : int
        Sides of each polygon, >= 3.
    r1, r2 : float
        Circumradius of each polygon.
    color : array_like, optional

    Returns
    -------
    TetMesh4
        Enclosed volume ``area(p-gon) * area(q-gon)``.
    """
    va, na = _polygon(_sides(p, "p"), r1)
    vb, nb = _polygon(_sides(q, "q"), r2)
    v, normals = _product(va, na, vb, nb)
    return convex_polytope(v, normals, "duoprism", color)


def cubinder(segments: int = 24, radius: float = 0.5, height: float = 1.0, color=None) -> TetMesh4:
    """Disc times square: a ``segments``-gon in the xz plane, a square in yw.

    Sliced at ``w = 0`` it is an upright cylinder (y is up).

    Parameters
    ----------
    segments : int
        Sides of the polygon approximating the disc.
    radius : float
        Circumradius of that polygon.
    height : float
        Side of the square ``[-height/2, height/2]^2`` in y and w.
    color : array_like, optional

    Returns
    -------
    TetMesh4
    """
    disc_v, disc_n = _polygon(_sides(segments, "segments"), radius)
    h = _positive(height, "height")
    # A square is the 4-gon with phase 45 degrees and circumradius h / sqrt(2).
    sq_v, sq_n = _polygon(4, h / 2**0.5, np.pi / 4)
    v, normals = _product(disc_v, disc_n, sq_v, sq_n)  # columns (x, z, y, w)
    order = [0, 2, 1, 3]
    return convex_polytope(v[:, order], normals[:, order], "cubinder", color)


def duocylinder(segments: int = 24, radius: float = 0.5, color=None) -> TetMesh4:
    """Disc times disc: the ``segments``-``segments`` duoprism of equal radii.

    Parameters
    ----------
    segments : int
    radius : float
        Circumradius of each polygon.
    color : array_like, optional

    Returns
    -------
    TetMesh4
    """
    n = _sides(segments, "segments")
    va, na = _polygon(n, radius)
    v, normals = _product(va, na, va, na)
    return convex_polytope(v, normals, "duocylinder", color)


def spherinder(radius: float = 0.5, height: float = 1.0, subdivisions: int = 2, color=None) -> TetMesh4:
    """Ball times segment: an icosphere in xyz times ``[-height/2, height/2]`` in w.

    Sliced at any ``|w| < height/2`` it is the icosphere.

    Parameters
    ----------
    radius : float
        Circumradius of the icosphere.
    height : float
        Extent along w.
    subdivisions : int
        Icosphere refinement (``20 * 4**subdivisions`` triangles).
    color : array_like, optional

    Returns
    -------
    TetMesh4
    """
    sv, faces = icosphere(_positive(radius, "radius"), subdivisions)
    fn = np.cross(sv[faces[:, 1]] - sv[faces[:, 0]], sv[faces[:, 2]] - sv[faces[:, 0]])
    h = _positive(height, "height") / 2.0
    v, normals = _product(sv, fn, [[-h], [h]], [[-1.0], [1.0]])
    return convex_polytope(v, normals, "spherinder", color)


def icosphere(radius: float = 1.0, subdivisions: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Geodesic sphere from a subdivided icosahedron (3D).

    Parameters
    ----------
    radius : float
    subdivisions : int
        Each step splits every triangle in four.

    Returns
    -------
    vertices : (10 * 4**s + 2, 3) float64
        On the sphere.
    faces : (20 * 4**s, 3) int64
        Counter-clockwise seen from outside.
    """
    if int(subdivisions) != subdivisions or subdivisions < 0:
        raise ValueError(f"subdivisions must be a whole number >= 0, got {subdivisions}")
    v = np.array(
        [
            [-1, PHI, 0],
            [1, PHI, 0],
            [-1, -PHI, 0],
            [1, -PHI, 0],
            [0, -1, PHI],
            [0, 1, PHI],
            [0, -1, -PHI],
            [0, 1, -PHI],
            [PHI, 0, -1],
            [PHI, 0, 1],
            [-PHI, 0, -1],
            [-PHI, 0, 1],
        ],
        dtype=np.float64,
    )
    f = np.array(
        [
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ],
        dtype=np.int64,
    )
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    for _ in range(int(subdivisions)):
        n = len(v)
        pairs = np.sort(f[:, [[0, 1], [1, 2], [2, 0]]], axis=2).reshape(-1, 2)
        edges, eid = np.unique(pairs, axis=0, return_inverse=True)
        m = v[edges[:, 0]] + v[edges[:, 1]]
        v = np.concatenate([v, m / np.linalg.norm(m, axis=1, keepdims=True)])
        ab, bc, ca = (n + eid.reshape(-1, 3)).T
        a, b, c = f.T
        f = np.stack(
            [np.stack(t, axis=1) for t in [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]], axis=1
        ).reshape(-1, 3)
    return v * radius, f


def _sides(k, what: str) -> int:
    if int(k) != k or k < 3:
        raise ValueError(f"{what} must be a whole number >= 3, got {k}")
    return int(k)


# ================================================================ registry
SHAPES: dict[str, Callable[..., TetMesh4]] = {
    "5-cell": simplex5,
    "simplex": simplex5,
    "tesseract": tesseract,
    "16-cell": cell16,
    "24-cell": cell24,
    "120-cell": cell120,
    "600-cell": cell600,
    "hypersphere": hypersphere,
    "duoprism": duoprism,
    "cubinder": cubinder,
    "duocylinder": duocylinder,
    "spherinder": spherinder,
}


#: What each shape parameter may be, for :func:`make_shape` and for levels
#: (``world/level.py`` checks an object's ``params`` with the same table).
#: ``(kind, (lo, hi))``: ``"whole"`` is an integer from ``lo`` to ``hi``;
#: ``"positive"`` is a finite number from ``lo`` to ``hi`` (sizes, in world
#: units). The whole-number bounds keep every shape under about 3 s and 400 MB
#: to build (``hypersphere`` with ``subdivisions=3`` has 307,200 tets, a
#: 128 x 128 ``duoprism`` 96,768); each subdivision multiplies the work by 8.
SHAPE_PARAM_RULES: dict[str, tuple[str, tuple[float, float]]] = {
    "radius": ("positive", (1e-3, 1e3)),
    "size": ("positive", (1e-3, 1e3)),
    "height": ("positive", (1e-3, 1e3)),
    "r1": ("positive", (1e-3, 1e3)),
    "r2": ("positive", (1e-3, 1e3)),
    "p": ("whole", (3, 128)),
    "q": ("whole", (3, 128)),
    "segments": ("whole", (3, 128)),
    "subdivisions": ("whole", (0, 3)),
}


def shape_param_problem(name: str, value) -> str | None:
    """Why ``value`` is not allowed for the shape parameter ``name`` (None if it is).

    Parameters outside :data:`SHAPE_PARAM_RULES` (``color``) are not judged here.
    """
    if name not in SHAPE_PARAM_RULES:
        return None
    kind, (lo, hi) = SHAPE_PARAM_RULES[name]
    is_number = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))
    if kind == "whole":
        whole = is_number and (isinstance(value, (int, np.integer)) or float(value).is_integer())
        if not (whole and lo <= value <= hi):
            return f"'{name}' must be a whole number from {lo} to {hi}, got {value!r}"
    elif not (is_number and np.isfinite(value) and lo <= value <= hi):
        return f"'{name}' must be a finite number from {lo:g} to {hi:g}, got {value!r}"
    return None


def make_shape(name: str, **params) -> TetMesh4:
    """Build a shape by its command-line name.

    Every parameter is checked against :data:`SHAPE_PARAM_RULES` before any
    work starts, so ``subdivisions=50`` is refused at once instead of filling
    memory.

    Parameters
    ----------
    name : str
        A key of :data:`SHAPES` (case and ``_``/``-`` are forgiven).
    **params
        Keyword arguments of that shape's builder.

    Returns
    -------
    TetMesh4

    Raises
    ------
    InputError
        One line naming the known shapes, or the parameter and its range.
    """
    key = str(name).strip().lower().replace("_", "-")
    if key not in SHAPES:
        raise InputError(f"unknown shape {name!r}; known shapes: {', '.join(SHAPES)}")
    builder = SHAPES[key]
    accepted = list(inspect.signature(builder).parameters)
    unknown = [p for p in params if p not in accepted]
    if unknown:
        raise InputError(f"shape {key!r} takes {', '.join(accepted)}; got unknown parameter(s) {', '.join(unknown)}")
    for pname, value in params.items():
        problem = shape_param_problem(pname, value)
        if problem:
            raise InputError(f"shape {key!r}: {problem}")
    try:
        return builder(**params)
    except (TypeError, ValueError) as e:
        given = ", ".join(f"{k}={v!r}" for k, v in params.items())
        raise InputError(f"shape {key!r} with {given}: {e}") from None
