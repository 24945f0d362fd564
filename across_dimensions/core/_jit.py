"""One place that configures numba for the core.

Compiled kernels are cached on disk so only the first run after an install pays
for compilation. Numba needs a writable cache directory: when the user has not
chosen one (``NUMBA_CACHE_DIR``), use the per-user cache folder rather than the
package folder, which may be read-only in a system or wheel install.
"""

from __future__ import annotations

import os

if "NUMBA_CACHE_DIR" not in os.environ:
    _base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    os.environ["NUMBA_CACHE_DIR"] = os.path.join(_base, "across-dimensions", "numba")

import numba  # noqa: E402  (must follow the environment set-up above)


def njit(*args, **kwargs):
    """``numba.njit`` with NumPy's error model: a division by zero gives inf or
    NaN instead of a Python exception, which would cost a branch per division
    in every kernel. The kernels guard their divisions themselves."""
    kwargs.setdefault("error_model", "numpy")
    return numba.njit(*args, **kwargs)
