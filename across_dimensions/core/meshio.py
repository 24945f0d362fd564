"""Writing projected 3D meshes to common file formats, welded and indexed.

Projections produce triangle soups: every triangle has its own three corners,
and flat regions are cut into many small triangles (a cube sliced from a
tesseract is 48 triangles over 26 points). A file made of that is a mesh that
Blender or trimesh sees as open. Before writing, :func:`indexed_mesh`

1. welds corners that share both position and colour (a point is split only
   where its colours differ), and
2. removes the points that only subdivide a flat region or a straight crease,
   by collapsing each into a neighbour when that changes neither the surface
   nor (beyond :data:`COLOR_TOL`) the colours, so the tesseract's section is written as 8
   points and 12 triangles.

OBJ, PLY and GLB (binary glTF 2.0) are written here with numpy alone, without
normals (every viewer derives them from the welded faces). Every writer goes
through :func:`~.fileio.atomic_writer`: the file is whole or absent.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .errors import InputError
from .fileio import FileProblem, atomic_writer

FORMATS = (".obj", ".ply", ".glb")
#: Largest colour change (per channel, linear 0..1) a removed point may cause.
#: The shapes' default colours blend bilinearly in y and w, which the slicer's
#: triangles follow only piecewise (a tesseract's section face is off a plain
#: linear blend by up to 0.019); 1/32 keeps each face's gradient within 8/255
#: while writing a flat face as the fewest triangles.
COLOR_TOL = 1.0 / 32.0


def save_trimesh3(mesh, path) -> tuple[int, int]:
    """Write a :class:`~across_dimensions.core.mesh.TriMesh3` by file extension, welded (:func:`indexed_mesh`).

    Returns
    -------
    (int, int)
        The vertices and triangles written.

    Raises
    ------
    InputError
        For an extension other than ``.obj``, ``.ply`` or ``.glb``.
    FileProblem
        The folder is missing or the file cannot be written.
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in FORMATS:
        raise InputError(f"{path}: unknown mesh format {ext or '(none)'!r}; expected one of {', '.join(FORMATS)}")
    if not (np.isfinite(mesh.vertices).all() and np.isfinite(mesh.colors).all()):
        raise InputError(
            f"{path}: the projected mesh has points at infinity or NaN; nothing was written "
            f"(a camera too close, or a field of view too narrow?)"
        )
    vertices, faces, colors = indexed_mesh(mesh)
    try:
        if ext == ".glb":
            data = _glb_bytes(vertices, faces, colors)  # before opening: a failure leaves nothing
            with atomic_writer(path, "wb") as f:
                f.write(data)
        else:
            with atomic_writer(path, "w", encoding="ascii") as f:
                (_write_obj if ext == ".obj" else _write_ply)(f, vertices, faces, colors)
    except OSError as e:
        raise FileProblem(f"{path}: cannot write it ({e.strerror or e})") from None
    return len(vertices), len(faces)


# ------------------------------------------------------------------ welding
def indexed_mesh(mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A projection's triangles as a welded, indexed mesh with per-vertex colours.

    Parameters
    ----------
    mesh : TriMesh3

    Returns
    -------
    vertices : (k, 3) float32
    faces : (f, 3) int64
        Same winding as the input; collapsed triangles dropped.
    colors : (k, 4) float32
    """
    if mesh.is_empty:
        return np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int64), np.zeros((0, 4), np.float32)
    pos = np.ascontiguousarray(mesh.vertices, dtype=np.float32) + np.float32(0.0)  # folds -0.0 into 0.0
    col = np.ascontiguousarray(mesh.colors, dtype=np.float32)
    # The slicer computes a shared edge's point and colour identically in every
    # tet, so exact (bitwise) equality is the right test.
    key = np.ascontiguousarray(np.hstack([pos.view(np.uint32), col.view(np.uint32)]))
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    faces = inverse.reshape(-1)[np.asarray(mesh.faces, dtype=np.int64)]
    faces = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])]
    vertices, colors = pos[first], col[first]
    faces = _collapse_flat(vertices.astype(np.float64), colors.astype(np.float64), faces)
    used = np.unique(faces)
    renumber = np.full(len(vertices), -1, np.int64)
    renumber[used] = np.arange(len(used))
    return vertices[used], renumber[faces], colors[used]


def _collapse_flat(v: np.ndarray, c: np.ndarray, faces: np.ndarray, max_passes: int = 8) -> np.ndarray:
    """Collapse points that only subdivide flat regions or straight creases.

    A point ``p`` is collapsed into a neighbour ``q`` when all triangles around
    it lie in one plane (any ``q``), or in two planes meeting along a straight
    line through ``p`` (``q`` one of its two neighbours on that line). The
    collapse is kept only if the mesh is closed around ``p``, the link
    condition holds (no duplicate triangles), no triangle flips or becomes
    degenerate, and the colour interpolated at ``p`` afterwards is within
    :data:`COLOR_TOL` of its own. So the surface is unchanged and only its
    triangulation is coarser.

    Parameters
    ----------
    v : (k, 3) float64
    c : (k, 4) float64
    faces : (f, 3) int64

    Returns
    -------
    (f', 3) int64
    """
    faces = faces.copy()
    if not len(faces):
        return faces
    p = v[faces]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    length = np.linalg.norm(n, axis=1)
    scale = max(float(np.abs(v).max()), 1e-30)
    normal = n / np.maximum(length, 1e-300)[:, None]
    # Only points whose triangles take at most two normal directions are candidates (vectorised prefilter).
    corner_vertex = faces.ravel()
    corner_normal = np.round(np.repeat(normal, 3, axis=0), 5)
    pairs = np.unique(np.hstack([corner_vertex[:, None].astype(np.float64), corner_normal]), axis=0)
    distinct = np.bincount(pairs[:, 0].astype(np.int64), minlength=len(v))
    candidates = np.flatnonzero((distinct >= 1) & (distinct <= 2))
    if not len(candidates):
        return faces
    alive = np.ones(len(faces), bool)
    around: dict[int, set] = {}
    for fi, row in enumerate(faces):
        for x in row:
            around.setdefault(int(x), set()).add(fi)
    tiny = (1e-7 * scale) ** 2  # twice the smallest triangle area we keep
    surface = _Surface(v, c, faces, normal, around, alive, tiny)
    for _ in range(max_passes):
        changed = False
        for x in candidates.tolist():
            fs = [f for f in around.get(x, ()) if alive[f]]
            if len(fs) < 3:
                continue
            targets = _collapse_targets(x, fs, faces, v, normal)
            for q in targets:
                if _try_collapse(surface, x, q, fs):
                    changed = True
                    break
        if not changed:
            break
    return faces[alive]


class _Surface(NamedTuple):
    """The triangles :func:`_collapse_flat` works on, changed in place by :func:`_try_collapse`."""

    v: np.ndarray  # (k, 3) float64 positions
    c: np.ndarray  # (k, 4) float64 colours
    faces: np.ndarray  # (f, 3) int64
    normal: np.ndarray  # (f, 3) float64, unit
    around: dict  # vertex -> the faces that used it
    alive: np.ndarray  # (f,) bool
    tiny: float  # twice the smallest triangle area kept


def _collapse_targets(x: int, fs: list, faces: np.ndarray, v: np.ndarray, normal: np.ndarray) -> list:
    """Neighbours ``x`` may collapse into: any (flat) or its two crease neighbours."""
    edges: dict[int, list] = {}
    for f in fs:
        row = faces[f].tolist()
        k = row.index(x)
        for y in (row[(k + 1) % 3], row[(k + 2) % 3]):
            edges.setdefault(y, []).append(f)
    if any(len(e) != 2 for e in edges.values()):
        return []  # open or non-manifold around x: leave it
    planes: list[np.ndarray] = []
    for f in fs:
        if not any(float(normal[f] @ pl) > 1 - 1e-9 for pl in planes):
            planes.append(normal[f])
            if len(planes) > 2:
                return []
    if len(planes) == 1:
        return list(edges)
    crease = [y for y, (f1, f2) in edges.items() if float(normal[f1] @ normal[f2]) < 1 - 1e-9]
    if len(crease) != 2:
        return []
    a, b = v[crease[0]] - v[x], v[crease[1]] - v[x]
    if np.linalg.norm(np.cross(a, b)) > 1e-9 * np.linalg.norm(a) * np.linalg.norm(b) or float(a @ b) >= 0:
        return []  # the crease bends at x: x is a corner
    return crease


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of ``(k, 3)`` arrays (np.cross is slow on many tiny calls)."""
    return np.stack(
        [
            a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
            a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
            a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
        ],
        axis=1,
    )


def _try_collapse(s: _Surface, x: int, q: int, fs: list) -> bool:
    """Collapse ``x`` into ``q`` if it keeps the surface and colours; report whether it did."""
    faces, normal, around, alive = s.faces, s.normal, s.around, s.alive
    ring_x = set(faces[fs].ravel().tolist()) - {x}
    ring_q = set(faces[[f for f in around[q] if alive[f]]].ravel().tolist()) - {q}
    if len(ring_x & ring_q) != 2:  # link condition: otherwise triangles would duplicate or fold
        return False
    rows = faces[fs]
    has_q = (rows == q).any(axis=1)
    kept = [f for f, h in zip(fs, has_q) if not h]
    removed = [f for f, h in zip(fs, has_q) if h]
    new = np.where(rows[~has_q] == x, q, rows[~has_q])
    p = s.v[new]
    n = _cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    nn = (n * n).sum(axis=1)
    if (nn <= s.tiny).any() or ((n * normal[kept]).sum(axis=1) <= 0).any():
        return False  # a triangle would vanish or flip
    n /= np.sqrt(nn)[:, None]
    if not _colour_kept(x, new, n, s.v, s.c):
        return False
    alive[removed] = False
    faces[kept] = new
    normal[kept] = n
    around[q].update(kept)
    around[x] = set()
    return True


def _colour_kept(x: int, rows: np.ndarray, n: np.ndarray, v: np.ndarray, c: np.ndarray) -> bool:
    """Whether the triangles ``rows`` interpolate ``x``'s colour at its position within :data:`COLOR_TOL`."""
    px = v[x]
    a, b, d = v[rows[:, 0]], v[rows[:, 1]], v[rows[:, 2]]
    # Barycentric coordinates of px in each triangle, by signed areas along its normal.
    area = (_cross(b - a, d - a) * n).sum(axis=1)
    w = (
        np.stack(
            [
                (_cross(d - b, px - b) * n).sum(axis=1),
                (_cross(a - d, px - d) * n).sum(axis=1),
                (_cross(b - a, px - a) * n).sum(axis=1),
            ],
            axis=1,
        )
        / area[:, None]
    )
    on_plane = np.abs(((px - a) * n).sum(axis=1)) <= 1e-6 * max(float(np.abs(v).max()), 1e-30)
    inside = np.flatnonzero((w >= -1e-7).all(axis=1) & on_plane)
    if not len(inside):
        return False
    k = inside[0]
    return bool((np.abs(w[k] @ c[rows[k]] - c[x]) <= COLOR_TOL).all())


# ------------------------------------------------------------------ writers
def _write_obj(f, vertices: np.ndarray, faces: np.ndarray, colors: np.ndarray) -> None:
    f.write("# written by across-dimensions: welded mesh, vertex colours as 'v x y z r g b'\n")
    if len(vertices):
        # Colours as the widely read "v x y z r g b" extension.
        np.savetxt(f, np.hstack([vertices.astype(np.float64), colors[:, :3]]), fmt="v %.7g %.7g %.7g %.4f %.4f %.4f")
    if len(faces):
        np.savetxt(f, faces + 1, fmt="f %d %d %d")


def _write_ply(f, vertices: np.ndarray, faces: np.ndarray, colors: np.ndarray) -> None:
    n, m = len(vertices), len(faces)
    f.write("ply\nformat ascii 1.0\ncomment written by across-dimensions\n")
    f.write(f"element vertex {n}\nproperty float x\nproperty float y\nproperty float z\n")
    f.write("property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n")
    f.write(f"element face {m}\nproperty list uchar uint vertex_indices\nend_header\n")
    if n:
        rgba = np.clip(colors * 255 + 0.5, 0, 255).astype(np.int64)
        np.savetxt(f, np.hstack([vertices.astype(np.float64), rgba]), fmt="%.7g %.7g %.7g %d %d %d %d")
    if m:
        np.savetxt(f, np.hstack([np.full((m, 1), 3), faces]), fmt="%d %d %d %d")


# glTF 2.0 constants: component types and buffer-view targets.
_FLOAT, _UNSIGNED_BYTE, _UNSIGNED_INT = 5126, 5121, 5125
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963


def _glb_bytes(vertices: np.ndarray, faces: np.ndarray, colors: np.ndarray) -> bytes:
    """A binary glTF 2.0 file: one indexed triangle mesh with per-vertex RGBA colours.

    Written here with numpy (positions float32, colours normalised uint8, indices
    uint32, each in its own 4-byte aligned buffer view) so the core needs no mesh
    library; an empty mesh gives a valid file holding one empty scene.
    """
    doc: dict = {"asset": {"version": "2.0", "generator": "across-dimensions"}, "scene": 0}
    binary = b""
    if len(faces):
        pos = np.ascontiguousarray(vertices, np.float32)
        rgba = np.clip(colors * 255 + 0.5, 0, 255).astype(np.uint8)
        idx = np.ascontiguousarray(faces, np.uint32).ravel()
        views, chunks, offset = [], [], 0
        for data, target in ((pos, _ARRAY_BUFFER), (rgba, _ARRAY_BUFFER), (idx, _ELEMENT_ARRAY_BUFFER)):
            raw = data.tobytes()
            views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(raw), "target": target})
            raw += b"\0" * (-len(raw) % 4)
            chunks.append(raw)
            offset += len(raw)
        binary = b"".join(chunks)
        doc |= {
            "buffers": [{"byteLength": len(binary)}],
            "bufferViews": views,
            "accessors": [
                {"bufferView": 0, "componentType": _FLOAT, "count": len(pos), "type": "VEC3",
                 "min": pos.min(axis=0).tolist(), "max": pos.max(axis=0).tolist()},
                {"bufferView": 1, "componentType": _UNSIGNED_BYTE, "normalized": True, "count": len(rgba),
                 "type": "VEC4"},
                {"bufferView": 2, "componentType": _UNSIGNED_INT, "count": len(idx), "type": "SCALAR"},
            ],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "indices": 2, "mode": 4}]}],
            "nodes": [{"mesh": 0}],
            "scenes": [{"nodes": [0]}],
        }  # fmt: skip
    else:
        doc["scenes"] = [{"nodes": []}]
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)  # chunks are 4-byte aligned, JSON padded with spaces
    out = struct.pack("<I4s", len(text), b"JSON") + text
    if binary:
        out += struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(out)) + out
