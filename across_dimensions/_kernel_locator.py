"""The numba cache locator of the shipped kernels (see :mod:`across_dimensions._shipped_kernels`).

Numba imports this module itself (``NUMBA_CACHE_LOCATOR_CLASSES``, set by
:func:`~across_dimensions._shipped_kernels.activate`) when it caches the first kernel.
"""

from __future__ import annotations

import copy
import os

from numba.core.caching import Cache, IndexDataCacheFile, UserProvidedCacheLocator, _CacheLocator

from . import _shipped_kernels as shipped


class ShippedLocator(_CacheLocator):
    """A kernel of ``core`` or ``physics`` cached in the shipped folder, keyed by its sources' digest.

    Chosen only for a kernel whose group's shipped kernels are current and whose index the folder
    holds (or, while ``ship_kernels`` fills the folder, for every kernel of the groups); any other
    goes to numba's next locator, the user's cache folder.
    """

    def __init__(self, py_func, py_file, group: str):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._group = group
        self._cache_path = os.path.join(os.environ[shipped.ACTIVE_ENV], group)

    def ensure_cache_path(self):
        if os.environ.get(shipped.FILL_ENV) != "1":  # read-only in play: the user's cache is written instead
            raise OSError(f"the shipped kernels in {self._cache_path} are read-only")
        os.makedirs(self._cache_path, exist_ok=True)

    def get_cache_path(self):
        return self._cache_path

    def get_source_stamp(self):
        # The sources' digest, not the file's time: what the manifest was checked against.
        return "sha256:" + shipped.digest(self._group)

    def get_disambiguator(self):
        return str(self._lineno)

    @classmethod
    def from_function(cls, py_func, py_file):
        folder = os.environ.get(shipped.ACTIVE_ENV)
        group = shipped.group_of(py_file)
        # Shipped kernels are compiled for one CPU target: a process (or child) compiling for
        # another one never looks there.
        if not folder or group is None or os.environ.get("NUMBA_CPU_NAME") != shipped.CPU:
            return None
        if os.environ.get(shipped.FILL_ENV) == "1":
            return cls(py_func, py_file, group)
        if group not in _current(folder):
            return None
        self = cls(py_func, py_file, group)
        index = os.path.join(self._cache_path, _index_name(py_func, py_file))
        return self if os.path.isfile(index) else None


_CURRENT: dict[str, list[str]] = {}


def _current(folder: str) -> list[str]:
    """The groups of the shipped folder compiled from these sources (read once per process)."""
    if folder not in _CURRENT:
        from pathlib import Path

        _CURRENT[folder] = shipped.current_groups(shipped.read_manifest(Path(folder)))
    return _CURRENT[folder]


def _index_name(py_func, py_file) -> str:
    """The file name numba gives a function's cache index (``caching.CacheImpl.get_filename_base``)."""
    import sys

    modname = os.path.splitext(os.path.basename(py_file))[0]
    qualname = getattr(py_func, "__qualname__", py_func.__name__).replace("<", "").replace(">", "")
    v = sys.version_info
    return f"{modname}.{qualname}-{py_func.__code__.co_firstlineno}.py{v[0]}{v[1]}{getattr(sys, 'abiflags', '')}.nbi"


def _user_cache(cache: Cache) -> Cache:
    """The same kernel's cache in the user's folder (``NUMBA_CACHE_DIR``), for the signatures the
    shipped folder lacks: such a signature compiles once per machine, as without shipped kernels."""
    user = getattr(cache, "_user_cache", None)
    if user is None:
        user = copy.copy(cache)
        user._impl = copy.copy(cache._impl)
        user._impl._locator = UserProvidedCacheLocator(cache._py_func, cache._impl.locator._py_file)
        user._cache_path = user._impl.locator.get_cache_path()
        stamp = user._impl.locator.get_source_stamp()
        user._cache_file = IndexDataCacheFile(user._cache_path, user._impl.filename_base, stamp)
        cache._user_cache = user
    return user


def _shipped(cache: Cache) -> bool:
    return isinstance(cache._impl.locator, ShippedLocator) and os.environ.get(shipped.FILL_ENV) != "1"


_load_overload, _save_overload = Cache.load_overload, Cache.save_overload


def _load(self, sig, target_context):
    data = _load_overload(self, sig, target_context)
    return _load_overload(_user_cache(self), sig, target_context) if data is None and _shipped(self) else data


def _save(self, sig, data):
    # The shipped folder is read-only in play (it may be a read-only install, or a checkout).
    _save_overload(_user_cache(self) if _shipped(self) else self, sig, data)


Cache.load_overload, Cache.save_overload = _load, _save
