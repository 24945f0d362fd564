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

import hashlib
from pathlib import Path

import numba  # noqa: E402
from numba.core import config  # noqa: E402

from across_dimensions.core import _jit  # noqa: F401  (numba configured as the core configures it)
from across_dimensions.core.fileio import FileProblem, atomic_write

_HERE = Path(__file__).resolve().parent
_STAMP = "physics-sources.sha256"


def cache_dir() -> Path | None:
    """Directory numba uses for this package's kernels, or None if unknown."""
    probe = str(_HERE / "world.py")
    if config.CACHE_DIR:
        try:
            from numba.core.caching import UserProvidedCacheLocator
        except ImportError:
            return None
        return Path(config.CACHE_DIR) / UserProvidedCacheLocator.get_suitable_cache_subpath(probe)
    return _HERE / "__pycache__"


def sources_digest() -> str:
    """SHA-256 over the physics modules that define kernels, and the numba version.

    Plain-Python modules (the world API, the benchmark) do not take part, so
    editing them does not force a recompile. The core's transform module
    takes part (the physics compiles its :func:`expm_skew` in), and so does
    :mod:`.state` (the kernels' argument types).
    """
    h = hashlib.sha256(numba.__version__.encode())
    paths = sorted(_HERE.glob("*.py")) + [_HERE.parent / "core" / "transform.py"]
    for path in paths:
        text = path.read_bytes()
        if b"@njit" not in text and b"@intrinsic" not in text and path.name != "state.py":
            continue
        h.update(path.name.encode())
        h.update(text)
    return h.hexdigest()


def drop_stale_kernels() -> bool:
    """Delete cached physics kernels if any physics source changed since they were built.

    Returns
    -------
    bool
        True if entries were dropped. Never raises on file-system errors: the
        worst case is a recompile.
    """
    try:
        d = cache_dir()
        if d is None:
            return False
        digest = sources_digest()
        stamp = d / _STAMP
        if stamp.is_file() and stamp.read_text() == digest:
            return False
        dropped = False
        if d.is_dir():
            for f in d.iterdir():
                if f.suffix in (".nbi", ".nbc"):
                    try:
                        f.unlink()
                        dropped = True
                    except FileNotFoundError:
                        pass
        d.mkdir(parents=True, exist_ok=True)  # numba's own cache folder: ours to create
        atomic_write(stamp, digest)
        return dropped
    except (OSError, FileProblem):
        return False
