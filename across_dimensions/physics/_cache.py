"""Keep numba's on-disk cache of the physics kernels in step with their sources.

Numba checks a cached kernel only against the timestamp of the file that
defines it. :func:`~across_dimensions.physics.pipeline.tick` compiles the
solver and collision routines of other files into itself, so after a change to
``solver.py`` alone the cached ``tick`` would still run the old solver. Before
any kernel loads, a digest of all the physics sources (and the numba version)
is compared with the one stored beside the cache; when they differ the
physics cache entries are dropped and rebuilt on first use.
"""

from __future__ import annotations

from pathlib import Path

from across_dimensions.core import stale_kernels

_HERE = Path(__file__).resolve().parent
_STAMP = "physics-sources.sha256"


def sources_digest() -> str:
    """SHA-256 over the physics modules that define kernels, and the numba version.

    Plain-Python modules (the world API, the benchmark) do not take part, so
    editing them does not force a recompile. The core's transform module
    takes part (the physics compiles its :func:`expm_skew` in), and so does
    :mod:`.state` (the kernels' argument types).
    """
    paths = list(_HERE.glob("*.py")) + [_HERE.parent / "core" / "transform.py"]
    return stale_kernels.sources_digest(paths, always=("state.py",))


def drop_stale_kernels() -> bool:
    """Delete cached physics kernels if any physics source changed since they were built.

    Returns
    -------
    bool
        True if entries were dropped. Never raises on file-system errors: the
        worst case is a recompile.
    """
    return stale_kernels.drop_stale_kernels(_HERE / "world.py", sources_digest(), _STAMP)
