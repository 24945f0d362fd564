"""Filling a closed surface with tetrahedra: pytetwild (fTetWild) in a child process.

pytetwild holds the GIL for the whole call and can abort the process on bad
input, so by default it runs in a child Python process: the caller's threads
(a game's loading screen) keep running, the caller can redraw a progress line
while it waits, and a crash becomes an :class:`~.errors.AssetError` instead of
taking the game down.

A bake is reproducible: one thread, and fTetWild's draws from the system's
entropy replaced by a fixed sequence (:mod:`.fixed_seed`), so the same surface
and settings give the same bytes on every run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from ...core.lift import orient_tets3
from .errors import AssetError

#: Ideal tet edge length as a fraction of the bounding-box diagonal.
DEFAULT_EDGE_LENGTH_FAC = 0.1
#: Seconds between calls of ``on_wait`` while the child runs.
WAIT_STEP = 0.1
#: What makes a bake the same on every run and machine: one thread (the parallel
#: loops' order would depend on the core count) and the start of fTetWild's fixed
#: sequence of "random" draws (see :mod:`.fixed_seed`).
REPRODUCIBLE = {"num_threads": 1, "seed": 20210501}

_WORKER = r"""
import json, sys
import numpy as np
import pytetwild
from pytetwild import PyfTetWildWrapper
from across_dimensions.world.assets.fixed_seed import fix_random_device
src, dst, kw = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
seed = kw.pop("seed", None)
if seed is not None:
    fix_random_device(PyfTetWildWrapper.__file__, seed)
with np.load(src) as d:
    v, f = d["vertices"], d["faces"]
tv, tt = pytetwild.tetrahedralize(v, f.astype(np.int32), quiet=True, **kw)
with open(dst, "wb") as out:
    np.savez(out, vertices=np.asarray(tv, np.float64), tets=np.asarray(tt, np.int64))
"""


def tetrahedralize(
    vertices,
    faces,
    edge_length_fac: float = DEFAULT_EDGE_LENGTH_FAC,
    *,
    isolate: bool = True,
    on_wait=None,
    **tetwild_kw,
) -> tuple[np.ndarray, np.ndarray]:
    """Fill a closed surface with tetrahedra using pytetwild (fTetWild).

    Parameters
    ----------
    vertices : (n, 3) array_like float
    faces : (f, 3) array_like int
    edge_length_fac : float
        Ideal tet edge length over the bounding-box diagonal; bigger is coarser
        and faster.
    isolate : bool
        Run pytetwild in a child process (default). It holds the GIL for the
        whole call and aborts the process on some inputs; isolated, other
        threads keep running and a crash raises instead of killing the game.
    on_wait : callable, optional
        Called with no arguments every :data:`WAIT_STEP` seconds while the
        child runs (to redraw a progress line). Only with ``isolate``.
    **tetwild_kw
        More ``pytetwild.tetrahedralize`` options (``epsilon``, ``coarsen``, ...);
        :data:`REPRODUCIBLE` unless given (``seed=None`` keeps fTetWild's own draws).

    Returns
    -------
    vertices : (n', 3) float64
        Only those the tets use.
    tets : (m, 4) int64
        Positive volume: ``d`` is on the side of ``(b - a) x (c - a)``. fTetWild's
        own convention is the opposite; the orientation is fixed per tet from
        geometry, so either convention (or a mix) comes out right.

    Raises
    ------
    AssetError
        pytetwild failed or produced no tets.
    """
    v = np.ascontiguousarray(vertices, np.float64)
    f = np.ascontiguousarray(faces, np.int64)
    kw = {**REPRODUCIBLE, "edge_length_fac": float(edge_length_fac), **tetwild_kw}
    tv, tt = _tetwild_child(v, f, kw, on_wait) if isolate else _tetwild_here(v, f, kw)
    if len(tt) == 0:
        raise AssetError("pytetwild produced no tets (is the surface closed and not flat?)")
    used = np.unique(tt)
    remap = np.full(len(tv), -1, np.int64)
    remap[used] = np.arange(len(used))
    tv, tt = tv[used], remap[tt]
    try:
        return tv, orient_tets3(tv, tt)
    except ValueError as e:
        raise AssetError(f"pytetwild produced an unusable mesh: {e}") from None


def _tetwild_here(v, f, kw):
    import pytetwild  # local: heavy, only bakes need it

    from .fixed_seed import fix_random_device

    kw = dict(kw)
    seed = kw.pop("seed", None)
    if seed is not None:  # patches this process's pytetwild for good: tests and tools only
        fix_random_device(pytetwild.PyfTetWildWrapper.__file__, seed)
    tv, tt = pytetwild.tetrahedralize(v, f.astype(np.int32), quiet=True, **kw)
    return np.asarray(tv, np.float64), np.asarray(tt, np.int64)


def _tetwild_child(v, f, kw, on_wait=None):
    with tempfile.TemporaryDirectory(prefix="ad-tetwild-") as tmp:
        src, dst = os.path.join(tmp, "in.npz"), os.path.join(tmp, "out.npz")
        np.savez(src, vertices=v, faces=f)
        # stderr goes to a file, not a pipe, so nothing has to drain it while
        # this thread wakes up to call on_wait.
        with open(os.path.join(tmp, "stderr.txt"), "w+b") as err:
            proc = subprocess.Popen(
                [sys.executable, "-c", _WORKER, src, dst, json.dumps(kw)],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=err,
                cwd=tmp,  # fTetWild writes __tracked_surface.stl into the working folder
            )
            try:
                while True:
                    try:
                        proc.wait(WAIT_STEP)
                        break
                    except subprocess.TimeoutExpired:
                        if on_wait is not None:
                            on_wait()
            finally:
                if proc.poll() is None:  # interrupted (Ctrl-C): do not leave it running
                    proc.kill()
                    proc.wait()
            err.seek(0)
            tail = err.read()[-4096:].decode(errors="replace").strip().splitlines()
        if proc.returncode != 0 or not os.path.exists(dst):
            why = tail[-1] if tail else f"exit status {proc.returncode}"
            raise AssetError(f"pytetwild failed: {why}")
        with np.load(dst) as d:
            return d["vertices"], d["tets"]
