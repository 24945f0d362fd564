"""Cross-section: slice a tetrahedral 4D mesh by a hyperplane into 3D triangles.

The hyperplane is the ``w = 0`` hyperplane of a 4D camera given by its pose
(camera-to-world 5x5 transform); the output lives in the camera's own xyz frame.
Which edges of a tet are cut, and in which order its polygon is wound, come
from the case table (:mod:`.cases`); the kernel turns each tet's object-space
normal (:func:`~.layout.layout_normals`) by the model-view's cofactor matrix
(:func:`~.section_kernels.normal_transform`).

Two implementations share these rules: :func:`cross_section` (numba, clustered,
single-threaded: this module is its Python front, :mod:`.section_kernels` its
kernels, :mod:`.layout` the mesh's slicing layout) and
:func:`cross_section_reference` (plain Python/numpy, the oracle the tests compare
against).
"""

from __future__ import annotations

import sys
import threading

import numpy as np

from .cases import (  # noqa: F401  (the case table, read here by tests and tools)
    CASE_COUNT,
    CASE_EDGES,
    CASE_EDGES_PADDED,
    CASE_LOCAL_EDGES,
    CASE_REVERSED,
    TET_EDGE_PAIRS,
)
from .layout import Layout, layout_colors, layout_edges, layout_normals, mesh_clusters
from .mesh import TetMesh4, TriMesh3, cross4
from .section_kernels import (  # noqa: F401
    POINTS_BY_EDGE,
    POINTS_BY_EDGE_SCAN,
    POINTS_BY_TET,
    Slicer,
    _emit,
    _find_cut,
    normal_transform,
    orientation,
)
from .transform import inverse

_IDENTITY = np.eye(5)
_IDENTITY.flags.writeable = False


def _model_view(mesh_model, camera_pose) -> np.ndarray:
    """Object-to-camera 5x5 transform."""
    view = _IDENTITY if camera_pose is None else inverse(camera_pose)
    model = _IDENTITY if mesh_model is None else np.asarray(mesh_model, dtype=np.float64)
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
        Its ``faces`` are ``arange(3 * triangles)``: a read-only view shared by
        every section (they are the same numbers every time).
    """
    mv = _model_view(model, camera_pose)
    layout = mesh_clusters(mesh)
    a = mv[:4, :4]
    # Bound on how far a unit object-space step moves camera-space w (np.linalg.norm's
    # own sum, without its checks).
    w_gain = float(np.sqrt(a[3].dot(a[3])))
    flip = orientation(mv)
    if flip == 0.0:  # too close to tell by cofactors: LU's sign, as ever
        flip = 1.0 if np.linalg.det(a) > 0 else -1.0
    ws = _workspace(mesh, layout)
    with ws.lock:
        slicer = ws.slicer(mesh)
        ncut, ntri = _find_cut(slicer, mv, w_gain, cull)
        if ntri == 0:
            return TriMesh3.empty()
        out = ws.output_block(30 * ntri)  # the three outputs in one block
        by_edge = EDGE_TABLE_FRACTION * ncut > len(layout.tets)
        if by_edge and ws.edges is None:
            ws.set_edges(layout_edges(layout))
            slicer = ws.slicer(mesh)
        if ws.tn.shape[1] < ncut:
            ws.grow_tets(ncut)
            slicer = ws.slicer(mesh)
        points = POINTS_BY_TET
        if by_edge:
            points = POINTS_BY_EDGE_SCAN if EDGE_SCAN_FRACTION * ncut > len(ws.edges[1]) else POINTS_BY_EDGE
        every_vertex = EVERY_VERTEX_FRACTION * ncut > len(layout.vertices)
        _emit(slicer, mv, flip, ncut, ntri, points, every_vertex, out)
    ov, on, oc = out[: 9 * ntri], out[9 * ntri : 18 * ntri], out[18 * ntri : 30 * ntri]
    return TriMesh3(ov.reshape(-1, 3), _faces(ntri), on.reshape(-1, 3), oc.reshape(-1, 4))


#: Move every vertex into camera space (one vectorized loop) when the cut tets are
#: more than the vertices over this (a cut tet has four), else only the cut tets' vertices.
EVERY_VERTEX_FRACTION = 4
#: Use a mesh's edge table (built on first need) once a section cuts more than one
#: tet in this many: it has about as many edges as the mesh has tets.
EDGE_TABLE_FRACTION = 16
#: On the edge path, find the cut edges by one pass over the edge table once the cut tets are
#: more than the edges over this: the pass costs about a fifth per edge of what it saves per cut tet.
EDGE_SCAN_FRACTION = 4
_NO_EDGES = (np.zeros((0, 6), np.uint32), np.zeros(0, np.uint32), np.zeros(0, np.uint32))


class _Workspace:
    """Scratch arrays for the sections of one layout, reused call after call.

    Fresh scratch arrays cost more than the slicing itself: the first write to
    each new page of memory is a page fault (about a microsecond per 4 KiB),
    and a dense section touches thousands of pages of scratch. Sections of one
    mesh from several threads take turns (``lock``). The kernels take the
    layout's arrays and these in one bundle (:meth:`slicer`), made again
    whenever one of them is replaced; its docstring says what each holds.
    """

    def __init__(self, layout: Layout):
        n, m = len(layout.vertices), len(layout.tets)
        self.layout = layout
        self.lock = threading.Lock()
        self.keep = np.empty(len(layout.lo), np.int64)
        self.above = np.empty(n, np.uint8)
        self.cut = np.empty(m, np.uint32)
        self.cmask = np.empty(m, np.uint8)
        self.g = np.empty(12)
        self.cam = np.empty(4 * n)
        self.vmark = np.zeros(n, np.uint8)
        self.edges = None  # layout_edges(layout), once a dense section needs it
        self.point = np.zeros(0, np.int32)
        self.tn = np.empty((3, 0), np.float32)
        self.grow_tets(0)
        self.blocks: list[np.ndarray] = []  # output blocks of earlier sections

    def output_block(self, size: int) -> np.ndarray:
        """A float32 array of at least ``size`` for a section's outputs.

        The outputs of an earlier section are reused once nothing outside holds
        them (their reference count is the pool's own): a game drops last
        frame's section, a benchmark each run's, and both then write into memory
        that is already mapped. A new block has room to spare, so a section
        that grows a little still fits next time.
        """
        for b in self.blocks:
            if size <= len(b) <= 2 * size + 4096 and sys.getrefcount(b) <= _FREE_REFS:
                return b
        b = np.empty(size + size // 4 + 1024, np.float32)
        if len(self.blocks) >= OUTPUT_BLOCKS:
            self.blocks.pop(0)  # the oldest: whoever holds it keeps it alive
        self.blocks.append(b)
        return b

    def slicer(self, mesh: TetMesh4) -> tuple:
        """The kernels' bundle, a :class:`~.section_kernels.Slicer` as a plain tuple:
        ``mesh``'s layout (in its current colours) and the scratch arrays."""
        colors = layout_colors(mesh, self.layout)
        if self._slicer is None or self._colors is not colors:
            lay = self.layout
            self._colors = colors
            self._slicer = tuple(Slicer(
                lay.vertices, lay.tets, colors, layout_normals(mesh, lay).reshape(-1),
                lay.lo, lay.hi, lay.centers, lay.radii, *(_NO_EDGES if self.edges is None else self.edges),
                self.keep, self.above, self.cut, self.cmask, self.g, self.cam, self.vmark, self.vlist,
                self.point, self.elist, self.rec, self.tj, self.n64, self.tn,
            ))  # fmt: skip
        return self._slicer

    def set_edges(self, edges) -> None:
        self.edges = edges
        self.point = np.full(len(edges[1]), -1, np.int32)
        self._slicer = None

    def grow_tets(self, count: int) -> None:
        """Room for ``count`` cut tets (and four times as many section points)."""
        count = max(count, self.tn.shape[1] * 5 // 4)  # grow by a quarter at least
        self.n64 = np.empty((3, count))
        self.tn = np.empty((3, count), np.float32)
        self.tj = np.empty(5 * count, np.int32)
        self.elist = np.empty(4 * count + 1, np.uint32)  # + 1: the edge scan writes one past its last point
        self.vlist = np.empty(4 * count, np.uint32)
        self.rec = np.empty(32 * count, np.float32)
        self._slicer = None


def _refs_when_free() -> int:
    """``sys.getrefcount`` of a block in :meth:`_Workspace.output_block`'s loop that nothing else holds."""
    blocks = [np.empty(0, np.float32)]
    for b in blocks:
        return sys.getrefcount(b)


_FREE_REFS = _refs_when_free()
#: Output blocks kept per mesh: the section on screen, the one being made, and spares.
OUTPUT_BLOCKS = 4


def _workspace(mesh: TetMesh4, layout: Layout) -> _Workspace:
    key = ("section_workspace", id(layout))
    ws = mesh._cache.get(key)
    if ws is None:
        ws = mesh._cache[key] = _Workspace(layout)
    return ws


_FACES = [np.zeros((0, 3), np.uint32)]


def _faces(ntri: int) -> np.ndarray:
    """``arange(3 * ntri).reshape(-1, 3)`` as a read-only view of one shared, growing array.

    An unwelded section's faces are always these numbers; writing them afresh
    for every section is a sizeable part of slicing a small mesh.
    """
    faces = _FACES[0]
    if len(faces) < ntri:
        faces = np.arange(3 * max(ntri, 2 * len(faces)), dtype=np.uint32).reshape(-1, 3)
        faces.flags.writeable = False
        _FACES[0] = faces
    return faces[:ntri]


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
