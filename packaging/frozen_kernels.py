"""The locator numba uses for the frozen game's shipped kernels (see :mod:`kernel_target`).

Numba imports this module itself (``NUMBA_CACHE_LOCATOR_CLASSES``, set by launch.py), after
launch.py has set numba's environment.
"""

from __future__ import annotations

import os
import sys

from kernel_target import FILL_ENV, SHIPPED_ENV, index_name
from numba.core.caching import Cache, UserProvidedCacheLocator


class ShippedLocator(UserProvidedCacheLocator):
    """Kernels of the game's modules, cached in the folder under their path inside the bundle.

    Chosen only for functions whose index the build shipped (or, while the build fills the
    cache, for every function of the bundle); any other goes to numba's next locator, the
    player's cache folder.
    """

    def __init__(self, py_func, py_file):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        bundle = getattr(sys, "_MEIPASS", os.path.dirname(os.path.abspath(sys.executable)))
        inside = os.path.relpath(os.path.dirname(os.path.abspath(py_file)), bundle)
        self._cache_path = os.path.join(os.environ[SHIPPED_ENV], inside)

    def ensure_cache_path(self):
        if os.environ.get(FILL_ENV) == "1":
            super().ensure_cache_path()
        elif not os.path.isdir(self._cache_path):
            raise OSError(f"no shipped kernels in {self._cache_path}")

    @classmethod
    def from_function(cls, py_func, py_file):
        if not os.environ.get(SHIPPED_ENV) or not os.path.isfile(py_file):
            return None
        bundle = os.path.abspath(getattr(sys, "_MEIPASS", os.path.dirname(sys.executable)))
        if os.path.commonpath([bundle, os.path.abspath(py_file)]) != bundle:
            return None
        self = cls(py_func, py_file)
        if os.environ.get(FILL_ENV) == "1":
            self.ensure_cache_path()
            return self
        return self if os.path.isfile(os.path.join(self._cache_path, index_name(py_func))) else None


_save_overload = Cache.save_overload


def _save_unless_shipped(self, sig, data):
    # A signature the build did not compile (none should be left) is compiled in play;
    # the folder may be read-only, so it is not cached rather than stopping the game.
    try:
        _save_overload(self, sig, data)
    except OSError:
        if not isinstance(self._impl.locator, ShippedLocator):
            raise


Cache.save_overload = _save_unless_shipped
