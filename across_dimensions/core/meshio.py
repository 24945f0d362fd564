"""Writing projected 3D meshes to common file formats.

OBJ and PLY are written here with numpy alone; GLB goes through trimesh,
imported only when asked for (the core's one deliberate optional import).
Every writer goes to a temporary file renamed into place, so a failure never
leaves half a file.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

FORMATS = (".obj", ".ply", ".glb")


def save_trimesh3(mesh, path) -> None:
    """Write a :class:`~across_dimensions.core.mesh.TriMesh3` by file extension.

    Raises
    ------
    ValueError
        For an extension other than ``.obj``, ``.ply`` or ``.glb``.
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in FORMATS:
        raise ValueError(f"{path}: unknown mesh format {ext or '(none)'!r}; expected one of {', '.join(FORMATS)}")
    if not path.parent.is_dir():
        raise FileNotFoundError(f"{path}: the folder {path.parent} does not exist")
    tmp = path.with_name(path.name + ".tmp")
    try:
        if ext == ".obj":
            _write_obj(mesh, tmp)
        elif ext == ".ply":
            _write_ply(mesh, tmp)
        else:
            _write_glb(mesh, tmp)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def _write_obj(mesh, path: Path) -> None:
    with open(path, "w", encoding="ascii") as f:
        f.write("# written by across-dimensions\n")
        # Vertex colours as the widely read "v x y z r g b" extension.
        rows = np.hstack([mesh.vertices, mesh.colors[:, :3]]) if len(mesh.vertices) else np.zeros((0, 6))
        np.savetxt(f, rows, fmt="v %.6g %.6g %.6g %.4f %.4f %.4f")
        np.savetxt(f, mesh.normals, fmt="vn %.5f %.5f %.5f")
        idx = mesh.faces.astype(np.int64) + 1
        np.savetxt(f, np.repeat(idx, 2, axis=1), fmt="f %d//%d %d//%d %d//%d")


def _write_ply(mesh, path: Path) -> None:
    n, m = len(mesh.vertices), len(mesh.faces)
    with open(path, "w", encoding="ascii") as f:
        f.write("ply\nformat ascii 1.0\ncomment written by across-dimensions\n")
        f.write(f"element vertex {n}\nproperty float x\nproperty float y\nproperty float z\n")
        f.write("property float nx\nproperty float ny\nproperty float nz\n")
        f.write("property uchar red\nproperty uchar green\nproperty uchar blue\n")
        f.write(f"element face {m}\nproperty list uchar uint vertex_indices\nend_header\n")
        rgb = np.clip(mesh.colors[:, :3] * 255 + 0.5, 0, 255).astype(np.int64)
        if n:
            rows = np.hstack([mesh.vertices.astype(np.float64), mesh.normals.astype(np.float64), rgb])
            np.savetxt(f, rows, fmt="%.6g %.6g %.6g %.5f %.5f %.5f %d %d %d")
        if m:
            np.savetxt(f, np.hstack([np.full((m, 1), 3), mesh.faces.astype(np.int64)]), fmt="%d %d %d %d")


def _write_glb(mesh, path: Path) -> None:
    import trimesh  # optional: only GLB export needs it

    t = trimesh.Trimesh(vertices=mesh.vertices, faces=mesh.faces, vertex_normals=mesh.normals,
                        vertex_colors=np.clip(mesh.colors * 255, 0, 255).astype(np.uint8), process=False)
    data = t.export(file_type="glb")
    with open(path, "wb") as f:
        f.write(data)
