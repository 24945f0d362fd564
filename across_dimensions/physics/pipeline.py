"""One fixed physics tick (several substeps) as a single compiled kernel.

Order of work (all in body-index and pair-key order, so the result depends only
on the inputs, never on timing or hashing):

1. bounding boxes, sort-and-sweep broadphase along the widest axis (bodies) plus a direct
   test against the few static world colliders (half-spaces, world boxes, and
   the level's solid objects as 4D boxes, convex solids or tet meshes);
2. wake sleeping islands touched by moving bodies;
3. narrowphase contacts for the pairs, sorted by pair key (so last tick's
   contacts can be matched for warm starting in one forward pass); box pairs
   that barely moved reuse last tick's manifold (:mod:`.reuse`), and box pairs
   that were apart try last tick's separating axis first;
4. solver rows for every contact (see :mod:`.solver`);
5. substeps of the soft-step solver: forces (gravity, optional inverse-cube
   attraction), warm start, solve, move, relax; then restitution;
6. islands (from the broadphase pairs) and sleeping.

The kernel checks buffer capacity before it changes any body, so the caller can
grow the buffers and call it again when it reports an overflow. Its arguments
are the named bundles of :mod:`.state` (bodies, static world, parameters,
contacts, warm start, solver rows, scratch).
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .bivector import compound, rotate_by, world_inverse_inertia
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
from .solver import (
    current_separation,
    prepare,
    restitution,
    soft_params,
    solve,
    store,
    warm_start,
)
from .sorting import argsort_by_body, argsort_stable
from .state import Bodies, Contacts, Manifolds, Scratch, SolverRows, SpinRows, StaticWorld, WarmStart
from .tet_mesh import box_tets, sphere_tets

STATIC = 0
KINEMATIC = 1
DYNAMIC = 2

#: Pair-key offset for static world colliders (body indices stay below it).
STATIC_KEY = 1 << 30


@njit(cache=True)
def _moving(i, kind, awake, vel, omg):
    """Whether body ``i`` can disturb others: awake dynamic or moving kinematic."""
    if kind[i] == DYNAMIC:
        return awake[i]
    if kind[i] == KINEMATIC:
        for m in range(4):
            if vel[i, m] != 0.0:
                return True
        for k in range(6):
            if omg[i, k] != 0.0:
                return True
    return False


@njit(cache=True)
def _support(i, shape, half, rot, d):
    """Half-width of body ``i`` along unit direction ``d``."""
    if shape[i] == SPHERE:
        return half[i, 0]
    s = 0.0
    for k in range(4):
        t = 0.0
        for m in range(4):
            t += rot[i, m, k] * d[m]
        s += half[i, k] * abs(t)
    return s


@njit(cache=True)
def _wake_island(j, nb, alive, kind, awake, timer, island):
    isl = island[j]
    for i in range(nb):
        if alive[i] and kind[i] == DYNAMIC and not awake[i] and island[i] == isl:
            awake[i] = True
            timer[i] = 0.0


@njit(cache=True)
def _sweep(order, slo, shi, sdyn, ax, cand):
    """Pairs of sorted bounds that overlap on all four axes, at least one body dynamic.

    Parameters
    ----------
    order : (N,) int64
        Body of each sorted slot.
    slo, shi : (4, na) float64
        Bounds of the alive bodies in sweep order (sorted by ``slo[ax]``).
    sdyn : (na,) bool
        Whether each is dynamic.
    ax : int
        Sweep axis.
    cand : (P, 2) int64
        Output: ``(min, max)`` body pairs.

    Returns
    -------
    int
        Pairs written, or -1 if ``cand`` is too small.
    """
    na = slo.shape[1]
    sweep_lo = slo[ax]
    hits = np.empty(na, dtype=np.int64)
    nc = 0
    for oi in range(na):
        i = order[oi]
        top = shi[ax, oi]
        l0 = slo[0, oi]
        l1 = slo[1, oi]
        l2 = slo[2, oi]
        l3 = slo[3, oi]
        h0 = shi[0, oi]
        h1 = shi[1, oi]
        h2 = shi[2, oi]
        h3 = shi[3, oi]
        # Without a branch on the overlap (``|`` does not short-circuit, and
        # every slot is written, kept or not): about one candidate in fifteen
        # overlaps, and a branch that unpredictable made this loop four times
        # slower.
        nh = 0
        for oj in range(oi + 1, na):
            if sweep_lo[oj] > top:
                break
            apart = (slo[0, oj] > h0) | (l0 > shi[0, oj]) | (slo[1, oj] > h1) | (l1 > shi[1, oj])
            apart |= (slo[2, oj] > h2) | (l2 > shi[2, oj]) | (slo[3, oj] > h3) | (l3 > shi[3, oj])
            hits[nh] = oj
            nh += 0 if apart else 1
        dyn = sdyn[oi]
        for q in range(nh):
            oj = hits[q]
            if not (dyn or sdyn[oj]):
                continue
            if nc == cand.shape[0]:
                return -1
            j = order[oj]
            cand[nc, 0] = min(i, j)
            cand[nc, 1] = max(i, j)
            nc += 1
    return nc


@njit(cache=True)
def find_pairs(bodies, static, h, base_margin, pairs, marg):
    """Broadphase: candidate pairs that need a narrowphase test.

    Parameters
    ----------
    bodies : Bodies
        Sleeping islands touched by moving bodies are woken.
    static : StaticWorld
    h : float
        Tick length: the margin covers the motion of one tick.
    base_margin : float
    pairs : (P, 2) int64
        Output: body a and body b (``b >= 0``) or ``-1 - s`` for static world
        collider ``s`` (half-spaces first, then world boxes, solid boxes, convex solids,
        tet meshes).
    marg : (N,) float64
        Output: per-body speculative margin ``base + h * (speed)``.

    Returns
    -------
    int
        Number of pairs, or ``-(needed)`` if ``pairs`` is too small.
    """
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    vel = bodies.velocity
    omg = bodies.angular_velocity
    awake = bodies.awake
    timer = bodies.sleep_timer
    island = bodies.island
    hs = static.half_spaces
    wb = static.boxes
    lo = np.empty((nb, 4))
    hi = np.empty((nb, 4))
    key = np.empty(nb)
    act = np.zeros(nb, dtype=np.bool_)
    ext = np.empty(4)
    for i in range(nb):
        key[i] = np.inf
        if not alive[i]:
            continue
        sp = 0.0
        for m in range(4):
            sp += vel[i, m] * vel[i, m]
        w2 = 0.0
        for k in range(6):
            w2 += omg[i, k] * omg[i, k]
        if shape[i] == SPHERE:
            for m in range(4):
                ext[m] = half[i, 0]
            rad = half[i, 0]
        else:
            rad = 0.0
            for m in range(4):
                e = 0.0
                for k in range(4):
                    e += abs(rot[i, m, k]) * half[i, k]
                ext[m] = e
                rad += half[i, m] * half[i, m]
            rad = np.sqrt(rad)
        marg[i] = base_margin + h * (np.sqrt(sp) + np.sqrt(w2) * rad)
        for m in range(4):
            lo[i, m] = pos[i, m] - ext[m] - marg[i]
            hi[i, m] = pos[i, m] + ext[m] + marg[i]
    # Sweep along the axis the bodies spread most along (a pile is taller than
    # it is wide): fewer bodies overlap each other's interval there. The pairs
    # found are the same whatever the axis (their order does not matter: the
    # narrowphase sorts them by key, islands take the smallest index as root).
    ax = 0
    best = -1.0
    for m in range(4):
        a_lo = np.inf
        a_hi = -np.inf
        for i in range(nb):
            if alive[i]:
                a_lo = min(a_lo, pos[i, m])
                a_hi = max(a_hi, pos[i, m])
        if a_hi - a_lo > best:
            best = a_hi - a_lo
            ax = m
    for i in range(nb):
        if alive[i]:
            key[i] = lo[i, ax]
    order = argsort_stable(key)
    cap = pairs.shape[0]
    n = 0
    # The bounds of the alive bodies (sorted first: the others have an infinite
    # key) copied in sweep order, one array per axis: the sweep then reads
    # memory in order instead of jumping between bodies (about 200 bodies share
    # an interval in a pile of 1000, so this loop is the broadphase's cost).
    na = 0
    while na < nb and alive[order[na]]:
        na += 1
    slo = np.empty((4, na))
    shi = np.empty((4, na))
    sdyn = np.empty(na, dtype=np.bool_)
    for o in range(na):
        i = order[o]
        for m in range(4):
            slo[m, o] = lo[i, m]
            shi[m, o] = hi[i, m]
        sdyn[o] = kind[i] == DYNAMIC
    # Collect overlapping pairs with at least one dynamic body, then wake
    # sleeping islands touched by moving bodies until nothing changes.
    # A pile has about ten neighbours per body; grown below when that is not enough.
    cand = np.empty((max(64, 16 * nb), 2), dtype=np.int64)
    nc = _sweep(order, slo, shi, sdyn, ax, cand)
    while nc < 0:
        # A buffer that grows inside the sweep would be reference-counted on
        # every step of it: grow it here and sweep again (rare).
        cand = np.empty((2 * cand.shape[0], 2), dtype=np.int64)
        nc = _sweep(order, slo, shi, sdyn, ax, cand)
    changed = True
    while changed:
        changed = False
        for p in range(nc):
            i = cand[p, 0]
            j = cand[p, 1]
            if kind[j] == DYNAMIC and not awake[j] and _moving(i, kind, awake, vel, omg):
                _wake_island(j, nb, alive, kind, awake, timer, island)
                changed = True
            elif kind[i] == DYNAMIC and not awake[i] and _moving(j, kind, awake, vel, omg):
                _wake_island(i, nb, alive, kind, awake, timer, island)
                changed = True
    for i in range(nb):
        act[i] = alive[i] and kind[i] == DYNAMIC and awake[i]
    for p in range(nc):
        i = cand[p, 0]
        j = cand[p, 1]
        if act[i] or act[j]:
            if n < cap:
                pairs[n, 0] = i
                pairs[n, 1] = j
            n += 1
    nh = hs.shape[0]
    nw = wb.shape[0]
    # The solids' own bounds along each axis (they do not move within a tick).
    so = static.solids
    ns = so.shape[0]
    cb = static.convex_bounds
    tb = static.tet_mesh_bounds
    sext = np.zeros((ns, 4))
    for s in range(ns):
        for m in range(4):
            e = 0.0
            for k in range(4):
                e += abs(so[s, 8 + 4 * m + k]) * so[s, 4 + k]
            sext[s, m] = e
    d = np.empty(4)
    for i in range(nb):
        if not act[i]:
            continue
        for s in range(nh):
            for m in range(4):
                d[m] = hs[s, m]
            dist = -hs[s, 4]
            for m in range(4):
                dist += d[m] * pos[i, m]
            if dist - _support(i, shape, half, rot, d) <= marg[i]:
                if n < cap:
                    pairs[n, 0] = i
                    pairs[n, 1] = -1 - s
                n += 1
        for s in range(wb.shape[0]):
            ok = True
            for m in range(3):
                if lo[i, m] > wb[s, m] + wb[s, 3 + m] or hi[i, m] < wb[s, m] - wb[s, 3 + m]:
                    ok = False
                    break
            if ok:
                if n < cap:
                    pairs[n, 0] = i
                    pairs[n, 1] = -1 - nh - s
                n += 1
        for s in range(ns):
            ok = True
            for m in range(4):
                if lo[i, m] > so[s, m] + sext[s, m] or hi[i, m] < so[s, m] - sext[s, m]:
                    ok = False
                    break
            if ok:
                if n < cap:
                    pairs[n, 0] = i
                    pairs[n, 1] = -1 - nh - nw - s
                n += 1
        for q in range(cb.shape[0]):
            ok = True
            for m in range(4):
                if lo[i, m] > cb[q, 4 + m] or hi[i, m] < cb[q, m]:
                    ok = False
                    break
            if ok:
                if n < cap:
                    pairs[n, 0] = i
                    pairs[n, 1] = -1 - nh - nw - ns - q
                n += 1
        nq = cb.shape[0]
        for q in range(tb.shape[0]):
            ok = True
            for m in range(4):
                if lo[i, m] > tb[q, 4 + m] or hi[i, m] < tb[q, m]:
                    ok = False
                    break
            if ok:
                if n < cap:
                    pairs[n, 0] = i
                    pairs[n, 1] = -1 - nh - nw - ns - nq - q
                n += 1
    if n > cap:
        return -n
    return n


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
    pairs = scratch.pairs
    marg = scratch.margin
    scratch_p = scratch.points
    scratch_d = scratch.point_depths
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    bound = bodies.bound
    hs = static.half_spaces
    wb = static.boxes
    # Arrays are taken out of the bundles once: reading a bundle's field inside
    # a loop costs a reference-count update per iteration.
    cp = contacts.point
    cn = contacts.normal
    cd = contacts.depth
    body_a = contacts.body_a
    body_b = contacts.body_b
    pair_key = contacts.key
    if npairs * MAX_POINTS > cp.shape[0]:
        return -npairs * MAX_POINTS
    keys = np.empty(npairs, dtype=np.int64)
    first = np.empty(npairs, dtype=np.int64)
    for p in range(npairs):
        a = pairs[p, 0]
        b = pairs[p, 1]
        keys[p] = (a << 32) | (b if b >= 0 else STATIC_KEY + (-1 - b))
        first[p] = a
    order = argsort_by_body(keys, first, bodies.count)
    nh = hs.shape[0]
    k = 0
    so = static.solids
    cpl = static.convex_planes
    cr = static.convex_ranges
    tets = static.tets
    tpl = static.tet_planes
    tby = static.tet_bary
    tbd = static.tet_bounds
    tr = static.tet_ranges
    tcp = scratch.tet_points
    tcn = scratch.tet_normals
    tcd = scratch.tet_depths
    tmo = static.tet_motion
    tsw = static.tet_sweep
    surf = contacts.surface_velocity
    # Work arrays of the loop, borrowed (see .borrow): the routines below get
    # them (and views of them) for every pair.
    own = np.empty((SCRATCH_ROWS + 17, 4))
    work = borrowed(own)
    wk = work[:SCRATCH_ROWS]
    vx = work[SCRATCH_ROWS]
    vh = work[SCRATCH_ROWS + 1]
    pn = work[SCRATCH_ROWS + 2]
    vs = work[SCRATCH_ROWS + 4 : SCRATCH_ROWS + 8]
    vr = np.eye(4)
    zero = np.zeros(4)
    nw = wb.shape[0]
    ns = so.shape[0]
    ncv = cr.shape[0]
    reuse_distance = prm.reuse_distance
    reuse_angle = prm.reuse_angle
    reuse = reuse_angle > 0.0
    base = prm.margin
    old_key = kept.key
    old_first = kept.first
    old_count = kept.count
    old_axis = kept.axis
    old_pose = kept.pose
    old_local = kept.local
    n_old = kept.pairs[0]
    new_key = kept_out.key
    new_first = kept_out.first
    new_count = kept_out.count
    new_axis = kept_out.axis
    new_pose = kept_out.pose
    new_local = kept_out.local
    pose = work[SCRATCH_ROWS + 8 : SCRATCH_ROWS + 13].reshape(20)
    solid_rot = work[SCRATCH_ROWS + 13 : SCRATCH_ROWS + 17]
    oi = 0
    n_new = 0
    rows = 0
    for op in range(npairs):
        p = order[op]
        a = pairs[p, 0]
        b = pairs[p, 1]
        got = 0
        tq = -1
        # The frame of b if this is a box pair whose manifold can be kept:
        # 1 body b, 2 a solid box, 0 the world; -1 not kept.
        frame = -1
        if reuse and shape[a] == BOX:
            if b >= 0:
                if shape[b] == BOX:
                    frame = 1
            else:
                s = -1 - b
                if s < nh + nw or nh + nw + ns <= s < nh + nw + ns + ncv:
                    frame = 0
                elif s < nh + nw + ns:
                    frame = 2
        fx = zero
        fr = vr
        if frame == 1:
            fx = pos[b]
            fr = rot[b]
        elif frame == 2:
            s = -1 - b - nh - nw
            fx = so[s, :4]
            for t in range(4):
                for q in range(4):
                    solid_rot[t, q] = so[s, 8 + 4 * t + q]
            fr = solid_rot
        reused = False
        tried = -1
        if frame >= 0:
            while oi < n_old and old_key[oi] < keys[p]:
                oi += 1
            if oi < n_old and old_key[oi] == keys[p]:
                if old_count[oi] == 0:
                    # Two boxes that were apart: try last tick's separating axis first.
                    tried = old_axis[oi]
                else:
                    pair_pose(pos[a], rot[a], fx, fr, pose)
                    reused = pose_close(pose, old_pose, oi, reuse_distance, reuse_angle)
            if reused:
                m = marg[a] + (marg[b] - base if b >= 0 else 0.0)
                got = emit_kept(old_local, old_first[oi], old_count[oi], pos[a], rot[a], fx, fr, m, cp, cn, cd, k)
                # Kept as it was (with the pose it was found at, so slow drift
                # still reaches the tolerance).
                new_key[n_new] = keys[p]
                new_first[n_new] = rows
                new_count[n_new] = old_count[oi]
                new_axis[n_new] = -1
                for t in range(20):
                    new_pose[n_new, t] = old_pose[oi, t]
                for j in range(old_count[oi]):
                    for t in range(12):
                        new_local[rows + j, t] = old_local[old_first[oi] + j, t]
                rows += old_count[oi]
                n_new += 1
        if reused:
            pass
        elif b >= 0:
            m = marg[a] + marg[b] - base
            # Bounding balls apart by more than the margin: no contact whatever
            # the shapes (a cheap exit before the full test; the box-box test
            # would find none either).
            d2 = 0.0
            for t in range(4):
                e = pos[b, t] - pos[a, t]
                d2 += e * e
            reach = 1.001 * (bound[a] + bound[b] + m)
            if d2 > reach * reach:
                pass
            elif shape[a] == SPHERE and shape[b] == SPHERE:
                got = sphere_sphere(pos[a], half[a, 0], pos[b], half[b, 0], m, wk, cp, cn, cd, k)
            elif shape[a] == BOX and shape[b] == SPHERE:
                got = box_sphere(pos[a], rot[a], half[a], pos[b], half[b, 0], m, wk, cp, cn, cd, k)
            elif shape[a] == SPHERE and shape[b] == BOX:
                got = box_sphere(pos[b], rot[b], half[b], pos[a], half[a, 0], m, wk, cp, cn, cd, k)
                for q in range(got):
                    for t in range(4):
                        cn[k + q, t] = -cn[k + q, t]
            elif tried >= 0 and separated_along(tried, pos[a], rot[a], half[a], pos[b], rot[b], half[b], m, wk):
                got = -1 - tried
            else:
                got = box_box(
                    pos[a], rot[a], half[a], pos[b], rot[b], half[b], m, scratch_p, scratch_d, wk, cp, cn, cd, k
                )
        else:
            s = -1 - b
            m = marg[a]
            if s < nh:
                for t in range(4):
                    pn[t] = hs[s, t]
                if shape[a] == SPHERE:
                    got = sphere_halfspace(pos[a], half[a, 0], pn, hs[s, 4], m, cp, cn, cd, k)
                else:
                    got = box_halfspace(
                        pos[a], rot[a], half[a], pn, hs[s, 4], m, scratch_p, scratch_d, wk, cp, cn, cd, k
                    )
            elif s >= nh + wb.shape[0] + so.shape[0] + cr.shape[0]:
                # A level's other solid object: the tets of its boundary.
                q = s - nh - wb.shape[0] - so.shape[0] - cr.shape[0]
                t0 = tr[q, 0]
                t1 = tr[q, 1]
                tq = q
                ax = int(tsw[q, 0])
                ext = tsw[q, 1]
                if shape[a] == SPHERE:
                    got = sphere_tets(
                        pos[a], half[a, 0], tets, tpl, tby, tbd, t0, t1, ax, ext, m, tcp, tcn, tcd, cp, cn, cd, k
                    )
                else:
                    got = box_tets(
                        pos[a], rot[a], half[a], tets, tpl, tby, tbd, t0, t1, ax, ext, m, tcp, tcn, tcd, cp, cn, cd, k
                    )
            elif s >= nh + wb.shape[0] + so.shape[0]:
                # A level's convex solid: against its facet of least penetration.
                q = s - nh - wb.shape[0] - so.shape[0]
                best = -np.inf
                bf = -1
                for f in range(cr[q, 0], cr[q, 1]):
                    sep = -cpl[f, 4]
                    for t in range(4):
                        sep += cpl[f, t] * pos[a, t]
                    if shape[a] == SPHERE:
                        sep -= half[a, 0]
                    else:
                        for t in range(4):
                            u = 0.0
                            for v in range(4):
                                u += cpl[f, v] * rot[a, v, t]
                            sep -= half[a, t] * abs(u)
                    if sep > best:
                        best = sep
                        bf = f
                if bf >= 0 and best <= m:
                    for t in range(4):
                        pn[t] = cpl[bf, t]
                    if shape[a] == SPHERE:
                        got = sphere_halfspace(pos[a], half[a, 0], pn, cpl[bf, 4], m, cp, cn, cd, k)
                    else:
                        got = box_halfspace(
                            pos[a], rot[a], half[a], pn, cpl[bf, 4], m, scratch_p, scratch_d, wk, cp, cn, cd, k
                        )
            elif s >= nh + wb.shape[0]:
                # A level's solid object: an oriented 4D box.
                s -= nh + wb.shape[0]
                for t in range(4):
                    vx[t] = so[s, t]
                    vh[t] = so[s, 4 + t]
                    for q in range(4):
                        vs[t, q] = so[s, 8 + 4 * t + q]
                if shape[a] == SPHERE:
                    got = box_sphere(vx, vs, vh, pos[a], half[a, 0], m, wk, cp, cn, cd, k)
                    for q in range(got):
                        for t in range(4):
                            cn[k + q, t] = -cn[k + q, t]
                else:
                    got = box_box(pos[a], rot[a], half[a], vx, vs, vh, m, scratch_p, scratch_d, wk, cp, cn, cd, k)
            else:
                # A world box spans all of w: make it a 4D box wide enough in w
                # that its w faces can never be the separating axis.
                s -= nh
                rad = 0.0
                for t in range(4):
                    rad += half[a, t] * half[a, t]
                for t in range(3):
                    vx[t] = wb[s, t]
                    vh[t] = wb[s, 3 + t]
                vx[3] = pos[a, 3]
                vh[3] = 4.0 * np.sqrt(rad) + 1.0
                if shape[a] == SPHERE:
                    got = box_sphere(vx, vr, vh, pos[a], half[a, 0], m, wk, cp, cn, cd, k)
                    for q in range(got):
                        for t in range(4):
                            cn[k + q, t] = -cn[k + q, t]
                else:
                    got = box_box(pos[a], rot[a], half[a], vx, vr, vh, m, scratch_p, scratch_d, wk, cp, cn, cd, k)
        apart = -1
        if got < 0:
            # box_box found a separating axis.
            apart = -1 - got
            got = 0
        if frame == 1 and apart >= 0:
            new_key[n_new] = keys[p]
            new_first[n_new] = rows
            new_count[n_new] = 0
            new_axis[n_new] = apart
            n_new += 1
        elif frame >= 0 and not reused and got > 0:
            pair_pose(pos[a], rot[a], fx, fr, pose)
            keep_points(cp, cn, cd, k, got, pos[a], rot[a], fx, fr, new_local, rows)
            new_key[n_new] = keys[p]
            new_first[n_new] = rows
            new_count[n_new] = got
            new_axis[n_new] = -1
            for t in range(20):
                new_pose[n_new, t] = pose[t]
            rows += got
            n_new += 1
        for q in range(got):
            body_a[k + q] = a
            body_b[k + q] = b
            pair_key[k + q] = keys[p]
            # A moving tet mesh's surface velocity at the point (zero for all else).
            for t in range(4):
                v = 0.0
                if tq >= 0:
                    v = tmo[tq, t, 4]
                    for j in range(4):
                        v += tmo[tq, t, j] * cp[k + q, j]
                surf[k + q, t] = v
        k += got
    kept_out.pairs[0] = n_new
    keep(own)
    return k


@njit(cache=True)
def apply_forces(bodies, prm, h):
    """Gravity, optional inverse-cube attraction and damping for awake dynamic bodies
    over a substep of ``h`` seconds (``prm``: a record of ``PARAMS_DTYPE``)."""
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    awake = bodies.awake
    pos = bodies.position
    vel = bodies.velocity
    omg = bodies.angular_velocity
    mass = bodies.mass
    gravity = prm.gravity
    G = prm.inverse_cube_G
    eps2 = prm.softening * prm.softening
    lin = 1.0 / (1.0 + h * prm.linear_damping)
    ang = 1.0 / (1.0 + h * prm.angular_damping)
    acc = np.zeros((nb, 4))
    if G != 0.0:
        # Gauss's law in 4D: |F| = G m1 m2 / r^3, so a_i = G m_j d / r^4.
        for i in range(nb):
            if not (alive[i] and kind[i] == DYNAMIC and awake[i]):
                continue
            for j in range(nb):
                if j == i or not alive[j] or mass[j] <= 0.0:
                    continue
                r2 = eps2
                for m in range(4):
                    t = pos[j, m] - pos[i, m]
                    r2 += t * t
                f = G * mass[j] / (r2 * r2)
                for m in range(4):
                    acc[i, m] += f * (pos[j, m] - pos[i, m])
    for i in range(nb):
        if not (alive[i] and kind[i] == DYNAMIC and awake[i]):
            continue
        for m in range(4):
            vel[i, m] = (vel[i, m] + h * (gravity[m] + acc[i, m])) * lin
        if ang != 1.0:
            for k in range(6):
                omg[i, k] *= ang


@njit(cache=True)
def integrate_positions(bodies, h, orthonormalise=True):
    """Move awake dynamic and kinematic bodies by one substep.

    Bodies with an isotropic inertia (hyperspheres, hypercubes) keep their
    angular velocity while free. Other boxes precess: their world angular
    momentum ``L = I_world(R) omega`` is what is conserved, so the rotation uses
    the midpoint rate recomputed from ``L`` and ``omega`` is re-derived from
    ``L`` afterwards (second order, and ``L`` is kept exactly).
    ``orthonormalise`` is passed on to :func:`.bivector.rotate_by`.
    """
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    awake = bodies.awake
    pos = bodies.position
    rot = bodies.rotation
    vel = bodies.velocity
    omg = bodies.angular_velocity
    inv_inertia = bodies.inv_inertia
    # Work arrays borrowed (see .borrow): rotate_by gets them for every body.
    own = np.empty((6, 4, 4))
    wk = borrowed(own)[:5]
    rh = borrowed(own)[5]
    own6 = np.empty((9, 6))
    M = borrowed(own6)[:6]
    lw = borrowed(own6)[6]
    lb = borrowed(own6)[7]
    wh = borrowed(own6)[8]
    for i in range(nb):
        if not alive[i] or kind[i] == STATIC:
            continue
        if kind[i] == DYNAMIC and not awake[i]:
            continue
        for m in range(4):
            pos[i, m] += h * vel[i, m]
        iso = True
        for k in range(1, 6):
            if inv_inertia[i, k] != inv_inertia[i, 0]:
                iso = False
        if iso or kind[i] == KINEMATIC:
            rotate_by(omg[i], h, rot[i], wk, orthonormalise)
            continue
        compound(rot[i], M)
        for k in range(6):
            s = 0.0
            for j in range(6):
                s += M[j, k] * omg[i, j]
            lb[k] = s / inv_inertia[i, k]
        for k in range(6):
            s = 0.0
            for j in range(6):
                s += M[k, j] * lb[j]
            lw[k] = s
        for a in range(4):
            for b in range(4):
                rh[a, b] = rot[i, a, b]
        rotate_by(omg[i], 0.5 * h, rh, wk, False)
        _omega_from_l(rh, inv_inertia[i], lw, M, wh)
        rotate_by(wh, h, rot[i], wk, orthonormalise)
        _omega_from_l(rot[i], inv_inertia[i], lw, M, omg[i])
    keep(own)
    keep(own6)


@njit(cache=True)
def _omega_from_l(r, inv_i, lw, M, out):
    compound(r, M)
    tmp = np.empty(6)
    for k in range(6):
        s = 0.0
        for j in range(6):
            s += M[j, k] * lw[j]
        tmp[k] = s * inv_i[k]
    for k in range(6):
        s = 0.0
        for j in range(6):
            s += M[k, j] * tmp[j]
        out[k] = s


@njit(cache=True)
def _find(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@njit(cache=True)
def update_sleep(bodies, npairs, pairs, prm):
    """Islands by union-find over the broadphase pairs; whole islands sleep.

    A body is calm when its speed and spin stay under the thresholds; an island
    sleeps once all its bodies have been calm for ``sleep_time``. Sleeping
    bodies keep the island id so a touch wakes all of them together.

    Islands join bodies whose (margin-expanded) boxes overlap, the same test
    that wakes sleepers: joining only bodies in actual contact would let two
    neighbours fall asleep at different times and wake each other forever.
    """
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    awake = bodies.awake
    vel = bodies.velocity
    omg = bodies.angular_velocity
    timer = bodies.sleep_timer
    island = bodies.island
    h = prm.tick_dt
    parent = np.arange(nb)
    stir = np.zeros(nb, dtype=np.bool_)
    for c in range(npairs):
        a = pairs[c, 0]
        b = pairs[c, 1]
        if b < 0:
            continue
        if kind[a] == DYNAMIC and kind[b] == DYNAMIC:
            ra = _find(parent, a)
            rb = _find(parent, b)
            if ra != rb:
                # Smaller index as root keeps island ids independent of order.
                if ra < rb:
                    parent[rb] = ra
                else:
                    parent[ra] = rb
        elif kind[a] == KINEMATIC and _moving(a, kind, awake, vel, omg):
            stir[b] = True
        elif kind[b] == KINEMATIC and _moving(b, kind, awake, vel, omg):
            stir[a] = True
    lin2 = prm.sleep_linear**2
    ang2 = prm.sleep_angular**2
    mint = np.full(nb, np.inf)
    for i in range(nb):
        if not (alive[i] and kind[i] == DYNAMIC and awake[i]):
            continue
        v2 = 0.0
        for m in range(4):
            v2 += vel[i, m] * vel[i, m]
        w2 = 0.0
        for k in range(6):
            w2 += omg[i, k] * omg[i, k]
        if v2 < lin2 and w2 < ang2 and not stir[i]:
            timer[i] += h
        else:
            timer[i] = 0.0
        r = _find(parent, i)
        if timer[i] < mint[r]:
            mint[r] = timer[i]
    if prm.allow_sleep == 0.0:
        return
    for i in range(nb):
        if not (alive[i] and kind[i] == DYNAMIC and awake[i]):
            continue
        r = _find(parent, i)
        if mint[r] >= prm.sleep_time:
            awake[i] = False
            island[i] = r
            for m in range(4):
                vel[i, m] = 0.0
            for k in range(6):
                omg[i, k] = 0.0


@njit(cache=True)
def _borrow(bodies, static, contacts, warm, rows, scratch):
    """The bundles with every array :func:`.borrow.borrowed` (the caller keeps the originals alive)."""
    b = bodies
    bodies = Bodies(
        b.count,
        borrowed(b.alive),
        borrowed(b.kind),
        borrowed(b.shape),
        borrowed(b.half_extents),
        borrowed(b.bound),
        borrowed(b.position),
        borrowed(b.rotation),
        borrowed(b.velocity),
        borrowed(b.angular_velocity),
        borrowed(b.mass),
        borrowed(b.inv_mass),
        borrowed(b.inv_inertia),
        borrowed(b.friction),
        borrowed(b.restitution),
        borrowed(b.awake),
        borrowed(b.sleep_timer),
        borrowed(b.island),
    )
    s = static
    static = StaticWorld(
        borrowed(s.half_spaces),
        borrowed(s.boxes),
        borrowed(s.solids),
        borrowed(s.convex_planes),
        borrowed(s.convex_ranges),
        borrowed(s.convex_bounds),
        borrowed(s.tets),
        borrowed(s.tet_planes),
        borrowed(s.tet_bary),
        borrowed(s.tet_bounds),
        borrowed(s.tet_ranges),
        borrowed(s.tet_mesh_bounds),
        borrowed(s.tet_sweep),
        borrowed(s.tet_motion),
    )
    c = contacts
    contacts = Contacts(
        borrowed(c.body_a),
        borrowed(c.body_b),
        borrowed(c.key),
        borrowed(c.point),
        borrowed(c.normal),
        borrowed(c.depth),
        borrowed(c.normal_impulse),
        borrowed(c.surface_velocity),
    )
    w = warm
    warm = WarmStart(
        borrowed(w.key),
        borrowed(w.local_point),
        borrowed(w.normal_impulse),
        borrowed(w.friction_impulse),
        borrowed(w.count),
    )
    sp = rows.spin
    spin = SpinRows(
        borrowed(sp.limits),
        borrowed(sp.planes),
        borrowed(sp.eff_mass),
        borrowed(sp.impulse),
    )
    r = rows
    rows = SolverRows(
        borrowed(r.direction),
        borrowed(r.anchor_a),
        borrowed(r.anchor_b),
        borrowed(r.normal_response),
        borrowed(r.eff_mass),
        borrowed(r.impulse),
        borrowed(r.local_point),
        borrowed(r.approach_speed),
        borrowed(r.max_normal_impulse),
        borrowed(r.friction),
        borrowed(r.restitution),
        borrowed(r.separation),
        spin,
    )
    x = scratch
    scratch = Scratch(
        borrowed(x.pairs),
        borrowed(x.margin),
        borrowed(x.points),
        borrowed(x.point_depths),
        borrowed(x.needed),
        borrowed(x.tet_points),
        borrowed(x.tet_normals),
        borrowed(x.tet_depths),
    )
    return bodies, static, contacts, warm, rows, scratch


@njit(cache=True)
def _borrow_kept(k):
    return Manifolds(
        borrowed(k.key),
        borrowed(k.first),
        borrowed(k.count),
        borrowed(k.axis),
        borrowed(k.pose),
        borrowed(k.local),
        borrowed(k.pairs),
    )


@njit(cache=True)
def tick(bodies, static, params, contacts, warm, rows, scratch, kept, kept_out):
    """Advance the world by one tick of ``tick_dt`` in ``substeps`` substeps.

    Parameters
    ----------
    bodies : Bodies
        Updated in place.
    static : StaticWorld
    params : (1,) PARAMS_DTYPE record array
    contacts : Contacts
        Output: this tick's contacts (the first ``n``, ``n`` returned).
    warm : WarmStart
        Last tick's impulses; replaced by this tick's.
    rows : SolverRows
        Solver scratch sized like ``contacts``.
    scratch : Scratch
    kept, kept_out : Manifolds
        Last tick's box manifolds, and where this tick's go (the caller swaps
        them after a tick that ran).

    Returns
    -------
    int
        Number of contacts solved; ``-1`` if ``scratch.pairs`` overflowed and
        ``-2`` if the contact arrays did (``scratch.needed[0]`` then holds the
        size needed). No body has moved in those cases; only sleeping islands
        may have woken.
    """
    # The arrays without reference counting (see .borrow): the caller holds them.
    bodies, static, contacts, warm, rows, scratch = _borrow(bodies, static, contacts, warm, rows, scratch)
    kept = _borrow_kept(kept)
    kept_out = _borrow_kept(kept_out)
    prm = params[0]
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    shape = bodies.shape
    pos = bodies.position
    rot = bodies.rotation
    inv_inertia = bodies.inv_inertia
    awake = bodies.awake
    dt = prm.tick_dt
    ns = int(prm.substeps)
    h = dt / ns
    npairs = find_pairs(bodies, static, dt, prm.margin, scratch.pairs, scratch.margin)
    if npairs < 0:
        scratch.needed[0] = -npairs
        return -1
    nc = narrowphase(npairs, bodies, static, scratch, contacts, kept, kept_out, prm)
    if nc < 0:
        scratch.needed[0] = -nc
        return -2
    iinv = np.zeros((nb, 6, 6))
    # Isotropic inverse inertia per body (balls, hypercubes, non-dynamic
    # bodies at 0), or -1 where the full 6x6 operator is needed.
    iso = np.zeros(nb)
    for i in range(nb):
        if alive[i] and kind[i] == DYNAMIC and awake[i]:
            world_inverse_inertia(rot[i], inv_inertia[i], iinv[i])
            iso[i] = inv_inertia[i, 0]
            for k in range(1, 6):
                if inv_inertia[i, k] != inv_inertia[i, 0]:
                    iso[i] = -1.0
    prepare(nc, contacts, bodies, iinv, iso, prm, warm, rows)
    own_iinv = iinv
    iinv = borrowed(own_iinv)
    x0 = pos[:nb].copy()
    r0 = rot[:nb].copy()
    dpos = np.zeros((nb, 4))
    drot = np.zeros((nb, 4, 4))
    for i in range(nb):
        for m in range(4):
            drot[i, m, m] = 1.0
    # Stiffness no faster than a quarter of the substep rate stays stable.
    hz = min(prm.contact_hertz, 0.25 / h)
    bias_rate, mass_scale, impulse_scale = soft_params(hz, prm.damping_ratio, h)
    inv_h = 1.0 / h
    iters = int(prm.iterations)
    relax = int(prm.relax_iterations)
    push = prm.max_push
    total = contacts.normal_impulse
    lam = rows.impulse
    for c in range(nc):
        total[c] = 0.0
    # The separations before the first substep; later substeps start with those
    # of the previous relax pass (the bodies have not moved since).
    current_separation(nc, contacts, rows, dpos, drot)
    for step in range(ns):
        apply_forces(bodies, prm, h)
        warm_start(nc, contacts, rows, bodies, iso, iinv)
        solve(nc, contacts, rows, bodies, iso, iinv, inv_h, True, bias_rate, mass_scale, impulse_scale, push, iters)
        # Rotations are re-orthonormalised once a tick, after the last substep.
        integrate_positions(bodies, h, step == ns - 1)
        for i in range(nb):
            if not alive[i] or kind[i] == STATIC:
                continue
            for m in range(4):
                dpos[i, m] = pos[i, m] - x0[i, m]
            if shape[i] == SPHERE:
                # A ball's contact point stays where the normal leaves its
                # centre however it spins; rotating the anchor would make a
                # rolling ball look lifted off the ground and let it sink.
                continue
            for m in range(4):
                for q in range(4):
                    s = 0.0
                    for k in range(4):
                        s += rot[i, m, k] * r0[i, q, k]
                    drot[i, m, q] = s
        current_separation(nc, contacts, rows, dpos, drot)
        solve(nc, contacts, rows, bodies, iso, iinv, inv_h, False, bias_rate, mass_scale, impulse_scale, push, relax)
        for c in range(nc):
            total[c] += lam[c, 0]
    for c in range(nc):
        total[c] -= lam[c, 0]
    restitution(nc, contacts, rows, bodies, iso, iinv, prm.restitution_threshold)
    for c in range(nc):
        total[c] += lam[c, 0]
    keep(own_iinv)
    store(nc, contacts, rows, warm)
    update_sleep(bodies, npairs, scratch.pairs, prm)
    return nc
