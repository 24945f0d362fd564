"""Borrowed views of the tick's arrays: no reference counting inside the kernels.

Numba counts references to every array it passes around: each call of a
compiled function with array arguments, each view such as ``pos[a]`` and each
array picked into a variable adds and later removes one, with an atomic
instruction on the array's shared count. In the physics tick these updates ran
millions of times a second (for one pile of 1000 bodies, about a third of the
tick was spent in them) although none of the arrays can be freed while the
tick runs: the caller holds them all.

:func:`borrowed` returns a view of an array without that count (its
``meminfo`` is null, as for a view of a global constant), so every count
update on it, and on views taken from it, is a null check instead of an atomic
operation. :func:`~across_dimensions.physics.pipeline.tick` borrows the arrays
of its bundles once, on entry (:func:`borrow_bodies` and the others below); the
kernels it calls see the same types and the same data.

The rule that makes this safe: a borrowed view lives no longer than the array it
came from. Never return one, store one in an array or bundle that outlives the
call, or borrow an array the kernel itself allocated and then drops.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from across_dimensions.core._jit import njit

from .state import Bodies, Contacts, Manifolds, Scratch, SolverRows, SpinRows, StaticWorld, WarmStart


@intrinsic
def borrowed(typingctx, arr):
    """A view of ``arr`` (same type, shape, strides and data) without a reference count.

    Parameters
    ----------
    arr : ndarray
        Any array the caller keeps alive for as long as the view is used.

    Returns
    -------
    ndarray
        The view; it does not keep ``arr`` alive.
    """
    if not isinstance(arr, types.Array):
        return None

    def codegen(context, builder, signature, args):
        src = context.make_array(arr)(context, builder, value=args[0])
        out = context.make_array(arr)(context, builder)
        out.meminfo = cgutils.get_null_value(out.meminfo.type)
        out.parent = cgutils.get_null_value(out.parent.type)
        out.nitems = src.nitems
        out.itemsize = src.itemsize
        out.data = src.data
        out.shape = src.shape
        out.strides = src.strides
        return out._getvalue()

    return arr(arr), codegen


@intrinsic
def keep(typingctx, arr):
    """Mark ``arr`` as used here, so a kernel's own array outlives the views borrowed from it.

    Numba frees an array after its last use; a kernel that works through
    ``borrowed(own)`` calls ``keep(own)`` after its last use of the view.
    Generates no code.
    """
    if not isinstance(arr, types.Array):
        return None

    def codegen(context, builder, signature, args):
        return context.get_dummy_value()

    return types.none(arr), codegen


@njit(cache=True)
def borrow_bodies(b):
    """``b`` (:class:`~.state.Bodies`) with every array borrowed; the caller keeps the originals alive."""
    return Bodies(
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


@njit(cache=True)
def borrow_static(s):
    """``s`` (:class:`~.state.StaticWorld`) with every array borrowed."""
    return StaticWorld(
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


@njit(cache=True)
def borrow_contacts(c):
    """``c`` (:class:`~.state.Contacts`) with every array borrowed."""
    return Contacts(
        borrowed(c.body_a),
        borrowed(c.body_b),
        borrowed(c.key),
        borrowed(c.point),
        borrowed(c.normal),
        borrowed(c.depth),
        borrowed(c.normal_impulse),
        borrowed(c.surface_velocity),
    )


@njit(cache=True)
def borrow_warm(w):
    """``w`` (:class:`~.state.WarmStart`) with every array borrowed."""
    return WarmStart(
        borrowed(w.key),
        borrowed(w.local_point),
        borrowed(w.normal_impulse),
        borrowed(w.friction_impulse),
        borrowed(w.count),
    )


@njit(cache=True)
def borrow_rows(r):
    """``r`` (:class:`~.state.SolverRows`) with every array borrowed."""
    return SolverRows(
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
        SpinRows(borrowed(r.spin.limits), borrowed(r.spin.planes), borrowed(r.spin.eff_mass), borrowed(r.spin.impulse)),
    )


@njit(cache=True)
def borrow_scratch(x):
    """``x`` (:class:`~.state.Scratch`) with every array borrowed."""
    return Scratch(
        borrowed(x.pairs),
        borrowed(x.margin),
        borrowed(x.points),
        borrowed(x.point_depths),
        borrowed(x.needed),
        borrowed(x.tet_points),
        borrowed(x.tet_normals),
        borrowed(x.tet_depths),
    )


@njit(cache=True)
def borrow_manifolds(k):
    """``k`` (:class:`~.state.Manifolds`) with every array borrowed."""
    return Manifolds(
        borrowed(k.key),
        borrowed(k.first),
        borrowed(k.count),
        borrowed(k.axis),
        borrowed(k.pose),
        borrowed(k.local),
        borrowed(k.pairs),
    )
