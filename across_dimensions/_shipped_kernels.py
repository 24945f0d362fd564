"""Kernels compiled once and shipped in the package, so a first start loads them instead of compiling.

``across_dimensions/kernels/KEY/`` (made by ``python -m across_dimensions.app.ship_kernels``)
holds numba's on-disk cache of the kernels of :mod:`~across_dimensions.core` and
:mod:`~across_dimensions.physics`, compiled for one platform (:func:`platform_key`: the
operating system, the processor family, the Python and the numba version) and for the baseline
CPU :data:`CPU` rather than the building machine's, so any x86-64 processor of the last decade
runs them. Compiling a kernel takes the first start minutes on two cores; loading it, a few
milliseconds.

Numba itself would tell a cached kernel is stale only by the modification time and size of the
file that defines it, which a fresh clone or an unpacked wheel does not keep, and not at all
when a kernel it compiles in from another file changed. The shipped kernels are keyed instead by
:func:`digest`: a SHA-256 of every source file of their package and of the packages below it
(``core`` for ``core``; ``core`` and ``physics`` for ``physics``; kernels reach nothing else).
:func:`activate` turns them on only when the manifest's digests are this checkout's; a kernel
whose sources changed, a platform without shipped kernels, a processor without the baseline's
features or a CPU target the user chose with ``NUMBA_CPU_NAME`` all compile into the user's own
cache as before: a stale kernel is never loaded.

This module imports no numba: :mod:`across_dimensions.app` calls :func:`activate` before numba
reads its environment. :mod:`across_dimensions._kernel_locator` holds the locator numba loads.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import json
import os
import platform
import sys
from functools import cache
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent
#: The shipped caches, one folder per :func:`platform_key`.
FOLDER = PACKAGE / "kernels"
#: The CPU the shipped kernels are compiled for, and the LLVM features it adds to x86-64
#: (as the standalone game's: packaging/kernel_target.py).
CPU = "x86-64-v2"
CPU_FEATURES = ("cx16", "sahf", "popcnt", "sse3", "ssse3", "sse4.1", "sse4.2")
#: The packages whose kernels ship, each with the source folders its kernels' digest covers.
GROUPS = {"core": ("core",), "physics": ("core", "physics")}
MANIFEST = "manifest.json"
#: Set while ``ship_kernels`` compiles: every kernel of :data:`GROUPS` is written to the shipped folder.
FILL_ENV = "ACROSS_DIMENSIONS_FILL_KERNELS"
#: Set by :func:`activate`: the shipped folder in use (read by the locator, in this process and its children).
ACTIVE_ENV = "ACROSS_DIMENSIONS_SHIPPED_KERNELS"
LOCATOR = "across_dimensions._kernel_locator.ShippedLocator"


def numba_version() -> str:
    return importlib.metadata.version("numba")


def platform_key() -> str:
    """``linux-x86_64-py311-numba0.68.1``: what a shipped cache is only valid for."""
    machine = platform.machine().lower().replace("amd64", "x86_64")
    return f"{sys.platform}-{machine}-py{sys.version_info[0]}{sys.version_info[1]}-numba{numba_version()}"


def shipped_dir() -> Path:
    """This platform's shipped cache (which may not exist)."""
    return FOLDER / platform_key()


@cache
def digest(group: str) -> str:
    """SHA-256 of every source file the kernels of ``group`` (a key of :data:`GROUPS`) can reach.

    Over the files' names and bytes, never their times: the same checkout gives the same digest
    wherever it is cloned or installed."""
    h = hashlib.sha256(platform_key().encode())
    for folder in GROUPS[group]:
        for path in sorted((PACKAGE / folder).rglob("*.py")):
            h.update(f"\n{path.relative_to(PACKAGE).as_posix()}\n".encode())
            h.update(path.read_bytes())
    return h.hexdigest()


def group_of(py_file: str) -> str | None:
    """The group whose kernels the source file ``py_file`` defines, or None for another file."""
    try:
        inside = Path(py_file).resolve().relative_to(PACKAGE)
    except ValueError:
        return None
    return inside.parts[0] if len(inside.parts) > 1 and inside.parts[0] in GROUPS else None


def read_manifest(folder: Path | None = None) -> dict | None:
    """The shipped cache's manifest (``{"cpu": ..., "digests": {group: digest}, ...}``), or None."""
    try:
        data = json.loads(((folder or shipped_dir()) / MANIFEST).read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and isinstance(data.get("digests"), dict) else None


def current_groups(manifest: dict | None) -> list[str]:
    """The groups whose shipped kernels were compiled from exactly these sources."""
    if manifest is None or manifest.get("cpu") != CPU:
        return []
    return [g for g in GROUPS if manifest["digests"].get(g) == digest(g)]


def runs_baseline() -> bool:
    """True when this processor runs code compiled for :data:`CPU` (LLVM is asked, as numba asks it)."""
    import llvmlite.binding as ll

    if not ll.get_process_triple().startswith("x86_64"):
        return False
    have = ll.get_host_cpu_features()
    return all(have.get(name, False) for name in CPU_FEATURES)


def why_not(environ=os.environ) -> str | None:
    """Why the shipped kernels cannot serve this process, or None when they can (some of them)."""
    if getattr(sys, "frozen", False):
        return "the standalone game ships its own kernels"
    if environ.get("NUMBA_CPU_NAME") or environ.get("NUMBA_CPU_FEATURES"):
        return "a CPU target was chosen with NUMBA_CPU_NAME or NUMBA_CPU_FEATURES"
    if environ.get("NUMBA_DISABLE_JIT") == "1" or environ.get("NUMBA_CACHE_LOCATOR_CLASSES"):
        return "numba's compiler or cache is configured by hand"
    try:
        manifest = read_manifest()
    except importlib.metadata.PackageNotFoundError:
        return "numba is not installed"
    if manifest is None:
        return f"no kernels are shipped for {platform_key()}"
    if not current_groups(manifest):
        return "the shipped kernels were compiled from other sources"
    if not runs_baseline():
        return f"this processor does not run {CPU} code"
    return None


def activate(environ=os.environ) -> bool:
    """Point numba at the shipped kernels when they serve this process; True if they do.

    Sets numba's CPU target to :data:`CPU` (the key under which the kernels are cached) and its
    locators to the shipped folder first, then the user's cache (``NUMBA_CACHE_DIR``, which must
    be set) for any kernel not shipped. Only effective before numba is first imported; the
    environment also carries to child processes.
    """
    if why_not(environ) is not None:
        return False
    environ.update(_activation())
    return True


def _activation() -> dict:
    """The variables :func:`activate` sets, and their values."""
    return {
        "NUMBA_CPU_NAME": CPU,
        "NUMBA_CPU_FEATURES": "",  # the features the name implies, not this machine's
        "NUMBA_CACHE_LOCATOR_CLASSES": f"{LOCATOR},numba.core.caching.UserProvidedCacheLocator",
        ACTIVE_ENV: str(shipped_dir()),
    }


def for_child(environ=os.environ) -> dict:
    """A copy of ``environ`` without what :func:`activate` set in it, so a child process started
    with it decides afresh, as a player's first start does (and sees no CPU target chosen)."""
    env = dict(environ)
    if ACTIVE_ENV in env:  # then activate() set these, not the user
        for k in _activation():
            env.pop(k, None)
    return env


def active() -> bool:
    """True when this process loads kernels from the shipped cache (:func:`activate` ran)."""
    return bool(os.environ.get(ACTIVE_ENV)) and os.environ.get(FILL_ENV) != "1"


def serve_all() -> bool:
    """True when the shipped kernels serve every group here: a warm-up only loads, nothing compiles."""
    return active() and len(current_groups(read_manifest(Path(os.environ[ACTIVE_ENV])))) == len(GROUPS)


def loaded_kernels() -> list:
    """The numba dispatchers of the package's modules imported so far, each once (numba is
    imported here only when asked: by then the game has chosen its kernels)."""
    from numba.core.dispatcher import Dispatcher

    seen = {}
    for name, module in list(sys.modules.items()):
        if module is not None and name.startswith("across_dimensions"):
            for v in list(vars(module).values()):
                if isinstance(v, Dispatcher):
                    seen[id(v)] = v
    return list(seen.values())
