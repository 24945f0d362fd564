"""The renderer's GPU buffers, one set per ``Drawable.key``.

A mesh is re-uploaded only when its drawable's ``revision`` changes, so a static world costs no
bus traffic, and a cross-section that changes every frame re-uses its buffers (they grow, never
shrink, while the key lives). Wire edges are derived on first use, and vertex arrays are made per
look and style.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.edges import feature_edges
from ..core.mesh import TriMesh3
from ..game.frame import Drawable
from .context import RenderError
from .near_first import piece_boxes

#: Bytes per vertex in the interleaved buffer: position 3f, normal 3f, colour 4f.
_STRIDE = 40
_ATTRS = (("in_pos", "3f", 12), ("in_normal", "3f", 12), ("in_color", "4f", 16))


class GpuMesh:
    """GPU buffers for one drawable key."""

    def __init__(self, key: str):
        self.key = key
        self.revision = None
        self.vbo: moderngl.Buffer | None = None
        self.ibo: moderngl.Buffer | None = None
        self.ebo: moderngl.Buffer | None = None  # wire edges
        self.vaos: dict[str, moderngl.VertexArray] = {}
        self.n_vertices = 0
        self.n_indices = 0
        self.n_edge_indices = -1  # -1: edges not derived for this revision
        self.center = np.zeros(3)  # bounding sphere in mesh space, for culling and ghost sorting
        self.radius = 0.0
        self.vertices: np.ndarray | None = None  # kept only until edges are derived
        self.faces: np.ndarray | None = None
        # Some vertex has no normal (a frustum projection's have none): the mesh is shaded flat
        # with its faces' screen-space normals, by a program of its own (shaders.program_source).
        self.flat_normals = False
        # Every triangle has one normal at its three vertices (a box's faces): shaded by a
        # program that works out per vertex what depends on the normal alone.
        self.faceted = False
        # A drawable with parts (see Drawable.parts): its pieces' boxes, where their faces
        # start, its faces as uploaded, and the order the index buffer holds them in.
        self.piece_boxes: np.ndarray | None = None
        self.parts: np.ndarray | None = None
        self.piece_faces: np.ndarray | None = None
        self.piece_order: np.ndarray | None = None

    def release(self) -> None:
        for vao in self.vaos.values():
            vao.release()
        self.vaos.clear()
        for name in ("vbo", "ibo", "ebo"):
            buf = getattr(self, name)
            if buf is not None:
                buf.release()
                setattr(self, name, None)


def write_buffer(ctx: moderngl.Context, buf: moderngl.Buffer | None, data: bytes) -> tuple[moderngl.Buffer, bool]:
    """Write ``data`` into ``buf``, growing it if needed; returns ``(buffer, created)``.

    Growing uses ``orphan`` on the same buffer object so vertex arrays that refer
    to it stay valid; capacity grows by 1.5x to avoid reallocating every frame
    for a cross-section that gains a few triangles at a time.
    """
    if buf is None:
        return ctx.buffer(data, dynamic=True), True
    if len(data) > buf.size:
        buf.orphan(int(len(data) * 1.5))
    buf.write(data)
    return buf, False


def faceted(normals: np.ndarray, faces: np.ndarray) -> bool:
    """Whether each triangle of ``faces (m, 3)`` has the same normal (of ``normals (n, 3)``) at
    its three vertices."""
    corners = normals[faces]
    return bool((corners == corners[:, :1]).all())


def check_parts(key: str, parts, n_faces: int) -> np.ndarray:
    """``parts`` of a drawable (see ``Drawable.parts``) as ``(k + 1,) int64``, checked."""
    p = np.asarray(parts)
    if p.ndim != 1 or len(p) < 2 or p[0] != 0 or p[-1] != n_faces or (np.diff(p) <= 0).any():
        raise RenderError(f"drawable {key!r}: parts must rise strictly from 0 to the face count {n_faces}, got {p!r}")
    return p.astype(np.int64)


def check_mesh(key: str, mesh: TriMesh3) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Validate and convert a mesh to ``(vertices, faces, normals, colors)`` float32/uint32 arrays."""
    v = np.asarray(mesh.vertices, np.float32).reshape(-1, 3)
    k = len(v)
    f = np.asarray(mesh.faces)
    if f.size and f.min() < 0:
        raise RenderError(f"drawable {key!r}: negative vertex index {int(f.min())} in faces")
    f = np.ascontiguousarray(f, np.uint32).reshape(-1, 3)
    if f.size and int(f.max()) >= k:
        # An out-of-range index makes the GPU read past the buffer: refuse it.
        raise RenderError(f"drawable {key!r}: face index {int(f.max())} out of range for {k} vertices")
    n = mesh.normals
    if n is None:
        n = np.zeros((k, 3), np.float32)  # shader falls back to facing the eye
    n = np.asarray(n, np.float32)
    if n.shape != (k, 3):
        raise RenderError(f"drawable {key!r}: normals must be ({k}, 3), got {n.shape}")
    c = mesh.colors
    if c is None:
        c = np.full((k, 4), 0.7, np.float32)
    c = np.asarray(c, np.float32)
    if c.ndim == 2 and c.shape[1] == 3:
        c = np.concatenate([c, np.ones((len(c), 1), np.float32)], axis=1)
    if c.shape != (k, 4):
        raise RenderError(f"drawable {key!r}: colors must be ({k}, 4) or ({k}, 3), got {c.shape}")
    return v, f, n, c


class MeshCache:
    """The :class:`GpuMesh` of every key drawn, counting uploads and releases in ``stats`` (a
    :class:`~.renderer.RenderStats`)."""

    def __init__(self, ctx: moderngl.Context, stats):
        self.ctx = ctx
        self.stats = stats
        self.meshes: dict[str, GpuMesh] = {}

    def keys(self) -> list[str]:
        """Keys that currently hold GPU buffers."""
        return sorted(self.meshes)

    @property
    def bytes(self) -> int:
        """Bytes of every vertex, index and edge buffer held."""
        return sum(b.size for gm in self.meshes.values() for b in (gm.vbo, gm.ibo, gm.ebo) if b is not None)

    def keep_only(self, used: set[str]) -> None:
        """Release the meshes of every key not in ``used``."""
        for key in [k for k in self.meshes if k not in used]:
            self.meshes.pop(key).release()
            self.stats.releases += 1

    def release(self) -> None:
        """Free every mesh's GPU objects."""
        for gm in self.meshes.values():
            gm.release()
        self.meshes.clear()

    def sync(self, d: Drawable) -> GpuMesh:
        """The key's buffers, uploading the drawable's mesh when its revision is new."""
        gm = self.meshes.get(d.key)
        if gm is None:
            gm = self.meshes[d.key] = GpuMesh(d.key)
        if gm.revision == d.revision and gm.revision is not None:
            return gm
        v, f, n, c = check_mesh(d.key, d.mesh)
        # (A level without walls has a static mesh of no faces, in no parts.)
        parts = None if d.parts is None or len(f) == 0 else check_parts(d.key, d.parts, len(f))
        gm.revision = d.revision
        gm.n_vertices, gm.n_indices = len(v), f.size
        gm.n_edge_indices = -1
        self.stats.uploads += 1
        self.stats.by_key[d.key] = self.stats.by_key.get(d.key, 0) + 1
        if f.size == 0:
            # Nothing to draw; keep any old buffers for when the mesh comes back.
            gm.vertices = gm.faces = None
            return gm
        gm.flat_normals = not n.any(axis=1).all()
        gm.faceted = not gm.flat_normals and faceted(n, f)
        gm.parts, gm.piece_boxes, gm.piece_faces, gm.piece_order = None, None, None, None
        if parts is not None:
            gm.parts, gm.piece_boxes, gm.piece_faces = parts, piece_boxes(v, f, parts), f
        inter = np.empty((len(v), 10), np.float32)
        inter[:, 0:3] = v
        inter[:, 3:6] = n
        inter[:, 6:10] = c
        data, idx = inter.tobytes(), f.tobytes()
        gm.vbo, new_v = write_buffer(self.ctx, gm.vbo, data)
        gm.ibo, new_i = write_buffer(self.ctx, gm.ibo, idx)
        self.stats.upload_bytes += len(data) + len(idx)
        if new_v or new_i:
            for vao in gm.vaos.values():
                vao.release()
            gm.vaos.clear()
        lo, hi = v.min(axis=0), v.max(axis=0)
        gm.center = 0.5 * (lo.astype(np.float64) + hi)
        gm.radius = float(np.sqrt(((v - gm.center) ** 2).sum(axis=1).max()))
        # Edges are derived lazily (only wire drawables need them); keep the
        # arrays until then.
        gm.vertices, gm.faces = v, f
        return gm

    def edges(self, gm: GpuMesh) -> int:
        """How many edge indices the mesh's wire drawing has (deriving them on first use)."""
        if gm.n_edge_indices < 0:
            e = feature_edges(gm.vertices, gm.faces) if gm.faces is not None else np.zeros((0, 2), np.uint32)
            self.stats.edge_builds += 1
            gm.n_edge_indices = e.size
            gm.vertices = gm.faces = None  # only needed to derive the edges
            if e.size:
                gm.ebo, created = write_buffer(self.ctx, gm.ebo, e.tobytes())
                if created:
                    for k in [k for k in gm.vaos if k[1] == "wire"]:
                        gm.vaos.pop(k).release()
        return gm.n_edge_indices

    def vao(self, gm: GpuMesh, prog: moderngl.Program, look: str, style: str) -> moderngl.VertexArray:
        """The vertex array of ``gm`` for ``prog``, the program of ``style`` in ``look`` (one per
        palette: a vertex array is bound to its program)."""
        key = (look, style, prog.glo)
        vao = gm.vaos.get(key)
        if vao is None:
            # Attributes a program doesn't use are optimised away by the GLSL
            # compiler; skip their bytes instead of binding them.
            fmt, names = [], []
            for name, f, size in _ATTRS:
                if name in prog:
                    fmt.append(f)
                    names.append(name)
                else:
                    fmt.append(f"{size}x")
            ibo = gm.ebo if style == "wire" else gm.ibo
            vao = self.ctx.vertex_array(prog, [(gm.vbo, " ".join(fmt), *names)], index_buffer=ibo, index_element_size=4)
            gm.vaos[key] = vao
        return vao
