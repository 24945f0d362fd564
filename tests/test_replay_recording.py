"""Recording a replay: the file on disk is a loadable replay at every moment.

While recording, the replay's file holds an append-only journal grown once per
simulated second; finishing replaces it atomically by the replay. A process
killed mid-run (SIGTERM with no handler, or SIGKILL) leaves a journal that
loads and plays back the same states, minus at most the last second.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.game.actions import Actions
from across_dimensions.game.playback import play
from across_dimensions.game.replay import FORMAT, JOURNAL_FORMAT, Recorder, Replay, ReplayError
from across_dimensions.game.sim import Game
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

REPO = Path(__file__).resolve().parents[1]
LEVEL1 = levels_dir() / "01_first_steps.toml"


@pytest.fixture(scope="module")
def level1():
    return load_level(LEVEL1)


def script(tick: int) -> Actions:
    """Deterministic input: long held runs that straddle the flushes, then mouse look every tick."""
    if tick < 100:
        return Actions(forward=1.0)
    if tick < 130:
        return Actions(w=1.0, yaw=0.01 * np.sin(tick))
    return Actions(forward=0.5, right=-0.5, yaw=0.003 * (tick % 7), pitch=-0.002, jump=tick % 40 == 0)


def drive(game: Game, recorder: Recorder, ticks: int, states: dict) -> None:
    for _ in range(ticks):
        a = script(game.tick)
        game.step(a)
        recorder.record(a)
        states[game.tick] = game.state_hash()


def test_journal_loads_after_every_flush_and_plays_back(level1, tmp_path):
    path = tmp_path / "rec.json"
    game = Game(level1)
    rec = Recorder(game, "01_first_steps", path)
    states: dict[int, str] = {}
    assert Replay.load(path).recovered and len(Replay.load(path).actions) == 0
    for flushed in (60, 120, 180):
        drive(game, rec, flushed + 30 - game.tick, states)  # half a second more is not on disk yet
        back = Replay.load(path)
        assert back.recovered
        assert len(back.actions) == flushed, "a flush must carry every tick up to it"
        assert back.hashes == {t: states[t] for t in range(60, flushed + 1, 60)}
        result = play(back, Game(level1))
        assert result.divergence is None
        assert result.final_hash == states[flushed]
    rec.close()


def test_finish_replaces_the_journal_by_the_replay(level1, tmp_path):
    path = tmp_path / "rec.json"
    game = Game(level1, seed=7)
    rec = Recorder(game, "01_first_steps", path)
    states: dict[int, str] = {}
    drive(game, rec, 250, states)
    replay = rec.finish()
    data = json.loads(path.read_text())  # plain strict JSON again
    assert data["format"] == FORMAT and data["seed"] == 7 and data["final"]["ticks"] == 250
    back = Replay.load(path)
    assert not back.recovered
    assert back.actions == replay.actions and len(back.actions) == 250
    assert back.final_hash == states[250]
    assert play(back, Game(level1, seed=7)).divergence is None
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rec.json"], "temporary files left behind"


def test_flush_continues_a_held_run_and_loading_merges_it(level1, tmp_path):
    path = tmp_path / "rec.json"
    game = Game(level1)
    rec = Recorder(game, "01_first_steps", path)
    drive(game, rec, 90, {})  # forward held across the flush at tick 60
    rec.close()
    lines = path.read_text().splitlines()
    assert json.loads(lines[0])["format"] == JOURNAL_FORMAT
    assert [json.loads(x) for x in lines[1:] if x.startswith("[")] == [
        [60, [1.0, 0, 0, 0, 0, 0]],
        [30, [1.0, 0, 0, 0, 0, 0]],
    ]
    assert Replay.load(path).actions.runs == [(90, Actions(forward=1.0))]


def test_a_last_line_cut_short_is_left_out(level1, tmp_path):
    path = tmp_path / "rec.json"
    game = Game(level1)
    rec = Recorder(game, "01_first_steps", path)
    drive(game, rec, 120, {})
    rec.close()
    with open(path, "a", encoding="utf-8") as f:
        f.write("[30,[1.0,0.0,0.0,0.0,0")  # the write the crash interrupted
    assert len(Replay.load(path).actions) == 120


@pytest.mark.parametrize(
    "line, needle",
    [
        ("[30,[1.0,0.0,0.0,0.0,0.0]]", "expected [forward"),
        ("[30,[NaN,0.0,0.0,0.0,0.0,0]]", "forward"),
        ("[1000000000,[1.0,0.0,0.0,0.0,0.0,0]]", "count"),
        ('{"tick": 61, "hash": "0123456789abcdef"}', "tick 61"),
        ('{"tick": 6000, "hash": "0123456789abcdef"}', "tick 6000"),
        ('"hello"', "expected a run"),
        ("{not json", "expected a run"),
    ],
)
def test_a_broken_complete_line_is_refused_by_number(level1, tmp_path, line, needle):
    path = tmp_path / "rec.json"
    game = Game(level1)
    rec = Recorder(game, "01_first_steps", path)
    drive(game, rec, 60, {})
    rec.close()
    lines = path.read_text().splitlines()
    with open(path, "a", encoding="utf-8") as f:
        f.write(line + "\n")
    with pytest.raises(ReplayError, match=f"line {len(lines) + 1}") as e:
        Replay.load(path)
    assert str(e.value).startswith(str(path)) and needle in str(e.value)


def test_recording_needs_an_existing_folder_and_creates_none(level1, tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        Recorder(Game(level1), "01_first_steps", tmp_path / "no" / "such" / "r.json")
    assert list(tmp_path.iterdir()) == []


def test_recording_starts_at_tick_zero(level1):
    game = Game(level1)
    game.step(Actions())
    with pytest.raises(ValueError, match="tick 0"):
        Recorder(game, "01_first_steps")


CHILD = textwrap.dedent("""
    import sys
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.replay import Recorder
    from across_dimensions.game.sim import Game
    from across_dimensions.world.level import load_level

    game = Game(load_level(sys.argv[1]))
    rec = Recorder(game, "01_first_steps", sys.argv[2])
    while True:  # until killed: walk, turn, step along w
        t = game.tick
        a = Actions(forward=1.0 if t % 200 < 120 else -0.5, yaw=0.004 * (t % 5), w=1.0 if t % 300 < 40 else 0.0)
        game.step(a)
        rec.record(a)
        if game.tick % 60 == 0:
            print(game.tick, game.state_hash(), flush=True)
""")


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_a_recording_killed_mid_run_leaves_a_loadable_replay(level1, tmp_path, signum):
    path = tmp_path / "killed.json"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p))
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(LEVEL1), str(path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        cwd=tmp_path,
    )
    seen: dict[int, str] = {}
    try:
        for line in child.stdout:
            tick, state = line.split()
            seen[int(tick)] = state
            if int(tick) >= 240:
                break
        child.send_signal(signum)
        child.wait(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert child.returncode == -signum, child.stderr.read()
    back = Replay.load(path)
    # Every second the child reported was on disk before it said so.
    assert back.recovered and len(back.actions) >= 240 and len(back.actions) % 60 == 0
    assert all(back.hashes[t] == s for t, s in seen.items() if t <= len(back.actions))
    result = play(back, Game(level1))
    assert result.divergence is None
    assert sorted(p.name for p in tmp_path.iterdir()) == ["killed.json"]
