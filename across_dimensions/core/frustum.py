"""Frustum (perspective) projection of a 4D mesh into 3D.

The 4D camera looks along its own +w axis. A camera-space point ``(x, y, z, w)``
in front of the near hyperplane (``w >= near``) maps to::

    (x, y, z) * f / w,    f = 1 / tan(fov / 2)

so a point at distance ``f`` keeps its size, farther points shrink (a
tesseract seen along w shows its small inner cube), and the 4D frustum's
boundary maps onto the cube ``[-1, 1]^3``. The distance ``w`` is kept per vertex
as ``depth`` for shading.

What is projected is the solid's 2-skeleton: each triangle of the tet mesh once,
leaving out triangles inside a flat cell (see :meth:`TetMesh4.feature_faces`).
Triangles crossing the near hyperplane are clipped in 4D before the divide, so
no NaN or infinity reaches the output.
"""

from __future__ import annotations

import numpy as np

from ._jit import njit
from .mesh import TetMesh4, TriMesh3
from .section import _model_view


def focal_length(fov_deg: float) -> float:
    """``1 / tan(fov / 2)`` for a field of view in degrees (0 < fov < 180)."""
    if not 0.0 < fov_deg < 180.0:
        raise ValueError(f"field of view must be between 0 and 180 degrees, got {fov_deg}")
    return float(1.0 / np.tan(np.radians(fov_deg) / 2.0))


def frustum_project(
    mesh: TetMesh4, camera_pose=None, fov_deg: float = 90.0, near: float = 0.05, model=None, all_faces: bool = False
) -> TriMesh3:
    """Project ``mesh`` through a 4D camera's frustum.

    Parameters
    ----------
    mesh : TetMesh4
    camera_pose : (5, 5) array_like, optional
        Camera-to-world transform; the camera looks along its local +w.
    fov_deg : float
        Field of view of the 4D camera, degrees.
    near : float
        Distance of the near hyperplane (> 0).
    model : (5, 5) array_like, optional
        Object-to-world transform.
    all_faces : bool
        Also project triangles inside flat cells.

    Returns
    -------
    TriMesh3
        Indexed: row ``i < n`` is mesh vertex ``i`` projected (unused if behind
        the near hyperplane), later rows are clip points. ``depth (k,) float32``
        is the distance along the camera's w. Faces are not consistently
        oriented and ``normals`` are zero: shade flat (the renderer derives face
        normals from screen-space derivatives) and draw both sides.
    """
    if near <= 0:
        raise ValueError(f"near distance must be positive, got {near}")
    f = focal_length(fov_deg)
    mv = _model_view(model, camera_pose)
    faces = mesh.unique_faces()[0] if all_faces else mesh.feature_faces()
    colors = mesh.vertex_colors()
    v, c, d, faces_out, nv, nf = _project(mesh.vertices, faces, colors, mv, f, float(near))
    if nf == 0:
        return TriMesh3.empty(with_depth=True)
    return TriMesh3(v[:nv], faces_out[:nf], np.zeros((nv, 3), np.float32), c[:nv], d[:nv])


@njit(cache=True)
def _project(v, faces, colors, mv, f, near):
    """Indexed output: every vertex in front of the near hyperplane is projected
    once (rows ``0..n-1``); clipping appends the points where edges cross it."""
    nv = v.shape[0]
    nf = faces.shape[0]
    cam = np.empty((nv, 4))
    # A clipped triangle adds at most 2 points; reserve for the worst case.
    cap_v = nv + 2 * nf
    out_v = np.zeros((cap_v, 3), np.float32)
    out_c = np.empty((cap_v, 4), np.float32)
    out_d = np.zeros(cap_v, np.float32)
    inside = np.empty(nv, np.bool_)
    for i in range(nv):
        for r in range(4):
            cam[i, r] = mv[r, 0] * v[i, 0] + mv[r, 1] * v[i, 1] + mv[r, 2] * v[i, 2] + mv[r, 3] * v[i, 3] + mv[r, 4]
        w = cam[i, 3]
        inside[i] = w >= near
        if inside[i]:
            sc = f / w
            out_v[i, 0] = cam[i, 0] * sc
            out_v[i, 1] = cam[i, 1] * sc
            out_v[i, 2] = cam[i, 2] * sc
            out_d[i] = w
        for r in range(4):
            out_c[i, r] = colors[i, r]
    out_f = np.empty((2 * nf, 3), np.uint32)
    poly = np.empty(4, np.int64)
    k_v = nv
    k_f = 0
    for fi in range(nf):
        a0 = faces[fi, 0]
        a1 = faces[fi, 1]
        a2 = faces[fi, 2]
        ninside = np.int64(inside[a0]) + np.int64(inside[a1]) + np.int64(inside[a2])
        if ninside == 3:
            out_f[k_f, 0] = a0
            out_f[k_f, 1] = a1
            out_f[k_f, 2] = a2
            k_f += 1
            continue
        if ninside == 0:
            continue
        # Sutherland-Hodgman against w >= near on one triangle: 3 or 4 points.
        k = 0
        for j in range(3):
            a = faces[fi, j]
            b = faces[fi, (j + 1) % 3]
            if inside[a]:
                poly[k] = a
                k += 1
            if inside[a] != inside[b]:
                s = (near - cam[a, 3]) / (cam[b, 3] - cam[a, 3])
                sc = f / near
                for r in range(3):
                    out_v[k_v, r] = (cam[a, r] + s * (cam[b, r] - cam[a, r])) * sc
                for r in range(4):
                    out_c[k_v, r] = colors[a, r] + s * (colors[b, r] - colors[a, r])
                out_d[k_v] = near
                poly[k] = k_v
                k_v += 1
                k += 1
        for tri in range(k - 2):
            out_f[k_f, 0] = poly[0]
            out_f[k_f, 1] = poly[tri + 1]
            out_f[k_f, 2] = poly[tri + 2]
            k_f += 1
    return out_v, out_c, out_d, out_f, k_v, k_f


def frustum_project_reference(
    mesh: TetMesh4, camera_pose=None, fov_deg: float = 90.0, near: float = 0.05, model=None, all_faces: bool = False
) -> TriMesh3:
    """Plain numpy frustum projection, the oracle for :func:`frustum_project`."""
    f = focal_length(fov_deg)
    mv = _model_view(model, camera_pose)
    cam = mesh.vertices.astype(np.float64) @ mv[:4, :4].T + mv[:4, 4]
    faces = mesh.unique_faces()[0] if all_faces else mesh.feature_faces()
    colors = mesh.vertex_colors()
    out_v, out_c, out_d = [], [], []
    for face in faces:
        pts, cs = [], []
        for j in range(3):
            a, b = face[j], face[(j + 1) % 3]
            if cam[a, 3] >= near:
                pts.append(cam[a])
                cs.append(colors[a])
            if (cam[a, 3] >= near) != (cam[b, 3] >= near):
                s = (near - cam[a, 3]) / (cam[b, 3] - cam[a, 3])
                p = cam[a] + s * (cam[b] - cam[a])
                p[3] = near
                pts.append(p)
                cs.append(colors[a] + s * (colors[b] - colors[a]))
        for i in range(1, len(pts) - 1):
            for j in (0, i, i + 1):
                out_v.append(pts[j][:3] * f / pts[j][3])
                out_d.append(pts[j][3])
                out_c.append(cs[j])
    if not out_v:
        return TriMesh3.empty(with_depth=True)
    v = np.array(out_v, np.float32)
    return TriMesh3(
        v,
        np.arange(len(v), dtype=np.uint32).reshape(-1, 3),
        np.zeros_like(v),
        np.array(out_c, np.float32),
        np.array(out_d, np.float32),
    )
