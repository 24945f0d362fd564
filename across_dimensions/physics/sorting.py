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


@njit(cache=True)
def argsort_by_body(keys, first, nb):
    """:func:`argsort_stable` of ``keys`` whose high part is a small body index.

    Counting sort by ``first`` (``0 <= first < nb``), then an insertion sort of
    each body's few entries by the full key: linear in the number of keys, where
    the merge sort takes ``log2(n)`` passes (a tick sorts about ten thousand pair
    keys). Both sorts are stable, so the order is exactly that of
    :func:`argsort_stable` whenever ``keys`` sort first by ``first``.

    Parameters
    ----------
    keys : (n,) int64
        Sort keys, ordered first by ``first``.
    first : (n,) int64
        Each key's body index.
    nb : int
        Bound on ``first``.

    Returns
    -------
    (n,) int64
    """
    n = keys.shape[0]
    start = np.zeros(nb + 1, dtype=np.int64)
    for p in range(n):
        start[first[p] + 1] += 1
    for i in range(nb):
        start[i + 1] += start[i]
    fill = start[:nb].copy()
    idx = np.empty(n, dtype=np.int64)
    for p in range(n):
        a = first[p]
        idx[fill[a]] = p
        fill[a] += 1
    for i in range(nb):
        for q in range(start[i] + 1, start[i + 1]):
            p = idx[q]
            key = keys[p]
            r = q
            # ">" (never ">="): equal keys keep their order.
            while r > start[i] and keys[idx[r - 1]] > key:
                idx[r] = idx[r - 1]
                r -= 1
            idx[r] = p
    return idx
