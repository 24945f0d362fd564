"""The regular polychora and the tessellated 3-sphere, as closed :class:`~.mesh.TetMesh4`.

Facet normals of the regular polychora are the vertices of the dual (5-cell:
its own negated vertices; tesseract <-> 16-cell; 24-cell <-> 24-cell; 120-cell
<-> 600-cell); :func:`~.polytope.convex_polytope` builds each from its
vertices and those normals. The 3-sphere is the 600-cell split 1 -> 8 on the
sphere.
"""

from __future__ import annotations

from itertools import permutations

import numpy as np

from .mesh import MeshError, TetMesh4
from .polytope import PALETTES, convex_polytope, finish_mesh, positive

PHI = (1.0 + 5.0**0.5) / 2.0


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
    v = _simplex_vertices() * positive(radius, "radius")
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
    h = positive(size, "size") / 2.0
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
    v = _signed_permutations([positive(radius, "radius"), 0.0, 0.0, 0.0])
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
    v = _signed_permutations([1.0, 1.0, 0.0, 0.0]) * (positive(radius, "radius") / 2**0.5)
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
    v = _cell120_vertices() * (positive(radius, "radius") / 8**0.5)
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
    v = _cell600_vertices() * positive(radius, "radius")
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
    radius = positive(radius, "radius")
    if int(subdivisions) != subdivisions or subdivisions < 0:
        raise ValueError(f"subdivisions must be a whole number >= 0, got {subdivisions}")
    base = cell600()
    v, tets = base.vertices.astype(np.float64), base.tets.astype(np.int64)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    for _ in range(int(subdivisions)):
        v, tets = _split_on_sphere(v, tets)
    return finish_mesh(v * radius, tets, "hypersphere", color, PALETTES["hypersphere"])


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
