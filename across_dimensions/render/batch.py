"""GPU side of :class:`~across_dimensions.game.frame.TriangleBatch`: one growing buffer per batch.

Per batch key there is one vertex buffer (and, for indexed batches, one index
buffer and one line buffer). A new revision uploads only the rows from
``changed_from`` on (``glBufferSubData`` at an offset), in place. Capacity is the next power of two of the data: it
grows at once, and shrinks after the data has fitted half of it for
:data:`SHRINK_AFTER` frames, so a scene that grows and empties ends with the
bytes it began with. :attr:`BatchBuffers.bytes`
counts every byte held, for tests and the benchmark.

The data comes from the engine's own kernels and is trusted: no range or
shape checks run per frame (they cost more than the upload on a 2-core machine).
"""

from __future__ import annotations

import moderngl
import numpy as np

from .context import color_writes

#: Smallest buffer made (bytes): a few small sections without regrowing.
MIN_BYTES = 64 * 1024

#: Unlit lines in one colour over a batch's triangles, pulled a little toward
#: the eye so they win the depth test against the faces they bound.
EDGE_VERTEX = """
#version 330
uniform mat4 u_view_proj;
in vec3 in_pos;
void main() {
    gl_Position = u_view_proj * vec4(in_pos, 1.0);
    gl_Position.z -= 4e-4 * gl_Position.w;
}
"""
EDGE_FRAGMENT = """
#version 330
uniform vec4 u_color;
out vec4 f_color;
void main() { f_color = u_color; }
"""
#: Depth only (the pre-pass): the same position sums as the scene shaders
#: (model times position, then view-projection), so the shading pass's depths
#: match and ``<=`` lets exactly the front fragment through.
DEPTH_VERTEX = """
#version 330
uniform mat4 u_view_proj;
uniform mat4 u_model;
in vec3 in_pos;
void main() {
    vec4 world = u_model * vec4(in_pos, 1.0);
    gl_Position = u_view_proj * world;
}
"""
DEPTH_FRAGMENT = """
#version 330
out vec4 f_color;
void main() { f_color = vec4(0.0); }
"""

_EYE4 = np.eye(4, dtype=np.float32).tobytes()
_EYE3 = np.eye(3, dtype=np.float32).tobytes()


def capacity_for(n: int, minimum: int) -> int:
    """The capacity held for ``n`` bytes (or rows): the next power of two, at least ``minimum``.

    A function of ``n`` alone, so once a scene has settled the memory held does
    not depend on the scene's history.
    """
    return max(int(minimum), 1 << max(int(n) - 1, 0).bit_length())


#: Frames a buffer must stay under half full before it shrinks (no thrashing
#: when a scene hovers around a power of two).
SHRINK_AFTER = 30


class _Buffer:
    """One GPU buffer: grows at once to the next power of two, shrinks after a while."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.buf = ctx.buffer(reserve=MIN_BYTES, dynamic=True)
        self.used = 0
        self._small = 0  # consecutive frames the data fitted a smaller capacity

    @property
    def size(self) -> int:
        return self.buf.size

    def write(self, data: np.ndarray, start_byte: int = 0) -> tuple[int, bool]:
        """Make the buffer hold ``data``, given that bytes before ``start_byte`` are already there.

        Call it every frame (``start_byte = data.nbytes`` when nothing changed)
        so an oversized buffer can shrink. Returns ``(bytes uploaded, reallocated)``.
        """
        n = data.nbytes
        want = capacity_for(n, MIN_BYTES)
        realloc = False
        if n > self.buf.size:
            realloc = True
        elif want < self.buf.size:
            self._small += 1
            realloc = self._small >= SHRINK_AFTER
        else:
            self._small = 0
        if realloc:
            self.buf.orphan(want)
            self._small = 0
            start_byte = 0
        # No orphaning when everything changes: a fresh store per frame costs the
        # driver a new allocation (page faults for every byte on llvmpipe, whose
        # large blocks come straight from mmap), while writing in place waits for
        # nothing: the last frame was presented, so finished, before this one began.
        self.used = n
        if n > start_byte:
            raw = memoryview(np.ascontiguousarray(data)).cast("B")
            self.buf.write(raw[start_byte:], offset=start_byte)
        return max(n - start_byte, 0), realloc

    def release(self) -> None:
        self.buf.release()


class _GpuBatch:
    def __init__(self, ctx: moderngl.Context):
        self.vbo = _Buffer(ctx)
        self.ibo: _Buffer | None = None
        self.ebo: _Buffer | None = None
        self.revision = None
        self.topology = None
        self.n_rows = 0
        self.n_faces = 0
        self.n_edges = 0
        self.vaos: dict[str, moderngl.VertexArray] = {}

    def buffers(self):
        return [b for b in (self.vbo, self.ibo, self.ebo) if b is not None]

    def release(self) -> None:
        for vao in self.vaos.values():
            vao.release()
        self.vaos.clear()
        for b in self.buffers():
            b.release()


class BatchBuffers:
    """GPU buffers and draw calls for a renderer's triangle batches.

    Parameters
    ----------
    ctx : moderngl.Context
    programs : dict of str to moderngl.Program
        The renderer's style programs (shared, not owned).
    """

    def __init__(self, ctx: moderngl.Context, programs: dict):
        self.ctx = ctx
        self.programs = programs
        self._edge_prog = ctx.program(vertex_shader=EDGE_VERTEX, fragment_shader=EDGE_FRAGMENT)
        self._depth_prog = ctx.program(vertex_shader=DEPTH_VERTEX, fragment_shader=DEPTH_FRAGMENT)
        self._batches: dict[str, _GpuBatch] = {}
        self.upload_bytes = 0  #: bytes sent by the last sync
        self.uploads = 0  #: lifetime count of vertex uploads
        self.partial_uploads = 0  #: of which only a changed range

    @property
    def bytes(self) -> int:
        """GPU buffer bytes held by every batch."""
        return sum(b.size for g in self._batches.values() for b in g.buffers())

    def keys(self) -> list[str]:
        return sorted(self._batches)

    def sync(self, batches, keep=()) -> None:
        """Upload what changed in ``batches``; release buffers of keys neither drawn nor in ``keep``."""
        self.upload_bytes = 0
        seen = set(keep)
        for tb in batches:
            seen.add(tb.key)
            g = self._batches.get(tb.key)
            if g is None:
                g = self._batches[tb.key] = _GpuBatch(self.ctx)
            v = tb.vertices
            if g.revision != tb.revision:
                start = 0
                if g.revision is not None and tb.revision == g.revision + 1 and tb.changed_from <= g.n_rows:
                    start = int(tb.changed_from) * v.strides[0]
                self.uploads += 1
                self.partial_uploads += start > 0
            else:
                start = v.nbytes  # unchanged: only the shrink check
            sent, _ = g.vbo.write(v, start)
            self.upload_bytes += sent
            g.revision, g.n_rows = tb.revision, len(v)
            if tb.faces is not None or tb.edges is not None:
                fresh = g.topology != tb.topology_revision
                for name, arr in (("ibo", tb.faces), ("ebo", tb.edges)):
                    if arr is None:
                        continue
                    b = getattr(g, name)
                    if b is None:
                        b = _Buffer(self.ctx)
                        setattr(g, name, b)
                        self._drop_vaos(g)  # made before this buffer existed
                    arr = np.ascontiguousarray(arr, np.uint32)
                    sent, _ = b.write(arr, 0 if fresh else arr.nbytes)
                    self.upload_bytes += sent
                g.topology = tb.topology_revision
                g.n_faces = 0 if tb.faces is None else len(tb.faces)
                g.n_edges = 0 if tb.edges is None else len(tb.edges)
        for key in [k for k in self._batches if k not in seen]:
            self._batches.pop(key).release()

    @staticmethod
    def _drop_vaos(g: _GpuBatch) -> None:
        for vao in g.vaos.values():
            vao.release()
        g.vaos.clear()

    def _vao(self, g: _GpuBatch, name: str, prog: moderngl.Program, index: _Buffer | None) -> moderngl.VertexArray:
        vao = g.vaos.get(name)
        if vao is None:
            fmt, names = [], []
            for attr, f, size in (("in_pos", "3f", 12), ("in_normal", "3f", 12), ("in_color", "4f", 16)):
                if attr in prog:
                    fmt.append(f)
                    names.append(attr)
                else:
                    fmt.append(f"{size}x")
            content = [(g.vbo.buf, " ".join(fmt), *names)]
            if index is None:
                vao = self.ctx.vertex_array(prog, content)
            else:
                vao = self.ctx.vertex_array(prog, content, index_buffer=index.buf, index_element_size=4)
            g.vaos[name] = vao
        return vao

    def _set_identity_model(self, prog: moderngl.Program) -> None:
        for name, value in (("u_model", _EYE4), ("u_normal_mat", _EYE3)):
            u = prog.get(name, None)  # not ``in``: a Program walks its members for that
            if u is not None:
                u.write(value)

    def draw(self, tb, view_proj_bytes: bytes, program: str | None = None) -> tuple[int, int, int]:
        """Draw one batch's triangles (and edges): returns ``(draw calls, triangles, lines)``.

        ``program`` names the program of :attr:`programs` to shade with (default: the batch's
        style). The caller sets the shared uniforms (view, light, fog, ghost look) and
        the blend and depth state of the pass.
        """
        g = self._batches[tb.key]
        name = program or tb.style
        prog = self.programs[name]
        indexed = tb.faces is not None
        n_tri = g.n_faces if indexed else g.n_rows // 3
        if n_tri == 0:
            return 0, 0, 0
        calls = 0
        ctx = self.ctx
        if tb.prepass:
            self._depth_prog["u_view_proj"].write(view_proj_bytes)
            self._depth_prog["u_model"].write(_EYE4)
            fbo = ctx.fbo
            depth_mask = fbo.depth_mask  # off in the ghost pass; the pre-pass must write depth
            color_writes(fbo, False)
            fbo.depth_mask = True
            self._render(g, "depth", self._depth_prog, indexed, n_tri)
            color_writes(fbo, True)
            fbo.depth_mask = depth_mask
            ctx.depth_func = "<="
            calls += 1
        self._set_identity_model(prog)
        self._render(g, f"{name}:{id(prog)}", prog, indexed, n_tri)  # one VAO per program (and look)
        calls += 1
        if tb.prepass:
            ctx.depth_func = "<"
        lines = 0
        if tb.edges is not None and g.n_edges:
            self._edge_prog["u_view_proj"].write(view_proj_bytes)
            self._edge_prog["u_color"].value = tuple(float(x) for x in tb.edge_color)
            self._vao(g, "edges", self._edge_prog, g.ebo).render(moderngl.LINES, vertices=2 * g.n_edges)
            calls += 1
            lines = g.n_edges
        return calls, n_tri, lines

    def triangles(self, tb) -> int:
        """How many triangles the batch's buffers hold now."""
        g = self._batches[tb.key]
        return g.n_faces if tb.faces is not None else g.n_rows // 3

    def draw_depth(self, tb, view_proj_bytes: bytes) -> int:
        """Draw the batch's triangles into the depth buffer only (a pre-pass; the caller masks
        colour and sets the depth state); returns the draw calls made."""
        n_tri = self.triangles(tb)
        if n_tri == 0:
            return 0
        self._depth_prog["u_view_proj"].write(view_proj_bytes)
        self._depth_prog["u_model"].write(_EYE4)
        self._render(self._batches[tb.key], "depth", self._depth_prog, tb.faces is not None, n_tri)
        return 1

    def _render(self, g: _GpuBatch, name: str, prog, indexed: bool, n_tri: int) -> None:
        vao = self._vao(g, name, prog, g.ibo if indexed else None)
        vao.render(moderngl.TRIANGLES, vertices=3 * n_tri)

    def release(self) -> None:
        for g in self._batches.values():
            g.release()
        self._batches.clear()
        self._edge_prog.release()
        self._depth_prog.release()
