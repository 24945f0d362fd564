"""``replay``, ``demo`` and ``play --record`` run as a user runs them (subprocesses).

- ``replay LEVEL REPLAY --json`` prints exactly one JSON object on stdout.
- Hostile replay files give exit status 2 and one line naming the file.
- ``play --record`` refuses a missing folder before any window opens, and in a
  real window (under Xvfb, when it is installed) a SIGTERM saves the recording.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import per_level, xvfb_display

from across_dimensions.game.replay import MAX_TICKS, Replay

REPO = Path(__file__).resolve().parents[1]
LEVELS = REPO / "levels"
LEVEL1 = LEVELS / "01_first_steps.toml"
#: Every shipped replay, by level name: each was recorded in the window, so playing it here
#: in a fresh process and matching its hashes checks determinism across processes.
# The 4D levels' replays; the Flatland prologue's has its own summary (tests/test_flatland_replay.py).
SHIPPED = {p.stem: p for p in sorted((LEVELS / "replays").glob("*.json")) if p.stem != "prologue"}
TIMEOUT = 240  # the first run may compile the numba kernels


def run(env, cwd, *args, timeout=TIMEOUT) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=timeout,
        cwd=cwd,
        env=env,
    )


def describe(r) -> str:
    return f"exit {r.returncode}\n--- stdout\n{r.stdout}--- stderr\n{r.stderr}"


def one_line_error(r, *needles, status=2) -> str:
    assert r.returncode == status, describe(r)
    assert "Traceback" not in r.stderr + r.stdout and "internal error" not in r.stderr, describe(r)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, describe(r)
    for needle in needles:
        assert needle.lower() in lines[0].lower(), f"{needle!r} missing\n{describe(r)}"
    return lines[0]


def replay_json(r) -> dict:
    """The single JSON object on stdout (nothing else there)."""
    assert r.stdout.endswith("\n") and r.stdout.count("\n") == 1, describe(r)
    return json.loads(r.stdout, parse_constant=lambda c: pytest.fail(f"{c} in --json output"))


# ------------------------------------------------------------------ --json
@pytest.mark.parametrize("name", per_level(SHIPPED))
def test_replay_json_for_the_shipped_replays(env, tmp_path, name):
    r = run(env, tmp_path, "replay", name, SHIPPED[name], "--json")
    assert r.returncode == 0, describe(r)
    out = replay_json(r)
    recorded = json.loads(SHIPPED[name].read_text())["final"]
    assert set(out) == {
        "level",
        "outcome",
        "ticks",
        "hash",
        "events",
        "causes",
        "energy",
        "position",
        "respawns",
        "divergence",
    }
    assert out["outcome"] == recorded["outcome"] == "complete"
    assert out["ticks"] == recorded["ticks"] and out["hash"] == recorded["hash"]
    assert out["divergence"] is None and out["respawns"] == 0
    assert isinstance(out["level"], str) and out["level"]
    assert len(out["position"]) == 4 and all(isinstance(v, float) and math.isfinite(v) for v in out["position"])
    assert all(isinstance(k, str) and k.islower() and isinstance(v, int) and v >= 0 for k, v in out["events"].items())
    assert {"crystal_collected", "energy_empty", "energy_spent", "w_blocked", "contact"} <= set(out["events"])
    if name == "01_first_steps":  # no rigid bodies, no energy
        assert out["events"]["contact"] == 0 and out["energy"] is None
        assert out["position"][3] > 0.9  # finished on the far side of the wall along w
    if name == "02_crystal_cache":  # the crystal in sight, then the one the radar shows
        assert out["events"]["crystal_collected"] == 2 and out["events"]["energy_spent"] > 0
        energy = out["energy"]
        assert energy["min"] == 0.0 and 0.0 <= energy["end"] <= energy["max"] <= 10.0
    if name == "03_tumbling_hall":  # bodies fall, land and roll: contacts begin
        assert out["events"]["contact"] > 0
        assert out["position"][2] > 5.0  # walked to the goal, far down the hall
    assert out["events"]["level_complete"] == 1
    # The plain output agrees.
    plain = run(env, tmp_path, "replay", name, SHIPPED[name])
    assert plain.returncode == 0, describe(plain)
    assert f"final state hash: {out['hash']}" in plain.stdout


def test_replay_json_reports_divergence_with_status_3(env, tmp_path):
    data = json.loads(SHIPPED["01_first_steps"].read_text())
    data["hashes"]["120"] = "0" * 16
    (tmp_path / "tampered.json").write_text(json.dumps(data))
    r = run(env, tmp_path, "replay", "01_first_steps", "tampered.json", "--json")
    assert r.returncode == 3, describe(r)
    out = replay_json(r)
    assert "tick 120" in out["divergence"] and out["outcome"] == "complete"
    assert "diverges" in r.stderr


def test_demo_runs(env, tmp_path):
    r = run(env, tmp_path, "demo")
    assert r.returncode == 0, describe(r)
    assert "complete after 475 ticks" in r.stdout


def test_screenshots_folder_parents_are_not_created(env, tmp_path):
    r = run(env, tmp_path, "replay", "01_first_steps", SHIPPED["01_first_steps"], "--screenshots", "no/such/dir")
    one_line_error(r, "no/such")
    assert not (tmp_path / "no").exists()


# --------------------------------------------------------- hostile replays
def _valid() -> dict:
    return {
        "format": "across-dimensions-replay",
        "version": 1,
        "level": "01_first_steps",
        "level_hash": hashlib.sha256(LEVEL1.read_bytes()).hexdigest(),
        "seed": 0,
        "tick_rate": 60,
        "hash_every": 60,
        "actions": [[45, [1.0, 0.0, 0.0, 0.0, 0.0, 0]]],
        "hashes": {},
        "final": {"ticks": 45, "hash": "", "outcome": None},
    }


def _make(kind: str, path: Path) -> None:
    raw = json.dumps(_valid())
    if kind == "run-1e9":
        raw = raw.replace("[[45,", "[[1000000000,")
    elif kind == "run-1e7":
        raw = raw.replace("[[45,", "[[10000000,")
    elif kind == "huge-int":
        raw = raw.replace('"seed": 0', '"seed": ' + "9" * 5000)
    elif kind == "nan-row":
        raw = raw.replace("[1.0, 0.0, 0.0, 0.0, 0.0, 0]", "[1.0, 0.0, 0.0, 0.0, NaN, 0]")
    elif kind == "deep":
        raw = "[" * 200_000
    elif kind == "seed-type":
        raw = raw.replace('"seed": 0', '"seed": "zero"')
    elif kind == "fifo":
        os.mkfifo(path)
        return
    elif kind == "100MB":
        with open(path, "wb") as f:
            f.truncate(100 * 2**20)
        return
    path.write_text(raw, encoding="utf-8")


HOSTILE = {
    "run-1e9": str(MAX_TICKS),
    "run-1e7": str(MAX_TICKS),
    "huge-int": "5000 digits",
    "nan-row": "NaN",
    "deep": "nested",
    "seed-type": "'seed'",
    "fifo": "FIFO",
    "100MB": "larger than",
}


@pytest.mark.parametrize("kind", HOSTILE)
def test_hostile_replay_is_refused_in_one_line(env, tmp_path, kind):
    if kind == "fifo" and not hasattr(os, "mkfifo"):
        pytest.skip("no FIFOs here")
    _make(kind, tmp_path / "hostile.json")
    start = time.perf_counter()
    r = run(env, tmp_path, "replay", "01_first_steps", "hostile.json", timeout=60)
    elapsed = time.perf_counter() - start
    one_line_error(r, "hostile.json", HOSTILE[kind])
    assert r.stdout == "", describe(r)
    # Python and numpy start-up included; the refusal itself takes milliseconds.
    assert elapsed < 30, f"{kind}: {elapsed:.1f} s"


def test_recovered_recording_plays_with_a_note(env, tmp_path):
    header = dict(_valid(), format="across-dimensions-replay-journal")
    for key in ("actions", "hashes", "final"):
        del header[key]
    (tmp_path / "cut.json").write_text(json.dumps(header) + "\n[75,[1.0,0.0,0.0,0.0,0.0,0]]\n[30,[1.0,0.0")
    r = run(env, tmp_path, "replay", "01_first_steps", "cut.json", "--json")
    assert r.returncode == 0, describe(r)
    assert replay_json(r)["ticks"] == 75
    assert "cut short" in r.stderr


# ------------------------------------------------------------ play --record
@pytest.mark.parametrize("display", [False, True], ids=["no-display", "display"])
def test_record_into_a_missing_folder_is_refused_before_the_window(env, tmp_path, display):
    e = {k: v for k, v in env.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    if display:
        e["DISPLAY"] = ":1999"  # no such server: the check must come first
    target = tmp_path / "nonexistent" / "dir" / "r.json"
    r = run(e, tmp_path, "play", "--record", target, timeout=60)
    one_line_error(r, str(target), "does not exist")
    assert not (tmp_path / "nonexistent").exists()


@pytest.fixture(scope="module")
def xvfb():
    """A virtual X display for a real window; skipped when Xvfb is not installed."""
    with xvfb_display(58, "ACROSS_DIMENSIONS_TEST_DISPLAY") as display:
        yield display


@pytest.mark.slow
def test_sigterm_in_the_window_saves_the_recording(env, tmp_path, xvfb):
    e = dict(env, DISPLAY=xvfb)
    e.pop("WAYLAND_DISPLAY", None)
    path = tmp_path / "r.json"
    settings = tmp_path / "settings.toml"
    settings.write_text("", encoding="utf-8")
    game = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "across_dimensions",
            "play",
            "01_first_steps",
            "--record",
            str(path),
            "--settings",
            str(settings),
            "--quit-after",
            "120",
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=e,
        cwd=tmp_path,
    )
    try:
        deadline = time.monotonic() + TIMEOUT
        while time.monotonic() < deadline and game.poll() is None:
            # Two simulated seconds on disk: the journal's header, runs and two hash lines.
            if path.exists() and path.read_text().count('"tick"') >= 2:
                break
            time.sleep(0.2)
        assert game.poll() is None, describe(subprocess.CompletedProcess([], game.returncode, *game.communicate()))
        game.send_signal(signal.SIGTERM)
        out, err = game.communicate(timeout=60)
    finally:
        if game.poll() is None:
            game.kill()
            game.wait()
    assert game.returncode == 128 + signal.SIGTERM, f"exit {game.returncode}\n{out}\n{err}"
    assert "Traceback" not in err and f"replay saved: {path}" in out, f"{out}\n{err}"
    data = json.loads(path.read_text())  # the journal was replaced by the finished replay
    assert data["format"] == "across-dimensions-replay" and data["final"]["ticks"] >= 120
    assert not Replay.load(path).recovered
    r = run(env, tmp_path, "replay", "01_first_steps", path, "--json")
    assert r.returncode == 0, describe(r)
    assert replay_json(r)["ticks"] == data["final"]["ticks"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.json", "settings.toml"]
