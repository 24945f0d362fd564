"""Shipped replays hold on every machine: kernels compiled for any x86-64, bakes shipped.

Each shipped replay was recorded in the window on one machine. Here every one is
played where nothing is cached: in fresh processes whose numba cache and user
cache (bakes, settings) are new empty folders, with the kernels compiled for a
generic x86-64 (``NUMBA_CPU_NAME=generic``: no AVX, no FMA) as on a player's
older or different CPU, and every state hash must match. The first process
compiles every kernel (about two minutes on the shared 2-core machine); the
others load them from this test's own cache. Kernels compiled for this CPU are
checked by ``tests/test_replay_cli.py``, which plays each shipped replay in a
fresh process too (CI starts with an empty cache).
"""

from __future__ import annotations

import json
import platform
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHIPPED = sorted((REPO / "levels" / "replays").glob("*.json"))
COMPILE_TIMEOUT = 900  # a cold compile on a loaded 2-core machine


def _fresh_env(env: dict, tmp: Path, cpu: str) -> dict:
    e = dict(env)
    e["NUMBA_CACHE_DIR"] = str(tmp / "numba")
    e["XDG_CACHE_HOME"] = str(tmp / "cache")  # an empty bake cache: the shipped bakes must serve
    e["XDG_DATA_HOME"] = str(tmp / "data")
    e["XDG_CONFIG_HOME"] = str(tmp / "config")
    e.pop("NUMBA_CPU_FEATURES", None)
    e["NUMBA_CPU_NAME"] = cpu
    return e


def test_every_shipped_replay_matches_with_generic_x86_64_kernels_and_fresh_caches(env, tmp_path):
    if platform.machine().lower() not in ("x86_64", "amd64"):
        pytest.skip("the generic target named here is x86-64's")
    e = _fresh_env(env, tmp_path, "generic")
    for i, replay in enumerate(SHIPPED):
        r = subprocess.run(
            [sys.executable, "-m", "across_dimensions", "replay", replay.stem, str(replay), "--json"],
            capture_output=True,
            text=True,
            cwd=tmp_path,
            env=e,
            timeout=COMPILE_TIMEOUT if i == 0 else 300,
        )
        assert r.returncode == 0, f"{replay.name}: exit {r.returncode}\n{r.stdout}\n{r.stderr}"
        out = json.loads(r.stdout)
        final = json.loads(replay.read_text())["final"]
        assert out["divergence"] is None, replay.name
        assert (out["outcome"], out["ticks"], out["hash"]) == (final["outcome"], final["ticks"], final["hash"])
    # Nothing was baked here: every mesh the levels lift came from assets/baked/.
    assert not list((tmp_path / "cache").rglob("*.npz"))
