"""The application: window, input, settings, the command line (the only package that imports pyglet).

Importing it first points numba's on-disk kernel cache at the platform's per-user
cache folder (``platformdirs.user_cache_dir("across-dimensions")/numba``; on Linux
``~/.cache/across-dimensions/numba``), beside the asset bake cache, unless the user
chose one with ``NUMBA_CACHE_DIR``. The core leaves that choice to its host: a
library user gets numba's own default. Then, where the package ships kernels compiled for this
platform from these very sources, numba is pointed at them
(:func:`across_dimensions._shipped_kernels.activate`): a first start loads instead of compiling.
"""

from __future__ import annotations

import os
import sys


def _configure_kernel_cache() -> None:
    # Must run before numba is imported anywhere: numba reads the variable once, on import.
    if "NUMBA_CACHE_DIR" not in os.environ:
        import platformdirs

        os.environ["NUMBA_CACHE_DIR"] = os.path.join(platformdirs.user_cache_dir("across-dimensions"), "numba")
    if "numba" not in sys.modules:  # numba reads its CPU target and locators once
        from .._shipped_kernels import activate

        activate()


_configure_kernel_cache()
