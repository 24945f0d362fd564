"""Lift tetrahedralized 3D solids into closed 4D solids (paper section 4.2).

A 3D solid ``S`` (tetrahedra) becomes the 4D solid swept by scaled copies of it
along ``w``::

    { (c + s(w) (p - c), w) : p in S, w_0 <= w <= w_{K-1} }

where ``c`` is the scaling centre and ``s`` is piecewise linear between the
layers ``w_k``. A constant ``s = 1`` gives a straight prism (the paper's "cube
into tesseract"); a profile that shrinks towards the ends gives the "hyper-depth"
of Fig. overlay: a viewer moving along ``w`` sees the object shrink and vanish
instead of popping out of existence.

Boundary of the 4D solid
------------------------
* **Caps**: the 3D tets at the first and last layer, facing ``-w`` and ``+w``.
* **Walls**: every boundary triangle of the 3D solid times every layer interval
  ``[w_k, w_{k+1}]``. The copies are homothetic about ``c``, so the three edges
  of such a cell meet in one point: the cell is a flat frustum (a straight prism
  when the scales are equal), split into three tets.
* **Tips**: a scale of exactly 0 is allowed at the first and/or last layer. That
  cap collapses to the point ``(c, w)``, and the last interval's walls become
  cones, one tet per boundary triangle. This is how a profile vanishes cleanly:
  a small positive end scale instead leaves end caps of tets ``scale**3`` times
  the size of the originals, which :meth:`TetMesh4.validate` rejects as
  degenerate once that is below ``1e-9`` of the mesh extent cubed.

Each prism ``a b c`` (bottom layer ``L``) to ``a' b' c'`` (top layer ``U``) is
split by the *minimum global index* rule: every quad side is cut by the diagonal
from its lowest-numbered vertex. Vertices are numbered layer by layer and, within
a layer, in the 3D solid's vertex order, so sorting the triangle as ``a < b < c``
gives the tets ``(aL bL cL cU) (aL bL bU cU) (aL aU bU cU)`` and the two prisms
sharing a quad always pick the same diagonal.

Orientation is computed from geometry, not from index bookkeeping: each tet's
``cross4`` normal is compared with the direction that must be outward (``-w`` /
``+w`` for the caps, the 3D triangle's outward normal for the walls, which is
exact because every section of the lifted solid is a scaled copy of ``S``) and
the tet is flipped where they disagree.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .mesh import TET_FACES, TetMesh4, cross4

PROFILES = ("prism", "round", "taper")


# --------------------------------------------------------------------- 3D solids
def box_solid(center, size) -> tuple[np.ndarray, np.ndarray]:
    """An axis-aligned box as six positively oriented tets (Kuhn split).

    Parameters
    ----------
    center : (3,) array_like
    size : float or (3,) array_like
        Full edge lengths, all > 0.

    Returns
    -------
    vertices : (8, 3) float64
        Corner ``i`` has offset ``+size/2`` on axis ``j`` where bit ``j`` of ``i`` is set.
    tets : (6, 4) int64
        Every tet runs along the main diagonal from corner 0 to corner 7, so
        any two boxes sharing a face split it the same way.
    """
    center = np.asarray(center, dtype=np.float64).reshape(3)
    size = np.broadcast_to(np.asarray(size, dtype=np.float64), (3,))
    if not (size > 0).all():
        raise ValueError(f"box_solid: size must be > 0 on every axis, got {size.tolist()}")
    bits = (np.arange(8)[:, None] >> np.arange(3)) & 1
    vertices = center + (bits - 0.5) * size
    tets = []
    # Kuhn: one monotone lattice path 0 -> 7 per axis permutation.
    for p in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
        a = 0
        b = a | 1 << p[0]
        c = b | 1 << p[1]
        tets.append((a, b, c, 7))
    return vertices, orient_tets3(vertices, np.array(tets, dtype=np.int64))


def tet_volumes3(vertices3, tets3) -> np.ndarray:
    """Signed volumes of 3D tets, ``(m,) float64`` (positive: ``d`` above face ``a b c``)."""
    p = np.asarray(vertices3, dtype=np.float64)[np.asarray(tets3)]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def orient_tets3(vertices3, tets3) -> np.ndarray:
    """The tets with negative volume reversed, ``(m, 4) int64``.

    Raises
    ------
    ValueError
        If a tet has (numerically) zero volume: it has no orientation to fix.
    """
    tets3 = np.array(tets3, dtype=np.int64).reshape(-1, 4)
    vol = tet_volumes3(vertices3, tets3)
    extent = float(np.ptp(np.asarray(vertices3, dtype=np.float64)[tets3.ravel()], axis=0).max()) if len(tets3) else 0.0
    flat = np.abs(vol) <= 1e-15 * max(extent, 1e-300) ** 3
    if flat.any():
        bad = np.flatnonzero(flat)
        raise ValueError(f"{len(bad)} tets have zero volume, e.g. {bad[:5].tolist()}")
    neg = vol < 0
    tets3[neg] = tets3[neg][:, [0, 2, 1, 3]]
    return tets3


def boundary_faces3(tets3) -> np.ndarray:
    """Faces used by exactly one tet, wound counter-clockwise seen from outside.

    Parameters
    ----------
    tets3 : (m, 4) int
        Positively oriented (see :func:`orient_tets3`).

    Returns
    -------
    (f, 3) int64

    Raises
    ------
    ValueError
        If a face is used by more than two tets (not a tetrahedralization).
    """
    tets3 = np.asarray(tets3, dtype=np.int64)
    # The same induced-face table as 4D works in 3D: for a positive tet the
    # face (b, c, d) etc. has its right-hand normal pointing away from the tet.
    faces = tets3[:, TET_FACES].reshape(-1, 3)
    _, first, counts = np.unique(np.sort(faces, axis=1), axis=0, return_index=True, return_counts=True)
    if (counts > 2).any():
        raise ValueError(f"{int((counts > 2).sum())} triangles are shared by more than two tets")
    return faces[first[counts == 1]]


def _check_surface_manifold(faces: np.ndarray) -> None:
    """Each boundary edge must bound exactly two triangles.

    A surface edge with four triangles (two solids touching along an edge, which
    tetrahedralizers can produce) would make its wall triangles shared by four
    4D tets, and the lifted mesh would not be a manifold.
    """
    edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    if (counts != 2).any():
        raise ValueError(
            f"the solid's boundary has {int((counts != 2).sum())} non-manifold edges "
            f"(used by {sorted(set(counts[counts != 2].tolist()))} triangles instead of 2)"
        )


# ----------------------------------------------------------------------- lifting
def extrude(vertices3, tets3, layers_w, layer_scales=None, center=None, colors=None, name: str = "") -> TetMesh4:
    """Sweep a tetrahedralized 3D solid along ``w`` into a closed 4D solid.

    Parameters
    ----------
    vertices3 : (n, 3) array_like float
    tets3 : (m, 4) array_like int
        Any orientation; zero-volume tets are an error.
    layers_w : (K,) array_like float
        Strictly increasing ``w`` of the copies, ``K >= 2``.
    layer_scales : (K,) array_like float, optional
        Scale of each copy about ``center``; default all 1 (a straight prism).
        Must be > 0, except that the first and/or last may be exactly 0 (a tip,
        see the module docstring).
    center : (3,) array_like float, optional
        Scaling centre; default the centre of the solid's bounding box. Pass the
        point where it rests on the floor to keep a shrinking object grounded.
    colors : (n, 3) or (n, 4) or (3,) or (4,) array_like float, optional
        Per 3D vertex (copied to every layer) or one colour for all.
    name : str

    Returns
    -------
    TetMesh4
        Closed and positively oriented. Vertices unused by ``tets3`` are dropped;
        the middle layers carry only the solid's surface vertices.
    """
    v3 = np.asarray(vertices3, dtype=np.float64).reshape(-1, 3)
    t3 = orient_tets3(v3, tets3)
    if len(t3) == 0:
        raise ValueError("extrude: the 3D solid has no tets")
    w, s = _check_layers(layers_w, layer_scales)
    used = np.unique(t3)
    c = (
        0.5 * (v3[used].min(axis=0) + v3[used].max(axis=0))
        if center is None
        else np.asarray(center, np.float64).reshape(3)
    )
    surf = boundary_faces3(t3)
    _check_surface_manifold(surf)
    tips = (s[0] == 0.0, s[-1] == 0.0)

    layer_sets = [_layer_vertices(k, len(w), tips, used, np.unique(surf)) for k in range(len(w))]
    index = _layer_index(layer_sets, len(v3))
    verts4, source = _layer_positions(v3, layer_sets, w, s, c)
    caps, caps_out = _cap_tets(t3, index, tips)
    walls, walls_out = _all_wall_tets(v3, surf, index, tips)
    tets4 = _orient_outward(verts4, np.concatenate([caps, walls]), np.concatenate([caps_out, walls_out]))
    return TetMesh4(verts4, tets4, _lift_colors(colors, source, len(v3)), name)


def _check_layers(layers_w, layer_scales) -> tuple[np.ndarray, np.ndarray]:
    w = np.asarray(layers_w, dtype=np.float64).reshape(-1)
    if len(w) < 2 or not (np.diff(w) > 0).all() or not np.isfinite(w).all():
        raise ValueError(f"extrude: layers_w must be >= 2 finite, strictly increasing values, got {w.tolist()}")
    s = np.ones_like(w) if layer_scales is None else np.asarray(layer_scales, dtype=np.float64).reshape(-1)
    if s.shape != w.shape:
        raise ValueError(f"extrude: {len(s)} layer_scales for {len(w)} layers")
    if not np.isfinite(s).all() or (s < 0).any() or (s[1:-1] <= 0).any():
        raise ValueError(
            f"extrude: layer scales must be > 0 (0 allowed only at the first/last layer), got {s.tolist()}"
        )
    if len(w) == 2 and (s == 0).all():
        raise ValueError("extrude: both ends are tips (scale 0) with no layer between them")
    return w, s


def _layer_vertices(k: int, n_layers: int, tips, used: np.ndarray, surface: np.ndarray) -> np.ndarray | None:
    """3D vertex ids present in layer ``k`` (sorted), or None for a tip."""
    end = 0 if k == 0 else (1 if k == n_layers - 1 else None)
    if end is None:
        return surface
    return None if tips[end] else used


def _layer_index(layer_sets, n3: int) -> list[np.ndarray]:
    """Per layer, a map ``(n3,) int64`` from 3D vertex id to 4D vertex id.

    A tip maps every id to its apex. Numbering layer after layer, each in 3D-id
    order, is what makes the min-global-index diagonal rule agree with sorting
    triangles by 3D id.
    """
    index, start = [], 0
    for ids in layer_sets:
        m = np.full(n3, -1, dtype=np.int64)
        if ids is None:
            m[:] = start
            start += 1
        else:
            m[ids] = start + np.arange(len(ids))
            start += len(ids)
        index.append(m)
    return index


def _layer_positions(v3, layer_sets, w, s, c) -> tuple[np.ndarray, np.ndarray]:
    """4D positions ``(N, 4) float64`` and their 3D source ids ``(N,) int64`` (-1: apex)."""
    blocks, sources = [], []
    for ids, wk, sk in zip(layer_sets, w, s):
        if ids is None:
            blocks.append(np.r_[c, wk][None])
            sources.append(np.array([-1]))
        else:
            blocks.append(np.c_[c + sk * (v3[ids] - c), np.full(len(ids), wk)])
            sources.append(ids)
    return np.concatenate(blocks), np.concatenate(sources)


def _cap_tets(t3, index, tips) -> tuple[np.ndarray, np.ndarray]:
    """The 3D tets at the first and last layer (unless a tip), with outward ``-w`` / ``+w``."""
    tets, out = [np.zeros((0, 4), np.int64)], [np.zeros((0, 4))]
    for end, k, w_dir in ((0, 0, -1.0), (1, len(index) - 1, 1.0)):
        if not tips[end]:
            tets.append(index[k][t3])
            out.append(np.broadcast_to([0.0, 0.0, 0.0, w_dir], (len(t3), 4)))
    return np.concatenate(tets), np.concatenate(out)


def _all_wall_tets(v3, surf, index, tips) -> tuple[np.ndarray, np.ndarray]:
    """Wall tets of every layer interval, with the outward direction each must face."""
    n3 = _face_normals(v3, surf)
    n4 = np.c_[n3, np.zeros(len(n3))]
    srt = np.sort(surf, axis=1)
    tets, out = [], []
    for k in range(len(index) - 1):
        walls, per_face = _wall_tets(srt, index[k], index[k + 1], tips, k, len(index))
        tets.append(walls)
        out.append(np.repeat(n4, per_face, axis=0))
    return np.concatenate(tets), np.concatenate(out)


def _wall_tets(tri_sorted, lo_index, hi_index, tips, k, n_layers) -> tuple[np.ndarray, int]:
    """Tets of the cells over boundary triangles between layers ``k`` and ``k+1``.

    Returns the tets ``(f * per_face, 4)`` grouped by triangle, and ``per_face``.
    """
    a, b, c = tri_sorted.T
    aL, bL, cL = lo_index[a], lo_index[b], lo_index[c]
    aU, bU, cU = hi_index[a], hi_index[b], hi_index[c]
    if k == 0 and tips[0]:  # cone from the apex (all of aL, bL, cL are it)
        return np.stack([aL, aU, bU, cU], axis=1), 1
    if k == n_layers - 2 and tips[1]:
        return np.stack([aL, bL, cL, aU], axis=1), 1
    tets = np.stack(
        [
            np.stack([aL, bL, cL, cU], axis=1),
            np.stack([aL, bL, bU, cU], axis=1),
            np.stack([aL, aU, bU, cU], axis=1),
        ],
        axis=1,
    )
    return tets.reshape(-1, 4), 3


def _face_normals(v3, faces) -> np.ndarray:
    p = v3[faces]
    return np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])


def _orient_outward(verts4, tets4, outward) -> np.ndarray:
    """Swap two vertices of every tet whose normal points against ``outward``."""
    p = verts4[tets4]
    n = cross4(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])
    flip = np.einsum("ij,ij->i", n, outward) < 0
    tets4 = tets4.copy()
    tets4[flip] = tets4[flip][:, [0, 2, 1, 3]]
    return tets4


def _lift_colors(colors, source: np.ndarray, n3: int) -> np.ndarray | None:
    if colors is None:
        return None
    c = np.asarray(colors, dtype=np.float32)
    if c.ndim == 1:
        return c  # TetMesh4 broadcasts one colour
    if c.shape[0] != n3:
        raise ValueError(f"extrude: {c.shape[0]} colours for {n3} vertices")
    apex = c.mean(axis=0)  # a tip has no single source vertex
    return np.where((source >= 0)[:, None], c[np.maximum(source, 0)], apex)


# ---------------------------------------------------------------------- profiles
def profile_scales(layers_w, w_center: float, half_depth: float, profile: str, floor: float = 0.0) -> np.ndarray:
    """Scale of each layer for a named hyper-depth profile.

    Parameters
    ----------
    layers_w : (K,) array_like float
    w_center : float
    half_depth : float
        > 0; the profile reaches its end at ``w_center +- half_depth``.
    profile : {"prism", "round", "taper"}
        ``prism``: all 1. ``round``: elliptic, ``sqrt(1 - x**2)`` with
        ``x = (w - w_center) / half_depth``. ``taper``: ``1 - |x|``.
    floor : float
        Lower bound for ``round`` and ``taper`` (>= 0). The default 0 puts tips at
        the ends so the object vanishes exactly there (see the module docstring
        for why a small positive floor makes meshes that fail validation). A
        layer beyond the ends gets ``floor``, which with ``floor = 0`` is only
        allowed as the first or last layer.

    Returns
    -------
    (K,) float64
    """
    w = np.asarray(layers_w, dtype=np.float64)
    if half_depth <= 0:
        raise ValueError(f"profile_scales: half_depth must be > 0, got {half_depth}")
    if floor < 0:
        raise ValueError(f"profile_scales: floor must be >= 0, got {floor}")
    x = np.clip(np.abs(w - w_center) / half_depth, 0.0, 1.0)
    if profile == "prism":
        return np.ones_like(w)
    if profile == "round":
        s = np.sqrt(1.0 - x * x)
    elif profile == "taper":
        s = 1.0 - x
    else:
        raise ValueError(f"unknown profile {profile!r}; expected one of {', '.join(PROFILES)}")
    return np.maximum(s, floor)


def profile_layers(w_center: float, depth: float, profile: str, layers: int = 9) -> np.ndarray:
    """Layer positions ``(K,) float64`` spanning ``w_center +- depth / 2``.

    A prism needs only its two ends; ``round`` gets its layers denser towards
    the ends (uniform in angle), where the ellipse bends fastest.
    """
    if depth <= 0:
        raise ValueError(f"depth must be > 0, got {depth}")
    if profile == "prism":
        return np.array([w_center - depth / 2, w_center + depth / 2])
    if layers < 3:
        raise ValueError(f"a {profile!r} profile needs layers >= 3, got {layers}")
    if profile == "round":
        # sin of uniform angles: exact 0 in the middle and exact +-1 at the ends.
        return w_center + depth / 2 * np.sin(np.linspace(-np.pi / 2, np.pi / 2, layers))
    return np.linspace(w_center - depth / 2, w_center + depth / 2, layers)


@dataclass(frozen=True)
class HyperDepth:
    """How far a 3D solid extends along ``w`` and how its section changes on the way.

    Attributes
    ----------
    w_center : float
    depth : float
        Full extent along ``w`` (> 0): the solid exists for ``|w - w_center| < depth / 2``.
    profile : {"prism", "round", "taper"}
    layers : int
        Number of copies for ``round``/``taper`` (a prism always uses 2).
    floor : float
        As in :func:`profile_scales`.
    """

    w_center: float = 0.0
    depth: float = 1.0
    profile: str = "round"
    layers: int = 9
    floor: float = 0.0


def extend_solid(vertices3, tets3, extent: HyperDepth, colors=None, center=None, name: str = "") -> TetMesh4:
    """Give a 3D solid a hyper-depth: :func:`profile_layers` + :func:`profile_scales` + :func:`extrude`.

    Parameters
    ----------
    vertices3 : (n, 3) array_like float
    tets3 : (m, 4) array_like int
    extent : HyperDepth
    colors, center, name
        As in :func:`extrude`.

    Returns
    -------
    TetMesh4
    """
    e = extent
    w = profile_layers(e.w_center, e.depth, e.profile, e.layers)
    s = profile_scales(w, e.w_center, e.depth / 2, e.profile, e.floor)
    return extrude(vertices3, tets3, w, s, center=center, colors=colors, name=name)
