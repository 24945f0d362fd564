"""The kernels shipped with the game, compiled once per platform (see :mod:`across_dimensions._shipped_kernels`).

For maintainers, after a kernel's source (anything in ``core/`` or ``physics/``) changed::

    python -m across_dimensions.app.ship_kernels           # compile them into across_dimensions/kernels/KEY/
    python -m across_dimensions.app.ship_kernels --check   # exit 1 if this platform's are missing or stale

Compiling plays what reaches every kernel with the signatures play uses: the start-up warm-up,
every shipped replay and one frame of each benchmark scene. Each runs in a child process whose
kernels all go to the shipped folder (a few minutes on two cores). Kernels from other sources
are never loaded (they are keyed by their sources' digest), so a stale folder only costs the
first start its compile; ``--check`` (run by ``tests/test_shipped_kernels.py``) says when.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .. import _shipped_kernels as shipped

PROG = "python -m across_dimensions.app.ship_kernels"


def _runs() -> list[list[str]]:
    """The commands (after ``python -m across_dimensions``) whose kernels are shipped."""
    from ..world.resources import levels_dir

    runs = [["warm-up"]]
    for replay in sorted((levels_dir() / "replays").glob("*.json")):
        runs.append(["replay", replay.stem, str(replay), "--json"])
    # The frustum view's batch kernel, which only the scene benchmark draws with (needs OpenGL).
    runs.append(["bench", "scene", "--n", "1", "--frames", "1", "--json"])
    return runs


def fill_env(folder: Path, home: str) -> dict:
    """The environment of a child that compiles every kernel into ``folder`` for the baseline CPU."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.update(
        {
            shipped.FILL_ENV: "1",
            shipped.ACTIVE_ENV: str(folder),
            "NUMBA_CPU_NAME": shipped.CPU,
            "NUMBA_CPU_FEATURES": "",
            "NUMBA_CACHE_LOCATOR_CLASSES": f"{shipped.LOCATOR},numba.core.caching.UserProvidedCacheLocator",
            "NUMBA_CACHE_DIR": os.path.join(home, "numba"),
            "ACROSS_DIMENSIONS_DATA_DIR": os.path.join(home, "data"),
            "ACROSS_DIMENSIONS_CACHE_DIR": os.path.join(home, "cache"),
        }
    )
    return env


def build(log=print) -> Path:
    """Compile every kernel into this platform's shipped folder (emptied first) and write its manifest."""
    folder = shipped.shipped_dir()
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as home:
        env = fill_env(folder, home)
        for args in _runs():
            cmd = [sys.executable, "-m", "across_dimensions.app.warmup"] if args == ["warm-up"] else None
            cmd = cmd or [sys.executable, "-m", "across_dimensions", *args]
            done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=3600)
            if done.returncode not in (0, 3) and args[0] != "bench":  # 3: a hash differs, compiled all the same
                raise RuntimeError(f"{' '.join(args[:2])} failed while compiling: {done.stderr.strip()[-2000:]}")
            log(f"{' '.join(args[:2])}: {time.perf_counter() - start:.0f} s")
    manifest = {
        "platform": shipped.platform_key(),
        "cpu": shipped.CPU,
        "digests": {g: shipped.digest(g) for g in shipped.GROUPS},
        "kernels": sum(1 for _ in folder.rglob("*.nbi")),
    }
    (folder / shipped.MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n")
    size = sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())
    log(f"{folder}: {manifest['kernels']} kernels, {size / 1e6:.1f} MB, {time.perf_counter() - start:.0f} s")
    return folder


def check() -> list[str]:
    """What is wrong with this platform's shipped kernels (nothing: an empty list)."""
    folder = shipped.shipped_dir()
    manifest = shipped.read_manifest(folder)
    if manifest is None:
        return [f"{folder}: no shipped kernels for {shipped.platform_key()} (run {PROG})"]
    current = shipped.current_groups(manifest)
    problems = [
        f"{folder}: the {g} kernels were compiled from other sources: stale, never loaded (run {PROG})"
        for g in shipped.GROUPS
        if g not in current
    ]
    if not problems:
        # A kernel that nothing of the runs above calls is missing from the folder and compiles
        # on a player's first use of it, in the middle of a frame.
        problems = [f"{folder}: {k} is not shipped (no run reaches it; add it to the warm-up)" for k in missing()]
    return problems


def missing() -> list[str]:
    """The game's kernels that this platform's shipped folder lacks, as their cache indexes'
    paths inside it (``physics/sightlines.segments_cross_boxes-33.py311.nbi``)."""
    from .freeze import unshipped_kernels

    return unshipped_kernels(shipped.shipped_dir(), in_package=True)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n")[0])
    p.add_argument("--check", action="store_true", help="change nothing; exit 1 if the kernels are missing or stale")
    args = p.parse_args(argv)
    if args.check:
        problems = check()
        for line in problems:
            print(line)
        if not problems:
            print(f"{shipped.shipped_dir()}: shipped kernels current")
        return 1 if problems else 0
    build()
    return 0


if __name__ == "__main__":
    sys.exit(main())
