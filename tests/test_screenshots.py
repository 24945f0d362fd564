"""Screenshots: named by date and time in the pictures folder, never overwriting, never fatal.

The window test (under Xvfb, with xdotool) also checks the game's other loose
ends a player meets in a window: F9 records into the data folder that
``ACROSS_DIMENSIONS_DATA_DIR`` names, and opening the editor (F2) after the
level file broke on disk is a notice, the game going on.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from datetime import datetime
from pathlib import Path

import pytest
from conftest import shots_in, xvfb_display

from across_dimensions.app import screenshots
from across_dimensions.app.editor import missing_message
from across_dimensions.app.screenshots import save_screenshot

REPO = Path(__file__).resolve().parents[1]
NOW = datetime(2026, 12, 2, 8, 41, 7)


def _png(path):
    Path(path).write_bytes(b"\x89PNG\r\n\x1a\n" + os.urandom(16))


def test_named_by_date_and_time_and_never_overwriting(tmp_path):
    names = []
    for _ in range(3):
        path, message = save_screenshot(_png, tmp_path, NOW)
        assert message == f"Screenshot saved: {path}"
        names.append(path.name)
    assert names == [
        "across-dimensions_2026-12-02_08-41-07.png",
        "across-dimensions_2026-12-02_08-41-07_2.png",
        "across-dimensions_2026-12-02_08-41-07_3.png",
    ]
    kept = (tmp_path / names[2]).read_bytes()
    (tmp_path / names[1]).unlink()  # a deleted shot: its name is free again, the others stay
    path, _ = save_screenshot(_png, tmp_path, NOW)
    assert path.name == names[1] and (tmp_path / names[2]).read_bytes() == kept
    assert [p.name for p in shots_in(tmp_path)] == [names[0], names[2], names[1]]


def test_a_write_failure_is_a_notice_and_leaves_nothing(tmp_path):
    blocker = tmp_path / "a file"
    blocker.write_text("")
    path, message = save_screenshot(_png, blocker / "shots", NOW)  # its folder cannot be made
    assert path is None and message.startswith(f"Screenshot not saved: {blocker / 'shots'}: ")

    def failing(p):
        raise OSError(28, "No space left on device")

    path, message = save_screenshot(failing, tmp_path, NOW)
    assert path is None and message.endswith("No space left on device")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a file"]  # the claimed name is given back


def test_the_folder_is_the_pictures_folder_unless_overridden(monkeypatch, tmp_path):
    import platformdirs

    monkeypatch.delenv(screenshots.DIR_ENV, raising=False)
    assert screenshots.screenshot_folder() == Path(platformdirs.user_pictures_dir()) / "Across Dimensions"
    monkeypatch.setenv(screenshots.DIR_ENV, str(tmp_path))
    assert screenshots.screenshot_folder() == tmp_path


@pytest.fixture(scope="module")
def xvfb():
    with xvfb_display(72, "ACROSS_DIMENSIONS_SHOTS_TEST_DISPLAY") as display:
        yield display


@pytest.mark.slow
def test_in_the_window_f12_f9_and_f2_never_end_the_game(env, tmp_path, xvfb):
    if shutil.which("xdotool") is None:
        pytest.skip("xdotool is not installed")
    level = tmp_path / "level.toml"
    shutil.copy(REPO / "levels" / "01_first_steps.toml", level)
    blocker = tmp_path / "not a folder"
    blocker.write_text("")
    settings = tmp_path / "settings.toml"
    settings.write_text("", encoding="utf-8")
    e = dict(env, DISPLAY=xvfb, ACROSS_DIMENSIONS_DATA_DIR=str(tmp_path / "data"))
    e[screenshots.DIR_ENV] = str(blocker / "shots")  # every screenshot fails to write
    e.pop("WAYLAND_DISPLAY", None)
    errors = tmp_path / "stderr.txt"

    def said(text: str, times: int = 1, within: float = 120.0) -> bool:
        """Wait until the game has written ``text`` to stderr ``times`` times (it may be busy)."""
        deadline = time.monotonic() + within
        while time.monotonic() < deadline and game.poll() is None:
            if errors.read_text(encoding="utf-8").count(text) >= times:
                return True
            time.sleep(0.2)
        return errors.read_text(encoding="utf-8").count(text) >= times

    def key(name, then=1.0):
        subprocess.run(["xdotool", "key", name], env=e, check=True)
        time.sleep(then)

    with errors.open("w", encoding="utf-8") as err_file:
        game = subprocess.Popen(
            [sys.executable, "-m", "across_dimensions", "play", str(level), "--settings", str(settings)],
            cwd=tmp_path,
            env=e,
            stdout=subprocess.PIPE,
            stderr=err_file,
            text=True,
        )
        try:
            for _ in range(900):  # the level's name in the caption: the kernels are loaded and it plays
                found = subprocess.run(["xdotool", "search", "--name", "First Steps"], env=e, capture_output=True)
                if found.stdout.strip():
                    break
                time.sleep(0.2)
            time.sleep(1.0)
            key("F12")
            assert said("warning: Screenshot not saved: ")
            key("F9", 2.5)  # record ...
            key("F9")  # ... and stop
            level.write_bytes(b"\xff\xfe not a level")
            key("F2")
            if missing_message() is None:  # with the editor extra, F2 reads the broken file and says so
                assert said(f"warning: Cannot open the editor: {level}: not a text file")
            key("F12")
            assert said("warning: Screenshot not saved: ", times=2)
            assert game.poll() is None, "the game ended"
        finally:
            game.terminate()
            out, _ = game.communicate(timeout=60)
    err = errors.read_text(encoding="utf-8")
    assert game.returncode in (0, 128 + 15), err
    assert "Traceback" not in err and "internal error" not in err, err
    assert err.count("warning: Screenshot not saved: ") == 2, err
    recordings = list((tmp_path / "data" / "replays").glob("level_*.json"))
    assert len(recordings) == 1 and f"replay saved: {recordings[0]}" in out, out + err
