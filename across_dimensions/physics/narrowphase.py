"""Narrowphase: the contact points of a tick's candidate pairs, in pair-key order.

Each pair goes to the routine of its two shapes (:mod:`.collide` for balls,
boxes and half-spaces, :mod:`.tet_mesh` for a level's tet meshes). Box pairs
that barely moved reuse last tick's manifold (:mod:`.reuse`), and box pairs
that were apart try last tick's separating axis first.

The work is done in passes over the pairs, one per job, each a loop that takes
its arrays out of the bundles once (a call per pair taking bundles would cost a
reference-count call per array, see :mod:`.state`):

1. :func:`_plan`: the pairs' keys, their order (by key) and the frame of each
   box pair whose manifold can be kept (a :class:`PairPlan`);
2. :func:`_reuse_pass`: last tick's manifold of each such pair, reused while
   the pair barely moved;
3. the shape tests: :func:`_body_pass` (two bodies), :func:`_plane_pass`
   (half-spaces and convex solids), :func:`_box_pass` (world boxes and solid
   boxes), :func:`_tet_pass` (tet meshes);
4. :func:`_compact`: the pairs' points, each written at its own slot of
   :data:`.collide.MAX_POINTS` rows, moved together in key order;
5. :func:`_keep_pass` (this tick's manifolds) and :func:`_label_pass` (pair
   names and surface velocities).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from across_dimensions.core._jit import njit

from .borrow import borrowed, keep
from .collide import (
    BOX,
    MAX_POINTS,
    SCRATCH_ROWS,
    SPHERE,
    box_box,
    box_halfspace,
    box_sphere,
    separated_along,
    sphere_halfspace,
    sphere_sphere,
)
from .reuse import emit_kept, keep_points, pair_pose, pose_close
from .sorting import argsort_by_body
from .state import STATIC_KEY
from .tet_mesh import box_tets, sphere_tets


class PairPlan(NamedTuple):
    """Per-pair arrays of one narrowphase, indexed by a pair's place in key order.

    Attributes
    ----------
    order : (P,) int64
        Row of ``Scratch.pairs`` of each place.
    key : (P,) int64
        Its pair key.
    frame : (P,) int64
        The frame of b if it is a box pair whose manifold can be kept: 1 body
        b, 2 a solid box, 0 the world (half-space, world box, convex solid);
        -1 not kept.
    tried : (P,) int64
        Last tick's separating axis of two boxes found apart, or -1.
    old : (P,) int64
        The kept manifold reused (its index in last tick's), or -1.
    got : (P,) int64
        Points found; ``-1 - axis`` for two boxes apart along ``axis``.
    tet : (P,) int64
        The tet mesh of a pair with one, or -1.
    start : (P,) int64
        First row of the pair's points after :func:`_compact`.
    """

    order: np.ndarray
    key: np.ndarray
    frame: np.ndarray
    tried: np.ndarray
    old: np.ndarray
    got: np.ndarray
    tet: np.ndarray
    start: np.ndarray


#: Rows of the narrowphase's work array: the routines' rows, then the small arrays below.
WORK_ROWS = SCRATCH_ROWS + 22
_X = SCRATCH_ROWS  # a static box's centre
_HALF = SCRATCH_ROWS + 1  # ... and half extents
_NORMAL = SCRATCH_ROWS + 2  # a half-space's normal
_ROT = SCRATCH_ROWS + 4  # a static box's rotation (4 rows)
_POSE = SCRATCH_ROWS + 8  # a pair's pose (5 rows, 20 values)
_SOLID_ROT = SCRATCH_ROWS + 13  # a solid box's rotation as a manifold's frame (4 rows)
_IDENTITY = SCRATCH_ROWS + 17  # (4 rows)
_ZERO = SCRATCH_ROWS + 21


@njit(cache=True)
def _plan(npairs, pairs, bodies, static, prm):
    """The :class:`PairPlan` of ``pairs[:npairs]``: keys, key order and the frames of kept manifolds."""
    shape = bodies.shape
    nh = static.half_spaces.shape[0]
    nw = static.boxes.shape[0]
    ns = static.solids.shape[0]
    ncv = static.convex_ranges.shape[0]
    keys = np.empty(npairs, dtype=np.int64)
    first = np.empty(npairs, dtype=np.int64)
    for p in range(npairs):
        a = pairs[p, 0]
        b = pairs[p, 1]
        keys[p] = (a << 32) | (b if b >= 0 else STATIC_KEY + (-1 - b))
        first[p] = a
    order = argsort_by_body(keys, first, bodies.count)
    frame = np.full(npairs, -1, dtype=np.int64)
    for op in range(npairs if prm.reuse_angle > 0.0 else 0):
        a = pairs[order[op], 0]
        b = pairs[order[op], 1]
        if shape[a] != BOX:
            continue
        if b >= 0:
            if shape[b] == BOX:
                frame[op] = 1
        else:
            s = -1 - b
            if s < nh + nw or nh + nw + ns <= s < nh + nw + ns + ncv:
                frame[op] = 0
            elif s < nh + nw + ns:
                frame[op] = 2
    none = np.full(npairs, -1, dtype=np.int64)
    return PairPlan(order, keys[order], frame, none, none.copy(), np.zeros(npairs, np.int64), none.copy(), none.copy())


@njit(inline="always")
def _frame_pose(frame, b, pos, rot, solids, first_solid, work):
    """Centre ``(4,)`` and rotation ``(4, 4)`` of the frame ``frame`` of a kept manifold (see
    :class:`PairPlan`); a solid box's rotation goes to ``work``'s rows."""
    if frame == 1:
        return pos[b], rot[b]
    if frame == 2:
        s = -1 - b - first_solid
        fr = work[_SOLID_ROT : _SOLID_ROT + 4]
        for t in range(4):
            for q in range(4):
                fr[t, q] = solids[s, 8 + 4 * t + q]
        return solids[s, :4], fr
    return work[_ZERO], work[_IDENTITY : _IDENTITY + 4]


@njit(cache=True)
def _reuse_pass(plan, bodies, static, scratch, contacts, prm, work, kept):
    """Reuse each kept manifold whose pair moved less than the tolerances (its points go to the
    pair's slot); note last tick's separating axis of two boxes found apart."""
    order, keys, frames, tried, olds, gots = plan.order, plan.key, plan.frame, plan.tried, plan.old, plan.got
    pairs = scratch.pairs
    marg = scratch.margin
    pos = bodies.position
    rot = bodies.rotation
    so = static.solids
    first_solid = static.half_spaces.shape[0] + static.boxes.shape[0]
    out = (contacts.point, contacts.normal, contacts.depth)
    pose = work[_POSE : _POSE + 5].reshape(20)
    old_key, old_first, old_count, old_axis, old_pose, old_local, n_old = kept
    oi = 0
    for op in range(order.shape[0]):
        if frames[op] < 0:
            continue
        while oi < n_old[0] and old_key[oi] < keys[op]:
            oi += 1
        if not (oi < n_old[0] and old_key[oi] == keys[op]):
            continue
        if old_count[oi] == 0:
            # Two boxes that were apart: try last tick's separating axis first.
            tried[op] = old_axis[oi]
            continue
        a = pairs[order[op], 0]
        b = pairs[order[op], 1]
        fx, fr = _frame_pose(frames[op], b, pos, rot, so, first_solid, work)
        pair_pose(pos[a], rot[a], fx, fr, pose)
        if pose_close(pose, old_pose, oi, prm.reuse_distance, prm.reuse_angle):
            m = marg[a] + (marg[b] - prm.margin if b >= 0 else 0.0)
            k = op * MAX_POINTS
            gots[op] = emit_kept(old_local, old_first[oi], old_count[oi], (pos[a], rot[a]), (fx, fr), m, out, k)
            olds[op] = oi


@njit(inline="always")
def _flip(cn, k, got):
    """Turn the normals of rows ``k .. k + got`` around (the routine saw the pair the other way)."""
    for q in range(got):
        for t in range(4):
            cn[k + q, t] = -cn[k + q, t]


@njit(cache=True)
def _body_pass(plan, bodies, scratch, contacts, prm, work):
    """Contacts of the pairs of two bodies (not reused) at their slots; ``-1 - axis`` as ``got``
    for two boxes apart along candidate ``axis``."""
    order, tried, olds, gots = plan.order, plan.tried, plan.old, plan.got
    pairs = scratch.pairs
    marg = scratch.margin
    sp = scratch.points
    sd = scratch.point_depths
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    bound = bodies.bound
    cp, cn, cd = contacts.point, contacts.normal, contacts.depth
    wk = work[:SCRATCH_ROWS]
    for op in range(order.shape[0]):
        a = pairs[order[op], 0]
        b = pairs[order[op], 1]
        if b < 0 or olds[op] >= 0:
            continue
        k = op * MAX_POINTS
        m = marg[a] + marg[b] - prm.margin
        # Bounding balls apart by more than the margin: no contact whatever
        # the shapes (a cheap exit before the full test; the box-box test
        # would find none either).
        d2 = 0.0
        for t in range(4):
            e = pos[b, t] - pos[a, t]
            d2 += e * e
        reach = 1.001 * (bound[a] + bound[b] + m)
        if d2 > reach * reach:
            continue
        if shape[a] == SPHERE and shape[b] == SPHERE:
            gots[op] = sphere_sphere(pos[a], half[a, 0], pos[b], half[b, 0], m, wk, cp, cn, cd, k)
        elif shape[a] == BOX and shape[b] == SPHERE:
            gots[op] = box_sphere(pos[a], rot[a], half[a], pos[b], half[b, 0], m, wk, cp, cn, cd, k)
        elif shape[a] == SPHERE and shape[b] == BOX:
            gots[op] = box_sphere(pos[b], rot[b], half[b], pos[a], half[a, 0], m, wk, cp, cn, cd, k)
            _flip(cn, k, gots[op])
        elif tried[op] >= 0 and separated_along(tried[op], pos[a], rot[a], half[a], pos[b], rot[b], half[b], m, wk):
            gots[op] = -1 - tried[op]
        else:
            gots[op] = box_box(pos[a], rot[a], half[a], pos[b], rot[b], half[b], m, sp, sd, wk, cp, cn, cd, k)


@njit(cache=True)
def _plane_pass(plan, bodies, static, scratch, contacts, work):
    """Contacts of bodies with half-spaces, and with convex solids through the facet of least
    penetration (when it is within the margin), at the pairs' slots."""
    order, olds, gots = plan.order, plan.old, plan.got
    pairs = scratch.pairs
    marg = scratch.margin
    sp = scratch.points
    sd = scratch.point_depths
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    hs = static.half_spaces
    cpl = static.convex_planes
    cr = static.convex_ranges
    nh = hs.shape[0]
    first_convex = nh + static.boxes.shape[0] + static.solids.shape[0]
    cp, cn, cd = contacts.point, contacts.normal, contacts.depth
    wk = work[:SCRATCH_ROWS]
    for op in range(order.shape[0]):
        a = pairs[order[op], 0]
        s = -1 - pairs[order[op], 1]
        if s < 0 or olds[op] >= 0 or nh <= s < first_convex or s >= first_convex + cr.shape[0]:
            continue
        m = marg[a]
        if s < nh:
            f = s
            planes = hs
        else:
            f = _least_penetration(cpl, cr[s - first_convex], a, shape, half, pos, rot)
            planes = cpl
            if f < 0 or _separation(cpl, f, a, shape, half, pos, rot) > m:
                continue
        pn = work[_NORMAL]
        for t in range(4):
            pn[t] = planes[f, t]
        k = op * MAX_POINTS
        if shape[a] == SPHERE:
            gots[op] = sphere_halfspace(pos[a], half[a, 0], pn, planes[f, 4], m, cp, cn, cd, k)
        else:
            gots[op] = box_halfspace(pos[a], rot[a], half[a], pn, planes[f, 4], m, sp, sd, wk, cp, cn, cd, k)


@njit(inline="always")
def _separation(planes, f, a, shape, half, pos, rot):
    """How far body ``a`` is outside facet half-space ``planes[f]`` (negative: into it)."""
    sep = -planes[f, 4]
    for t in range(4):
        sep += planes[f, t] * pos[a, t]
    if shape[a] == SPHERE:
        sep -= half[a, 0]
    else:
        for t in range(4):
            u = 0.0
            for v in range(4):
                u += planes[f, v] * rot[a, v, t]
            sep -= half[a, t] * abs(u)
    return sep


@njit(inline="always")
def _least_penetration(planes, rows, a, shape, half, pos, rot):
    """The facet among ``planes[rows[0] : rows[1]]`` body ``a`` is furthest outside of (-1 if none)."""
    best = -np.inf
    bf = -1
    for f in range(rows[0], rows[1]):
        sep = _separation(planes, f, a, shape, half, pos, rot)
        if sep > best:
            best = sep
            bf = f
    return bf


@njit(cache=True)
def _box_pass(plan, bodies, static, scratch, contacts, work):
    """Contacts of bodies with the level's solid boxes and with world boxes, at the pairs' slots.

    A world box spans all of w: it is made a 4D box wide enough in w that its
    w faces can never be the separating axis.
    """
    order, olds, gots = plan.order, plan.old, plan.got
    pairs = scratch.pairs
    marg = scratch.margin
    sp = scratch.points
    sd = scratch.point_depths
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    wb = static.boxes
    so = static.solids
    nh = static.half_spaces.shape[0]
    nw = wb.shape[0]
    cp, cn, cd = contacts.point, contacts.normal, contacts.depth
    wk = work[:SCRATCH_ROWS]
    vx = work[_X]
    vh = work[_HALF]
    vs = work[_ROT : _ROT + 4]
    vr = work[_IDENTITY : _IDENTITY + 4]
    for op in range(order.shape[0]):
        a = pairs[order[op], 0]
        s = -1 - pairs[order[op], 1] - nh
        if s < 0 or s >= nw + so.shape[0] or olds[op] >= 0:
            continue
        if s >= nw:
            s -= nw
            for t in range(4):
                vx[t] = so[s, t]
                vh[t] = so[s, 4 + t]
                for q in range(4):
                    vs[t, q] = so[s, 8 + 4 * t + q]
            br = vs
        else:
            rad = 0.0
            for t in range(4):
                rad += half[a, t] * half[a, t]
            for t in range(3):
                vx[t] = wb[s, t]
                vh[t] = wb[s, 3 + t]
            vx[3] = pos[a, 3]
            vh[3] = 4.0 * np.sqrt(rad) + 1.0
            br = vr
        k = op * MAX_POINTS
        if shape[a] == SPHERE:
            gots[op] = box_sphere(vx, br, vh, pos[a], half[a, 0], marg[a], wk, cp, cn, cd, k)
            _flip(cn, k, gots[op])
        else:
            gots[op] = box_box(pos[a], rot[a], half[a], vx, br, vh, marg[a], sp, sd, wk, cp, cn, cd, k)


@njit(cache=True)
def _tet_pass(plan, bodies, static, scratch, contacts):
    """Contacts of bodies with the level's tet meshes (the boundaries of its other solid objects)."""
    order, gots, tet = plan.order, plan.got, plan.tet
    pairs = scratch.pairs
    marg = scratch.margin
    tcp, tcn, tcd = scratch.tet_points, scratch.tet_normals, scratch.tet_depths
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    tets, tpl, tby, tbd = static.tets, static.tet_planes, static.tet_bary, static.tet_bounds
    tr = static.tet_ranges
    tsw = static.tet_sweep
    first = static.half_spaces.shape[0] + static.boxes.shape[0] + static.solids.shape[0]
    first += static.convex_ranges.shape[0]
    cp, cn, cd = contacts.point, contacts.normal, contacts.depth
    for op in range(order.shape[0]):
        a = pairs[order[op], 0]
        q = -1 - pairs[order[op], 1] - first
        if q < 0:
            continue
        t0 = tr[q, 0]
        t1 = tr[q, 1]
        ax = int(tsw[q, 0])
        ext = tsw[q, 1]
        m = marg[a]
        k = op * MAX_POINTS
        tet[op] = q
        if shape[a] == SPHERE:
            gots[op] = sphere_tets(
                pos[a], half[a, 0], tets, tpl, tby, tbd, t0, t1, ax, ext, m, tcp, tcn, tcd, cp, cn, cd, k
            )
        else:
            gots[op] = box_tets(
                pos[a], rot[a], half[a], tets, tpl, tby, tbd, t0, t1, ax, ext, m, tcp, tcn, tcd, cp, cn, cd, k
            )


@njit(cache=True)
def _compact(plan, contacts):
    """Move each pair's points from its slot to follow the previous pair's; returns the count.

    A pair's slot starts at or after where its points go, so rows move
    forward only and none is overwritten before it is read.
    """
    gots, start = plan.got, plan.start
    cp, cn, cd = contacts.point, contacts.normal, contacts.depth
    k = 0
    for op in range(gots.shape[0]):
        got = max(gots[op], 0)
        start[op] = k
        src = op * MAX_POINTS
        if src != k:
            for q in range(got):
                for t in range(4):
                    cp[k + q, t] = cp[src + q, t]
                    cn[k + q, t] = cn[src + q, t]
                cd[k + q] = cd[src + q]
        k += got
    return k


@njit(cache=True)
def _keep_pass(plan, bodies, static, scratch, contacts, work, kept, kept_out):
    """This tick's box manifolds, in key order: reused ones as they were (with the pose they were
    found at, so slow drift still reaches the tolerance), new ones in the bodies' frames, and
    the separating axis of two boxes found apart."""
    order, frames, olds, gots, start = plan.order, plan.frame, plan.old, plan.got, plan.start
    pairs = scratch.pairs
    pos = bodies.position
    rot = bodies.rotation
    so = static.solids
    first_solid = static.half_spaces.shape[0] + static.boxes.shape[0]
    found = (contacts.point, contacts.normal, contacts.depth)
    pose = work[_POSE : _POSE + 5].reshape(20)
    old_key, old_first, old_count, old_axis, old_pose, old_local, _ = kept
    new_key, new_first, new_count, new_axis, new_pose, new_local, new_pairs = kept_out
    n_new = 0
    rows = 0
    for op in range(order.shape[0]):
        frame = frames[op]
        got = gots[op]
        oi = olds[op]
        if frame < 0 or (oi < 0 and got == 0) or (got < 0 and frame != 1):
            continue
        new_key[n_new] = plan.key[op]
        new_first[n_new] = rows
        new_axis[n_new] = -1
        if oi >= 0:
            new_count[n_new] = old_count[oi]
            new_pose[n_new] = old_pose[oi]
            new_local[rows : rows + old_count[oi]] = old_local[old_first[oi] : old_first[oi] + old_count[oi]]
        elif got < 0:
            new_count[n_new] = 0
            new_axis[n_new] = -1 - got
        else:
            a = pairs[order[op], 0]
            fx, fr = _frame_pose(frame, pairs[order[op], 1], pos, rot, so, first_solid, work)
            pair_pose(pos[a], rot[a], fx, fr, pose)
            keep_points(found, start[op], got, (pos[a], rot[a]), (fx, fr), new_local, rows)
            new_count[n_new] = got
            new_pose[n_new] = pose
        rows += new_count[n_new]
        n_new += 1
    new_pairs[0] = n_new


@njit(cache=True)
def _label_pass(plan, scratch, contacts, tet_motion):
    """Name each point's pair, and give it the surface velocity of its tet mesh there (zero for
    all else: only a moving tet mesh's surface moves)."""
    order, keys, gots, tet, start = plan.order, plan.key, plan.got, plan.tet, plan.start
    pairs = scratch.pairs
    cp = contacts.point
    body_a = contacts.body_a
    body_b = contacts.body_b
    pair_key = contacts.key
    surf = contacts.surface_velocity
    for op in range(order.shape[0]):
        tq = tet[op]
        for q in range(start[op], start[op] + max(gots[op], 0)):
            body_a[q] = pairs[order[op], 0]
            body_b[q] = pairs[order[op], 1]
            pair_key[q] = keys[op]
            for t in range(4):
                v = 0.0
                if tq >= 0:
                    v = tet_motion[tq, t, 4]
                    for j in range(4):
                        v += tet_motion[tq, t, j] * cp[q, j]
                surf[q, t] = v


@njit(cache=True)
def narrowphase(npairs, bodies, static, scratch, contacts, kept, kept_out, prm):
    """Contacts of all candidate pairs (``scratch.pairs[:npairs]``) in pair-key order.

    A body and a static collider get contacts up to the body's margin apart
    (``scratch.margin``: the ``margin`` parameter plus what the body can move
    in a tick); two bodies up to ``margin`` plus what each can move, the rest
    margin counted once per pair as Box2D's speculative distance is (counted
    per body, half the contacts of a resting pile were gaps of 2 to 4 cm that
    never closed).

    Box pairs (with each other or with a static collider other than a tet
    mesh) reuse their manifold in ``kept`` while they move less than
    ``reuse_distance`` and turn less than ``reuse_angle`` (see :mod:`.reuse`;
    an angle of 0 turns reuse off); every box manifold of this tick goes to
    ``kept_out``. ``prm`` is the world's record of ``PARAMS_DTYPE``.

    Returns
    -------
    int
        Number of contacts written to ``contacts``, or ``-(needed)`` when it
        cannot hold the worst case.
    """
    if npairs * MAX_POINTS > contacts.point.shape[0]:
        return -npairs * MAX_POINTS
    plan = _plan(npairs, scratch.pairs, bodies, static, prm)
    # The passes' work rows, borrowed (see .borrow): the routines get views of them for every pair.
    own = np.zeros((WORK_ROWS, 4))
    work = borrowed(own)
    for t in range(4):
        work[_IDENTITY + t, t] = 1.0
    _reuse_pass(plan, bodies, static, scratch, contacts, prm, work, kept)
    _body_pass(plan, bodies, scratch, contacts, prm, work)
    _plane_pass(plan, bodies, static, scratch, contacts, work)
    _box_pass(plan, bodies, static, scratch, contacts, work)
    _tet_pass(plan, bodies, static, scratch, contacts)
    k = _compact(plan, contacts)
    _keep_pass(plan, bodies, static, scratch, contacts, work, kept, kept_out)
    _label_pass(plan, scratch, contacts, static.tet_motion)
    keep(own)
    return k
