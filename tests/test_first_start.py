"""The first start never looks hung: the warm-up says what it does, how far, for how long, and
how long is left; the start-up view can be left with Esc; timings count from the command's start."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from conftest import headless_window

from across_dimensions.app import warmup
from across_dimensions.app.warmup import BackgroundWarmUp, kernel_counts, warm_progress


def _warm(done=2, kernels=(0, 0, 0), compiling=True, elapsed=30.0):
    w = BackgroundWarmUp()
    w.done, w.label, w.kernels, w.compiling = done, warmup.STEPS[done][0], kernels, compiling
    return w, w.started + elapsed


def test_the_status_says_the_step_the_kernels_the_time_and_an_estimate_only_once_it_can():
    w, now = _warm(kernels=(0, 0, 0))
    assert "starting the compiler, 0:30 so far" in w.status(now)
    w, now = _warm(kernels=(3, 90, 0))
    assert "loading the kernels" in w.status(now) and "Compiling" not in w.status(now)  # nothing compiled
    w, now = _warm(kernels=(3, 90, 2), elapsed=4.0)
    assert w.status(now) == "4D physics, 3 of 90 kernels, 0:04 so far"  # too early to tell what is left
    w, now = _warm(kernels=(30, 90, 30), elapsed=60.0)
    # 30 kernels a minute, 60 to go: at most about two more minutes.
    assert w.status(now) == "4D physics, 30 of 90 kernels, 1:00 so far, at most about 2:00 left"
    assert w.fraction() == max(2 / len(warmup.STEPS), 30 / 90)
    w, now = _warm(compiling=False)
    assert "loading the kernels" in w.status(now)


def test_the_panel_line_moves_once_a_second_and_goes_when_ready():
    w, _ = _warm(kernels=(30, 90, 30))
    line = warm_progress(w)
    assert line[:2] == (2, len(warmup.STEPS)) and "kernels" in line[2] and 0 < line[3] <= 1
    w.finished.set()
    assert warm_progress(w) is None and warm_progress(None) is None


def test_kernel_counts_read_the_dispatchers():
    from across_dimensions.core import section  # noqa: F401  a module full of kernels

    ready, total, compiled = kernel_counts()
    assert total > 5 and 0 <= ready <= total and 0 <= compiled <= total


_ESC = """
import pyglet
pyglet.options["headless"] = True
from types import SimpleNamespace
from pathlib import Path
from across_dimensions.app.views.startup import StartupView
went = []
session = SimpleNamespace(window=None, warm=None, bindings=SimpleNamespace(action_of=lambda kind, code: None),
                          to_title=lambda: went.append("title"))
view = StartupView(session, Path("levels/02_crystal_cache.toml"))
view.on_key_press(pyglet.window.key.ESCAPE, 0)
print(went)
"""


def test_esc_leaves_the_start_up_view_for_the_title():
    out = subprocess.run([sys.executable, "-c", _ESC], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "['title']"


def test_timing_counts_seconds_from_the_commands_start():
    code = "import time; time.sleep(1.2); from across_dimensions.app.session import timing; timing('now')"
    env = {**os.environ, "ACROSS_DIMENSIONS_TIMING": "1"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env=env)
    assert out.returncode == 0, out.stderr
    line = next(ln for ln in out.stdout.splitlines() if ln.startswith("timing: now at "))
    seconds = float(line.split(" at ")[1].split()[0])
    assert 1.2 <= seconds < 60.0  # the sleep and the imports, from the process's start


_AFTER_FIRST_FRAME = headless_window("""
import time
before = [s.warm.ident is not None, s.sound._opened]
w.switch_to(); w.dispatch_events(); w.update(0.0); w.on_draw(); w.flip()
drawn = [s.warm.ident is not None, s.sound._opened]
time.sleep(0.01)
pyglet.clock.tick()  # the loop's next pass
after = [s.warm.ident is not None, s.sound._opened]
print(before, drawn, after)
s.warm.join()
""")


def test_the_warm_up_and_the_audio_device_wait_for_the_first_frame():
    # Both would delay the title: the warm-up's thread takes the interpreter from the window's
    # set-up, and opening the audio device looks for libraries with ldconfig.
    out = subprocess.run([sys.executable, "-c", _AFTER_FIRST_FRAME], capture_output=True, text=True, timeout=300)
    if out.returncode == 77:
        pytest.skip(out.stdout.strip())
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "[False, False] [False, False] [True, True]"


def test_loading_the_shipped_kernels_names_the_step_and_moves_the_bar():
    w = BackgroundWarmUp()
    w._loading(2, len(warmup.STEPS), warmup.STEPS[2][0])
    assert w.status(w.started) == f"{warmup.STEPS[2][0]}, loading the kernels, 0:00 so far"
    assert w.fraction() == 2 / len(warmup.STEPS)
    w.done = len(warmup.STEPS)  # a child compiled every step: the bar stays full while loading
    w._loading(1, len(warmup.STEPS), warmup.STEPS[1][0])
    assert w.fraction() == 1.0


class _Waiting(BackgroundWarmUp):
    """A warm-up that runs until told it is done (its thread does no work)."""

    def run(self) -> None:
        self.finished.wait()


def test_the_title_shows_the_warm_up_only_once_it_has_run_a_second():
    # Loading the shipped kernels takes half a second: a panel for that long would move the menu
    # under the pointer. A start-up view (a level waiting) shows it at once.
    w = _Waiting()
    assert warm_progress(w, after=warmup.TITLE_PANEL_AFTER) is None  # not started: the first frame
    w.start()
    try:
        early, late = w.started + 0.5 * warmup.TITLE_PANEL_AFTER, w.started + 1.5 * warmup.TITLE_PANEL_AFTER
        assert warm_progress(w, after=warmup.TITLE_PANEL_AFTER, now=early) is None
        assert warm_progress(w, now=early) is not None
        assert warm_progress(w, after=warmup.TITLE_PANEL_AFTER, now=late)[2].endswith("0:01 so far")
    finally:
        w.finished.set()
        w.join()
    assert warm_progress(w, after=warmup.TITLE_PANEL_AFTER, now=late) is None  # ready
