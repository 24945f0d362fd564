"""``across-dimensions edit LEVEL`` run as a user runs it, and the editor key in play.

The window tests need Xvfb (skipped without it) and the optional extra
``editor`` (skipped without it); they check the panels are really drawn by
reading back a screenshot.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import shots_in, xvfb_display

from across_dimensions.app.editor import EXTRA_MODULES, INSTALL_HINT, missing
from across_dimensions.render.png import read_png

REPO = Path(__file__).resolve().parents[1]
TIMEOUT = 240
#: ImGui's default dark style: the main menu bar's background is (0.14, 0.14, 0.14) -> 36 in 8 bits.
MENU_BAR_GREY = 36
MENU_BAR_ROWS = slice(2, 17)  # the menu bar is 19 px high with the default font; its text sits in the middle


@pytest.fixture(scope="module")
def env() -> dict:
    e = dict(os.environ)
    e.setdefault("NUMBA_CACHE_DIR", str(REPO / ".numba_cache"))
    e["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), e.get("PYTHONPATH")) if p)
    e.pop("WAYLAND_DISPLAY", None)
    return e


def run(env, cwd, *args, code=None) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-c", code, *args] if code else [sys.executable, "-m", "across_dimensions", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT, cwd=cwd, env=env)


WITHOUT_IMGUI = (
    "import sys; sys.modules['imgui_bundle'] = None; "  # as if it were not installed
    "from across_dimensions.app.cli import main; sys.exit(main(sys.argv[1:]))"
)


def test_edit_without_the_extra_says_what_to_install_in_one_line(env, tmp_path):
    r = run(env, tmp_path, "edit", "02_crystal_cache", code=WITHOUT_IMGUI)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and INSTALL_HINT in lines[0] and "imgui-bundle" in lines[0], r.stderr
    assert "Traceback" not in r.stderr and r.stdout == ""


def test_edit_refuses_an_unknown_level_and_a_missing_display(env, tmp_path):
    if missing():
        pytest.skip(f"the editor extra is not installed ({', '.join(missing())})")
    r = run(env, tmp_path, "edit", "no_such_level")
    assert r.returncode == 2 and "no_such_level" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    e = dict(env, DISPLAY=":917")  # no X server there
    r = run(e, tmp_path, "edit", "02_crystal_cache")
    assert r.returncode == 1 and "DISPLAY=:917" in r.stderr and "Traceback" not in r.stderr


def test_edit_needs_a_level(env, tmp_path):
    r = run(env, tmp_path, "edit")
    assert r.returncode == 2 and "level" in r.stderr


@pytest.fixture(scope="module")
def xvfb():
    """A virtual X display for a real window; skipped when Xvfb is not installed."""
    if missing():
        pytest.skip(f"the editor extra is not installed ({', '.join(missing())})")
    with xvfb_display(77, "ACROSS_DIMENSIONS_EDITOR_TEST_DISPLAY") as display:
        yield display


def _menu_bar(png: Path) -> np.ndarray:
    image = read_png(png)
    return image[MENU_BAR_ROWS, :, :3].astype(int)


@pytest.mark.slow
def test_edit_opens_a_window_with_the_panels(env, tmp_path, xvfb):
    settings = tmp_path / "settings.toml"
    settings.write_text("", encoding="utf-8")
    e = dict(env, DISPLAY=xvfb, ACROSS_DIMENSIONS_SCREENSHOT_DIR=str(tmp_path / "screenshots"))
    r = run(
        e, tmp_path, "edit", "02_crystal_cache", "--settings", settings, "--screenshot-after", "2", "--quit-after", "4"
    )
    assert r.returncode == 0, r.stderr
    shots = shots_in(tmp_path / "screenshots")
    assert len(shots) == 1, r.stdout + r.stderr
    shot = shots[0]
    bar = _menu_bar(shot)
    # The menu bar: mostly ImGui's grey, with its light text (File Edit Add View Play) on the left.
    assert np.mean(np.abs(bar - MENU_BAR_GREY) <= 3) > 0.8
    assert bar[:, :220].max() > 150
    assert not list(tmp_path.glob("imgui.ini"))  # ImGui keeps no layout file in the user's folder


@pytest.mark.slow
def test_the_editor_key_in_play_opens_the_editor(env, tmp_path, xvfb):
    if shutil.which("xdotool") is None:
        pytest.skip("xdotool is not installed")
    settings = tmp_path / "settings.toml"
    settings.write_text("", encoding="utf-8")
    e = dict(env, DISPLAY=xvfb, ACROSS_DIMENSIONS_SCREENSHOT_DIR=str(tmp_path / "screenshots"))
    game = subprocess.Popen(
        [sys.executable, "-m", "across_dimensions", "play", "02_crystal_cache", "--settings", str(settings)],
        cwd=tmp_path,
        env=e,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        for _ in range(600):  # the level's name in the caption: the kernels are loaded and it plays
            found = subprocess.run(
                ["xdotool", "search", "--name", "Crystal Cache"], env=e, capture_output=True, text=True
            )
            if found.stdout.strip():
                break
            time.sleep(0.2)
        time.sleep(1.0)
        shots = tmp_path / "screenshots"

        def key(name, then=0.8):
            subprocess.run(["xdotool", "key", name], env=e, check=True)
            time.sleep(then)

        key("F12")  # the game
        key("F2")  # to the editor
        key("F12")
        key("F2")  # back to the game
        key("F12")
        for _ in range(50):
            if len(shots_in(shots)) == 3:
                break
            time.sleep(0.1)
    finally:
        game.terminate()
        out, err = game.communicate(timeout=30)
    assert game.returncode in (0, 128 + 15), err
    bars = [_menu_bar(p) for p in shots_in(shots)]
    in_editor = [np.mean(np.abs(b - MENU_BAR_GREY) <= 3) > 0.8 for b in bars]
    assert in_editor == [False, True, False], (in_editor, out, err)


def test_the_readme_installs_the_extra_from_the_source_folder():
    import tomllib

    section = (REPO / "README.md").read_text(encoding="utf-8").split("## The level editor", 1)[1]
    line = section.split("```", 2)[1].strip().splitlines()[0]
    assert line.split("#")[0].strip() == 'pip install -e ".[editor]"'  # works in a checkout, no index needed
    extra = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["project"]["optional-dependencies"]
    names = {d.split(">")[0].split("=")[0].strip().lower() for d in extra["editor"]}
    assert {d.lower() for d in EXTRA_MODULES.values()} <= names
    assert 'pip install -e ".[editor]"' in INSTALL_HINT
