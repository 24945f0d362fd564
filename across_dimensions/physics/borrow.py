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
of its bundles once, on entry; the kernels it calls see the same types and the
same data.

The rule that makes this safe: a borrowed view lives no longer than the array it
came from. Never return one, store one in an array or bundle that outlives the
call, or borrow an array the kernel itself allocated and then drops.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


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
