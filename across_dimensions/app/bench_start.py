"""``bench start``: how long a fresh install takes to the title and to the first level frame.

Each row starts the game as a child process, as a player would the first time after an install:
an empty kernel cache (``NUMBA_CACHE_DIR``), data, settings and bake folders, with
``ACROSS_DIMENSIONS_TIMING`` set, and reads its ``timing:`` lines (seconds from the child's own
start). The baseline, measured in the same run, is a later start: the same command again on the
cache the first start filled. The busy variant runs the same first starts while ``--busy N``
processes (``python -c 'while 1: pass'``) keep the processor's cores busy. Needs a display
(``DISPLAY``; Xvfb will do).
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

from .. import _shipped_kernels as shipped
from .options import UserError

LEVEL = "01_first_steps"
#: Seconds: the title interactive and the first level frame, on a quiet 2-core machine; the first
#: level frame with four busy processes.
TITLE_TARGET, LEVEL_TARGET, BUSY_TARGET = 2.0, 10.0, 60.0
TIMEOUT = 1800.0  # a cold compile on a busy 2-core machine
_TIMING = re.compile(r"^timing: (.+?) at ([0-9.]+) s$")


def fresh_env(home: str) -> dict:
    """The environment of a first start: this one's, with every folder the game writes new and empty."""
    env = shipped.for_child()  # this process's own start chose its kernels: the child decides afresh
    for name, sub in (
        ("NUMBA_CACHE_DIR", "numba"),
        ("ACROSS_DIMENSIONS_DATA_DIR", "data"),
        ("ACROSS_DIMENSIONS_SCREENSHOT_DIR", "shots"),
        ("ACROSS_DIMENSIONS_CACHE_DIR", "cache"),
        ("ACROSS_DIMENSIONS_CONFIG_DIR", "config"),
    ):
        env[name] = os.path.join(home, sub)
    env["ACROSS_DIMENSIONS_TIMING"] = "1"
    return env


def timings(args: list[str], env: dict) -> dict[str, float]:
    """Run ``across-dimensions ARGS`` and return its ``timing:`` lines as ``{what: seconds}``
    (``what`` without its figures: ``kernels ready``, not ``kernels ready after 3.1 s of warm-up``),
    and its CPU seconds as ``cpu``."""
    cmd = [sys.executable, "-m", "across_dimensions", *args]
    used = _children_cpu()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=TIMEOUT)
    if done.returncode != 0:
        raise UserError(f"bench start: {' '.join(args)} failed: {done.stderr.strip()[-800:]}")
    # The CPU time of the whole run (to its exit, half a second after the frame): on a busy
    # machine the figure that says what the start costs, apart from the wait for a core.
    out = {"cpu": _children_cpu() - used}
    for line in done.stdout.splitlines():
        m = _TIMING.match(line.strip())
        if m:
            out.setdefault(m.group(1).split(" after ")[0], float(m.group(2)))
    return out


def _children_cpu() -> float:
    """CPU seconds of this process's finished children (0 where the platform does not count them)."""
    try:
        import resource  # Unix only
    except ImportError:
        return 0.0
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    return used.ru_utime + used.ru_stime


@contextmanager
def busy(n: int):
    """``n`` processes spinning on a core each, for as long as the block runs."""
    spinners = [subprocess.Popen([sys.executable, "-c", "while 1: pass"]) for _ in range(n)]
    try:
        yield
    finally:
        for p in spinners:
            p.kill()
            p.wait()


def _starts(tag: str, out) -> list[dict]:
    """One first start of the title and one of a level, each in fresh folders, then a later start."""
    rows = []
    with tempfile.TemporaryDirectory() as home:
        env = fresh_env(home)
        t = timings(["play", "--quit-after", "0.5"], env)
        rows.append(
            {"run": f"{tag}first start, title", "what": "title", "seconds": t.get("first frame"), "cpu": t["cpu"]}
        )
    with tempfile.TemporaryDirectory() as home:
        env = fresh_env(home)
        level = ["play", LEVEL, "--screenshot-after", "0.001", "--quit-after", "0.5"]
        for run in ("first start", "later start (baseline)"):
            t = timings(level, env)
            rows.append({"run": f"{tag}{run}, {LEVEL}", "what": "level", "seconds": t.get("first level frame")})
            rows[-1].update({"cpu": t["cpu"], "kernels ready": t.get("kernels ready")})
    if not tag and importlib.util.find_spec("imgui_bundle") is not None:  # the editor's window, at once
        with tempfile.TemporaryDirectory() as home:
            t = timings(["edit", LEVEL, "--quit-after", "0.5"], fresh_env(home))
            rows.append(
                {"run": "first start, editor", "what": "editor", "seconds": t.get("first frame"), "cpu": t["cpu"]}
            )
    for r in rows:
        ready = f", kernels ready at {_s(r['kernels ready']).strip()}" if r.get("kernels ready") else ""
        out(f"  {r['run']:48s} {_s(r['seconds'])}  (CPU {r['cpu']:.1f} s for the whole run{ready})")
    return rows


def _without_bytecode() -> int:
    """How many of the game's modules have no compiled bytecode (``__pycache__``) beside them."""
    package = Path(__file__).resolve().parents[1]
    return sum(not os.path.exists(importlib.util.cache_from_source(str(f))) for f in package.rglob("*.py"))


def _s(x: float | None) -> str:
    return "-" if x is None else f"{x:6.2f} s"


def run(busy_n: int = 4, out=print) -> list[dict]:
    """The rows: quiet first starts, then (``busy_n`` > 0) the same with ``busy_n`` busy processes."""
    if not os.environ.get("DISPLAY"):
        raise UserError("bench start: needs a display for the game's window (set DISPLAY; Xvfb will do)")
    why = shipped.why_not(fresh_env(tempfile.gettempdir()))
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    out(f"Shipped kernels: {'in use' if why is None else 'not used: ' + why}; {os.cpu_count()} cores, load {load}")
    missing = _without_bytecode()
    if missing and os.environ.get("PYTHONDONTWRITEBYTECODE"):
        out(
            f"note: {missing} of the game's modules have no compiled bytecode and PYTHONDONTWRITEBYTECODE is set: "
            "every start compiles them (about 0.3 s on two cores), which an installed game does not"
        )
    t0 = time.perf_counter()
    rows = _starts("", out)
    if busy_n:
        with busy(busy_n):
            rows += _starts(f"{busy_n} busy: ", out)
    out(f"({time.perf_counter() - t0:.0f} s in all)")
    return rows


def targets(rows: list[dict]) -> list[tuple[str, str, bool | None]]:
    """``(target, measured, met)`` for each target with a row."""
    found = []
    for r in rows:
        busy_row = "busy" in r["run"]
        if "later" in r["run"] or (busy_row and r["what"] == "title"):
            continue
        limit = BUSY_TARGET if busy_row else (LEVEL_TARGET if r["what"] == "level" else TITLE_TARGET)
        first = {"title": "title interactive", "editor": "editor window drawn", "level": "first level frame"}
        name = f"{first[r['what']]} <= {limit:.0f} s"
        name += ", busy" if busy_row else ", quiet"
        found.append((name, _s(r["seconds"]).strip(), None if r["seconds"] is None else r["seconds"] <= limit))
    return found


def print_targets(rows: list[dict], out=print) -> None:
    out("Targets (a fresh install, 2 cores):")
    for name, measured, ok in targets(rows):
        mark = "n/a " if ok is None else ("PASS" if ok else "FAIL")
        out(f"  [{mark}] {name:62s} measured: {measured}")
