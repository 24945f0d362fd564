"""Replays agree across CPUs: numpy's BLAS kernels are pinned before numpy is imported.

OpenBLAS picks its kernels by CPU, and its AVX-512 ones round differently from the AVX2 ones
the shipped replays were recorded with (``across_dimensions/_blas.py``). These tests run the
game in fresh processes with no OpenBLAS setting of their own, as on a player's machine.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

from across_dimensions import _blas

REPO = Path(__file__).resolve().parents[1]


def _avx2() -> bool:
    try:
        return _blas._has_avx2(Path("/proc/cpuinfo").read_text(errors="replace"))
    except OSError:
        return False


def _clean_env(**extra) -> dict:
    """The caller's environment without any OpenBLAS setting, this checkout first on the path."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("OPENBLAS")}
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p)
    env.update(extra)
    return env


def _coretype_seen(env) -> str:
    code = "import across_dimensions, os; print(os.environ.get('OPENBLAS_CORETYPE', '-'))"
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return r.stdout.strip()


def test_cpu_flags_are_read_from_the_flags_line():
    assert _blas._has_avx2("processor : 0\nflags : fpu sse2 avx avx2 fma\n")
    assert not _blas._has_avx2("processor : 0\nflags : fpu sse2 avx\nbugs : avx2_ghost\n")
    assert not _blas._has_avx2("no flags here\n")


def test_the_kernels_are_pinned_unless_the_player_chose_or_numpy_came_first(tmp_path):
    expected = _blas.CORETYPE if sys.platform.startswith("linux") and _avx2() else "-"
    assert _coretype_seen(_clean_env()) == expected
    assert _coretype_seen(_clean_env(OPENBLAS_CORETYPE="Sandybridge")) == "Sandybridge"
    # In this process numpy is loaded: setting the variable now would change nothing.
    import numpy  # noqa: F401  (loaded already in a full run; run alone, this file had not)

    env = {}
    assert _blas.pin_kernels(env) is None and env == {}


def test_without_proc_the_cpu_is_asked_through_llvm(monkeypatch, tmp_path):
    """A chroot or container without /proc: the kernels are pinned all the same (unpinned, an
    AVX-512 machine's kernels made the Tumbling Hall diverge at tick 880 in a Debian 11 root)."""
    monkeypatch.delitem(sys.modules, "numpy", raising=False)  # as in a process that has not imported it yet
    missing = str(tmp_path / "no-proc" / "cpuinfo")
    if platform.system() == "Linux" and platform.machine().lower() in ("x86_64", "amd64"):
        env = {}
        assert _blas.pin_kernels(env, missing, host_avx2=lambda: True) == _blas.CORETYPE
        assert env == {"OPENBLAS_CORETYPE": _blas.CORETYPE}
    env = {}
    assert _blas.pin_kernels(env, missing, host_avx2=lambda: False) is None and env == {}
    if Path("/proc/cpuinfo").exists():
        assert _blas._llvm_has_avx2() == _avx2()  # LLVM and the kernel agree where both can say


@pytest.mark.skipif(not _avx2(), reason="the pinned kernels need AVX2")
def test_a_shipped_physics_replay_reaches_its_hashes_in_a_fresh_process_without_blas_settings(tmp_path):
    """The Armory's crate and bodies are where the kernels' rounding shows first (tick 600 with
    the AVX-512 kernels): played from a clean environment, every recorded hash matches."""
    replay = REPO / "levels" / "replays" / "04_armory.json"
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "replay", "04_armory", str(replay), "--json"],
        env=_clean_env(),
        capture_output=True,
        text=True,
        timeout=240,
        cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr  # 3: the replay diverged from its recorded hashes
    result = json.loads(r.stdout)
    final = json.loads(replay.read_text())["final"]
    assert result["divergence"] is None
    assert (result["hash"], result["outcome"]) == (final["hash"], final["outcome"])
