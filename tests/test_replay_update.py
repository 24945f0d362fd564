"""``replay LEVEL REPLAY --update-hashes`` run as a user runs it (subprocesses).

After a deliberate change of the simulation the recorded actions still hold but the state
hashes do not: the command records them again and rewrites the file, only when the run still
ends as recorded. A short shipped replay (the Tumbling Hall, 1320 ticks) keeps it quick.
"""

from __future__ import annotations

import json

import pytest
from test_replay_cli import SHIPPED, describe, one_line_error, replay_json, run

NAME = "03_tumbling_hall"
SOURCE = SHIPPED[NAME]


def _compact(data: dict) -> str:
    """The recorder's spelling of a replay (compact JSON, one line)."""
    return json.dumps(data, separators=(",", ":")) + "\n"


@pytest.mark.slow
def test_update_hashes_repairs_a_wrong_hash_and_keeps_the_actions(env, tmp_path):
    data = json.loads(SOURCE.read_text())
    data["hashes"]["120"] = "0" * 16
    path = tmp_path / "run.json"
    path.write_text(_compact(data))
    assert run(env, tmp_path, "replay", NAME, path).returncode == 3  # the wrong hash is caught first

    r = run(env, tmp_path, "replay", NAME, path, "--update-hashes")
    assert r.returncode == 0, describe(r)
    # every periodic hash and the final one are checked
    assert r.stdout.strip().splitlines() == [f"{path}: hashes updated (1 of {len(data['hashes']) + 1} changed)"], (
        describe(r)
    )
    after = json.loads(path.read_text())
    original = json.loads(SOURCE.read_text())
    assert json.dumps(after["actions"]) == json.dumps(original["actions"])  # same rows, same spelling
    assert after["hashes"] == original["hashes"] and after["final"] == original["final"]
    assert path.read_text() == SOURCE.read_text()  # the recorder's layout, byte for byte
    assert [p.name for p in tmp_path.iterdir()] == ["run.json"]  # no temporary file left behind

    check = run(env, tmp_path, "replay", NAME, path)
    assert check.returncode == 0, describe(check)

    again = run(env, tmp_path, "replay", NAME, path, "--update-hashes", "--json")
    assert again.returncode == 0, describe(again)
    out = replay_json(again)
    assert out["updated"] is False and out["outcome"] == "complete" and out["divergence"] is None
    assert "hashes unchanged" in again.stderr


def test_a_replay_that_no_longer_completes_is_left_untouched(env, tmp_path):
    data = json.loads(SOURCE.read_text())
    data["actions"][-1][0] = 1  # stops short of the goal; final.ticks must be the sum of the runs
    ticks = sum(count for count, _ in data["actions"])
    data["final"]["ticks"] = ticks
    data["hashes"] = {k: v for k, v in data["hashes"].items() if int(k) <= ticks}
    path = tmp_path / "short.json"
    path.write_text(_compact(data))
    before = path.read_bytes()

    r = run(env, tmp_path, "replay", NAME, path, "--update-hashes", "--json")
    assert r.returncode == 1, describe(r)
    out = replay_json(r)
    assert out["updated"] is False and out["outcome"] is None and out["ticks"] == ticks
    line = one_line_error(r, str(path), 'expected outcome "complete"', f"at tick {ticks}", status=1)
    assert "not finished" in line
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["short.json"]


def test_a_changed_level_file_is_refused_as_replay_refuses_it(env, tmp_path):
    data = json.loads(SOURCE.read_text())
    data["level_hash"] = "0" * 64
    data["hashes"]["120"] = "0" * 16  # and the states differ: the change reached the simulation
    path = tmp_path / "other.json"
    path.write_text(_compact(data))
    before = path.read_bytes()
    r = run(env, tmp_path, "replay", NAME, path, "--update-hashes")
    one_line_error(r, "level file changed", status=3)
    assert path.read_bytes() == before


def test_a_level_file_changed_without_touching_the_simulation_gets_its_header_only(env, tmp_path):
    """An edit of a level's hints changes the file's hash, not a single state: every state plays
    as recorded, so only the header's level hash is written again."""
    data = json.loads(SOURCE.read_text())
    data["level_hash"] = "0" * 64
    path = tmp_path / "hints.json"
    path.write_text(_compact(data))
    r = run(env, tmp_path, "replay", NAME, path, "--update-hashes")
    assert r.returncode == 0, r.stderr
    assert "hashes unchanged; level hash" in r.stdout
    assert path.read_bytes() == SOURCE.read_bytes()


@pytest.mark.parametrize("extra", [["--no-check"], ["--screenshots", "shots"]])
def test_update_hashes_refuses_options_that_contradict_it(env, tmp_path, extra):
    path = tmp_path / "run.json"
    path.write_bytes(SOURCE.read_bytes())
    r = run(env, tmp_path, "replay", NAME, path, "--update-hashes", *extra)
    one_line_error(r, "--update-hashes", extra[0], status=2)
    assert path.read_bytes() == SOURCE.read_bytes()
    assert not (tmp_path / "shots").exists()


def test_actions_the_recorder_would_spell_differently_are_never_rewritten(env, tmp_path):
    data = json.loads(SOURCE.read_text())
    data["actions"][0][1][0] = 1  # forward as the whole number 1: plays the same, written back as 1.0
    data["hashes"]["120"] = "0" * 16
    path = tmp_path / "edited.json"
    path.write_text(_compact(data))
    before = path.read_bytes()
    r = run(env, tmp_path, "replay", NAME, path, "--update-hashes")
    one_line_error(r, str(path), "entry 'actions'", "left untouched", status=2)
    assert path.read_bytes() == before
