"""Reuse of box contact manifolds while a pair barely moves (temporal coherence).

Resting bodies move by fractions of a millimetre per tick, yet the box-box
narrowphase (56 separating axes, then clipping each box against the other)
is the costliest part of a tick in a pile. So a box pair's manifold is kept in
the two bodies' own frames (:class:`~.state.Manifolds`): while the pair's
relative pose stays within ``reuse_distance`` and ``reuse_angle`` of the pose
it was found at, its points ride along with the bodies and only their depths
are measured again. Past either tolerance, or for a new pair, the full test
runs and its manifold is stored. This is the body-pair cache of established
engines (Jolt keeps manifolds while a pair moves under 1 mm and 2 degrees).

A point is kept as its place on each body's surface, in that body's frame,
plus the normal in a's frame; its depth is then ``(s_a - s_b) . n`` and it is
reported half-way between the surfaces, as the narrowphase reports points.
The frame of a static collider is the world's, or a solid box's own pose.
"""

from __future__ import annotations

from across_dimensions.core._jit import njit


@njit(cache=True)
def pair_pose(xa, ra, xb, rb, out):
    """The pose of frame b seen from body a: ``R_a^T (x_b - x_a)``, then ``R_a^T R_b`` row-major.

    Parameters
    ----------
    xa, xb : (4,) float64
    ra, rb : (4, 4) float64
        Rotations (columns are the axes).
    out : (20,) float64
    """
    for i in range(4):
        s = 0.0
        for m in range(4):
            s += ra[m, i] * (xb[m] - xa[m])
        out[i] = s
        for j in range(4):
            t = 0.0
            for m in range(4):
                t += ra[m, i] * rb[m, j]
            out[4 + 4 * i + j] = t


@njit(cache=True)
def pose_close(pose, old, j, distance, angle):
    """Whether ``pose`` is within ``distance`` and (about) ``angle`` of stored pose ``old[j]``.

    The turn is measured as ``|dR|_F^2 <= 2 angle^2``, which is exact to second
    order for a turn by ``angle`` in one plane.
    """
    d2 = 0.0
    for i in range(4):
        e = pose[i] - old[j, i]
        d2 += e * e
    r2 = 0.0
    for i in range(4, 20):
        e = pose[i] - old[j, i]
        r2 += e * e
    return d2 <= distance * distance and r2 <= 2.0 * angle * angle


@njit(cache=True)
def emit_kept(local, first, count, frame_a, frame_b, margin, out, k):
    """Write the kept points ``local[first : first + count]`` at the bodies' current poses.

    ``frame_a``, ``frame_b`` are each ``(centre (4,), rotation (4, 4))``. Points
    further apart than ``margin`` are left out (they stay kept).

    Returns
    -------
    int
        Points written to ``out`` (:class:`~.state.Points`) from row ``k``.
    """
    xa, ra = frame_a
    xb, rb = frame_b
    out_p, out_n, out_d = out
    got = 0
    for j in range(first, first + count):
        depth = 0.0
        for m in range(4):
            sa = xa[m]
            sb = xb[m]
            nm = 0.0
            for i in range(4):
                sa += ra[m, i] * local[j, i]
                sb += rb[m, i] * local[j, 4 + i]
                nm += ra[m, i] * local[j, 8 + i]
            out_p[k + got, m] = 0.5 * (sa + sb)
            out_n[k + got, m] = nm
            depth += (sa - sb) * nm
        if depth >= -margin:
            out_d[k + got] = depth
            got += 1
    return got


@njit(cache=True)
def keep_points(found, k, got, frame_a, frame_b, local, row):
    """Store points ``k .. k + got`` of ``found`` (:class:`~.state.Points`) in the bodies' frames
    (``frame_a``, ``frame_b``: ``(centre, rotation)`` each) from row ``row`` of ``local``.

    A point ``p`` with normal ``n`` and depth ``d`` lies half-way between the
    surfaces: a's surface point is ``p + d n / 2`` and b's ``p - d n / 2``.
    """
    cp, cn, cd = found
    xa, ra = frame_a
    xb, rb = frame_b
    for q in range(got):
        c = k + q
        for i in range(4):
            sa = 0.0
            sb = 0.0
            nl = 0.0
            for m in range(4):
                h = 0.5 * cd[c] * cn[c, m]
                sa += ra[m, i] * (cp[c, m] + h - xa[m])
                sb += rb[m, i] * (cp[c, m] - h - xb[m])
                nl += ra[m, i] * cn[c, m]
            local[row + q, i] = sa
            local[row + q, 4 + i] = sb
            local[row + q, 8 + i] = nl
