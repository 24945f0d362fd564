"""Saves shared by two games, and what killed saves leave behind.

- Two game processes on one data folder, each holding its progress in memory
  and saving after every level, lose nothing: each save merges under a lock.
- Temporary files of killed saves are removed at the next start, and only those.
- F9 recordings go to the data folder that ``ACROSS_DIMENSIONS_DATA_DIR`` names.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from across_dimensions.app import saves
from across_dimensions.app.saves import Progress, load_progress, save_progress

#: One game: progress read once at start, then a level finished and saved, again and again.
_GAME = """
import sys
from across_dimensions.app.saves import load_progress, save_progress
who, n = sys.argv[1], int(sys.argv[2])
progress, _ = load_progress()
for i in range(n):
    progress.finish(f"{who}{i:03d}", 10.0 + i)
    progress.found_crystals(f"{who}{i:03d}", 1, 3)
    save_progress(progress)
"""


def test_two_games_on_one_data_folder_keep_every_finished_level(env, tmp_path):
    e = dict(env, ACROSS_DIMENSIONS_DATA_DIR=str(tmp_path))
    n = 60
    games = [
        subprocess.Popen([sys.executable, "-c", _GAME, who, str(n)], env=e, stderr=subprocess.PIPE, text=True)
        for who in ("a", "b")
    ]
    for g in games:
        _, err = g.communicate(timeout=120)
        assert g.returncode == 0, err
    progress, warnings = load_progress(tmp_path / "progress.json")
    assert warnings == []
    assert sorted(progress.finished) == sorted(f"{who}{i:03d}" for who in "ab" for i in range(n))
    assert progress.finished["a007"] == 17.0 and progress.crystals["b059"] == (1, 3)
    assert not [p for p in tmp_path.iterdir() if p.suffix == ".tmp"]


def test_a_merge_keeps_the_best_of_both():
    mine = Progress(finished={"a": 30.0, "b": 20.0}, crystals={"a": (1, 3)}, current="b", checkpoint=1)
    other = Progress(finished={"a": 25.0, "c": 40.0}, crystals={"a": (2, 3), "c": (0, 2)}, current="c")
    mine.merge(other)
    assert mine.finished == {"a": 25.0, "b": 20.0, "c": 40.0}
    assert mine.crystals == {"a": (2, 3), "c": (0, 2)}
    assert (mine.current, mine.checkpoint) == ("b", 1)  # Continue resumes where this game is


def test_a_save_takes_in_what_another_game_saved(tmp_path):
    path = tmp_path / "progress.json"
    first = Progress()
    first.finish("01_first_steps", 30.0)
    save_progress(first, path)
    second = Progress()
    second.finish("02_crystal_cache", 50.0)
    save_progress(second, path)
    assert set(second.finished) == {"01_first_steps", "02_crystal_cache"}  # the menu sees both
    assert set(load_progress(path)[0].finished) == {"01_first_steps", "02_crystal_cache"}


def test_temporary_files_of_killed_saves_are_removed_at_start(tmp_path):
    ours = [tmp_path / f".progress.json.{s}.tmp" for s in ("abcd1234", "x_y_z_09")]
    others = [
        tmp_path / n for n in (".progress.json.tmp", ".settings.toml.abcd1234.tmp", "notes.tmp", "progress.json.bak")
    ]
    for p in ours + others:
        p.write_text("{")
    progress, warnings = load_progress(tmp_path / "progress.json")
    assert warnings == [] and progress.finished == {}
    assert not any(p.exists() for p in ours)
    assert all(p.exists() for p in others)


@pytest.mark.slow
def test_a_killed_saver_leaves_nothing_after_the_next_start(env, tmp_path):
    e = dict(env, ACROSS_DIMENSIONS_DATA_DIR=str(tmp_path))
    for _ in range(5):  # killed at a random point of its saves, often mid-write
        g = subprocess.Popen([sys.executable, "-c", _GAME, "k", "100000"], env=e, stderr=subprocess.DEVNULL)
        time.sleep(1.5)
        os.kill(g.pid, signal.SIGKILL)
        g.wait()
    load_progress(tmp_path / "progress.json")
    assert not [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
    assert load_progress(tmp_path / "progress.json")[0].finished  # and the progress itself is whole


def test_recordings_follow_the_data_folder(monkeypatch, tmp_path):
    monkeypatch.setenv(saves.DATA_DIR_ENV, str(tmp_path))
    assert saves.replay_folder() == tmp_path / "replays"
    monkeypatch.delenv(saves.DATA_DIR_ENV)
    assert saves.replay_folder().parent == saves.data_folder() != tmp_path
    recording = (Path(saves.__file__).parent / "recording.py").read_text()
    assert "replay_folder()" in recording and "user_data_dir" not in recording  # F9 asks saves
