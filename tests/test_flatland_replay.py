"""The prologue's shipped replay, played by the ``replay`` command in a fresh process: it completes
the level with its recorded hashes; a changed action is caught; --update-hashes, --json and
--screenshots work for a prologue level as they do for a 4D one."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest

from across_dimensions.game.flatland import FlatGame
from across_dimensions.game.playback import play
from across_dimensions.game.replay import Replay
from across_dimensions.world.flat_level import load_flat_level
from across_dimensions.world.resources import levels_dir

LEVEL = levels_dir() / "prologue.toml"
REPLAY = levels_dir() / "replays" / "prologue.json"


def cli(env, *args, timeout=600) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
    )


def test_the_shipped_replay_completes_the_prologue_in_a_fresh_process(env):
    r = cli(env, "replay", LEVEL, REPLAY, "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    rep = Replay.load(REPLAY)
    assert out["outcome"] == "complete" and out["divergence"] is None
    assert out["ticks"] == rep.final_ticks and out["hash"] == rep.final_hash
    assert out["events"]["item_taken"] == 1 and out["events"]["door_opened"] == 1
    assert out["position"][0] > 52.0  # on the pad, past the pit
    assert len(rep.hashes) == rep.final_ticks // 60


def test_the_replay_plays_in_process_with_the_same_hashes():
    result = play(Replay.load(REPLAY), FlatGame(load_flat_level(LEVEL)))
    assert result.divergence is None and result.outcome == "complete"


@pytest.mark.slow
def test_a_changed_action_is_caught_as_a_divergence(tmp_path, env):
    data = json.loads(REPLAY.read_text())
    i = next(i for i, (count, row) in enumerate(data["actions"]) if row[1] == 1.0 and count > 30)
    count, row = data["actions"][i]
    data["actions"][i] = [count, [row[0], -1.0, *row[2:]]]  # a run of walking right walks left instead
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    r = cli(env, "replay", LEVEL, bad)
    assert r.returncode == 3 and "replay diverges at tick" in r.stderr, r.stderr


@pytest.mark.slow
def test_update_hashes_keeps_a_replay_that_still_holds(tmp_path, env):
    copy = tmp_path / "prologue.json"
    shutil.copy(REPLAY, copy)
    r = cli(env, "replay", LEVEL, copy, "--update-hashes")
    assert r.returncode == 0 and "hashes unchanged" in r.stdout, r.stderr
    assert copy.read_bytes() == REPLAY.read_bytes()


@pytest.mark.slow
@pytest.mark.gl
def test_screenshots_of_a_prologue_replay(tmp_path, env):
    shots = tmp_path / "shots"
    r = cli(env, "replay", "prologue", REPLAY, "--screenshots", shots, "--every", "400", "--size", "320x180")
    assert r.returncode == 0, r.stderr
    ticks = Replay.load(REPLAY).final_ticks
    assert sorted(p.name for p in shots.glob("*.png")) == [f"frame_{t:05d}.png" for t in range(0, ticks + 1, 400)]
