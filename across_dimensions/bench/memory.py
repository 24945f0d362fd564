"""Peak resident memory of ``play`` on a level, measured in a child process.

The child is the real game (``python -m across_dimensions play LEVEL --quit-after S``): its
window, its kernels, its level, drawn for ``S`` seconds after the first frame. Its peak
resident set comes from the kernel's accounting of that one child (``os.wait4``), so the
benchmark's own memory is not counted. The window needs an X display: ``DISPLAY`` when it is
set, else a private Xvfb started for the measurement (and stopped after it).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile

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
            child = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            try:
                _, status, usage = os.wait4(child.pid, 0)
            finally:
                child.returncode = 0  # reaped by wait4
            err = child.stderr.read().decode(errors="replace").strip()
            child.stderr.close()
            if os.waitstatus_to_exitcode(status) != 0:
                return None, f"play exited with {os.waitstatus_to_exitcode(status)}: {err[-200:]}"
            return usage.ru_maxrss / 1024.0, f"play {os.path.basename(str(level))} for {seconds:g} s"
    finally:
        if xvfb is not None:
            xvfb.terminate()
            xvfb.wait()
