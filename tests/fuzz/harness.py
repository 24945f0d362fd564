"""Run fuzz cases in a worker process and judge what a user would have seen.

:class:`Worker` keeps one long-lived worker (numba's start-up is paid once),
sends it a case, and kills and restarts it when a case outlives the hard time
limit or the process dies. :func:`judge` turns a case and the worker's reply
into a list of :class:`Failure`, each with a category from :data:`CATEGORIES`.
"""

from __future__ import annotations

import json
import os
import re
import selectors
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from .cases import REPO, Case, command_line

__all__ = ["Worker", "Failure", "judge", "report", "leftover_temporaries", "CATEGORIES", "MEMORY_LIMIT"]

#: Address-space cap of the worker: enough for the game (numba reserves a lot of
#: virtual memory) and any sane input, small enough that a bomb cannot hurt the machine.
MEMORY_LIMIT = int(3.5 * 2**30)

CATEGORIES = {
    "hang": "did not finish within the time limit",
    "worker died": "the worker process died (crash, abort, or killed past the hard limit)",
    "traceback": "a Python traceback reached the output",
    "internal error": "'internal error' reported for bad input",
    "exception": "an exception escaped the entry point",
    "exit status": "exit status outside the allowed set",
    "unnamed file": "a refusal that names neither the file nor the option",
    "python warning": "a Python warning (e.g. numpy RuntimeWarning) reached the user",
    "accepted bad input": "input that must be refused was accepted",
    "non-finite state": "a level that loads plays into NaN/inf, or the player leaves the w range",
    "body left w range": "a rigid body drifted out of the level's w range",
    "non-finite output": "a written mesh has NaN or inf vertices",
    "leftover temporary": "a *.tmp file was left in the input or output folder",
    "invalid JSON written": "a file written as JSON is not strict JSON",
    "invalid settings accepted": "the settings loader returned settings its own validation rejects",
    "settings round trip": "saved settings do not load back the same",
    "no performance warning": "check-level said ok, with no warning, to a level far too heavy for 60 Hz",
    "clobbered file": "a write went through a squatted temporary name, or did not happen",
    "harness": "the harness itself failed to set the case up",
}

#: How Python's warnings module prints: ``path.py:72: RuntimeWarning: message``.
_WARNING = re.compile(r":\d+: [A-Z]\w*Warning: ")


@dataclass
class Failure:
    category: str
    message: str


class Worker:
    """One worker process serving cases (see :mod:`.worker`).

    Parameters
    ----------
    log : Path
        The worker's own stderr (start-up problems) goes here.
    timeout : float
        Per-step limit enforced inside the worker; the parent kills the worker
        if a whole case has not answered after ``timeout * steps + grace``.
    """

    def __init__(self, log: Path, timeout: float = 10.0, memory_limit: int = MEMORY_LIMIT, grace: float = 15.0):
        self.log = Path(log)
        self.timeout = timeout
        self.memory_limit = memory_limit
        self.grace = grace
        self.proc: subprocess.Popen | None = None
        self.starts = 0
        self._buf = b""

    def _env(self) -> dict:
        env = dict(os.environ)
        tests = str(Path(__file__).resolve().parents[1])
        env["PYTHONPATH"] = os.pathsep.join(p for p in (tests, str(REPO), env.get("PYTHONPATH")) if p)
        if "NUMBA_CACHE_DIR" not in env:  # keep the user's compiled kernels although XDG_CACHE_HOME moves
            base = env.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
            env["NUMBA_CACHE_DIR"] = os.path.join(base, "across-dimensions", "numba")
        home = self.log.parent / "worker-home"
        for var, sub in (("XDG_CACHE_HOME", "cache"), ("XDG_CONFIG_HOME", "config"), ("XDG_DATA_HOME", "data")):
            env[var] = str(home / sub)  # bake cache, settings and recordings stay out of the user's folders
        env["ACROSS_DIMENSIONS_CONFIG_DIR"] = str(home / "config" / "across-dimensions")
        env.pop("DISPLAY", None)
        env.pop("PYTHONWARNINGS", None)
        return env

    def start(self) -> None:
        self.log.parent.mkdir(parents=True, exist_ok=True)
        with open(self.log, "ab") as log:
            self.proc = subprocess.Popen(
                [sys.executable, "-m", "fuzz.worker", str(self.memory_limit)],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=log,
                env=self._env(),
                start_new_session=True,
            )
        self.starts += 1
        self._buf = b""
        ready = self._readline(300.0)  # a cold numba cache compiles for about a minute
        if ready is None:
            self.stop()
            raise RuntimeError(f"the fuzz worker did not start; see {self.log}")

    def stop(self) -> None:
        if self.proc is None:
            return
        if self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)  # its own session: the worker and its children only
            except ProcessLookupError:
                pass
        self.proc.wait()
        for f in (self.proc.stdin, self.proc.stdout):
            try:
                f.close()
            except OSError:
                pass
        self.proc = None

    def _readline(self, timeout: float) -> bytes | None:
        deadline = time.monotonic() + timeout
        fd = self.proc.stdout.fileno()
        with selectors.DefaultSelector() as sel:
            sel.register(fd, selectors.EVENT_READ)
            while b"\n" not in self._buf:
                left = deadline - time.monotonic()
                if left <= 0 or not sel.select(left):
                    return None
                chunk = os.read(fd, 1 << 16)
                if not chunk:
                    return None
                self._buf += chunk
        line, _, self._buf = self._buf.partition(b"\n")
        return line

    def run(self, steps: list[dict], timeout: float | None = None) -> dict:
        """Run one case's steps; ``{"steps": [...]}`` or ``{"died": reason}``."""
        if self.proc is None or self.proc.poll() is not None:
            self.start()
        timeout = self.timeout if timeout is None else timeout
        t0 = time.monotonic()
        try:
            self.proc.stdin.write((json.dumps({"steps": steps, "timeout": timeout}) + "\n").encode())
            self.proc.stdin.flush()
        except BrokenPipeError:
            self.stop()
            return {"died": "the worker had exited before the case started"}
        line = self._readline(sum(max(s.get("timeout", 0), timeout) for s in steps) + self.grace)
        if line is None:
            alive = self.proc.poll() is None
            code = self.proc.returncode
            self.stop()
            if alive:
                return {
                    "died": f"no answer after {time.monotonic() - t0:.0f} s (stuck outside Python?); killed",
                    "hang": True,
                }
            how = f"killed by signal {-code}" if code is not None and code < 0 else f"exit status {code}"
            return {"died": f"the worker process ended ({how}) during the case"}
        return json.loads(line)


def leftover_temporaries(folder: Path) -> list[str]:
    """Names of ``*.tmp`` / ``.*.tmp`` files anywhere under ``folder``."""
    found = []
    for root, dirs, files in os.walk(folder, followlinks=False):
        found += [os.path.relpath(os.path.join(root, f), folder) for f in files + dirs if f.endswith(".tmp")]
    return sorted(found)


def _non_finite_obj(path: Path) -> str | None:
    try:
        text = path.read_text(errors="replace")
    except OSError:
        return None
    for n, line in enumerate(text.splitlines(), 1):
        if line.startswith("v "):
            low = line.lower()
            if "nan" in low or "inf" in low:
                return f"{path.name} line {n}: {line[:80]}"
    return None


def _names_something(text: str, names) -> bool:
    return any(n and n in text for n in names)


def judge(case: Case, steps: list[dict], reply: dict, folder: Path) -> list[Failure]:
    """Every way the reply breaks the rules for a user-facing entry point."""
    out: list[Failure] = []
    if "died" in reply:
        out.append(Failure("hang" if reply.get("hang") else "worker died", reply["died"]))
    results = reply.get("steps", [])
    for i, (step, res) in enumerate(zip(steps, results)):
        if res.get("skipped"):
            continue
        what = command_line(step) if step["op"] == "cli" else f"{step['op']} {step.get('path', '')}"
        text = res.get("stdout", "") + res.get("stderr", "")
        if res["timed_out"]:
            out.append(Failure("hang", f"{what}: still running after {res['seconds']:.1f} s"))
            continue
        if res["exception"]:
            cat = "harness" if step["op"] == "write_replay" else "exception"
            tb = (res.get("traceback") or "").strip().splitlines()
            out.append(Failure(cat, f"{what}: {res['exception']} (at {tb[-3].strip() if len(tb) >= 3 else '?'})"))
        if "Traceback (most recent call last)" in text:
            out.append(Failure("traceback", f"{what}: {_first(text, 'Traceback')}"))
        if "internal error" in text:
            out.append(Failure("internal error", f"{what}: {_first(text, 'internal error')}"))
        if _WARNING.search(res.get("stderr", "")):
            out.append(Failure("python warning", f"{what}: {_first(res['stderr'], _WARNING)}"))
        for cat, msg in res.get("problems", []):
            out.append(Failure(cat, f"{what}: {msg}"))
        if step["op"] != "cli" or res["exception"]:
            if step["op"] == "settings" and case.must_refuse and not res.get("warnings") and not res["exception"]:
                out.append(Failure("accepted bad input", f"{what}: loaded with no warning ({case.detail})"))
            continue
        code = res["exit"]
        if code not in step["allowed"] and "internal error" not in text:
            why = f" ({step['why']})" if step.get("why") else ""
            out.append(
                Failure(
                    "exit status",
                    f"{what}: exit {code}, expected one of {step['allowed']}{why}: {_last_line(res['stderr'])}",
                )
            )
        named = _names_something(res["stderr"], case.names)
        if code not in (0, 3, None) and "internal error" not in text and not named:
            out.append(
                Failure(
                    "unnamed file",
                    f"{what}: exit {code} and the message names none of "
                    f"{list(case.names)}: {_last_line(res['stderr'])}",
                )
            )
        if i == 0 and case.must_refuse and code in (0, 3):
            out.append(Failure("accepted bad input", f"{what}: exit {code} for {case.detail}"))
        if code == 0 and step.get("warn_or_refuse") and "warn" not in text.lower():
            out.append(Failure("no performance warning", f"{what}: ok with no warning for {case.detail}"))
        if step.get("must_create") and not Path(step["must_create"]).is_file():
            out.append(Failure("clobbered file", f"{what}: {step['must_create']} was not written"))
        for path, content in (step.get("unchanged") or {}).items():
            try:
                now = Path(path).read_text()
            except OSError as e:
                now = f"<{e}>"
            if now != content:
                out.append(Failure("clobbered file", f"{what}: {path} changed to {now[:60]!r}"))
        if code == 0 and step.get("check_obj"):
            bad = _non_finite_obj(Path(step["check_obj"]))
            if bad:
                out.append(Failure("non-finite output", f"{what}: {bad}"))
    planted = {n if n.startswith("out/") else f"in/{n}" for n in case.files}
    left = [f for f in leftover_temporaries(folder) if f not in planted]
    if left:
        out.append(Failure("leftover temporary", f"left behind: {', '.join(left[:5])}"))
    return out


def _first(text: str, needle) -> str:
    for line in text.splitlines():
        if needle.search(line) if hasattr(needle, "search") else needle in line:
            return line.strip()[:300]
    return ""


def _last_line(text: str) -> str:
    lines = [ln for ln in text.strip().splitlines() if ln.strip()]
    return lines[-1].strip()[:300] if lines else "(no message)"


def report(case: Case, steps: list, reply: dict, folder: Path, failures: list[Failure]) -> str:
    """A failing case as text: what it is, where its files are, what ran, what broke, how to rerun it."""
    lines = [
        f"fuzz case {case.index} (seed {case.seed}): {case.kind} / {case.mutation}: {case.detail}",
        f"files: {folder / 'in'}",
    ]
    for step, res in zip(steps, reply.get("steps", [])):
        what = command_line(step) if step["op"] == "cli" else f"[{step['op']}] {step.get('path', '')}"
        if res.get("skipped"):
            lines.append(f"  $ {what}    (skipped)")
        else:
            lines.append(f"  $ {what}    -> exit {res['exit']}, {res.get('seconds', 0):.2f} s")
    lines += [f"[{f.category}] {f.message}" for f in failures]
    lines.append(
        f"rerun: python -m pytest tests/test_fuzz.py --fuzz-seed {case.seed} --fuzz-case {case.index}"
        f"    or: python -m tests.fuzz --seed {case.seed} --case {case.index}"
    )
    return "\n".join(lines)
