"""Peak resident memory of ``play`` on a level, measured in a child process.

The child is the real game (``python -m across_dimensions play LEVEL --quit-after S``): its
window, its kernels, its level, drawn for ``S`` seconds after the first frame. Its peak
resident set is read from ``/proc/PID/status`` (``VmHWM``) while it runs: the kernel's
accounting of the child at its exit (``os.wait4``'s ``ru_maxrss``) starts from the resident set
of the process that started it (Linux keeps the larger of the two across ``exec``), so it
measured the benchmark itself once that was larger, after drawing every level. Where there is
no ``/proc``, ``ru_maxrss`` it is. The window needs an X display: ``DISPLAY`` when it is
set, else a private Xvfb started for the measurement (and stopped after it).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time

#: Peak memory allowed to ``play`` on the largest level (megabytes).
TARGET_MB = 400.0


def _private_display() -> tuple[subprocess.Popen | None, str | None]:
    """Start an Xvfb on a free display number; ``(process, ":N")`` or ``(None, None)``."""
    if shutil.which("Xvfb") is None:
        return None, None
    r, w = os.pipe()
    proc = subprocess.Popen(
        ["Xvfb", "-displayfd", str(w), "-screen", "0", "1280x720x24", "-nolisten", "tcp"],
        pass_fds=(w,),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(w)
    with os.fdopen(r) as f:
        number = f.readline().strip()
    if not number.isdigit():
        proc.terminate()
        proc.wait()
        return None, None
    return proc, f":{number}"


#: Seconds between two reads of the child's peak: it only rises, and the game's peak comes
#: with the level's loading and first frames, seconds before it quits.
WATCH_EVERY = 0.05


def _wait_watching(pid: int) -> tuple[int, object, int]:
    """Wait for ``pid`` to exit, reading its peak resident set (``VmHWM``, kB) meanwhile;
    ``(wait status, resource usage, last peak read or 0)``."""
    peak = 0
    while True:
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done:
            return status, usage, peak
        peak = max(peak, _peak_kb(pid))
        time.sleep(WATCH_EVERY)


def _peak_kb(pid: int) -> int:
    """``VmHWM`` of a running process in kB, 0 when it cannot be read (no ``/proc``, gone)."""
    try:
        with open(f"/proc/{pid}/status", encoding="ascii", errors="replace") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except (OSError, ValueError, IndexError):
        pass
    return 0


def play_peak_mb(level: str, seconds: float = 5.0) -> tuple[float | None, str]:
    """Peak resident megabytes of ``play level`` over ``seconds`` of play, and a note.

    Returns ``(None, why)`` when it could not be measured (no display, the game failed).
    """
    xvfb, display = (None, os.environ.get("DISPLAY"))
    if not display:
        xvfb, display = _private_display()
        if display is None:
            return None, "no X display and no Xvfb to start one"
    try:
        with tempfile.TemporaryDirectory() as data:
            # A fresh data folder: the player's settings and saves stay out of the figure.
            env = {
                **os.environ,
                "DISPLAY": display,
                "ACROSS_DIMENSIONS_DATA_DIR": data,
                "ACROSS_DIMENSIONS_CONFIG_DIR": data,
            }
            cmd = [sys.executable, "-m", "across_dimensions", "play", str(level), "--quit-after", f"{seconds:g}"]
            with tempfile.TemporaryFile() as err_file:
                child = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=err_file)
                try:
                    status, usage, peak_kb = _wait_watching(child.pid)
                finally:
                    child.returncode = 0  # reaped by wait4
                err_file.seek(0)
                err = err_file.read().decode(errors="replace").strip()
            if os.waitstatus_to_exitcode(status) != 0:
                return None, f"play exited with {os.waitstatus_to_exitcode(status)}: {err[-200:]}"
            mb = peak_kb / 1024.0 if peak_kb else usage.ru_maxrss / 1024.0
            return mb, f"play {os.path.basename(str(level))} for {seconds:g} s"
    finally:
        if xvfb is not None:
            xvfb.terminate()
            xvfb.wait()
