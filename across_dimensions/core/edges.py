"""Edges worth drawing in a wireframe: creases and borders, not the diagonals that split flat quads.

Pure geometry (numpy), kept apart from the GPU code that draws the lines so it
can be used and tested without an OpenGL context.
"""

from __future__ import annotations

import numpy as np

__all__ = ["feature_edges"]


def feature_edges(
    vertices: np.ndarray, faces: np.ndarray, angle_tol: float = 1e-3, weld_tol: float = 1e-5
) -> np.ndarray:
    """The edges to draw for a wireframe.

    Triangle soups (each triangle with its own vertices, as cross-sections are)
    are welded by position so shared edges are found, and edges whose two
    triangles are coplanar (a quad's diagonal) are dropped.

    Parameters
    ----------
    vertices : (k, 3) float32
    faces : (f, 3) uint32
    angle_tol : float
        Radians; neighbours within this angle count as coplanar.
    weld_tol : float
        Positions closer than this (per axis, after rounding) are one vertex.

    Returns
    -------
    (e, 2) uint32
        Indices into ``vertices``.
    """
    if len(faces) == 0:
        return np.zeros((0, 2), np.uint32)
    v = vertices.astype(np.float64)
    q = np.round(v / weld_tol).astype(np.int64)
    _, inverse = np.unique(q, axis=0, return_inverse=True)
    welded = inverse.reshape(-1)[faces.astype(np.int64)]  # (f, 3)
    # All three edges of every triangle, in original and welded indices.
    orig = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    wedge = np.sort(welded[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    keep_nondegenerate = wedge[:, 0] != wedge[:, 1]
    p = v[faces.astype(np.int64)]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    face_of = np.repeat(np.arange(len(faces)), 3)
    key = wedge[:, 0] * (int(wedge.max()) + 1) + wedge[:, 1]
    order = np.argsort(key, kind="stable")
    ks = key[order]
    starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    counts = np.diff(np.r_[starts, len(ks)])
    first = order[starts]
    keep = np.ones(len(starts), bool)
    # An edge shared by exactly two triangles is a crease only if their planes differ
    # (abs: triangle soups need not be consistently wound).
    two = counts == 2
    a = face_of[order[starts[two]]]
    b = face_of[order[starts[two] + 1]]
    coplanar = np.abs(np.einsum("ij,ij->i", n[a], n[b])) > np.cos(angle_tol)
    keep[np.flatnonzero(two)[coplanar]] = False
    keep &= keep_nondegenerate[first]
    return np.ascontiguousarray(orig[first[keep]], dtype=np.uint32)
