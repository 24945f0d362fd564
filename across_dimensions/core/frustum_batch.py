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

from typing import NamedTuple

import numpy as np

from ._jit import njit
from .frustum import focal_length
from .mesh import TetMesh4
from .section_batch_tets import CULL_MARGIN, ROW


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
    apex : (f,) int64
        Per feature face, the vertex of its first tet that is not on it: projected, it lies
        on the inner side of the face wherever the face is on the projection's outline.
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
        tet = mesh.tets[owners[:, 0]].astype(np.int64)
        on_face = (tet[:, :, None] == faces[feat].astype(np.int64)[:, None, :]).any(axis=2)
        apex = tet[~on_face]  # one vertex per row: a face is three of its tet's four
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
        edge_faces = edge_faces.astype(np.int64)
        mesh._cache[key] = (owners, np.ascontiguousarray(n), offsets, edge_ptr, edge_faces, apex)
    return mesh._cache[key]


class FrustumPool(NamedTuple):
    """Every distinct mesh once, concatenated; faces, edges and tets numbered within their mesh.

    Attributes
    ----------
    vertices : (n, 4) float32
    colors : (n, 4) float32
    faces : (f, 3) uint32
        Feature faces (:meth:`~.mesh.TetMesh4.feature_faces`), local vertex numbers.
    edges : (e, 2) uint32
        :func:`solid_edges`, local vertex numbers.
    owners : (f, 2) int64
        Per face: the local tets on either side (:func:`silhouette_data`).
    normals : (m, 4) float64
    offsets : (m,) float64
        Per tet: its hyperplane ``normal . x = offset``.
    edge_ptr, edge_end : (e,) int64
        Per edge: its range in ``edge_faces``.
    edge_faces : (k,) int64
        Local face numbers.
    apex : (f,) int64
        Per face: a local vertex on its inner side (:func:`silhouette_data`).
    """

    vertices: np.ndarray
    colors: np.ndarray
    faces: np.ndarray
    edges: np.ndarray
    owners: np.ndarray
    normals: np.ndarray
    offsets: np.ndarray
    edge_ptr: np.ndarray
    edge_end: np.ndarray
    edge_faces: np.ndarray
    apex: np.ndarray


class Placed(NamedTuple):
    """The instances to project.

    Attributes
    ----------
    ranges : (k, 8) int64
        Per instance, its mesh's vertex, face and edge ranges in the pool, its first tet, and
        1 if the mesh is closed (every face between two tets), else 0.
    mvs : (k, 5, 5) float64
        Object to 4D camera.
    place : (k, 4) float64
        Uniform scale and xyz offset of the projected shape in the 3D world.
    eyes : (k, 4) float64
        The 4D eye in each object's own coordinates.
    """

    ranges: np.ndarray
    mvs: np.ndarray
    place: np.ndarray
    eyes: np.ndarray


class Lens(NamedTuple):
    """The 4D camera's focal length, near distance, whether to keep only the silhouette, and
    the 3D eye the projections are seen from (``eye (3,) float64``; ``facing``: whether it is
    given, to leave out the outline's far side)."""

    focal: float
    near: float
    silhouette: bool
    facing: bool
    eye: np.ndarray


class Projected(NamedTuple):
    """The shared outputs: ``vertices (r, 10) float32``, ``faces (f, 3) uint32``, ``edges (e, 2) uint32``."""

    vertices: np.ndarray
    faces: np.ndarray
    edges: np.ndarray


class FrustumScratch(NamedTuple):
    """Per instance: camera-space vertices ``cam (n, 4) float64``, which are in front of the
    near hyperplane ``inside (n,) bool``, which faces are kept ``keep (f,) bool``, a clipped
    polygon ``poly (4,) int64``; ``counts (4,) int64``: rows, faces, edges written and faces clipped."""

    cam: np.ndarray
    inside: np.ndarray
    keep: np.ndarray
    poly: np.ndarray
    counts: np.ndarray


class _Pool:
    def __init__(self):
        self.index: dict[int, int] = {}
        self.meshes: list[TetMesh4] = []
        self.arrays = FrustumPool(
            vertices=np.zeros((0, 4), np.float32),
            colors=np.zeros((0, 4), np.float32),
            faces=np.zeros((0, 3), np.uint32),
            edges=np.zeros((0, 2), np.uint32),
            owners=np.zeros((0, 2), np.int64),
            normals=np.zeros((0, 4)),
            offsets=np.zeros(0),
            edge_ptr=np.zeros(0, np.int64),
            edge_end=np.zeros(0, np.int64),
            edge_faces=np.zeros(0, np.int64),
            apex=np.zeros(0, np.int64),
        )
        # per mesh: v lo, v hi, f lo, f hi, e lo, e hi, tet lo, closed
        self.ranges = np.zeros((0, 8), np.int64)
        self.max_vertices, self.max_faces = 0, 0

    def add(self, mesh: TetMesh4) -> int:
        k = self.index.get(id(mesh))
        if k is None:
            a = self.arrays
            f, e = mesh.feature_faces(), solid_edges(mesh)
            owners, normals, offsets, edge_ptr, edge_faces, apex = silhouette_data(mesh)
            r = [len(a.vertices), len(a.vertices) + len(mesh.vertices)]
            r += [len(a.faces), len(a.faces) + len(f), len(a.edges), len(a.edges) + len(e)]
            r += [len(a.normals), int((owners[:, 1] >= 0).all())]
            # Edge ranges: one pointer per edge, into the pooled face lists.
            ptr = np.concatenate([a.edge_ptr, edge_ptr[:-1] + len(a.edge_faces)])
            all_faces = np.concatenate([a.edge_faces, edge_faces])
            self.arrays = FrustumPool(
                vertices=np.concatenate([a.vertices, mesh.vertices]),
                colors=np.concatenate([a.colors, mesh.vertex_colors().astype(np.float32)]),
                faces=np.concatenate([a.faces, f.astype(np.uint32)]),
                edges=np.concatenate([a.edges, e]),
                owners=np.concatenate([a.owners, owners]),
                normals=np.concatenate([a.normals, normals]),
                offsets=np.concatenate([a.offsets, offsets]),
                edge_ptr=ptr,
                edge_end=np.append(ptr[1:], len(all_faces)),
                edge_faces=all_faces,
                apex=np.concatenate([a.apex, apex]),
            )
            self.ranges = np.concatenate([self.ranges, [r]])
            self.max_vertices = max(self.max_vertices, len(mesh.vertices))
            self.max_faces = max(self.max_faces, len(f))
            k = self.index[id(mesh)] = len(self.meshes)
            self.meshes.append(mesh)
        return k

    def scratch(self, ws: FrustumScratch | None) -> FrustumScratch:
        """``ws`` if it is large enough for every mesh of the pool, else a new one."""
        n, f = self.max_vertices, self.max_faces
        if ws is not None and len(ws.cam) >= n and len(ws.keep) >= f:
            return ws
        return FrustumScratch(
            np.empty((n, 4)), np.empty(n, np.bool_), np.empty(f, np.bool_), np.empty(4, np.int64), np.zeros(4, np.int64)
        )


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
        self._scratch = None  # the kernel's FrustumScratch, grown with the pool
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
        self,
        meshes,
        model_views,
        place,
        fov_deg: float = 90.0,
        near: float = 0.05,
        silhouette: bool = True,
        eye=None,
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
        eye : (3,) array_like, optional
            Where the 3D camera sees the projections from. Given, the outline's faces that
            face away from it are left out too, and the edges only they hold: the outline
            is a closed surface, so its near side hides its far side. Not for an instance
            whose projection's box holds the eye (one sees its inside then).
        """
        pool = self._pool
        ids = np.array([pool.add(m) for m in meshes], np.int64)
        self._scratch = pool.scratch(self._scratch)
        r = pool.ranges[ids] if len(ids) else np.zeros((0, 8), np.int64)
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
        placed = Placed(r, mvs, place, np.ascontiguousarray(eyes))
        facing = eye is not None
        eye3 = np.asarray(eye if facing else (0.0, 0.0, 0.0), np.float64).reshape(3)
        lens = Lens(focal_length(fov_deg), float(near), bool(silhouette), facing, eye3)
        counts = _project_batch(pool.arrays, placed, lens, Projected(self._v, self._f, self._e), self._scratch)
        nv_out, nf_out, ne_out, clipped = counts
        signature = (tuple(ids.tolist()), nv_out, nf_out, ne_out)
        if clipped or silhouette or signature != self._signature:
            self.topology_revision += 1  # the silhouette moves with every turn
        self._signature = None if clipped else signature
        self._counts = (int(nv_out), int(nf_out), int(ne_out))
        self.revision += 1


@njit(cache=True)
def _project_batch(pool, placed, lens, out, ws):
    """Project every instance into ``out``; returns the rows, faces and edges written and
    the faces clipped by the near hyperplane."""
    counts = ws.counts
    counts[:] = 0
    for k in range(placed.ranges.shape[0]):
        base = counts[0]
        all_inside = _project_vertices(pool, placed, k, lens, out.vertices, ws)
        cull = lens.silhouette and all_inside
        closed = placed.ranges[k, 7] != 0
        facing = cull and lens.facing and closed and _eye_outside(out.vertices, base, counts[0], lens.eye)
        _project_faces(pool, placed, k, lens, np.int64(cull) + np.int64(facing), base, out, ws)
        _project_edges(pool, placed, k, cull, base, out.edges, ws)
    return counts[0], counts[1], counts[2], counts[3]


@njit(inline="always")
def _project_vertices(pool, placed, k, lens, out, ws):
    """Instance ``k``'s vertices into camera space (``ws.cam``) and, projected and placed,
    into rows of ``out`` (a vertex behind the near hyperplane at the placement's origin,
    unused); returns whether every vertex is in front of it."""
    verts, colors, cam, inside = pool.vertices, pool.colors, ws.cam, ws.inside
    v_lo, v_hi = placed.ranges[k, 0], placed.ranges[k, 1]
    mv = placed.mvs[k]
    place = placed.place[k]
    focal, near, s_place = lens.focal, lens.near, place[0]
    o = ws.counts[0]
    all_inside = True
    for i in range(v_hi - v_lo):
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
            sc = focal / w
            for r in range(3):
                row[r] = np.float32(cam[i, r] * sc) * s_place + place[1 + r]
        else:
            for r in range(3):
                row[r] = place[1 + r]
        row[3] = 0.0
        row[4] = 0.0
        row[5] = 0.0
        for r in range(4):
            row[6 + r] = colors[vi, r]
        o += 1
    ws.counts[0] = o
    return all_inside


#: A face of the outline turned away from the 3D eye by less than this (the cosine) keeps its edges.
RIM_MARGIN = 0.3


@njit(inline="always")
def _eye_outside(rows, lo, hi, eye):
    """Is ``eye`` outside the box of the projected points ``rows[lo:hi, :3]``?"""
    inside = True
    for r in range(3):
        mn, mx = np.inf, -np.inf
        for i in range(lo, hi):
            mn = min(mn, rows[i, r])
            mx = max(mx, rows[i, r])
        inside = inside and mn <= eye[r] <= mx
    return not inside


@njit(inline="always")
def _away(rows, a, b, c, q, eye):
    """How clearly the projected triangle ``a, b, c`` (rows) faces away from the eye: 0 if it
    does not (or its inner side is unclear), else the squared cosine between its outward
    normal and the direction to the eye. ``q``: a row on the triangle's inner side (a thin
    projected tet leaves it unclear). No root and one division: it runs for every outline face."""
    ax, ay, az = np.float64(rows[a, 0]), np.float64(rows[a, 1]), np.float64(rows[a, 2])
    ux, uy, uz = rows[b, 0] - ax, rows[b, 1] - ay, rows[b, 2] - az
    vx, vy, vz = rows[c, 0] - ax, rows[c, 1] - ay, rows[c, 2] - az
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    qx, qy, qz = rows[q, 0] - ax, rows[q, 1] - ay, rows[q, 2] - az
    ex, ey, ez = eye[0] - ax, eye[1] - ay, eye[2] - az
    n2 = nx * nx + ny * ny + nz * nz
    sq = nx * qx + ny * qy + nz * qz
    se = nx * ex + ny * ey + nz * ez
    clear = sq * sq > (CULL_MARGIN * CULL_MARGIN) * n2 * (qx * qx + qy * qy + qz * qz)
    cos2 = se * se / max(n2 * (ex * ex + ey * ey + ez * ez), 1e-300)
    return cos2 if clear and (sq > 0.0) == (se > 0.0) else 0.0  # the eye on the inner side


@njit(inline="always")
def _project_faces(pool, placed, k, lens, cull, base, out, ws):
    """Instance ``k``'s faces into ``out.faces`` (rows from ``base`` on), clipped by the near
    hyperplane (new points into ``out.vertices``); with ``cull`` 1, only the silhouette's, and
    with 2 only those of them facing ``lens.eye`` (:func:`_away`).

    A face on the silhouette lies between a cell facing the eye and one facing away.
    Which faces are kept goes into ``ws.keep`` for :func:`_project_edges`.
    """
    faces, owners, normals, offsets, colors = pool.faces, pool.owners, pool.normals, pool.offsets, pool.colors
    cam, inside, keep, poly, counts = ws.cam, ws.inside, ws.keep, ws.poly, ws.counts
    ov, out_f = out.vertices, out.faces
    v_lo, f_lo, f_hi, t_lo = placed.ranges[k, 0], placed.ranges[k, 2], placed.ranges[k, 3], placed.ranges[k, 6]
    place = placed.place[k]
    e0, e1, e2, e3 = placed.eyes[k, 0], placed.eyes[k, 1], placed.eyes[k, 2], placed.eyes[k, 3]
    focal, near, s_place = lens.focal, lens.near, place[0]
    o, of, clipped = counts[0], counts[1], counts[3]
    for fi in range(f_lo, f_hi):
        keep[fi - f_lo] = True
        if cull != 0 and owners[fi, 1] >= 0:
            ta = t_lo + owners[fi, 0]
            tb = t_lo + owners[fi, 1]
            fa = offsets[ta] - (normals[ta, 0] * e0 + normals[ta, 1] * e1 + normals[ta, 2] * e2 + normals[ta, 3] * e3)
            fb = offsets[tb] - (normals[tb, 0] * e0 + normals[tb, 1] * e1 + normals[tb, 2] * e2 + normals[tb, 3] * e3)
            if (fa > 0.0) == (fb > 0.0):
                keep[fi - f_lo] = False
                continue
        a0, a1, a2 = faces[fi, 0], faces[fi, 1], faces[fi, 2]
        if cull == 2:
            away = _away(ov, base + a0, base + a1, base + a2, base + pool.apex[fi], lens.eye)
            # A far face near the rim keeps its edges: drawn over the near side's rim, their
            # lines' width shows past it, as when every face is drawn.
            keep[fi - f_lo] = away < RIM_MARGIN * RIM_MARGIN
            if away > CULL_MARGIN * CULL_MARGIN:
                continue
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
                sc = focal / near
                row = ov[o]
                for r in range(3):
                    row[r] = np.float32((cam[a, r] + s * (cam[b, r] - cam[a, r])) * sc) * s_place + place[1 + r]
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
    counts[0], counts[1], counts[3] = o, of, clipped


@njit(inline="always")
def _project_edges(pool, placed, k, cull, base, out_e, ws):
    """Instance ``k``'s edges in front of the near hyperplane into ``out_e``; with ``cull``
    only those of a kept face (:func:`_project_faces`)."""
    edges, edge_ptr, edge_end, edge_faces = pool.edges, pool.edge_ptr, pool.edge_end, pool.edge_faces
    inside, keep = ws.inside, ws.keep
    oe = ws.counts[2]
    for ei in range(placed.ranges[k, 4], placed.ranges[k, 5]):
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
    ws.counts[2] = oe
