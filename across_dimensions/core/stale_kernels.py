"""Keep numba's on-disk cache of a package's kernels in step with all of its sources.

Numba checks a cached kernel only against the file that defines it. A kernel that compiles
helpers of other files into itself (the batched slicer's tet path lives in
``section_batch_tets.py``, the physics tick compiles the solver in) would still run the old
helpers after a change to their file alone. So before any kernel loads, a digest of the
package's kernel sources (and the numba version) is compared with the one stored beside its
cache; when they differ, the package's cache entries are dropped and rebuilt on first use.
The shipped kernels are keyed by such a digest already (see ``_shipped_kernels``).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numba
from numba.core import config

from .fileio import FileProblem, atomic_write


def cache_dir(probe: Path) -> Path | None:
    """Directory numba uses for the kernels of ``probe``'s folder, or None if unknown."""
    if config.CACHE_DIR:
        try:
            from numba.core.caching import UserProvidedCacheLocator
        except ImportError:
            return None
        return Path(config.CACHE_DIR) / UserProvidedCacheLocator.get_suitable_cache_subpath(str(probe))
    return probe.parent / "__pycache__"


def sources_digest(paths, always=()) -> str:
    """SHA-256 over the numba version and those of ``paths`` that define kernels (or are named
    in ``always``: modules whose types the kernels take). Plain-Python modules take no part,
    so editing them forces no recompile."""
    h = hashlib.sha256(numba.__version__.encode())
    for path in sorted(paths):
        text = path.read_bytes()
        if b"@njit" not in text and b"@intrinsic" not in text and path.name not in always:
            continue
        h.update(path.name.encode())
        h.update(text)
    return h.hexdigest()


def drop_stale_kernels(probe: Path, digest: str, stamp_name: str) -> bool:
    """Delete the cached kernels of ``probe``'s folder unless ``digest`` is the one they were
    built from (kept in ``stamp_name`` beside them). Returns True if entries were dropped.

    Never raises on file-system errors: the worst case is a recompile.
    """
    try:
        d = cache_dir(probe)
        if d is None:
            return False
        stamp = d / stamp_name
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


def drop_stale_core_kernels() -> bool:
    """:func:`drop_stale_kernels` for the core's own kernels."""
    here = Path(__file__).resolve().parent
    return drop_stale_kernels(here / "section.py", sources_digest(here.glob("*.py")), "core-sources.sha256")
