"""Making a loaded triangle soup a closed, outward-wound surface, with trimesh's repair.

The steps are trimesh's own: building the mesh with ``process=True`` welds
duplicate vertices (exporters split them along UV and normal seams, which
would otherwise look like holes); ``unique_faces`` and ``nondegenerate_faces``
then drop repeated and zero-area triangles; :func:`trimesh.repair.fill_holes` closes triangle and quad
holes (what exporters drop; bigger ones are modelling errors);
:func:`trimesh.repair.fix_normals` with ``multibody=True`` makes neighbours
agree on winding and turns every inside-out piece outward. trimesh uses
networkx for the graph work.

What trimesh leaves unsaid (a surface still open, non-orientable, or with
no volume) becomes an :class:`~.errors.AssetError` naming the file.
"""

from __future__ import annotations

import numpy as np

from .errors import AssetError


def repair_surface(vertices, faces, path="mesh") -> tuple[np.ndarray, np.ndarray]:
    """Weld, drop bad faces, fill small holes, fix winding and inversion.

    A surface that needs none of it comes back with the same vertices and
    faces, only reordered as described under Returns.

    Parameters
    ----------
    vertices : (n, 3) array_like float
    faces : (f, 3) array_like int
        Indices into ``vertices``.
    path : str or Path
        Only for messages.

    Returns
    -------
    vertices : (n', 3) float64
        Only the referenced ones, sorted by ``x``, then ``y``, then ``z``, so
        the result (and the tetrahedralization made from it) does not depend
        on the order a file lists its vertices.
    faces : (f', 3) int64
        Closed, consistently wound, counter-clockwise seen from outside.

    Raises
    ------
    AssetError
        When the surface is still not closed, is non-orientable or encloses no volume.
    """
    import trimesh  # local: only baking needs it

    v = np.asarray(vertices, np.float64).reshape(-1, 3)
    f = np.asarray(faces, np.int64).reshape(-1, 3)
    if len(f) and (f.min() < 0 or f.max() >= len(v)):
        raise AssetError(f"{path}: faces refer to vertices that do not exist")
    mesh = trimesh.Trimesh(v, f, process=True)
    # After welding, so faces that differed only by duplicated vertices are seen as one.
    mesh.update_faces(mesh.unique_faces() & mesh.nondegenerate_faces())
    if len(mesh.faces) == 0:
        raise AssetError(f"{path}: contains no triangles (all are degenerate)")
    trimesh.repair.fill_holes(mesh)
    open_edges, nonmanifold = edge_problems(mesh.faces)
    if open_edges or nonmanifold:
        what = ", ".join(
            x
            for x in (
                f"{open_edges} open edges" if open_edges else "",
                f"{nonmanifold} edges shared by more than two triangles" if nonmanifold else "",
            )
            if x
        )
        raise AssetError(f"{path}: surface is not watertight after repair ({what}); close it in the modelling tool")
    trimesh.repair.fix_normals(mesh, multibody=True)
    if not mesh.is_winding_consistent:
        raise AssetError(f"{path}: surface is non-orientable (like a Moebius strip); it has no inside")
    if not mesh.volume > 0:
        raise AssetError(f"{path}: surface encloses no volume")
    mesh.remove_unreferenced_vertices()
    return sorted_by_position(np.asarray(mesh.vertices, np.float64), np.asarray(mesh.faces, np.int64))


def edge_problems(faces: np.ndarray) -> tuple[int, int]:
    """Counts of undirected edges used by one face (open) and by more than two (non-manifold).

    Parameters
    ----------
    faces : (f, 3) int
    """
    edges = np.sort(np.asarray(faces)[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts == 1).sum()), int((counts > 2).sum())


def sorted_by_position(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Renumber vertices in lexicographic ``(x, y, z)`` order.

    fTetWild's output depends on the order of its input vertices; a canonical
    order makes a bake a function of the surface alone. It is also the order
    bakes made before trimesh did the repair had, so their results still hold.
    """
    order = np.lexsort(vertices.T[::-1])
    rank = np.empty(len(order), np.int64)
    rank[order] = np.arange(len(order))
    return vertices[order], rank[faces]
