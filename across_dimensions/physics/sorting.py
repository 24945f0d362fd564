"""A small stable argsort for the compiled pipeline.

``np.argsort(kind="mergesort")`` works inside numba but takes seconds to
compile for each key type; this bottom-up merge sort does the same job (stable,
so ties keep index order and the result is deterministic) and compiles fast.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit


@njit(cache=True)
def argsort_stable(keys):
    """Indices that sort ``keys`` ascending; equal keys keep their order.

    Parameters
    ----------
    keys : (n,) float64 or int64

    Returns
    -------
    (n,) int64
    """
    n = keys.shape[0]
    idx = np.arange(n)
    tmp = np.empty(n, dtype=np.int64)
    width = 1
    while width < n:
        lo = 0
        while lo < n:
            mid = min(lo + width, n)
            hi = min(lo + 2 * width, n)
            i = lo
            j = mid
            k = lo
            while i < mid and j < hi:
                # "<=" takes from the left run on ties: stability.
                if keys[idx[i]] <= keys[idx[j]]:
                    tmp[k] = idx[i]
                    i += 1
                else:
                    tmp[k] = idx[j]
                    j += 1
                k += 1
            while i < mid:
                tmp[k] = idx[i]
                i += 1
                k += 1
            while j < hi:
                tmp[k] = idx[j]
                j += 1
                k += 1
            lo = hi
        idx, tmp = tmp, idx
        width *= 2
    return idx
