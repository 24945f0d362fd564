"""Shipped replays hold on every machine: kernels compiled for any x86-64, bakes shipped.

Each shipped replay was recorded in the window on one machine. Here every one is
played where nothing is cached: in fresh processes whose numba cache and user
cache (bakes, settings) are new empty folders, with the kernels compiled for a
generic x86-64 (``NUMBA_CPU_NAME=generic``: no AVX, no FMA) as on a player's
older or different CPU, and every state hash must match. The first process
compiles every kernel (about two minutes on the shared 2-core machine); the
others load them from this test's own cache, so it is marked slow (CI runs it with
``pytest -m slow``). Kernels compiled for this CPU are checked by
``tests/test_replay_cli.py`` in the default run, which plays each shipped replay in a
fresh process too (CI starts with an empty cache).
"""

from __future__ import annotations

import ast
import json
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]
SHIPPED = sorted((REPO / "levels" / "replays").glob("*.json"))
COMPILE_TIMEOUT = 900  # a cold compile on a loaded 2-core machine


def _fresh_env(env: dict, tmp: Path, cpu: str) -> dict:
    e = dict(env)
    e["NUMBA_CACHE_DIR"] = str(tmp / "numba")
    e["ACROSS_DIMENSIONS_CACHE_DIR"] = str(tmp / "cache")  # an empty bake cache: the shipped bakes must serve
    e["XDG_DATA_HOME"] = str(tmp / "data")
    e["XDG_CONFIG_HOME"] = str(tmp / "config")
    e.pop("NUMBA_CPU_FEATURES", None)
    e["NUMBA_CPU_NAME"] = cpu
    return e


@pytest.mark.slow
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
    # Nothing was baked here: every mesh the levels lift came from assets/baked/. (The cache
    # holds repaired 3D surfaces of the [[mesh]] props, read back on the next load; no tets.)
    cached = list((tmp_path / "cache").rglob("*.npz"))
    assert cached and not [p for p in cached if "tets" in np.load(p).files]


# ------------------------------------------------------------ the C library
#: numpy's hypot is the C library's, which rounds differently in glibc 2.31 and 2.36: with
#: 2.31's (Debian 11, Ubuntu 20.04) a hit's direction came out a bit apart and Crossfire's
#: replay diverged at tick 1800.
#: The simulation takes lengths with sqrt, which IEEE arithmetic rounds the same everywhere.
#: (Python's own ``math.hypot`` is CPython's code, the same everywhere, but inside a numba
#: kernel it too becomes the C library's.)
SIMULATION = ("core", "physics", "game", "world")
KERNEL_PACKAGES = ("core", "physics")


def test_the_simulation_calls_no_c_library_hypot():
    found = []
    for folder in SIMULATION:
        for path in sorted((REPO / "across_dimensions" / folder).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text())):
                if not (isinstance(node, ast.Attribute) and node.attr == "hypot"):
                    continue
                owner = node.value.id if isinstance(node.value, ast.Name) else ""
                if owner in ("np", "numpy") or (owner == "math" and folder in KERNEL_PACKAGES):
                    found.append(f"{path.relative_to(REPO)}:{node.lineno}")
    assert found == []


# ------------------------------------------------------------ format versions
def _shipped(name: str) -> dict:
    return json.loads((REPO / "levels" / "replays" / f"{name}.json").read_text())


def _load(tmp_path: Path, data: dict):
    from across_dimensions.game.replay import Replay, ReplayError

    path = tmp_path / "r.json"
    path.write_text(json.dumps(data))
    try:
        return Replay.load(path)
    except ReplayError as e:
        return str(e)


def test_a_version_1_replay_with_presses_is_refused(tmp_path):
    data = _shipped("09_hive")  # its rows carry {"fire": 1}: version 2's
    del data["bakes"], data["arsenal"]
    data["version"] = 1
    why = _load(tmp_path, data)
    assert isinstance(why, str) and "r.json: entry 'actions' #1" in why and "says version 1" in why
    data["version"] = 2
    assert not isinstance(_load(tmp_path, data), str)


def test_a_key_of_a_later_version_is_refused(tmp_path):
    data = _shipped("01_first_steps")
    data["version"] = 2
    why = _load(tmp_path, data)
    assert "entry 'bakes'" in why and "version 3 of the format has it, this replay says version 2" in why
    data = _shipped("01_first_steps")
    del data["bakes"]
    assert "entry 'bakes': missing" in _load(tmp_path, data)
    data = _shipped("01_first_steps")
    del data["arsenal"]
    assert "entry 'arsenal': missing" in _load(tmp_path, data)
    data = _shipped("09_hive")
    data["bakes"] = {"meshes/tree.obj": "xyz"}
    assert "entry 'bakes' 'meshes/tree.obj'" in _load(tmp_path, data)


# ------------------------------------------------------------ as a player runs it
def _run(env, cwd, *args):
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=300,
    )


def test_a_replay_of_another_level_names_it_at_once(env, tmp_path):
    replay = REPO / "levels" / "replays" / "09_hive.json"
    for extra in ([], ["--json"]):
        r = _run(env, tmp_path, "replay", "01_first_steps", replay, *extra)
        assert r.returncode == 2, r.stderr
        (line,) = r.stderr.splitlines()
        assert "recorded on the level '09_hive', not on 01_first_steps" in line
        assert f"replay 09_hive {replay}" in line and "Traceback" not in r.stderr
        if extra:  # the same line, as one JSON object on stdout
            assert json.loads(r.stdout) == {"error": line, "status": 2}
        else:
            assert r.stdout == ""


def test_replay_json_prints_every_error_as_json_too(env, tmp_path):
    (tmp_path / "bad.json").write_text("{not json")
    cases = [
        (["replay", "01_first_steps", "missing.json", "--json"], 2, "missing.json: no such file"),
        (["replay", "01_first_steps", "bad.json", "--json"], 2, "invalid JSON"),
        (
            ["replay", "no_such_level", str(REPO / "levels" / "replays" / "01_first_steps.json"), "--json"],
            2,
            "no level",
        ),
        (["replay", "--json"], 2, "the following arguments are required"),
    ]
    for args, status, needle in cases:
        r = _run(env, tmp_path, *args)
        assert r.returncode == status, (args, r.stderr)
        (line,) = r.stderr.splitlines()
        assert needle in line, (args, line)
        assert json.loads(r.stdout) == {"error": line, "status": status}
    r = _run(env, tmp_path, "replay", "01_first_steps", "missing.json")  # without --json: stderr only
    assert r.returncode == 2 and r.stdout == ""


@pytest.mark.slow
def test_a_replay_recorded_with_another_bake_names_the_asset(env, tmp_path):
    import hashlib

    data = _shipped("09_hive")
    source = hashlib.sha256((REPO / "levels" / "09_hive.toml").read_bytes()).hexdigest()
    data["bakes"] = {"meshes/tree.obj": "ab" * 32}  # as if recorded where the tree baked otherwise
    h = hashlib.sha256(source.encode())
    h.update(("\nmeshes/tree.obj=" + "ab" * 32).encode())
    data["level_hash"] = h.hexdigest()
    (tmp_path / "other.json").write_text(json.dumps(data))
    r = _run(env, tmp_path, "replay", "09_hive", "other.json", "--json")
    assert r.returncode == 3, r.stderr
    out = json.loads(r.stdout)
    assert out["divergence"].startswith("asset meshes/tree.obj baked differently: ")
    assert "abababababab" in out["divergence"] and "the bake shipped with the game" in out["divergence"]
    assert "diverges at tick" not in r.stderr
