"""One fixed physics tick (several substeps) as a single compiled kernel.

The stages, each in its own module, in this order (all in body-index and
pair-key order, so the result depends only on the inputs, never on timing or
hashing):

1. :mod:`.broadphase`: bounding boxes, sort-and-sweep, pairs with the static
   world; sleeping islands touched by moving bodies wake (:mod:`.islands`);
2. :mod:`.narrowphase`: contacts for the pairs, sorted by pair key, box
   manifolds kept while a pair barely moves (:mod:`.reuse`);
3. :mod:`.prepare`: solver rows for every contact, warm started;
4. substeps of the soft-step solver: forces, warm start, solve
   (:mod:`.solver`), move (:mod:`.integration`), relax; then restitution;
5. :mod:`.islands`: islands from the broadphase pairs, and sleeping.

The kernel checks buffer capacity before it changes any body, so the caller can
grow the buffers and call it again when it reports an overflow. Its arguments
are the named bundles of :mod:`.state` (bodies, static world, parameters,
contacts, warm start, solver rows, scratch, manifolds).
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .borrow import (
    borrow_bodies,
    borrow_contacts,
    borrow_manifolds,
    borrow_rows,
    borrow_scratch,
    borrow_static,
    borrow_warm,
    borrowed,
    keep,
)
from .broadphase import find_pairs
from .integration import apply_forces, integrate_positions, track_motion
from .islands import update_sleep
from .narrowphase import narrowphase
from .prepare import prepare, world_inertia
from .solver import current_separation, restitution, softness, solve, store, warm_start
from .state import Inertia


@njit(cache=True)
def _substeps(nc, bodies, contacts, rows, inertia, prm):
    """The substeps of a tick: forces, warm start, solve, move, relax.

    ``contacts.normal_impulse`` gets each contact's normal impulse summed over
    the substeps' relax passes (for events).
    """
    nb = bodies.count
    ns = int(prm.substeps)
    h = prm.tick_dt / ns
    x0 = bodies.position[:nb].copy()
    r0 = bodies.rotation[:nb].copy()
    dpos = np.zeros((nb, 4))
    drot = np.zeros((nb, 4, 4))
    for i in range(nb):
        for m in range(4):
            drot[i, m, m] = 1.0
    soft = softness(prm.contact_hertz, prm.damping_ratio, h, prm.max_push)
    iters = int(prm.iterations)
    relax = int(prm.relax_iterations)
    total = contacts.normal_impulse
    lam = rows.impulse
    for c in range(nc):
        total[c] = 0.0
    # The separations before the first substep; later substeps start with those
    # of the previous relax pass (the bodies have not moved since).
    current_separation(nc, contacts, rows, dpos, drot)
    for step in range(ns):
        apply_forces(bodies, prm, h)
        warm_start(nc, contacts, rows, bodies, inertia)
        solve(nc, contacts, rows, bodies, inertia, soft, True, iters)
        # Rotations are re-orthonormalised once a tick, after the last substep.
        integrate_positions(bodies, h, step == ns - 1)
        track_motion(bodies, x0, r0, dpos, drot)
        current_separation(nc, contacts, rows, dpos, drot)
        solve(nc, contacts, rows, bodies, inertia, soft, False, relax)
        for c in range(nc):
            total[c] += lam[c, 0]


@njit(cache=True)
def tick(bodies, static, params, contacts, warm, rows, scratch, manifolds):
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
    manifolds : (Manifolds, Manifolds)
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
    bodies = borrow_bodies(bodies)
    static = borrow_static(static)
    contacts = borrow_contacts(contacts)
    warm = borrow_warm(warm)
    rows = borrow_rows(rows)
    scratch = borrow_scratch(scratch)
    kept = borrow_manifolds(manifolds[0])
    kept_out = borrow_manifolds(manifolds[1])
    prm = params[0]
    npairs = find_pairs(bodies, static, prm.tick_dt, prm.margin, scratch.pairs, scratch.margin)
    if npairs < 0:
        scratch.needed[0] = -npairs
        return -1
    nc = narrowphase(npairs, bodies, static, scratch, contacts, kept, kept_out, prm)
    if nc < 0:
        scratch.needed[0] = -nc
        return -2
    own = world_inertia(bodies)
    inertia = Inertia(borrowed(own.iso), borrowed(own.full))
    prepare(nc, contacts, bodies, inertia, prm, warm, rows)
    _substeps(nc, bodies, contacts, rows, inertia, prm)
    total = contacts.normal_impulse
    lam = rows.impulse
    for c in range(nc):
        total[c] -= lam[c, 0]
    restitution(nc, contacts, rows, bodies, inertia, prm.restitution_threshold)
    for c in range(nc):
        total[c] += lam[c, 0]
    keep(own.iso)
    keep(own.full)
    store(nc, contacts, rows, warm)
    update_sleep(bodies, npairs, scratch.pairs, prm)
    return nc
