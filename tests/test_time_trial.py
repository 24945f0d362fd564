"""Time trials: a finished run kept as its level's ghost, raced as a figure, split at checkpoints.

Headless: the track and its file, the ghost storage (atomic, a corrupt one set aside), that a
logged and raced run leaves the live game's state hashes as a shipped replay has them, the
splits, and the figure's fade along w. The window's side is in tests/test_level_complete.py.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.app.ghost_saves import ghost_path, load_ghost, replay_path, save_ghost
from across_dimensions.app.time_trial import Race, RunLog, keep_ghost
from across_dimensions.core.fileio import FileProblem
from across_dimensions.game.actions import Actions
from across_dimensions.game.ghost_run import GhostTrack, TrackRecorder
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import Game
from across_dimensions.render.ghost_figure import KEY, W_REACH, figure_mesh, ghost_drawable
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

ARRIVAL = levels_dir() / "00_arrival.toml"
ARRIVAL_REPLAY = levels_dir() / "replays" / "00_arrival.json"


def _track(ticks=5, every=2, splits=None) -> GhostTrack:
    rows = [[float(i), 0.0, 2.0 * i, 0.1 * i, 0.5] for i in range(-(-ticks // every) + 1)]
    return GhostTrack("00_arrival", "ab" * 32, ticks, np.array(rows), splits or {}, every)


def _log_arrival(race: Race | None = None) -> tuple[Game, RunLog, list[str]]:
    """Arrival played by its shipped replay with a run log, and ``race``'s figure asked for
    every tick as the window draws it: the state hashes taken on the way."""
    replay = Replay.load(ARRIVAL_REPLAY)
    game = Game(load_level(ARRIVAL))
    log = RunLog(game, "00_arrival")
    hashes = []
    for tick, actions in enumerate(replay.actions, 1):
        game.step(actions)
        log.record(game, actions)
        if race is not None:
            race.figure(game, game.frame(alpha=0.5), 0.5)
        if tick in replay.hashes:
            hashes.append(game.state_hash())
    hashes.append(game.state_hash())
    return game, log, hashes


# ---- the track ----------------------------------------------------------------------------
def test_a_track_reads_back_the_same_and_interpolates_between_rows():
    ghost = _track(ticks=5, every=2, splits={0: 3})
    back = GhostTrack.from_json(ghost.to_json())
    assert (back.level, back.ticks, back.every, back.splits) == ("00_arrival", 5, 2, {0: 3})
    assert np.allclose(back.track, ghost.track, atol=1e-4) and back.track.shape == (4, 5)  # to 0.1 mm
    feet, yaw = back.pose_at(1.0)  # half way from the row at tick 0 to the one at tick 2
    assert np.allclose(feet, [0.5, 0.0, 1.0, 0.05]) and yaw == 0.5
    assert np.allclose(back.pose_at(99.0)[0], ghost.track[-1, :4])  # after the goal: where it ended
    assert np.allclose(back.pose_at(-3.0)[0], ghost.track[0, :4])
    # Yaw turns the short way round: from 3.1 to -3.1 rad passes pi, not 0.
    turn = GhostTrack("x", "y", 2, np.array([[0, 0, 0, 0, 3.1], [0, 0, 0, 0, -3.1]], float), every=2)
    assert abs(turn.pose_at(1.0)[1] - np.pi) < 1e-9


@pytest.mark.parametrize(
    ("change", "entry"),
    [
        ({"format": "x"}, "format"),
        ({"version": 9}, "version 9"),
        ({"ticks": 0}, "ticks"),
        ({"every": 0}, "every"),
        ({"track": [[0, 0, 0, 0, 0]]}, "track: expected 4 rows"),
        ({"track": [[0, 0, 0, 0, 0]] * 3 + [[0, 0, "x", 0, 0]]}, "track[3]"),
        ({"track": [[0, 0, 0, 0, 0]] * 3 + [[0, 0, 1e300, 0, 0]]}, "track[3]"),
        ({"splits": [[0, 99]]}, "splits"),
        ({"level": ""}, "level"),
    ],
)
def test_a_file_that_is_no_ghost_is_refused_naming_the_entry(change, entry):
    data = json.loads(_track().to_json())
    data.update(change)
    with pytest.raises(ValueError, match=None) as e:
        GhostTrack.from_json(json.dumps(data))
    assert entry in str(e.value)


def test_splits_are_taken_when_a_checkpoint_is_first_reached(tmp_path):
    level = (
        LevelBuilder(spawn=(0.0, 0.0, -5.0, 0.0), goal=(0.0, 1.0, 5.0))
        .table("health", max=100.0)
        .add("checkpoint", name="middle", position=[0.0, 0.0, 0.0, 0.0], size=[6.0, 3.0, 1.0])
        .load(tmp_path)
    )
    game = Game(level)
    track = TrackRecorder(game)
    said, first_event = [], None
    while game.outcome != "complete" and game.tick < 600:
        game.step(Actions(forward=1.0))
        reached = track.record(game)
        if reached is not None:
            said.append((reached, game.tick))
        if first_event is None and any(e.kind == "checkpoint_reached" for e in game.events):
            first_event = game.tick
    assert game.outcome == "complete" and first_event is not None
    assert said == [(0, first_event)] and track.splits == {0: first_event}  # once, on the tick it was touched
    ghost = track.finish(game, "test", "ab" * 32)
    assert ghost.ticks == game.tick and len(ghost.track) == -(-ghost.ticks // ghost.every) + 1
    race = Race(ghost)
    assert race.split(0, first_event + 30, "middle") == f"Checkpoint middle: 0:{first_event / 60 + 0.5:04.1f}   +0.5 s"
    assert race.split(0, first_event - 60, "middle").endswith("   -1.0 s")  # a second ahead of the ghost
    assert Race(None).split(0, first_event, "middle").endswith(f"0:{first_event / 60:04.1f}")  # no ghost: no delta
    assert race.split(3, first_event, "").startswith("Checkpoint 4:")  # one the ghost never reached


# ---- the ghost never touches the game -----------------------------------------------------
def test_a_logged_and_raced_run_keeps_the_replays_state_hashes(tmp_path):
    replay = Replay.load(ARRIVAL_REPLAY)
    game, log, alone = _log_arrival()
    expected = [replay.hashes[t] for t in sorted(replay.hashes)] + [replay.final_hash]
    assert alone == expected and game.tick == replay.final_ticks
    ghost, logged = log.finished
    # The log is the run as far as its goal: a replay of the same actions and hashes, and a track.
    assert ghost.ticks == game.completed_tick == logged.final_ticks and logged.outcome == "complete"
    assert all(logged.hashes[t] == replay.hashes[t] for t in logged.hashes)
    assert np.allclose(ghost.pose_at(0)[0], game.level.spawn)
    # Racing that ghost (its figure drawn every tick) changes nothing of the game.
    _, _, raced = _log_arrival(Race(ghost))
    assert raced == expected
    # The run's replay plays back alone, as a player would check it.
    save_ghost(ghost, logged, tmp_path)
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "replay", str(ARRIVAL), str(replay_path("00_arrival", tmp_path))],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0 and "complete" in r.stdout, r.stdout + r.stderr


# ---- storage --------------------------------------------------------------------------------
def test_a_ghost_is_written_whole_and_a_failed_write_keeps_the_old_one(tmp_path):
    ghost = _track(ticks=9)
    replay = Replay("00_arrival", "ab" * 32)
    save_ghost(ghost, replay, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["00_arrival.json", "00_arrival.replay.json"]
    before = ghost_path("00_arrival", tmp_path).read_bytes()
    broken = Replay("00_arrival", "ab" * 32, actions=[Actions(forward=float("nan"))])  # strict JSON refuses it
    with pytest.raises(FileProblem):
        save_ghost(_track(ticks=3), broken, tmp_path)
    assert ghost_path("00_arrival", tmp_path).read_bytes() == before  # the old ghost, whole
    assert sorted(p.name for p in tmp_path.iterdir()) == ["00_arrival.json", "00_arrival.replay.json"]  # no temp
    back, warnings = load_ghost("00_arrival", tmp_path)
    assert warnings == [] and back.ticks == 9
    assert load_ghost("01_first_steps", tmp_path) == (None, [])  # none yet: no warning


@pytest.mark.parametrize("text", ["{not json", '{"format": "across-dimensions-ghost", "version": 1}', "", "[]"])
def test_a_corrupt_ghost_is_set_aside_with_one_warning(tmp_path, text):
    path = ghost_path("00_arrival", tmp_path)
    for n in (1, 2):
        path.write_text(text)
        ghost, warnings = load_ghost("00_arrival", tmp_path)
        assert ghost is None and len(warnings) == 1
        assert str(path) in warnings[0] and f"kept as 00_arrival.corrupt-{n}.json" in warnings[0]
        assert not path.exists() and (tmp_path / f"00_arrival.corrupt-{n}.json").read_text() == text
    # Another level's ghost under this name is set aside too.
    other = _track()
    other.level = "01_first_steps"
    path.write_text(other.to_json())
    ghost, warnings = load_ghost("00_arrival", tmp_path)
    assert ghost is None and "'01_first_steps'" in warnings[0] and not path.exists()


def test_only_a_faster_run_replaces_the_ghost(tmp_path, monkeypatch):
    monkeypatch.setenv("ACROSS_DIMENSIONS_DATA_DIR", str(tmp_path))
    _, log, _ = _log_arrival()
    warned = []
    assert keep_ghost(None, warned.append) == (None, False)  # a run not from the start: nothing kept
    assert keep_ghost(log, warned.append) == (None, True)  # the first: kept
    kept = json.loads(ghost_path("00_arrival", tmp_path / "ghosts").read_text())
    slower = _track(ticks=log.finished[0].ticks + 60)
    slower.level_hash = log.level_hash
    save_ghost(slower, log.finished[1], tmp_path / "ghosts")
    before, now = keep_ghost(log, warned.append)
    assert now and before.ticks == slower.ticks  # faster than the one kept: replaces it
    assert json.loads(ghost_path("00_arrival", tmp_path / "ghosts").read_text()) == kept
    before, now = keep_ghost(log, warned.append)
    assert not now and before.ticks == log.finished[0].ticks  # as fast: the kept one stays
    stale = _track(ticks=10)  # faster, but on another version of the level: not raced, replaced
    save_ghost(stale, log.finished[1], tmp_path / "ghosts")
    assert keep_ghost(log, warned.append) == (None, True)
    race, line = Race.of_level("00_arrival", "cd" * 32, warned.append)
    assert race.ghost is None and "older version" in line
    race, line = Race.of_level("00_arrival", log.level_hash, warned.append)
    assert race.ghost.ticks == log.finished[0].ticks and line.startswith("Time trial: race your best run, 0:09.7")
    assert warned == []


# ---- the figure ---------------------------------------------------------------------------------
def test_the_figure_is_player_sized_closed_and_fades_along_w():
    mesh = figure_mesh()
    tri = mesh.vertices[mesh.faces].astype(np.float64)
    volume = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6
    assert volume > 0.1  # wound counter-clockwise seen from outside (a closed surface's volume)
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    assert np.allclose([lo[1], hi[1]], [0.0, 1.75]) and hi[0] - lo[0] <= 0.7
    feet = np.array([1.0, 0.0, 2.0, 0.3])
    on = ghost_drawable(feet, 0.0, 0.3)
    assert on.key == KEY and on.style == "ghost" and on.opacity == 1.0 and np.allclose(on.model[:3, 3], feet[:3])
    assert abs(ghost_drawable(feet, 0.0, 0.3 + W_REACH / 2).opacity - 0.5) < 1e-9
    assert ghost_drawable(feet, 0.0, 0.3 - W_REACH) is None  # out of the slice: not drawn
    turned = ghost_drawable(feet, np.pi / 2, 0.3)  # yaw 90 degrees looks along +x: the visor's +z goes there
    assert np.allclose(turned.model[:3, :3] @ [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])


def test_the_ghost_folder_lives_with_the_progress(tmp_path, monkeypatch):
    monkeypatch.setenv("ACROSS_DIMENSIONS_DATA_DIR", str(tmp_path))
    assert ghost_path("00_arrival") == tmp_path / "ghosts" / "00_arrival.json"
    assert Path(replay_path("00_arrival")).parent == tmp_path / "ghosts"
