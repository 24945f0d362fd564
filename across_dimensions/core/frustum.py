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


def frustum_project(mesh: TetMesh4, camera_pose=None, fov_deg: float = 90.0, near: float = 0.05, model=None,
                    all_faces: bool = False) -> TriMesh3:
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
        With ``depth`` ``(k,) float32``; normals are per-triangle and not
        oriented (draw both sides).
    """
    if near <= 0:
        raise ValueError(f"near distance must be positive, got {near}")
    f = focal_length(fov_deg)
    mv = _model_view(model, camera_pose)
    faces = mesh.unique_faces()[0] if all_faces else mesh.feature_faces()
    colors = mesh.vertex_colors()
    v, n, c, d, count = _project(mesh.vertices, faces, colors, mv, f, float(near))
    if count == 0:
        return TriMesh3.empty(with_depth=True)
    k = 3 * count
    return TriMesh3(v[:k], np.arange(k, dtype=np.uint32).reshape(-1, 3), n[:k], c[:k], d[:k])


@njit(cache=True)
def _project(v, faces, colors, mv, f, near):
    nv = v.shape[0]
    cam = np.empty((nv, 4))
    for i in range(nv):
        for r in range(4):
            cam[i, r] = (mv[r, 0] * v[i, 0] + mv[r, 1] * v[i, 1] + mv[r, 2] * v[i, 2]
                         + mv[r, 3] * v[i, 3] + mv[r, 4])
    nf = faces.shape[0]
    cap = 2 * nf
    out_v = np.empty((3 * cap, 3), np.float32)
    out_n = np.empty((3 * cap, 3), np.float32)
    out_c = np.empty((3 * cap, 4), np.float32)
    out_d = np.empty(3 * cap, np.float32)
    poly = np.empty((4, 4))  # clipped polygon, camera space
    pc = np.empty((4, 4))
    o = 0
    for fi in range(nf):
        ninside = 0
        for j in range(3):
            if cam[faces[fi, j], 3] >= near:
                ninside += 1
        if ninside == 0:
            continue
        # Sutherland-Hodgman against w >= near, on a triangle: at most 4 points.
        k = 0
        for j in range(3):
            a = faces[fi, j]
            b = faces[fi, (j + 1) % 3]
            wa = cam[a, 3]
            wb = cam[b, 3]
            if wa >= near:
                for r in range(4):
                    poly[k, r] = cam[a, r]
                    pc[k, r] = colors[a, r]
                k += 1
            if (wa >= near) != (wb >= near):
                s = (near - wa) / (wb - wa)
                for r in range(4):
                    poly[k, r] = cam[a, r] + s * (cam[b, r] - cam[a, r])
                    pc[k, r] = colors[a, r] + s * (colors[b, r] - colors[a, r])
                poly[k, 3] = near
                k += 1
        # Perspective divide.
        for j in range(k):
            sc = f / poly[j, 3]
            for r in range(3):
                poly[j, r] *= sc
        ax, ay, az = poly[1, 0] - poly[0, 0], poly[1, 1] - poly[0, 1], poly[1, 2] - poly[0, 2]
        bx, by, bz = poly[2, 0] - poly[0, 0], poly[2, 1] - poly[0, 1], poly[2, 2] - poly[0, 2]
        nx = ay * bz - az * by
        ny = az * bx - ax * bz
        nz = ax * by - ay * bx
        ln = np.sqrt(nx * nx + ny * ny + nz * nz)
        if ln > 0.0:
            nx /= ln
            ny /= ln
            nz /= ln
        for tri in range(k - 2):
            for j in range(3):
                src = 0 if j == 0 else tri + j
                for r in range(3):
                    out_v[o, r] = poly[src, r]
                out_n[o, 0] = nx
                out_n[o, 1] = ny
                out_n[o, 2] = nz
                for r in range(4):
                    out_c[o, r] = pc[src, r]
                out_d[o] = poly[src, 3]
                o += 1
    return out_v, out_n, out_c, out_d, o // 3


def frustum_project_reference(mesh: TetMesh4, camera_pose=None, fov_deg: float = 90.0, near: float = 0.05,
                              model=None, all_faces: bool = False) -> TriMesh3:
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
    p = v.reshape(-1, 3, 3).astype(np.float64)
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    normals = np.repeat(n, 3, axis=0).astype(np.float32)
    return TriMesh3(v, np.arange(len(v), dtype=np.uint32).reshape(-1, 3), normals, np.array(out_c, np.float32),
                    np.array(out_d, np.float32))
