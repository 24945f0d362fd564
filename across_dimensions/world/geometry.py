"""Plain 3D geometry for the parts of a level that exist at every w."""

from __future__ import annotations

import numpy as np

from ..core.mesh import TriMesh3

# Each face of a unit box: 4 corners (counter-clockwise seen from outside in
# the right-hand-rule sense) and the outward normal.
_BOX_FACES = [
    ([1, 0, 0], [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)]),
    ([-1, 0, 0], [(0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)]),
    ([0, 1, 0], [(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)]),
    ([0, -1, 0], [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)]),
    ([0, 0, 1], [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]),
    ([0, 0, -1], [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)]),
]


def box_trimesh(center, size, color) -> TriMesh3:
    """An axis-aligned box as 12 flat-shaded triangles.

    Parameters
    ----------
    center, size : (3,) array_like
    color : (4,) array_like
    """
    center = np.asarray(center, dtype=np.float64)
    size = np.asarray(size, dtype=np.float64)
    verts, norms = [], []
    for normal, quad in _BOX_FACES:
        corners = [center + (np.asarray(c) - 0.5) * size for c in quad]
        for i in (0, 1, 2, 0, 2, 3):
            verts.append(corners[i])
            norms.append(normal)
    v = np.asarray(verts, np.float32)
    return TriMesh3(
        v,
        np.arange(len(v), dtype=np.uint32).reshape(-1, 3),
        np.asarray(norms, np.float32),
        np.tile(np.asarray(color, np.float32), (len(v), 1)),
    )


def surface_trimesh(vertices, faces, color, model=None) -> TriMesh3:
    """A flat-shaded triangle mesh from an indexed surface.

    Parameters
    ----------
    vertices : (n, 3) array_like
    faces : (f, 3) array_like of int
    color : (4,) array_like
    model : (4, 4) array_like, optional
        Applied to the vertices first.
    """
    v = np.asarray(vertices, dtype=np.float64)
    if model is not None:
        m = np.asarray(model, dtype=np.float64)
        v = v @ m[:3, :3].T + m[:3, 3]
    p = v[np.asarray(faces)].reshape(-1, 3)
    tri = p.reshape(-1, 3, 3)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    return TriMesh3(
        p.astype(np.float32),
        np.arange(len(p), dtype=np.uint32).reshape(-1, 3),
        np.repeat(n, 3, axis=0).astype(np.float32),
        np.tile(np.asarray(color, np.float32), (len(p), 1)),
    )


def face_runs(meshes) -> np.ndarray:
    """``(k + 1,) int64``: where the faces of each non-empty one of ``meshes`` start in
    :func:`merge_trimeshes` of them, then their count (see ``Drawable.parts``)."""
    return np.cumsum([0] + [len(m.faces) for m in meshes if not m.is_empty], dtype=np.int64)


def merge_trimeshes(meshes) -> TriMesh3:
    """Concatenate triangle soups (depth is dropped)."""
    meshes = [m for m in meshes if not m.is_empty]
    if not meshes:
        return TriMesh3.empty()
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
    return TriMesh3(
        np.concatenate([m.vertices for m in meshes]),
        np.concatenate([m.faces + np.uint32(o) for m, o in zip(meshes, offsets)]),
        np.concatenate([m.normals for m in meshes]),
        np.concatenate([m.colors for m in meshes]),
    )


def placement_matrix(position, scale, yaw_deg) -> np.ndarray:
    """3D model matrix ``(4, 4) float64``: scale, turn about y, then move."""
    c, s = np.cos(np.radians(yaw_deg)), np.sin(np.radians(yaw_deg))
    rot = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    m = np.eye(4)
    m[:3, :3] = rot * np.asarray(scale, dtype=np.float64)
    m[:3, 3] = position
    return m
