"""Which numba kernels the frozen game uses: those shipped in its folder, compiled for a baseline CPU.

Numba finds a cached kernel by its index key: the signature, the code generator's
``(target triple, CPU name, CPU features)`` and hashes of the bytecode. The build
(``python -m across_dimensions.app.freeze``) compiles every kernel with
``NUMBA_CPU_NAME=x86-64-v2`` and ``NUMBA_CPU_FEATURES=""`` (the features the name implies,
nothing of the build machine's own) into ``_internal/numba_cache``, laid out by the
source folders' paths inside the bundle, so the cache is found wherever the folder is
unpacked. At start-up ``launch.py`` asks the same of numba when the processor runs
x86-64-v2 code (:func:`runs_baseline`), and numba then loads every kernel from the folder
through :class:`ShippedLocator`: nothing compiles and nothing is written. On another
processor, or when the player chose a CPU target with ``NUMBA_CPU_NAME``, the kernels
compile for the player's own CPU into the player's cache folder, as they would unfrozen.

Why x86-64-v2 (SSE4.2, POPCNT, CMPXCHG16B): every x86-64 processor sold in the last
decade runs it, including the Atom-class Celeron and Pentium Silver chips without AVX
that x86-64-v3 would leave out, and RHEL 9 requires it of its own machines. The kernels
are mostly scalar loops over small arrays, where AVX2's wider vectors have little to work
on. Measured against x86-64-v3 (AVX2) on a 2-core AMD EPYC, ``across-dimensions bench``
runs taking turns: the physics piles the same (1,000 bodies 7.9-8.0 ms a tick either way),
the dense worst-case section 0.97-1.11 ms against 1.07-1.22, ten enemies' frame 1.28-1.36 ms
against 1.38-1.51; not worth a second set of kernels in the package.

This module imports no numba (launch.py uses it before numba reads its environment);
:mod:`frozen_kernels` holds the locator numba loads.
"""

from __future__ import annotations

import os
import sys

#: The CPU the shipped kernels are compiled for, and the LLVM features it adds to x86-64.
BASELINE_CPU = "x86-64-v2"
BASELINE_FEATURES = ("cx16", "sahf", "popcnt", "sse3", "ssse3", "sse4.1", "sse4.2")
#: The shipped cache's folder inside the bundle.
FOLDER = "numba_cache"
#: Set by launch.py: the shipped cache to read (or, while the build fills it, to write).
SHIPPED_ENV = "ACROSS_DIMENSIONS_SHIPPED_KERNELS"
#: Set by the build only: compile into the shipped cache.
FILL_ENV = "ACROSS_DIMENSIONS_FILL_KERNELS"


def runs_baseline() -> bool:
    """True when this processor runs code compiled for :data:`BASELINE_CPU`.

    Asks LLVM (as numba does for its own target), so it works the same on every system.
    """
    import llvmlite.binding as ll

    if not ll.get_process_triple().startswith("x86_64"):
        return False
    have = ll.get_host_cpu_features()
    return all(have.get(name, False) for name in BASELINE_FEATURES)


def index_name(py_func) -> str:
    """The file name numba gives a function's cache index (``caching.CacheImpl``)."""
    modname = os.path.splitext(os.path.basename(py_func.__code__.co_filename))[0]
    qualname = getattr(py_func, "__qualname__", py_func.__name__).replace("<", "").replace(">", "")
    lineno = py_func.__code__.co_firstlineno
    v = sys.version_info
    return f"{modname}.{qualname}-{lineno}.py{v[0]}{v[1]}{getattr(sys, 'abiflags', '')}.nbi"
