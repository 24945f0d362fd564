"""Many placed meshes projected through their 4D frustums in one kernel call.

The batched counterpart of :func:`core.frustum.frustum_project`: each instance
has a model-view transform (object to 4D camera), and the projected 3D shape is
then placed in the 3D world by a uniform scale and an offset (a frustum view
shown as an object in the 3D scene, as the editor does). The output is one
shared array of vertices in the renderer's interleaved layout (position,
normal, colour: 10 float32), one triangle index array and one line index array
for the solid's edges, all with global row numbers, so a whole scene is drawn
with one call per pass.

Vertex ``i`` of an instance lands at row ``base + i`` (projected even when it
is behind the near hyperplane, then unused); points where edges cross the near
hyperplane follow the instance's vertices. Faces are clipped like
:func:`~core.frustum.frustum_project` (same sums, same order), so their
positions are identical to it. Normals are zero: the renderer shades flat with
the screen-space face normal. Edges with an end behind the near hyperplane are
left out.
"""

from __future__ import annotations

import numpy as np

from ._jit import njit
from .frustum import focal_length
from .mesh import TetMesh4
from .section_batch import ROW


def solid_edges(mesh: TetMesh4, angle_tol: float = 1e-4) -> np.ndarray:
    """The edges of a 4D solid worth drawing: those of its flat 2-faces, not the
    diagonals that triangulate them. ``(e, 2) uint32``, cached on the mesh.

    An edge of :meth:`TetMesh4.feature_faces` is a diagonal when exactly two
    feature triangles share it and they lie in one 2-plane.
    """
    key = ("solid_edges", angle_tol)
    if key not in mesh._cache:
        faces = mesh.feature_faces().astype(np.int64)
        e = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        face_of = np.repeat(np.arange(len(faces)), 3)
        code = e[:, 0] * len(mesh.vertices) + e[:, 1]
        order = np.argsort(code, kind="stable")
        cs = code[order]
        starts = np.flatnonzero(np.r_[True, cs[1:] != cs[:-1]])
        counts = np.diff(np.r_[starts, len(cs)])
        keep = np.ones(len(starts), bool)
        two = np.flatnonzero(counts == 2)
        v = mesh.vertices.astype(np.float64)
        fa = faces[face_of[order[starts[two]]]]
        fb = faces[face_of[order[starts[two] + 1]]]
        # The vertex of b not on the shared edge lies in a's plane: a diagonal.
        pa = v[fa]
        u1, u2 = pa[:, 1] - pa[:, 0], pa[:, 2] - pa[:, 0]
        ea = e[order[starts[two]]]
        other = np.where((fb != ea[:, :1]) & (fb != ea[:, 1:]), fb, -1).max(axis=1)
        d = v[other] - pa[:, 0]
        basis = np.stack([u1, u2], axis=1)  # (k, 2, 4)
        g = np.einsum("kia,kja->kij", basis, basis)
        rhs = np.einsum("kia,ka->ki", basis, d)
        sol = np.linalg.solve(g + 1e-300 * np.eye(2), rhs[..., None])[..., 0]
        resid = d - np.einsum("ki,kia->ka", sol, basis)
        scale = np.maximum(np.linalg.norm(d, axis=1), 1e-300)
        flat = np.linalg.norm(resid, axis=1) <= angle_tol * scale
        keep[two[flat]] = False
        mesh._cache[key] = np.ascontiguousarray(e[order[starts[keep]]], dtype=np.uint32)
    return mesh._cache[key]


def silhouette_data(mesh: TetMesh4, angle_tol: float = 1e-4):
    """What the silhouette test needs, cached on the mesh.

    Returns
    -------
    owners : (f, 2) int64
        The two tets on either side of each feature face (-1: an open edge of the mesh).
    normals : (m, 4) float64
        Each tet's outward normal.
    offsets : (m,) float64
        ``normal . vertex`` for a vertex of the tet: its hyperplane is ``normal . x = offset``.
    edge_ptr : (e + 1,) int64, edge_faces : (k,) int64
        For each edge of :func:`solid_edges`, the feature faces that contain it (CSR).
    """
    key = ("silhouette", angle_tol)
    if key not in mesh._cache:
        faces, owners = mesh.unique_faces()
        n = mesh.tet_normals()
        nn = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
        a, b = owners[:, 0], owners[:, 1]
        cos = np.where(b >= 0, np.einsum("ij,ij->i", nn[a], nn[np.maximum(b, 0)]), -1.0)
        feat = cos < np.cos(angle_tol)
        assert np.array_equal(faces[feat], mesh.feature_faces(angle_tol))
        owners = np.ascontiguousarray(owners[feat])
        offsets = np.einsum("ij,ij->i", n, mesh.vertices.astype(np.float64)[mesh.tets[:, 0]])
        # Edges -> the feature faces containing them.
        ff = mesh.feature_faces(angle_tol).astype(np.int64)
        nv = len(mesh.vertices)
        fe = np.sort(ff[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        fcode = fe[:, 0] * nv + fe[:, 1]
        face_of = np.repeat(np.arange(len(ff)), 3)
        e = solid_edges(mesh, angle_tol).astype(np.int64)
        ecode = np.sort(e, axis=1) @ np.array([nv, 1])
        order = np.argsort(fcode, kind="stable")
        lo = np.searchsorted(fcode[order], ecode, "left")
        hi = np.searchsorted(fcode[order], ecode, "right")
        edge_ptr = np.concatenate([[0], np.cumsum(hi - lo)]).astype(np.int64)
        edge_faces = np.concatenate([face_of[order[x:y]] for x, y in zip(lo, hi)] or [np.zeros(0, np.int64)])
        mesh._cache[key] = (owners, np.ascontiguousarray(n), offsets, edge_ptr, edge_faces.astype(np.int64))
    return mesh._cache[key]


class _Pool:
    def __init__(self):
        self.index: dict[int, int] = {}
        self.meshes: list[TetMesh4] = []
        self.vertices = np.zeros((0, 4), np.float32)
        self.colors = np.zeros((0, 4), np.float32)
        self.faces = np.zeros((0, 3), np.uint32)  # local vertex numbers
        self.edges = np.zeros((0, 2), np.uint32)
        self.owners = np.zeros((0, 2), np.int64)  # per face: local tets on either side
        self.normals = np.zeros((0, 4))  # per tet
        self.offsets = np.zeros(0)
        self.edge_ptr = np.zeros(0, np.int64)  # per edge: range in edge_faces (pooled)
        self.edge_faces = np.zeros(0, np.int64)  # local face numbers
        # per mesh: v lo, v hi, f lo, f hi, e lo, e hi, tet lo
        self.ranges = np.zeros((0, 7), np.int64)

    def add(self, mesh: TetMesh4) -> int:
        k = self.index.get(id(mesh))
        if k is None:
            f, e = mesh.feature_faces(), solid_edges(mesh)
            owners, normals, offsets, edge_ptr, edge_faces = silhouette_data(mesh)
            r = [len(self.vertices), len(self.vertices) + len(mesh.vertices)]
            r += [len(self.faces), len(self.faces) + len(f), len(self.edges), len(self.edges) + len(e)]
            r += [len(self.normals)]
            self.vertices = np.concatenate([self.vertices, mesh.vertices])
            self.colors = np.concatenate([self.colors, mesh.vertex_colors().astype(np.float32)])
            self.faces = np.concatenate([self.faces, f.astype(np.uint32)])
            self.edges = np.concatenate([self.edges, e])
            self.owners = np.concatenate([self.owners, owners])
            self.normals = np.concatenate([self.normals, normals])
            self.offsets = np.concatenate([self.offsets, offsets])
            # Edge ranges: one pointer per edge, into the pooled face lists.
            self.edge_ptr = np.concatenate([self.edge_ptr, edge_ptr[:-1] + len(self.edge_faces)])
            self.edge_faces = np.concatenate([self.edge_faces, edge_faces])
            self.ranges = np.concatenate([self.ranges, [r]])
            k = self.index[id(mesh)] = len(self.meshes)
            self.meshes.append(mesh)
        return k

    def edge_ends(self) -> np.ndarray:
        """End of each edge's range in :attr:`edge_faces`."""
        return np.append(self.edge_ptr[1:], len(self.edge_faces))


class FrustumBatch:
    """Projects placed meshes through their 4D frustums into shared arrays.

    Attributes
    ----------
    vertices : (k, 10) float32
    faces : (f, 3) uint32
        Rows of :attr:`vertices`.
    edges : (e, 2) uint32
    topology_revision : int
        Bumped when :attr:`faces` or :attr:`edges` changed (instances added or
        removed, or clipping against the near hyperplane); otherwise only the
        vertices need uploading.
    """

    def __init__(self):
        self._pool = _Pool()
        self._v = np.zeros((0, ROW), np.float32)
        self._f = np.zeros((0, 3), np.uint32)
        self._e = np.zeros((0, 2), np.uint32)
        self._counts = (0, 0, 0)
        self._signature = None
        self.topology_revision = 0
        self.revision = 0

    @property
    def vertices(self) -> np.ndarray:
        return self._v[: self._counts[0]]

    @property
    def faces(self) -> np.ndarray:
        return self._f[: self._counts[1]]

    @property
    def edges(self) -> np.ndarray:
        return self._e[: self._counts[2]]

    @property
    def capacity_bytes(self) -> int:
        return self._v.nbytes + self._f.nbytes + self._e.nbytes

    def update(
        self, meshes, model_views, place, fov_deg: float = 90.0, near: float = 0.05, silhouette: bool = True
    ) -> None:
        """Project every instance.

        Parameters
        ----------
        meshes : sequence of TetMesh4
        model_views : (k, 5, 5) float64
            Object to 4D camera (the camera looks along its +w).
        place : (k, 4) float64
            Per instance: uniform scale and xyz offset of the projected shape in the 3D world.
        silhouette : bool
            Keep only the faces on the projected solid's outer surface (and their
            edges): a face between a cell facing the 4D camera and one facing away.
            Drawn opaque, the others are hidden inside the projection anyway. An
            instance cut by the near hyperplane keeps every face (one can see into it).
        """
        pool = self._pool
        ids = np.array([pool.add(m) for m in meshes], np.int64)
        r = pool.ranges[ids] if len(ids) else np.zeros((0, 7), np.int64)
        nv, nf, ne = r[:, 1] - r[:, 0], r[:, 3] - r[:, 2], r[:, 5] - r[:, 4]
        # Worst case: every face clipped into a quad with two new points.
        cap_v, cap_f, cap_e = int((nv + 2 * nf).sum()), int(2 * nf.sum()), int(ne.sum())
        if cap_v > len(self._v) or cap_v * 4 < len(self._v):
            self._v = np.empty((cap_v, ROW), np.float32)
        if cap_f > len(self._f) or cap_f * 4 < len(self._f):
            self._f = np.empty((cap_f, 3), np.uint32)
        if cap_e > len(self._e) or cap_e * 4 < len(self._e):
            self._e = np.empty((cap_e, 2), np.uint32)
        mvs = np.ascontiguousarray(np.asarray(model_views, np.float64).reshape(len(ids), 5, 5))
        place = np.ascontiguousarray(np.asarray(place, np.float64).reshape(len(ids), 4))
        # The 4D eye in each object's own coordinates: -L^-1 t for model-view [L t].
        eyes = -np.linalg.solve(mvs[:, :4, :4], mvs[:, :4, 4:5])[..., 0] if len(ids) else np.zeros((0, 4))
        counts = _project_batch(
            pool.vertices, pool.colors, pool.faces, pool.edges, r, mvs, place, focal_length(fov_deg), float(near),
            self._v, self._f, self._e,
            pool.owners, pool.normals, pool.offsets, pool.edge_ptr, pool.edge_ends(), pool.edge_faces,
            np.ascontiguousarray(eyes), bool(silhouette),
        )  # fmt: skip
        nv_out, nf_out, ne_out, clipped = counts
        signature = (tuple(ids.tolist()), nv_out, nf_out, ne_out)
        if clipped or silhouette or signature != self._signature:
            self.topology_revision += 1  # the silhouette moves with every turn
        self._signature = None if clipped else signature
        self._counts = (int(nv_out), int(nf_out), int(ne_out))
        self.revision += 1


@njit(cache=True)
def _project_batch(
    verts, colors, faces, edges, ranges, mvs, place, f, near, out, out_f, out_e,
    owners, normals, offsets, edge_ptr, edge_end, edge_faces, eyes, silhouette,
):  # fmt: skip
    o = 0
    of = 0
    oe = 0
    clipped = 0
    inside = np.empty(0, np.bool_)
    cam = np.empty((0, 4))
    keep = np.empty(0, np.bool_)
    poly = np.empty(4, np.int64)
    for k in range(ranges.shape[0]):
        v_lo, v_hi = ranges[k, 0], ranges[k, 1]
        f_lo, f_hi = ranges[k, 2], ranges[k, 3]
        t_lo = ranges[k, 6]
        n = v_hi - v_lo
        if cam.shape[0] < n:
            cam = np.empty((n, 4))
            inside = np.empty(n, np.bool_)
        if keep.shape[0] < f_hi - f_lo:
            keep = np.empty(f_hi - f_lo, np.bool_)
        mv = mvs[k]
        s_place = place[k, 0]
        base = o
        all_inside = True
        for i in range(n):
            vi = v_lo + i
            for r in range(4):
                cam[i, r] = (
                    mv[r, 0] * verts[vi, 0] + mv[r, 1] * verts[vi, 1] + mv[r, 2] * verts[vi, 2]
                    + mv[r, 3] * verts[vi, 3] + mv[r, 4]
                )  # fmt: skip
            w = cam[i, 3]
            inside[i] = w >= near
            all_inside = all_inside and inside[i]
            row = out[o]
            if inside[i]:
                sc = f / w
                for r in range(3):
                    row[r] = np.float32(cam[i, r] * sc) * s_place + place[k, 1 + r]
            else:
                for r in range(3):
                    row[r] = place[k, 1 + r]
            row[3] = 0.0
            row[4] = 0.0
            row[5] = 0.0
            for r in range(4):
                row[6 + r] = colors[vi, r]
            o += 1
        cull = silhouette and all_inside
        e0, e1, e2, e3 = eyes[k, 0], eyes[k, 1], eyes[k, 2], eyes[k, 3]
        for fi in range(f_lo, f_hi):
            keep[fi - f_lo] = True
            if cull and owners[fi, 1] >= 0:
                # A face on the outline lies between a cell facing the eye and one facing away.
                ta = t_lo + owners[fi, 0]
                tb = t_lo + owners[fi, 1]
                fa = offsets[ta] - (
                    normals[ta, 0] * e0 + normals[ta, 1] * e1 + normals[ta, 2] * e2 + normals[ta, 3] * e3
                )
                fb = offsets[tb] - (
                    normals[tb, 0] * e0 + normals[tb, 1] * e1 + normals[tb, 2] * e2 + normals[tb, 3] * e3
                )
                if (fa > 0.0) == (fb > 0.0):
                    keep[fi - f_lo] = False
                    continue
            a0, a1, a2 = faces[fi, 0], faces[fi, 1], faces[fi, 2]
            nin = np.int64(inside[a0]) + np.int64(inside[a1]) + np.int64(inside[a2])
            if nin == 3:
                out_f[of, 0] = base + a0
                out_f[of, 1] = base + a1
                out_f[of, 2] = base + a2
                of += 1
                continue
            if nin == 0:
                continue
            clipped += 1
            m = 0
            for j in range(3):
                a = faces[fi, j]
                b = faces[fi, (j + 1) % 3]
                if inside[a]:
                    poly[m] = base + a
                    m += 1
                if inside[a] != inside[b]:
                    s = (near - cam[a, 3]) / (cam[b, 3] - cam[a, 3])
                    sc = f / near
                    row = out[o]
                    for r in range(3):
                        row[r] = np.float32((cam[a, r] + s * (cam[b, r] - cam[a, r])) * sc) * s_place + place[k, 1 + r]
                    row[3] = 0.0
                    row[4] = 0.0
                    row[5] = 0.0
                    for r in range(4):
                        row[6 + r] = colors[v_lo + a, r] + s * (colors[v_lo + b, r] - colors[v_lo + a, r])
                    poly[m] = o
                    o += 1
                    m += 1
            for tri in range(m - 2):
                out_f[of, 0] = poly[0]
                out_f[of, 1] = poly[tri + 1]
                out_f[of, 2] = poly[tri + 2]
                of += 1
        for ei in range(ranges[k, 4], ranges[k, 5]):
            a, b = edges[ei, 0], edges[ei, 1]
            if not (inside[a] and inside[b]):
                continue
            shown = not cull
            for j in range(edge_ptr[ei], edge_end[ei]):
                if keep[edge_faces[j]]:
                    shown = True
                    break
            if shown:
                out_e[oe, 0] = base + a
                out_e[oe, 1] = base + b
                oe += 1
    return o, of, oe, clipped
