"""Products of lower-dimensional shapes: duoprisms, the cubinder, the duocylinder, the spherinder.

A product ``A x B`` has facets ``(facet of A) x B`` with normal ``(n_A, 0)`` and
``A x (facet of B)`` with normal ``(0, n_B)``; :func:`~.polytope.convex_polytope`
builds each from its vertices and those normals.
"""

from __future__ import annotations

import numpy as np

from .mesh import TetMesh4
from .polychora import PHI
from .polytope import convex_polytope, positive


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
    h = positive(height, "height")
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
    sv, faces = icosphere(positive(radius, "radius"), subdivisions)
    fn = np.cross(sv[faces[:, 1]] - sv[faces[:, 0]], sv[faces[:, 2]] - sv[faces[:, 0]])
    h = positive(height, "height") / 2.0
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
