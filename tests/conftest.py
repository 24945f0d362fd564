"""Shared fixtures: one offscreen OpenGL context, golden-image comparison."""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import time
from pathlib import Path

import pytest

# Before numpy: importing the package pins numpy's BLAS kernels (across_dimensions/_blas.py), so
# replays played in this process match their recorded hashes on a CPU with AVX-512 too.
import across_dimensions  # noqa: F401

# Before numba is imported, as the game does at its start: this process loads the shipped
# kernels instead of compiling them (minutes on two cores), and caches the rest where the caller
# chose (``NUMBA_CACHE_DIR``), else in the player's cache folder. The `env` fixture gives child
# processes the environment without this choice, so each starts as a player's would.
import across_dimensions.app  # noqa: F401
from across_dimensions import _shipped_kernels

GOLDEN_DIR = Path(__file__).parent / "golden"
REPO = Path(__file__).resolve().parents[1]

#: The shipped levels whose whole-level runs take longest (the longest replays, the most
#: entities): a test run once per level runs these with the slow tests, so the default run
#: stays within 15 minutes on a slow 2-core machine and every level is still covered by CI.
HEAVY_LEVELS = frozenset({"05_blast_and_field", "07_orthogonal_worlds", "09_hive", "10_cloister", "11_crossfire"})


def per_level(values, stem=lambda v: Path(v).stem) -> list:
    """``pytest.param`` per level (a name or a path), with the stem as its id; those of
    :data:`HEAVY_LEVELS` marked ``slow``."""
    return [pytest.param(v, id=stem(v), marks=[pytest.mark.slow] if stem(v) in HEAVY_LEVELS else []) for v in values]


def standing_frames(levels, grid: int = 2, every: int = 3):
    """``(level, (x, z, yaw), frame)``: each shipped level of ``levels`` seen from every
    ``every``-th of ``bench levels``' standing poses on a ``grid x grid`` lattice (walls close
    up, the floor, 4D matter in front), the player placed there and the frame built."""
    from across_dimensions.bench.levels import _poses
    from across_dimensions.game.sim import Game
    from across_dimensions.world.level import load_level
    from across_dimensions.world.resources import resolve_level

    for level in levels:
        game = Game(load_level(resolve_level(level)))
        feet = game.player.position[[1, 3]]
        for x, z, yaw in _poses(game, grid)[::every]:
            game.place_player((x, feet[0], z, feet[1]), yaw, 0.0)
            yield level, (x, z, yaw), game.frame()


@pytest.fixture(scope="module")
def env() -> dict:
    """Environment for running the command as a subprocess: this checkout first on the path, the
    numba cache as the caller set it (a test module may define its own)."""
    e = _shipped_kernels.for_child()
    e["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), e.get("PYTHONPATH")) if p)
    e.pop("PYTHONWARNINGS", None)
    return e


@pytest.fixture(scope="session")
def gl_ctx():
    """One standalone EGL context for the session (skips when EGL is unavailable)."""
    from across_dimensions.render.context import RenderError, create_offscreen_context

    try:
        ctx = create_offscreen_context()
    except RenderError as e:
        pytest.skip(f"no OpenGL context through EGL: {e}")
    yield ctx
    ctx.release()


@pytest.fixture
def compare_golden(tmp_path):
    """``compare_golden(name, image)`` against ``tests/golden/<name>.png``.

    Tolerant to llvmpipe rounding: fails when the mean absolute difference is
    2/255 or more, or 1% of pixels differ by more than 32/255. With
    ``REGENERATE_GOLDEN=1`` (or when the file is missing) it writes the image
    and skips, asking for a look before committing.
    """
    import numpy as np

    from across_dimensions.render.png import read_png, write_png

    def compare(name: str, img: np.ndarray) -> None:
        path = GOLDEN_DIR / f"{name}.png"
        if os.environ.get("REGENERATE_GOLDEN") == "1" or not path.exists():
            GOLDEN_DIR.mkdir(parents=True, exist_ok=True)
            write_png(path, img)
            pytest.skip(f"wrote golden image {path}; check it by eye and commit it")
        want = read_png(path)
        assert want.shape == img.shape, f"golden {path} is {want.shape}, rendered {img.shape}"
        diff = np.abs(want.astype(int) - img.astype(int))
        mean = diff.mean()
        bad = (diff.max(axis=2) > 32).mean()
        if mean >= 2.0 or bad >= 0.01:
            write_png(tmp_path / f"{name}_actual.png", img)
            write_png(tmp_path / f"{name}_diff.png", np.clip(diff * 4, 0, 255).astype(np.uint8))
            pytest.fail(
                f"{name}: mean abs diff {mean:.2f}/255 (limit 2), {bad:.2%} pixels off by > 32 (limit 1%); "
                f"actual and diff images in {tmp_path}; if the change is intended rerun with REGENERATE_GOLDEN=1"
            )

    return compare


# ------------------------------------------------------------------ fuzzing
# Options and the failure summary of tests/test_fuzz.py (the suite itself lives in tests/fuzz/).
FUZZ_DEFAULT_CASES = 300
FUZZ_DEFAULT_SEED = 20261201
_FUZZ_FAILURES = pytest.StashKey[list]()


def pytest_addoption(parser):
    group = parser.getgroup("fuzz", "fuzzing of levels, replays, settings, meshes and options (tests/test_fuzz.py)")
    group.addoption(
        "--fuzz-cases",
        type=int,
        default=FUZZ_DEFAULT_CASES,
        metavar="N",
        help=f"number of fuzz cases to generate and run (default {FUZZ_DEFAULT_CASES})",
    )
    group.addoption(
        "--fuzz-seed",
        type=int,
        default=FUZZ_DEFAULT_SEED,
        metavar="S",
        help=f"seed of the generated cases (default {FUZZ_DEFAULT_SEED})",
    )
    group.addoption(
        "--fuzz-case",
        type=int,
        action="append",
        default=[],
        metavar="I",
        help="run only case I (repeatable), e.g. to rerun a reported failure",
    )
    group.addoption(
        "--fuzz-timeout",
        type=float,
        default=10.0,
        metavar="SECONDS",
        help="time limit of each command run on a case (default 10)",
    )
    group.addoption(
        "--fuzz-keep",
        default=None,
        metavar="DIR",
        help="write the failing cases' files under DIR (default: pytest's temporary folder)",
    )


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "fuzz: generated hostile inputs run through the command line (see tests/test_fuzz.py; --fuzz-cases N)",
    )


@pytest.fixture(scope="session")
def fuzz_failures(request) -> list:
    """Failures of fuzz cases as ``(label, category, message)``, summarised at the end of the run."""
    return request.config.stash.setdefault(_FUZZ_FAILURES, [])


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    failures = config.stash.get(_FUZZ_FAILURES, [])
    if not failures:
        return
    by_category: dict[str, list] = {}
    for label, category, message in failures:
        by_category.setdefault(category, []).append((label, message))
    tr = terminalreporter
    tr.section("fuzz failures by category")
    for category, items in sorted(by_category.items(), key=lambda kv: -len(kv[1])):
        cases = sorted({label for label, _ in items})
        tr.write_line(f"{category}: {len(items)} in {len(cases)} case(s), e.g. {', '.join(cases[:4])}")
        tr.write_line(f"    {items[0][1][:300]}")


_HEADLESS_WINDOW = r"""
import sys
import pyglet
pyglet.options["headless"] = True
try:
    from across_dimensions.app.settings import Settings
    from across_dimensions.app.window import GameWindow
    w = GameWindow(Settings())
except Exception as e:
    print(f"no headless pyglet window: {e}")
    sys.exit(77)
s = w.session
"""


def headless_window(script: str) -> str:
    """A child process's script that drives the game's window, headless: ``script`` after a
    start that exits with 77 (the test then skips) where pyglet cannot open a window, and leaves
    the window in ``w`` and its session in ``s``. The window is driven in a fresh process because
    pyglet's headless mode must be chosen before its window module loads."""
    return _HEADLESS_WINDOW + script


def shots_in(folder: Path) -> list[Path]:
    """The game's screenshots in ``folder``, oldest first (their names are the time they were taken)."""
    return sorted(folder.glob("across-dimensions_*.png"), key=lambda p: p.stat().st_mtime_ns)


@contextlib.contextmanager
def xvfb_display(number: int, env_var: str):
    """A virtual X display ``:number`` for a real window, stopped afterwards.

    Skips the test when Xvfb is not installed, the display is taken (``env_var``
    chooses another number) or the server does not start.
    """
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb is not installed")
    number = int(os.environ.get(env_var, str(number)))
    if Path(f"/tmp/.X{number}-lock").exists():
        pytest.skip(f"display :{number} is in use (set {env_var})")
    server = subprocess.Popen(
        ["Xvfb", f":{number}", "-screen", "0", "1280x720x24", "-nolisten", "tcp"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        for _ in range(100):
            if Path(f"/tmp/.X11-unix/X{number}").exists():
                break
            time.sleep(0.05)
        else:
            pytest.skip("Xvfb did not start")
        yield f":{number}"
    finally:
        server.terminate()
        server.wait(timeout=10)


@pytest.fixture(autouse=True, scope="session")
def _own_data_folder(tmp_path_factory):
    """The game's saves (progress.json) and screenshots go to folders of the test run, never the
    player's own; child processes inherit them through the environment."""
    if not os.environ.get("ACROSS_DIMENSIONS_DATA_DIR"):
        os.environ["ACROSS_DIMENSIONS_DATA_DIR"] = str(tmp_path_factory.mktemp("data"))
    if not os.environ.get("ACROSS_DIMENSIONS_SCREENSHOT_DIR"):
        os.environ["ACROSS_DIMENSIONS_SCREENSHOT_DIR"] = str(tmp_path_factory.mktemp("screenshots"))
    yield
