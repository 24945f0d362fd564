"""The cross-section's case table: which edges of a tet a hyperplane cuts, in which order.

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

The table fixes which edges form the polygon and their cyclic order. The
section's outward normal is the xyz part of the tet's outward 4D normal
(``cross4`` of its edges, times the sign of the model-view's determinant), and
the polygon's winding against it depends on the case alone
(:data:`CASE_REVERSED`), so triangles come out counter-clockwise seen from
outside whatever the tet's vertex order, with no geometry per tet to decide it.
The kernels (:mod:`.section_kernels`, :mod:`.batch_kernels`) read these tables
as constants.
"""

from __future__ import annotations

import numpy as np

from .mesh import cross4


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
# The same table with a triangle's unused fourth edge repeating its third, so a
# kernel can always compute four points (the fourth then equals the third).
CASE_EDGES_PADDED = CASE_EDGES.copy()
CASE_EDGES_PADDED[CASE_COUNT == 3, 3] = CASE_EDGES[CASE_COUNT == 3, 2]
#: A tet's six edges as vertex pairs (lower local index first); ``CASE_LOCAL_EDGES[mask, e]``
#: is which of them ``CASE_EDGES_PADDED[mask, e]`` is.
TET_EDGE_PAIRS = np.array([(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)], np.int64)
CASE_LOCAL_EDGES = np.array(
    [
        [[tuple(p) for p in TET_EDGE_PAIRS.tolist()].index(tuple(sorted(e))) if e[0] != e[1] else 0 for e in row]
        for row in CASE_EDGES_PADDED.tolist()
    ],
    np.int64,
)

#: ``CASE_LOCAL_EDGES`` flat, as bytes (``[4 * mask + e]``): the kernels' copy.
CASE_LOCAL_FLAT = CASE_LOCAL_EDGES.astype(np.uint8).reshape(-1)


def _build_case_reversed() -> np.ndarray:
    """Whether each case's polygon, in table order, is clockwise seen from outside.

    The outward normal is ``cross4`` of the tet's edges (times the sign of the
    model-view's determinant) and the polygon's corners lie on the same edges,
    so the two turn together: for a tet that is not flat, the polygon's winding
    against the normal depends on the case alone (any non-flat tet can be
    deformed into any other of its case without flattening it or its section).
    Read off one tet here; ``tests/test_section_kernels.py`` checks random ones.

    Returns
    -------
    (2, 16) uint8
        Row 0 for a model-view of positive determinant, row 1 (the opposite) for
        a mirroring one; 0 for the cases that cut nothing.
    """
    rev = np.zeros(16, np.uint8)
    for mask in range(1, 15):
        w = np.array([1.0 if mask >> i & 1 else -1.0 for i in range(4)]) * (1.0 + 0.1 * np.arange(4))
        p = np.column_stack([np.vstack([np.zeros(3), np.eye(3)]), w])
        pts = []
        for a, b in CASE_EDGES[mask, : CASE_COUNT[mask]]:
            s = p[a, 3] / (p[a, 3] - p[b, 3])
            pts.append(p[a, :3] + s * (p[b, :3] - p[a, :3]))
        normal = cross4(p[1] - p[0], p[2] - p[0], p[3] - p[0])[:3]
        if len(pts) == 4:
            poly = np.cross(pts[2] - pts[0], pts[3] - pts[1])
        else:
            poly = np.cross(pts[1] - pts[0], pts[2] - pts[0])
        rev[mask] = poly @ normal < 0
    return np.stack([rev, np.where(CASE_COUNT > 0, 1 - rev, 0).astype(np.uint8)])


#: ``CASE_REVERSED[det < 0, mask]``: a case's polygon is wound the other way round (see
#: :func:`_build_case_reversed`).
CASE_REVERSED = _build_case_reversed()

#: Triangles a tet makes, by case (0 when it is not cut).
CASE_TRIANGLES = np.where(CASE_COUNT > 0, CASE_COUNT - 2, 0).astype(np.int64)
