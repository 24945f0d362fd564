"""A mesh laid out for slicing: tets sorted into clusters, with what the kernels read per tet.

Built once per mesh and cached on it (``TetMesh4._cache``): the clustered order
(:func:`mesh_clusters`), the tets' object-space normals, the colours in that
order and, once a dense section needs it, the table of edges.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import njit
from .cases import TET_EDGE_PAIRS
from .mesh import TetMesh4, cross4

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


def layout_normals(mesh: TetMesh4, layout: Layout) -> np.ndarray:
    """Outward normals ``(m, 4) float32`` of the layout's tets in object space (cached).

    Not unit: the slicers turn them and make their xyz unit per section. Float32, as the
    normals they end as: a dense section reads one per cut tet, and half the bytes read
    is a few percent of its time."""
    key = ("layout_normals", id(layout))  # layouts live as long as the mesh (its cache)
    if key not in mesh._cache:
        p = layout.vertices.astype(np.float64)[layout.tets]
        n = cross4(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])
        mesh._cache[key] = np.ascontiguousarray(n, dtype=np.float32)
    return mesh._cache[key]


def layout_colors(mesh: TetMesh4, layout: Layout) -> np.ndarray:
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


def layout_edges(layout) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The edges of a layout's tets, each once.

    Returns
    -------
    tet_edges : (m, 6) uint32
        Edge number of each tet's edges, in :data:`TET_EDGE_PAIRS` order.
    edge_lo, edge_hi : (e,) uint32
        Each edge's vertices, lower index first (the end a section point is
        interpolated from, see :func:`~.section_kernels._points_by_tet`).
    """
    tets = layout.tets.astype(np.int64)
    a, b = tets[:, TET_EDGE_PAIRS[:, 0]], tets[:, TET_EDGE_PAIRS[:, 1]]
    n = max(len(layout.vertices), 1)
    key = np.minimum(a, b) * n + np.maximum(a, b)
    uniq, inverse = np.unique(key.ravel(), return_inverse=True)
    return (
        np.ascontiguousarray(inverse.reshape(-1, 6).astype(np.uint32)),
        (uniq // n).astype(np.uint32),
        (uniq % n).astype(np.uint32),
    )
