"""Replay files a player or modder hands the game: every entry typed, bounded and named.

Each hostile file is made here, in the test, from a valid replay of level 1.
Loading must refuse it with one line naming the file (and the entry), quickly
and in bounded memory: ``Replay.load`` never expands runs into per-tick lists.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import time
import tracemalloc
from pathlib import Path

import pytest

from across_dimensions.game.actions import BUTTONS, MAX_LOOK, Actions
from across_dimensions.game.playback import play
from across_dimensions.game.replay import FORMAT, MAX_BYTES, MAX_TICKS, ActionRuns, Replay, ReplayError
from across_dimensions.game.sim import Game
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

LEVEL1 = levels_dir() / "01_first_steps.toml"
ROW = [1.0, 0.0, 0.0, 0.0, 0.0, 0]


def valid() -> dict:
    """A short valid replay of level 1: walk, strafe and turn, move along w, jump."""
    return {
        "format": FORMAT,
        "version": 2,
        "level": "01_first_steps",
        "level_hash": hashlib.sha256(LEVEL1.read_bytes()).hexdigest(),
        "seed": 0,
        "tick_rate": 60,
        "hash_every": 60,
        "actions": [[45, ROW], [30, [0.5, 0.3, 0.02, -0.01, 0.5, 0]], [45, [1.0, 0.0, 0.0, 0.0, -1.0, 1]]],
        "hashes": {},
        "final": {"ticks": 120, "hash": "", "outcome": None},
    }


def refused(path: Path, *needles: str) -> str:
    """Load ``path``; assert one ReplayError line naming the file and the needles, fast and in bounded memory."""
    tracemalloc.start()
    start = time.perf_counter()
    try:
        with pytest.raises(ReplayError) as e:
            Replay.load(path)
        seconds = time.perf_counter() - start
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    msg = str(e.value)
    assert msg.startswith(f"{path}: "), msg
    assert "\n" not in msg and len(msg) < 400, msg
    for needle in needles:
        assert needle.lower() in msg.lower(), f"{needle!r} not in: {msg}"
    # Generous bounds (the machine is shared): the old loader took 40 s and 15 GB here.
    assert seconds < 5.0, f"took {seconds:.1f} s: {msg}"
    # Parsed JSON takes about ten times the text's size (a list and float objects per run).
    assert peak < 16 * path.stat().st_size + 16 * 2**20, f"peak {peak / 2**20:.0f} MiB for {msg}"
    return msg


def write(tmp_path: Path, data, name: str = "bad.json") -> Path:
    path = tmp_path / name
    path.write_text(data if isinstance(data, str) else json.dumps(data), encoding="utf-8")
    return path


def mutated(**changes) -> dict:
    data = valid()
    for key, value in changes.items():
        if value is _DELETE:
            del data[key]
        else:
            data[key] = value
    return data


_DELETE = object()


# ------------------------------------------------------------- valid files
def test_valid_replay_loads_and_plays(tmp_path):
    rep = Replay.load(write(tmp_path, valid(), "ok.json"))
    assert len(rep.actions) == 120 and len(rep.actions.runs) == 3
    result = play(rep, Game(load_level(LEVEL1)))
    assert result.divergence is None and result.ticks == 120


def test_shipped_replays_load_and_round_trip(tmp_path):
    for name in ("01_first_steps", "03_tumbling_hall"):
        original = levels_dir() / "replays" / f"{name}.json"
        rep = Replay.load(original)
        rep.save(tmp_path / f"{name}.json")
        assert json.loads((tmp_path / f"{name}.json").read_text()) == json.loads(original.read_text())


def test_runs_stay_runs_in_memory(tmp_path):
    data = valid()
    data["actions"] = [[MAX_TICKS - 1, ROW], [1, [0.0, 0.0, 0.0, 0.0, 0.0, 0]]]
    data["final"]["ticks"] = MAX_TICKS
    rep = Replay.load(write(tmp_path, data))
    assert len(rep.actions) == MAX_TICKS and len(rep.actions.runs) == 2
    it = iter(rep.actions)
    assert next(it) == Actions(forward=1.0)


def test_save_writes_strict_json_and_no_temporary_files(tmp_path):
    rep = Replay("01_first_steps", "0" * 64, actions=[Actions(yaw=0.1), Actions(yaw=0.1), Actions(w=1.0)])
    rep.final_ticks = 3
    rep.save(tmp_path / "r.json")
    text = (tmp_path / "r.json").read_text()
    json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in a saved replay"))
    assert json.loads(text)["actions"] == [[2, [0.0, 0.0, 0.1, 0.0, 0.0, 0]], [1, [0.0, 0.0, 0.0, 0.0, 1.0, 0]]]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.json"]


def test_save_refuses_non_finite_actions(tmp_path):
    rep = Replay("01_first_steps", "0" * 64, actions=[Actions(w=math.nan)])
    with pytest.raises(ValueError, match="r.json: cannot save"):
        rep.save(tmp_path / "r.json")
    assert list(tmp_path.iterdir()) == []


def test_save_never_creates_folders(tmp_path):
    rep = Replay("01_first_steps", "0" * 64)
    with pytest.raises(ValueError, match="does not exist"):
        rep.save(tmp_path / "no" / "such" / "r.json")
    assert list(tmp_path.iterdir()) == []


def test_action_runs_keep_signed_zeros_apart():
    runs = ActionRuns([Actions(pitch=0.0), Actions(pitch=-0.0), Actions(pitch=-0.0)])
    assert [c for c, _ in runs.runs] == [1, 2]
    assert math.copysign(1.0, list(runs)[-1].pitch) == -1.0


# ------------------------------------------------------------ actions rows
@pytest.mark.parametrize(
    "row, needle",
    [
        ([1.0, 0.0, 0.0, 0.0, 1.5, 0], "w"),
        ([-1.01, 0.0, 0.0, 0.0, 0.0, 0], "forward"),
        ([0.0, 2, 0.0, 0.0, 0.0, 0], "right"),
        ([0.0, 0.0, 3.2, 0.0, 0.0, 0], "yaw"),
        ([0.0, 0.0, 0.0, -4.0, 0.0, 0], "pitch"),
        ([0.0, 0.0, 1e300, 0.0, 0.0, 0], "yaw"),
        ([0.0, 0.0, 0.0, 0.0, 0.0, -1], "buttons"),
        ([0.0, 0.0, 0.0, 0.0, 0.0, 1 << len(BUTTONS)], "buttons"),  # a bit past the last button
        ([0.0, 0.0, 0.0, 0.0, 0.0, True], "buttons"),
        ([0.0, 0.0, 0.0, 0.0, 0.0, 1.0], "buttons"),
        ([True, 0.0, 0.0, 0.0, 0.0, 0], "forward"),
        ([0.0, "0", 0.0, 0.0, 0.0, 0], "right"),
        ([0.0, 0.0, None, 0.0, 0.0, 0], "yaw"),
        ([0.0, 0.0, 0.0, 0.0, 0], "expected [forward"),
        ([0.0, 0.0, 0.0, 0.0, 0.0, 0, 0], "presses: expected a table"),
        ([0.0, 0.0, 0.0, 0.0, 0.0, 0, {}, 0], "expected [forward"),
        ({"forward": 1}, "expected [forward"),
    ],
)
def test_bad_rows_name_the_run_and_the_axis(tmp_path, row, needle):
    data = valid()
    data["actions"][1] = [30, row]
    refused(write(tmp_path, data), "'actions' #1", needle)


@pytest.mark.parametrize("text", ["NaN", "Infinity", "-Infinity", "1e999", "-1e400"])
def test_non_finite_numbers_are_refused_at_their_entry(tmp_path, text):
    raw = json.dumps(valid()).replace("[0.5, 0.3, 0.02, -0.01, 0.5, 0]", f"[0.5, 0.3, 0.02, -0.01, {text}, 0]")
    assert text in raw
    refused(write(tmp_path, raw), "'actions' #1", "w", "finite")


def test_look_bound_is_pi_per_tick():
    assert MAX_LOOK == pytest.approx(math.pi)
    assert Actions.from_row([0.0, 0.0, math.pi, -math.pi, 0.0, 0]).yaw == math.pi
    with pytest.raises(ValueError, match="yaw"):
        Actions.from_row([0.0, 0.0, math.nextafter(math.pi, 4.0), 0.0, 0.0, 0])


def test_clamped_actions_are_finite_and_bounded():
    wild = Actions(forward=5.0, right=-math.inf, yaw=1e300, pitch=math.nan, w=-2.0, jump=True)
    safe = wild.clamped()
    assert safe == Actions(forward=1.0, right=0.0, yaw=MAX_LOOK, pitch=0.0, w=-1.0, jump=True)
    assert Actions.from_row(safe.to_row()) == safe
    assert math.copysign(1.0, Actions(yaw=-0.0).clamped().yaw) == 1.0
    calm = Actions(forward=0.5, yaw=0.01)
    assert calm.clamped() is calm


# -------------------------------------------------------- run-length bombs
@pytest.mark.parametrize("count", [10**9, 10**7, MAX_TICKS + 1])
def test_huge_run_lengths_are_refused_before_anything_is_built(tmp_path, count):
    data = valid()
    data["actions"][0] = [count, ROW]
    refused(write(tmp_path, data), "'actions' #0", str(MAX_TICKS))


def test_run_lengths_are_checked_on_their_sum(tmp_path):
    data = valid()
    data["actions"] = [[MAX_TICKS // 2, ROW], [MAX_TICKS // 2, [0.0] * 5 + [0]], [1, ROW]]
    refused(write(tmp_path, data), "'actions' #2", "longer than")


def test_many_runs_are_refused_by_the_tick_limit(tmp_path):
    # More one-tick runs than a replay may have ticks: 12 MB, within the size limit.
    runs = ",".join(["[1,[1.0,0.0,0.0,0.0,0.0,0]],[1,[0.0,0.0,0.0,0.0,0.0,0]]"] * (MAX_TICKS // 2 + 1))
    raw = json.dumps(valid()).replace('"actions": [', '"actions": [' + runs + ",", 1)
    path = write(tmp_path, raw)
    start = time.perf_counter()
    with pytest.raises(ReplayError, match=f"'actions': .* more than the {MAX_TICKS} ticks") as e:
        Replay.load(path)
    assert str(e.value).startswith(str(path))
    assert time.perf_counter() - start < 60  # a guard against a hang, not a speed goal (see the benchmark)


@pytest.mark.parametrize("digits", [50, 4000])
def test_huge_integers_are_named(tmp_path, digits):
    raw = json.dumps(valid()).replace("[[45, ", f"[[{'9' * digits}, ", 1)
    refused(write(tmp_path, raw), "'actions' #0", "count", f"{digits} digits")


@pytest.mark.parametrize("digits", [4301, 5000, 100_000])
def test_integers_beyond_pythons_limit_are_located(tmp_path, digits):
    # json refuses more than 4300 digits itself; the message says where.
    raw = json.dumps(valid()).replace('"seed": 0', '"seed": ' + "7" * digits)
    column = raw.index("777") + 1
    refused(write(tmp_path, raw), f"{digits} digits", f"line 1 column {column}")


def test_huge_float_is_refused_at_its_entry(tmp_path):
    refused(write(tmp_path, mutated(seed=1e300)), "'seed'")
    raw = json.dumps(valid()).replace('"hash_every": 60', '"hash_every": 1e999')
    refused(write(tmp_path, raw), "'hash_every'", "inf")


@pytest.mark.parametrize("depth", [100, 100_000])
def test_deep_nesting(tmp_path, depth):
    raw = json.dumps(valid()).replace('"hashes": {}', '"hashes": ' + "[" * depth + "]" * depth)
    refused(write(tmp_path, raw), "hashes" if depth == 100 else "nested too deeply")


def test_deep_nesting_alone(tmp_path):
    refused(write(tmp_path, "[" * 1_000_000), "nested too deeply")


# ------------------------------------------------------------ header fields
BAD_HEADERS = [
    ("format", 1, "not a replay"),
    ("format", "something-else", "not a replay"),
    ("format", _DELETE, "not a replay"),
    ("version", 9, "version 9"),
    ("version", True, "'version'"),
    ("version", "1", "'version'"),
    ("version", 1.0, "'version'"),
    ("version", None, "'version'"),
    ("version", _DELETE, "'version'"),
    ("level", "", "'level'"),
    ("level", 5, "'level'"),
    ("level", None, "'level'"),
    ("level", "a\nb", "'level'"),
    ("level", "x" * 300, "'level'"),
    ("level", _DELETE, "'level'"),
    ("level_hash", "h", "'level_hash'"),
    ("level_hash", 5, "'level_hash'"),
    ("level_hash", "A" * 64, "'level_hash'"),
    ("level_hash", "0" * 63, "'level_hash'"),
    ("level_hash", _DELETE, "'level_hash'"),
    ("seed", -1, "'seed'"),
    ("seed", 2**64, "'seed'"),
    ("seed", True, "'seed'"),
    ("seed", 1.5, "'seed'"),
    ("seed", "0", "'seed'"),
    ("seed", None, "'seed'"),
    ("seed", _DELETE, "'seed'"),
    ("tick_rate", 30, "30 Hz"),
    ("tick_rate", True, "'tick_rate'"),
    ("tick_rate", "60", "'tick_rate'"),
    ("tick_rate", 60.0, "'tick_rate'"),
    ("tick_rate", _DELETE, "'tick_rate'"),
    ("hash_every", 0, "'hash_every'"),
    ("hash_every", -60, "'hash_every'"),
    ("hash_every", True, "'hash_every'"),
    ("hash_every", 1.5, "'hash_every'"),
    ("hash_every", MAX_TICKS + 1, "'hash_every'"),
    ("hash_every", _DELETE, "'hash_every'"),
    ("actions", "x", "'actions'"),
    ("actions", {}, "'actions'"),
    ("actions", None, "'actions'"),
    ("actions", [[0, ROW]], "'actions' #0"),
    ("actions", [[1.5, ROW]], "'actions' #0"),
    ("actions", [[True, ROW]], "'actions' #0"),
    ("actions", [[1, ROW, 3]], "'actions' #0"),
    ("actions", [5], "'actions' #0"),
    ("actions", _DELETE, "'actions'"),
    ("hashes", [], "'hashes'"),
    ("hashes", {"x": "0" * 16}, "'hashes' 'x'"),
    ("hashes", {"060": "0" * 16}, "'hashes' '060'"),
    ("hashes", {"-60": "0" * 16}, "'hashes' '-60'"),
    ("hashes", {"61": "0" * 16}, "tick 61"),
    ("hashes", {"6000": "0" * 16}, "tick 6000"),
    ("hashes", {"60": 5}, "'hashes' '60'"),
    ("hashes", {"60": "XYZ"}, "'hashes' '60'"),
    ("hashes", {"٦٠": "0" * 16}, "'hashes'"),
    ("hashes", _DELETE, "'hashes'"),
    ("final", [], "'final'"),
    ("final", {"ticks": 120}, "'final'"),
    ("final", {"ticks": 121, "hash": "", "outcome": None}, "'final' 'ticks'"),
    ("final", {"ticks": True, "hash": "", "outcome": None}, "'final' 'ticks'"),
    ("final", {"ticks": 120, "hash": 5, "outcome": None}, "'final' 'hash'"),
    ("final", {"ticks": 120, "hash": "zz", "outcome": None}, "'final' 'hash'"),
    ("final", {"ticks": 120, "hash": "", "outcome": 5}, "'final' 'outcome'"),
    ("final", {"ticks": 120, "hash": "", "outcome": "Complete!"}, "'final' 'outcome'"),
    ("final", {"ticks": 120, "hash": "", "outcome": None, "extra": 1}, "'final'"),
    ("final", _DELETE, "'final'"),
    ("comment", "hello", "unknown entry"),
]


@pytest.mark.parametrize(
    "key, value, needle",
    BAD_HEADERS,
    ids=[f"{k}={'missing' if v is _DELETE else str(v)[:20]}" for k, v, _ in BAD_HEADERS],
)
def test_every_header_field_is_typed_and_range_checked(tmp_path, key, value, needle):
    refused(write(tmp_path, mutated(**{key: value})), needle)


@pytest.mark.parametrize(
    "raw, needle",
    [
        ("", "invalid JSON"),
        ("{not json", "invalid JSON"),
        ("null", "not a replay"),
        ("[1, 2]", "not a replay"),
        ('"across-dimensions-replay"', "not a replay"),
    ],
)
def test_not_a_replay(tmp_path, raw, needle):
    refused(write(tmp_path, raw), needle)


def test_duplicate_keys_are_refused(tmp_path):
    raw = json.dumps(valid()).replace('"seed": 0', '"seed": 0, "seed": 1')
    refused(write(tmp_path, raw), "'seed'", "twice")


def test_trailing_data_is_refused(tmp_path):
    refused(write(tmp_path, json.dumps(valid()) + "\n" + json.dumps(valid())), "invalid JSON", "line 2")


def test_pretty_printed_replay_loads(tmp_path):
    rep = Replay.load(write(tmp_path, json.dumps(valid(), indent=2)))
    assert len(rep.actions) == 120


def test_byte_order_mark_is_accepted(tmp_path):
    path = tmp_path / "bom.json"
    path.write_bytes(b"\xef\xbb\xbf" + json.dumps(valid()).encode())
    assert len(Replay.load(path).actions) == 120


# ----------------------------------------------------------- special files
def test_not_utf8(tmp_path):
    path = tmp_path / "latin1.json"
    path.write_bytes(json.dumps(valid()).replace("01_first_steps", "caf\u00e9").encode("latin-1"))
    refused(path, "UTF-8")


def test_missing_file(tmp_path):
    with pytest.raises(ReplayError, match="no such file") as e:
        Replay.load(tmp_path / "nosuch.json")
    assert str(tmp_path / "nosuch.json") in str(e.value)


def test_folder(tmp_path):
    with pytest.raises(ReplayError, match="folder"):
        Replay.load(tmp_path)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_fifo_does_not_hang(tmp_path):
    os.mkfifo(tmp_path / "pipe.json")
    refused(tmp_path / "pipe.json", "FIFO")


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_symlink_to_dev_zero(tmp_path):
    (tmp_path / "zero.json").symlink_to("/dev/zero")
    refused(tmp_path / "zero.json", "device")


def test_file_over_the_size_limit(tmp_path):
    path = tmp_path / "big.json"
    with open(path, "wb") as f:  # sparse: 100 MB on paper, nothing on the disk
        f.truncate(100 * 2**20)
    assert MAX_BYTES < 100 * 2**20
    refused(path, "larger than")
