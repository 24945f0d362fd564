"""Lines of sight against axis-aligned boxes (compiled kernels).

Does the segment from an eye to a point cross a box? The slab test, with the segment's
parameter ``t`` in [0, 1]: the occlusion test of the drawing asks it of a handful of
segments and boxes a frame, where numpy's cost per call, not the arithmetic, would be the
time (a dozen array operations for ten pairs cost some 30 us; a kernel call, two).
"""

from __future__ import annotations

from across_dimensions.core._jit import njit

#: A direction component nearer zero than this is taken as this (positive), so the slab
#: test never divides by zero and a segment along a face stays on one side of it.
TINY = 1e-12


@njit(inline="always")
def _crosses(eye, end, lo, hi):
    """Does the segment from ``eye`` to ``end`` (3 floats each, indexable) cross the box
    ``[lo, hi]``?"""
    enter, leave = -1e300, 1e300
    for a in range(3):
        d = end[a] - eye[a]
        inv = 1.0 / (TINY if abs(d) < TINY else d)
        t0 = (lo[a] - eye[a]) * inv
        t1 = (hi[a] - eye[a]) * inv
        enter = max(enter, min(t0, t1))
        leave = min(leave, max(t0, t1))
    return enter <= leave and enter <= 1.0 and leave >= 0.0


@njit(cache=True)
def segments_cross_boxes(eye, ends, boxes, out):
    """Does the segment from ``eye (3,)`` to each of ``ends (m, 3)`` cross each of
    ``boxes (k, 2, 3)`` (lower and upper corners)? Into ``out (m, k) bool``; returns
    whether any does."""
    anyone = False
    for i in range(ends.shape[0]):
        for j in range(boxes.shape[0]):
            hit = _crosses(eye, ends[i], boxes[j, 0], boxes[j, 1])
            out[i, j] = hit
            anyone |= hit
    return anyone


@njit(cache=True)
def segments_cross_their_boxes(eye, ends, boxes, out):
    """Does the segment from ``eye (3,)`` to ``ends[i] (m, 3)`` cross ``boxes[i] (m, 2, 3)``,
    for each ``i``? Into ``out (m,) bool``."""
    for i in range(ends.shape[0]):
        out[i] = _crosses(eye, ends[i], boxes[i, 0], boxes[i, 1])
