"""Cross-section: slice a tetrahedral 4D mesh by a hyperplane into 3D triangles.

The hyperplane is the ``w = 0`` hyperplane of a 4D camera given by its pose
(camera-to-world 5x5 transform); the output lives in the camera's own xyz frame.

Case table
----------
Each tet's four vertices are classified by the sign of their camera-space w
(``d > 0`` is "above"; ``d == 0`` counts as below, a consistent tie-break that
keeps sections closed). Bit ``i`` of the case index is set when vertex ``i`` is
above, giving 16 cases:

====================  ====================  ===============================
cases                 vertices above        cut edges, in cycle order
====================  ====================  ===============================
0, 15                 none / all            nothing
1, 2, 4, 8            one: ``a``            ``ab ac ad`` -> one triangle
14, 13, 11, 7         three (one below b)   ``ba bc bd`` -> one triangle
3, 5, 6, 9, 10, 12    two: ``a0 a1``        ``a0b0 a0b1 a1b1 a1b0`` -> a quad
====================  ====================  ===============================

The table fixes which edges form the polygon and their cyclic order; the
winding is then fixed per tet by the tet's outward 4D normal projected into the
hyperplane (the section's outward normal), so triangles come out
counter-clockwise seen from outside whatever the tet's vertex order.

Two implementations share these rules: :func:`cross_section` (numba, clustered,
single-threaded) and :func:`cross_section_reference` (plain Python/numpy, the
oracle the tests compare against).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import njit
from .mesh import TetMesh4, TriMesh3, cross4
from .transform import inverse


def _build_case_table() -> tuple[np.ndarray, np.ndarray]:
    edges = np.zeros((16, 4, 2), dtype=np.int64)
    count = np.zeros(16, dtype=np.int64)
    for mask in range(16):
        above = [i for i in range(4) if mask >> i & 1]
        below = [i for i in range(4) if not mask >> i & 1]
        if len(above) == 1:
            cyc = [(above[0], b) for b in below]
        elif len(below) == 1:
            cyc = [(below[0], a) for a in above]
        elif len(above) == 2:
            a0, a1 = above
            b0, b1 = below
            cyc = [(a0, b0), (a0, b1), (a1, b1), (a1, b0)]
        else:
            cyc = []
        count[mask] = len(cyc)
        for k, e in enumerate(cyc):
            edges[mask, k] = e
    return edges, count


CASE_EDGES, CASE_COUNT = _build_case_table()


def _model_view(mesh_model, camera_pose) -> np.ndarray:
    """Object-to-camera 5x5 transform."""
    view = np.eye(5) if camera_pose is None else inverse(camera_pose)
    model = np.eye(5) if mesh_model is None else np.asarray(mesh_model, dtype=np.float64)
    return view @ model


def cross_section(mesh: TetMesh4, camera_pose=None, model=None, cull: bool = True) -> TriMesh3:
    """Slice ``mesh`` by the camera's ``w = 0`` hyperplane.

    Parameters
    ----------
    mesh : TetMesh4
    camera_pose : (5, 5) array_like, optional
        Camera-to-world transform; identity slices at world ``w = 0`` and keeps
        world xyz.
    model : (5, 5) array_like, optional
        Object-to-world transform of the mesh.
    cull : bool
        Skip clusters of tets whose bounding sphere the hyperplane misses
        (False scans every tet, for benchmarks).

    Returns
    -------
    TriMesh3
        Unwelded triangles (three vertices each) with flat outward normals and
        interpolated colours, in the camera's xyz frame. Empty when nothing is cut.
    """
    mv = _model_view(model, camera_pose)
    layout = mesh_clusters(mesh)
    tets, lo, hi, centers, radii = layout.tets, layout.lo, layout.hi, layout.centers, layout.radii
    colors = _layout_colors(mesh, layout)
    # Bound on how far a unit object-space step moves camera-space w.
    w_gain = float(np.linalg.norm(mv[3, :4]))
    flip = 1.0 if np.linalg.det(mv[:4, :4]) > 0 else -1.0
    if not cull:
        lo, hi = lo[:1], hi[-1:]
        centers, radii = centers[:1], np.array([np.inf])
    cut, ntri = _find_cut(layout.vertices, tets, mv, lo, hi, centers, radii, w_gain, CASE_COUNT, cull)
    if ntri == 0:
        return TriMesh3.empty()
    v, n, c = _emit(layout.vertices, tets, colors, mv, flip, cut, ntri, CASE_EDGES, CASE_COUNT)
    faces = np.arange(3 * ntri, dtype=np.uint32).reshape(-1, 3)
    return TriMesh3(v, faces, n, c)


CLUSTER_SIZE = 64


class Layout(NamedTuple):
    """A mesh rearranged for slicing (see :func:`mesh_clusters`)."""

    vertices: np.ndarray  # (n', 4) float32, in order of first use by the sorted tets
    tets: np.ndarray  # (m, 4) uint32, sorted into clusters, indexing ``vertices``
    source: np.ndarray  # (n',) int64, the original index of each vertex
    lo: np.ndarray  # (c,) int64, first tet of each cluster
    hi: np.ndarray  # (c,) int64, one past its last tet
    centers: np.ndarray  # (c, 4) float64, bounding sphere centres
    radii: np.ndarray  # (c,) float64


def mesh_clusters(mesh: TetMesh4, size: int = CLUSTER_SIZE) -> Layout:
    """Tets sorted into spatially coherent clusters with bounding spheres.

    Cached on the mesh. Sorting by a 4D Morton code of tet centroids makes each
    run of ``size`` tets compact, so a hyperplane far from a cluster's sphere
    skips all of its tets without touching them. Vertices are renumbered in the
    order the sorted tets first use them, so a cluster's vertices sit together
    in memory: the gathers of a scan hit the cache instead of main memory.
    """
    key = ("clusters", size)
    if key not in mesh._cache:
        v = mesh.vertices.astype(np.float64)
        cent = v[mesh.tets].mean(axis=1)
        lo_b, hi_b = cent.min(axis=0), cent.max(axis=0)
        q = ((cent - lo_b) / np.maximum(hi_b - lo_b, 1e-12) * 255).astype(np.uint64)
        code = np.zeros(len(cent), np.uint64)
        for bit in range(8):
            for axis in range(4):
                code |= ((q[:, axis] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(4 * bit + axis)
        sorted_tets = mesh.tets[np.argsort(code, kind="stable")]
        used, first = np.unique(sorted_tets.ravel(), return_index=True)
        source = used[np.argsort(first, kind="stable")]
        renumber = np.empty(len(mesh.vertices), np.int64)
        renumber[source] = np.arange(len(source))
        tets = np.ascontiguousarray(renumber[sorted_tets].astype(np.uint32))
        vertices = np.ascontiguousarray(mesh.vertices[source])
        starts = np.arange(0, len(tets), size, dtype=np.int64)
        ends = np.minimum(starts + size, len(tets))
        centers, radii = _cluster_spheres(vertices.astype(np.float64), tets, starts, ends)
        mesh._cache[key] = Layout(vertices, tets, source, starts, ends, centers, radii)
    return mesh._cache[key]


def _layout_colors(mesh: TetMesh4, layout: Layout) -> np.ndarray:
    """The mesh's vertex colours in the layout's order (cached with the colours)."""
    key = ("layout_colors", len(layout.source))
    colors = mesh.vertex_colors()
    entry = mesh._cache.get(key)
    if entry is None or entry[0] is not colors:
        entry = (colors, np.ascontiguousarray(colors[layout.source]))
        mesh._cache[key] = entry
    return entry[1]


@njit(cache=True)
def _cluster_spheres(v, tets, starts, ends):
    nc = len(starts)
    centers = np.zeros((nc, 4))
    radii = np.zeros(nc)
    for c in range(nc):
        lo = np.full(4, np.inf)
        hi = np.full(4, -np.inf)
        for t in range(starts[c], ends[c]):
            for k in range(4):
                for a in range(4):
                    x = v[tets[t, k], a]
                    lo[a] = min(lo[a], x)
                    hi[a] = max(hi[a], x)
        ctr = 0.5 * (lo + hi)
        r2 = 0.0
        for t in range(starts[c], ends[c]):
            for k in range(4):
                s = 0.0
                for a in range(4):
                    d = v[tets[t, k], a] - ctr[a]
                    s += d * d
                r2 = max(r2, s)
        centers[c] = ctr
        radii[c] = np.sqrt(r2)
    return centers, radii


@njit(cache=True)
def _find_cut(v, tets, mv, lo, hi, centers, radii, w_gain, case_count, lazy):
    """Indices of tets the hyperplane cuts, and the number of triangles they make.

    One byte per vertex (is it above?) keeps the per-tet gathers in cache and
    the case index branch-free. With ``lazy`` the bytes are filled only for
    vertices of clusters that survive culling, so a scene mostly far from the
    hyperplane costs little more than its cluster count.
    """
    m0, m1, m2, m3, m4 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    n = v.shape[0]
    above = np.empty(n, np.uint8)
    if lazy:
        above[:] = 2  # not computed yet
    else:
        for i in range(n):
            above[i] = (m0 * v[i, 0] + m1 * v[i, 1] + m2 * v[i, 2] + m3 * v[i, 3] + m4) > 0.0
    cut = np.empty(tets.shape[0], np.int64)
    ncut = 0
    ntri = 0
    for c in range(lo.shape[0]):
        dc = m0 * centers[c, 0] + m1 * centers[c, 1] + m2 * centers[c, 2] + m3 * centers[c, 3] + m4
        if abs(dc) > radii[c] * w_gain:
            continue
        if lazy:
            for t in range(lo[c], hi[c]):
                for k in range(4):
                    i = tets[t, k]
                    if above[i] == 2:
                        above[i] = (m0 * v[i, 0] + m1 * v[i, 1] + m2 * v[i, 2] + m3 * v[i, 3] + m4) > 0.0
        for t in range(lo[c], hi[c]):
            mask = above[tets[t, 0]] | (above[tets[t, 1]] << 1) | (above[tets[t, 2]] << 2) | (above[tets[t, 3]] << 3)
            if mask != 0 and mask != 15:
                cut[ncut] = t
                ncut += 1
                ntri += case_count[mask] - 2
    return cut[:ncut], ntri


@njit(inline="always")
def _tet_normal(p, flip):
    """Unit outward normal of the section of the tet with camera-space corners ``p`` ``(4, 4)``:
    the xyz part of cross4(p1 - p0, p2 - p0, p3 - p0), times ``flip`` (+-1); zero stays zero."""
    ux, uy, uz, uw = p[1, 0] - p[0, 0], p[1, 1] - p[0, 1], p[1, 2] - p[0, 2], p[1, 3] - p[0, 3]
    vx, vy, vz, vw = p[2, 0] - p[0, 0], p[2, 1] - p[0, 1], p[2, 2] - p[0, 2], p[2, 3] - p[0, 3]
    tx, ty, tz, tw = p[3, 0] - p[0, 0], p[3, 1] - p[0, 1], p[3, 2] - p[0, 2], p[3, 3] - p[0, 3]
    nx = -(uy * (vz * tw - vw * tz) - uz * (vy * tw - vw * ty) + uw * (vy * tz - vz * ty))
    ny = ux * (vz * tw - vw * tz) - uz * (vx * tw - vw * tx) + uw * (vx * tz - vz * tx)
    nz = -(ux * (vy * tw - vw * ty) - uy * (vx * tw - vw * tx) + uw * (vx * ty - vy * tx))
    nx *= flip
    ny *= flip
    nz *= flip
    ln = np.sqrt(nx * nx + ny * ny + nz * nz)
    if ln > 0.0:
        nx /= ln
        ny /= ln
        nz /= ln
    return nx, ny, nz


@njit(cache=True)
def _emit(v, tets, colors, mv, flip, cut, ntri, case_edges, case_count):
    """Triangles of the cut tets: positions, flat outward normals and colours.

    When the cut tets are many for the vertices they use (a dense section, the
    worst case), each vertex is moved into camera space once and kept (a vertex
    belongs to ~20 tets); when they are few among many vertices (a sparse
    section of a big mesh), per tet, which touches no per-vertex memory. Both
    compute the same sums in the same order, so the output is identical.
    """
    out_v = np.empty((3 * ntri, 3), np.float32)
    out_n = np.empty((3 * ntri, 3), np.float32)
    out_c = np.empty((3 * ntri, 4), np.float32)
    p = np.empty((4, 4))  # camera-space tet vertices
    q = np.empty((4, 3))  # polygon points
    qc = np.empty((4, 4))
    n = v.shape[0]
    cached = 4 * cut.shape[0] > n
    cam = np.empty((n if cached else 0, 4))
    done = np.zeros(n if cached else 0, np.uint8)
    o = 0
    for idx in range(cut.shape[0]):
        t = cut[idx]
        mask = 0
        for k in range(4):
            vi = tets[t, k]
            if cached:
                if done[vi] == 0:
                    done[vi] = 1
                    for r in range(4):
                        cam[vi, r] = (
                            mv[r, 0] * v[vi, 0]
                            + mv[r, 1] * v[vi, 1]
                            + mv[r, 2] * v[vi, 2]
                            + mv[r, 3] * v[vi, 3]
                            + mv[r, 4]
                        )
                for r in range(4):
                    p[k, r] = cam[vi, r]
            else:
                for r in range(4):
                    p[k, r] = (
                        mv[r, 0] * v[vi, 0] + mv[r, 1] * v[vi, 1] + mv[r, 2] * v[vi, 2] + mv[r, 3] * v[vi, 3] + mv[r, 4]
                    )
            if p[k, 3] > 0.0:
                mask |= 1 << k
        nx, ny, nz = _tet_normal(p, flip)
        k = case_count[mask]
        for e in range(k):
            a = case_edges[mask, e, 0]
            b = case_edges[mask, e, 1]
            if tets[t, a] > tets[t, b]:
                # Interpolate from the lower vertex index, so the tets sharing this
                # edge compute bit-identical points.
                a, b = b, a
            s = p[a, 3] / (p[a, 3] - p[b, 3])
            for r in range(3):
                q[e, r] = p[a, r] + s * (p[b, r] - p[a, r])
            ca = tets[t, a]
            cb = tets[t, b]
            for r in range(4):
                qc[e, r] = colors[ca, r] + s * (colors[cb, r] - colors[ca, r])
        # Winding: compare the polygon's own normal with the outward normal.
        ax, ay, az = q[1, 0] - q[0, 0], q[1, 1] - q[0, 1], q[1, 2] - q[0, 2]
        bx, by, bz = q[2, 0] - q[0, 0], q[2, 1] - q[0, 1], q[2, 2] - q[0, 2]
        if k == 4:  # use the quad's diagonals: robust when one triangle is a sliver
            ax, ay, az = q[2, 0] - q[0, 0], q[2, 1] - q[0, 1], q[2, 2] - q[0, 2]
            bx, by, bz = q[3, 0] - q[1, 0], q[3, 1] - q[1, 1], q[3, 2] - q[1, 2]
        cxp = ay * bz - az * by
        cyp = az * bx - ax * bz
        czp = ax * by - ay * bx
        reverse = cxp * nx + cyp * ny + czp * nz < 0.0
        # Fan from point 0: triangles (0, t+1, t+2), or (0, t+2, t+1) reversed.
        d1 = 2 if reverse else 1
        d2 = 3 - d1
        for tri in range(k - 2):
            _put(out_v, out_n, out_c, o, q, qc, 0, nx, ny, nz)
            _put(out_v, out_n, out_c, o + 1, q, qc, tri + d1, nx, ny, nz)
            _put(out_v, out_n, out_c, o + 2, q, qc, tri + d2, nx, ny, nz)
            o += 3
    return out_v, out_n, out_c


@njit(inline="always")
def _put(out_v, out_n, out_c, o, q, qc, src, nx, ny, nz):
    out_v[o, 0] = q[src, 0]
    out_v[o, 1] = q[src, 1]
    out_v[o, 2] = q[src, 2]
    out_n[o, 0] = nx
    out_n[o, 1] = ny
    out_n[o, 2] = nz
    out_c[o, 0] = qc[src, 0]
    out_c[o, 1] = qc[src, 1]
    out_c[o, 2] = qc[src, 2]
    out_c[o, 3] = qc[src, 3]


def cross_section_reference(mesh: TetMesh4, camera_pose=None, model=None) -> TriMesh3:
    """Plain-Python cross-section: the oracle for :func:`cross_section`.

    Same contract, written for clarity: one tet at a time, no clusters, numpy
    vector maths. Slow; use it in tests on small meshes.
    """
    mv = _model_view(model, camera_pose)
    flip = 1.0 if np.linalg.det(mv[:4, :4]) > 0 else -1.0
    cam = mesh.vertices.astype(np.float64) @ mv[:4, :4].T + mv[:4, 4]
    colors = mesh.vertex_colors()
    verts, norms, cols = [], [], []
    for tet in mesh.tets:
        p = cam[tet]
        above = [i for i in range(4) if p[i, 3] > 0]
        below = [i for i in range(4) if p[i, 3] <= 0]
        if not above or not below:
            continue
        if len(above) == 2:
            cycle = [(above[0], below[0]), (above[0], below[1]), (above[1], below[1]), (above[1], below[0])]
        elif len(above) == 1:
            cycle = [(above[0], b) for b in below]
        else:
            cycle = [(below[0], a) for a in above]
        pts, cs = [], []
        for a, b in cycle:
            if tet[a] > tet[b]:
                a, b = b, a
            s = p[a, 3] / (p[a, 3] - p[b, 3])
            pts.append(p[a, :3] + s * (p[b, :3] - p[a, :3]))
            cs.append(colors[tet[a]] + s * (colors[tet[b]] - colors[tet[a]]))
        normal = flip * cross4(p[1] - p[0], p[2] - p[0], p[3] - p[0])[:3]
        normal = normal / (np.linalg.norm(normal) or 1.0)
        if len(pts) == 4:
            poly_n = np.cross(pts[2] - pts[0], pts[3] - pts[1])
        else:
            poly_n = np.cross(pts[1] - pts[0], pts[2] - pts[0])
        if poly_n @ normal < 0:
            pts = [pts[0]] + pts[1:][::-1]
            cs = [cs[0]] + cs[1:][::-1]
        for i in range(1, len(pts) - 1):
            for j in (0, i, i + 1):
                verts.append(pts[j])
                cols.append(cs[j])
                norms.append(normal)
    if not verts:
        return TriMesh3.empty()
    v = np.array(verts, np.float32)
    return TriMesh3(
        v, np.arange(len(v), dtype=np.uint32).reshape(-1, 3), np.array(norms, np.float32), np.array(cols, np.float32)
    )
