"""A first start loads the shipped kernels, never stale ones, and reaches its first level frame.

The package ships numba's cache of its kernels for one platform (``across_dimensions/kernels/``,
made by ``python -m across_dimensions.app.ship_kernels``), keyed by a digest of their sources.
Here, from this checkout as CI clones it: the shipped kernels are current, a changed source
makes them unused (and numba compiles instead), and a first start with every folder fresh
reaches its first frame, compiling nothing when the kernels are shipped. How fast is
``bench start``'s to say.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import REPO, xvfb_display

from across_dimensions import _shipped_kernels as shipped

COLD = 1800  # seconds: a cold compile on a loaded 2-core machine, where nothing is shipped


def test_the_shipped_kernels_are_current(env):
    if not shipped.shipped_dir().is_dir():
        pytest.skip(f"no kernels are shipped for {shipped.platform_key()}")
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions.app.ship_kernels", "--check"],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert r.returncode == 0, r.stdout + r.stderr
    assert "current" in r.stdout


def _copy(tmp_path: Path, digests: dict) -> Path:
    """A shipped folder with the real manifest's entries but the given digests."""
    folder = tmp_path / shipped.platform_key()
    folder.mkdir()
    manifest = {"platform": shipped.platform_key(), "cpu": shipped.CPU, "digests": digests}
    (folder / shipped.MANIFEST).write_text(json.dumps(manifest))
    return folder


def test_a_changed_source_makes_the_shipped_kernels_unused(tmp_path, monkeypatch):
    current = {g: shipped.digest(g) for g in shipped.GROUPS}
    monkeypatch.setattr(shipped, "shipped_dir", lambda: tmp_path / shipped.platform_key())
    _copy(tmp_path, current)
    assert shipped.current_groups(shipped.read_manifest()) == list(shipped.GROUPS)
    (tmp_path / shipped.platform_key() / shipped.MANIFEST).write_text(
        json.dumps({"cpu": shipped.CPU, "digests": dict(current, physics="0" * 64)})
    )
    assert shipped.current_groups(shipped.read_manifest()) == ["core"]
    # One byte more in a physics source changes the physics digest, not the core's.
    shipped.digest.cache_clear()
    monkeypatch.setattr(shipped, "PACKAGE", tmp_path / "pkg")
    for g in ("core", "physics"):
        shutil.copytree(REPO / "across_dimensions" / g, tmp_path / "pkg" / g)
    assert shipped.digest("core") == current["core"] and shipped.digest("physics") == current["physics"]
    with open(tmp_path / "pkg" / "physics" / "solver.py", "a") as f:
        f.write("\n")
    shipped.digest.cache_clear()
    assert shipped.digest("core") == current["core"] and shipped.digest("physics") != current["physics"]
    shipped.digest.cache_clear()


def test_the_locator_serves_only_current_shipped_kernels(tmp_path, monkeypatch):
    from across_dimensions import _kernel_locator
    from across_dimensions.core import section_kernels

    kernel = next(v for v in vars(section_kernels).values() if hasattr(v, "py_func") and v._can_compile)
    func, source = kernel.py_func, kernel.py_func.__code__.co_filename
    folder = _copy(tmp_path, {g: shipped.digest(g) for g in shipped.GROUPS})
    (folder / "core").mkdir()
    (folder / "core" / _kernel_locator._index_name(func, source)).write_bytes(b"")
    monkeypatch.setenv(shipped.ACTIVE_ENV, str(folder))
    monkeypatch.setenv("NUMBA_CPU_NAME", shipped.CPU)
    monkeypatch.delenv(shipped.FILL_ENV, raising=False)
    monkeypatch.setattr(_kernel_locator, "_CURRENT", {})
    locator = _kernel_locator.ShippedLocator.from_function(func, source)
    assert locator is not None and locator.get_cache_path() == str(folder / "core")
    assert locator.get_source_stamp() == "sha256:" + shipped.digest("core")
    with pytest.raises(OSError):  # read-only in play
        locator.ensure_cache_path()
    monkeypatch.setenv("NUMBA_CPU_NAME", "generic")  # compiled for another target: not these
    assert _kernel_locator.ShippedLocator.from_function(func, source) is None
    monkeypatch.setenv("NUMBA_CPU_NAME", shipped.CPU)
    (folder / shipped.MANIFEST).write_text(json.dumps({"cpu": shipped.CPU, "digests": {"core": "stale"}}))
    monkeypatch.setattr(_kernel_locator, "_CURRENT", {})
    assert _kernel_locator.ShippedLocator.from_function(func, source) is None


def test_a_chosen_cpu_target_or_a_stale_folder_compiles_as_before(tmp_path, monkeypatch):
    assert "NUMBA_CPU_NAME" in shipped.why_not({"NUMBA_CPU_NAME": "generic"})
    monkeypatch.setattr(shipped, "shipped_dir", lambda: tmp_path / "none")
    assert shipped.why_not({}).startswith("no kernels are shipped")
    environ = {}
    assert not shipped.activate(environ) and environ == {}


@pytest.fixture(scope="module")
def display():
    with xvfb_display(67, "ACROSS_DIMENSIONS_START_TEST_DISPLAY") as d:
        yield d


def test_a_first_start_with_fresh_folders_reaches_its_first_level_frame(env, display, tmp_path):
    from across_dimensions.app.bench_start import fresh_env

    e = fresh_env(str(tmp_path))
    e.update(DISPLAY=display, PYTHONPATH=env["PYTHONPATH"])
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "play", "01_first_steps", "--screenshot-after", "0.001"]
        + ["--quit-after", "0.5"],
        capture_output=True,
        text=True,
        env=e,
        timeout=COLD,
    )
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    lines = [ln.split(" at ")[0] for ln in r.stdout.splitlines() if ln.startswith("timing: ")]
    assert lines[0] == "timing: window open" and "timing: first frame" in lines, lines
    assert lines[-1] == "timing: first level frame", lines
    shots = list((tmp_path / "shots").glob("*.png"))
    assert len(shots) == 1 and shots[0].stat().st_size > 10_000
    if shipped.why_not(e) is None:  # every kernel came from the package: nothing compiled here
        assert not list((tmp_path / "numba").rglob("*.nbi")), "kernels compiled although shipped"


_NEW_SIGNATURE = """
import json
import numpy as np
import across_dimensions.app  # points numba at the shipped kernels
from across_dimensions.core.transform import _series_on_powers as k
k(1.0, 2.0, 0.5)  # the signature the game uses: shipped
shipped_hits = sum(k.stats.cache_hits.values())
k(np.float32(1.0), np.float32(2.0), np.float32(0.5))  # one the folder lacks
print(json.dumps([shipped_hits, sum(k.stats.cache_hits.values()), sum(k.stats.cache_misses.values())]))
"""


def test_a_signature_not_shipped_compiles_once_into_the_users_cache(env, tmp_path):
    if shipped.why_not({}) is not None:
        pytest.skip(shipped.why_not({}))
    folder = shipped.shipped_dir() / "core"
    before = {p.name: p.stat().st_mtime_ns for p in folder.iterdir()}
    e = dict(env, NUMBA_CACHE_DIR=str(tmp_path / "numba"))
    runs = []
    for _ in range(2):
        r = subprocess.run([sys.executable, "-c", _NEW_SIGNATURE], capture_output=True, text=True, env=e, timeout=600)
        assert r.returncode == 0, r.stderr[-2000:]
        runs.append(json.loads(r.stdout.strip().splitlines()[-1]))
    assert runs == [[1, 1, 1], [1, 2, 0]]  # compiled in the first process only, then loaded
    assert [p.name for p in (tmp_path / "numba").rglob("transform._series_on_powers-*.nbi")]
    assert {p.name: p.stat().st_mtime_ns for p in folder.iterdir()} == before  # never written


def test_bench_start_needs_a_display_and_says_so(env):
    e = {k: v for k, v in env.items() if k != "DISPLAY"}
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "bench", "start"],
        capture_output=True,
        text=True,
        env=e,
        timeout=120,
    )
    assert r.returncode == 2 and "needs a display" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.slow
def test_bench_start_times_a_fresh_title_level_and_editor(env, display):
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "bench", "start", "--busy", "0", "--json"],
        capture_output=True,
        text=True,
        env=dict(env, DISPLAY=display),
        timeout=3 * COLD,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    rows = json.loads(r.stdout)
    assert all(row["seconds"] > 0 for row in rows) and len(rows) >= 3
    assert "[PASS]" in r.stderr or "[FAIL]" in r.stderr  # the targets' lines go to stderr with --json
