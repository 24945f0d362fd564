"""One place that configures numba for the core.

Kernels are compiled with ``cache=True`` so only the first run after an install
pays for compilation. Where the cache lives is the host's choice, not the
core's: the game (``across_dimensions.app``) points ``NUMBA_CACHE_DIR`` at the
platform's cache folder before numba is imported; a library user gets numba's
default (the package's ``__pycache__``, or numba's per-user folder when that is
read-only).
"""

from __future__ import annotations

import numba


def njit(*args, **kwargs):
    """``numba.njit`` with NumPy's error model: a division by zero gives inf or
    NaN instead of a Python exception, which would cost a branch per division
    in every kernel. The kernels guard their divisions themselves."""
    kwargs.setdefault("error_model", "numpy")
    return numba.njit(*args, **kwargs)
