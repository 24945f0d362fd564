"""The design probe: ``[design] needs``, the bots, the soft-lock proofs and the command.

Each shipped level must show no bypass and no soft-lock. The default run probes the
:data:`QUICK` levels (seconds); the others take minutes between them on both cores, so they are
``slow`` (``pytest -m slow``, which CI runs too). Levels that fail today are expected failures
(``xfail(strict=True)``) listing what the probe finds, so fixing a level turns its test from
XFAIL to a strict XPASS failure that asks for the mark to go.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import IDLE
from across_dimensions.game.sim import Game
from across_dimensions.probe.proofs import softlocks
from across_dimensions.probe.route import planned_route
from across_dimensions.probe.runner import probe
from across_dimensions.probe.skills import swing_distance
from across_dimensions.world.design import NEEDS
from across_dimensions.world.json_schema import level_schema
from across_dimensions.world.level import LevelError
from across_dimensions.world.resources import level_files, prologue_files

REPO = Path(__file__).resolve().parents[1]
TIMEOUT = 600

#: What the probe finds on the shipped levels today (issue: levels that demand what they teach).
KNOWN: dict = {}
#: The levels probed in the default run: a few seconds each (Crossfire alone takes two minutes).
QUICK = ("00_arrival", "01_first_steps", "02_crystal_cache")


def corridor(needs) -> LevelBuilder:
    """A straight corridor with nothing in the way, declaring ``[design] needs``."""
    return LevelBuilder(
        "Corridor", spawn=(0.0, 0.0, -6.0, 0.0), goal=(0.0, 1.0, 6.0), goal_size=(3.0, 2.0, 2.0), floor=(6.0, 1.0, 16.0)
    ).table("design", needs=needs)


def run(env, *args) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
        env=env,
        cwd=REPO,
    )


def _probed(paths) -> dict:
    return {r["level"]: r for r in probe(paths, workers=2)}


@pytest.fixture(scope="module")
def quick_rows() -> dict:
    return _probed([p for p in level_files() if p.stem in QUICK])


@pytest.fixture(scope="module")
def slow_rows() -> dict:
    return _probed([p for p in prologue_files() + level_files() if p.stem not in QUICK])


def _param(stem: str):
    marks = [pytest.mark.xfail(strict=True, reason=KNOWN[stem])] if stem in KNOWN else []
    return pytest.param(stem, marks=marks if stem in QUICK else [*marks, pytest.mark.slow])


@pytest.mark.parametrize("stem", [_param(p.stem) for p in prologue_files() + level_files()])
def test_each_level_demands_what_it_teaches_and_never_traps(request, stem):
    row = request.getfixturevalue("quick_rows" if stem in QUICK else "slow_rows")[stem]
    assert row["strategies_run"]
    assert not row["bypasses"] and not row["softlocks"], json.dumps(row, indent=1)


def test_rows_name_strategies_and_what_they_avoided(quick_rows):
    for row in quick_rows.values():
        assert set(row) == {"level", "needs", "strategies_run", "bypasses", "softlocks", "seconds"}
        for b in row["bypasses"]:
            assert b["strategy"] in row["strategies_run"] and set(b["avoided"]) <= set(row["needs"])
            assert b["won_tick"] > 0
        for s in row["softlocks"]:
            assert s["strategy"] in row["strategies_run"] and s["proof"]


# ------------------------------------------------------------------ [design]
def test_design_needs_are_read_and_checked(tmp_path):
    assert corridor(["w_move", "gun"]).load(tmp_path).needs == ("w_move", "gun")
    with pytest.raises(LevelError) as e:
        corridor(["w_move", "fly", "w_move"]).load(tmp_path, extra="[design.x]\n")
    text = "\n".join(e.value.problems)
    assert "[design]: field 'needs': entry #2: expected one of w_move" in text and "got 'fly'" in text
    assert "entry #3: 'w_move' is listed twice" in text
    with pytest.raises(LevelError, match="expected a list of distinct words"):
        corridor("gun").load(tmp_path)


def test_every_shipped_level_declares_its_needs_and_the_schema_knows_them():
    for p in level_files():
        assert "[design]" in p.read_text(), p
    schema = level_schema()["$defs"]["design"]["properties"]["needs"]
    assert schema["items"]["enum"] == list(NEEDS) and schema["uniqueItems"]


# ------------------------------------------------------------------ pieces
def test_swing_distance_puts_the_bullet_at_the_wanted_w():
    class Gun:
        speed, period, lifetime, amplitude = 12.0, 2.0, 5.0, 1.0

    for dw in (0.3, 0.7, -0.5):
        d = swing_distance(Gun, dw, 0.05)
        # The bullet's w after d metres: A sin(2 pi d / (speed period)), within the tolerance.
        assert abs(np.sin(2 * np.pi * d / 24.0) - dw) <= 0.05
    assert swing_distance(Gun, 1.6, 0.2) is None  # beyond the swing


def switch_room(start: float) -> LevelBuilder:
    """A door the gun opens by hitting its switch, with ``start`` energy and a shot costing 1."""
    return (
        LevelBuilder(
            w_range=(-0.5, 0.5),
            spawn=(0.0, 0.0, -6.0, 0.0),
            goal=(0.0, 1.0, 8.0),
            goal_size=(3.0, 2.0, 2.0),
            floor=(8.0, 1.0, 20.0),
        )
        .table("energy", start=start, max=5.0)
        .weapon("gun", cost=1.0)
        .object([0.0, 2.0, 4.0, 0.0], name="door", scale=[8.0, 4.0, 0.4, 3.0])
        .add("target", name="switch", position=[0.0, 1.6, 0.0, 0.0], opens="door")
    )


def test_energy_proof_needs_a_bar_too_short_and_nothing_to_refill_it(tmp_path):
    def locks(start: float, crystal: bool = False) -> list:
        room = switch_room(start)
        if crystal:  # a crystal lies in the level
            room.crystal([2.0, 1.0, -4.0, 0.0], energy=1.0)
        level = room.load(tmp_path)
        game = Game(level)
        game.step(IDLE)  # the first tick sets the switches up
        return softlocks(game, planned_route(level))

    assert any(f.startswith("energy: 0.5 left") for f in locks(0.5))  # a shot costs 1
    assert locks(1.0) == []
    assert locks(0.5, crystal=True) == []


# ------------------------------------------------------------------ the command
def test_probe_command_json_on_a_level_with_nothing_to_find(env):
    r = run(env, "probe", "00_arrival", "--json", "--workers", "1")
    assert r.returncode == 0, r.stderr
    (row,) = json.loads(r.stdout)
    assert row["level"] == "00_arrival" and row["needs"] == [] and "straight" in row["strategies_run"]
    assert row["bypasses"] == [] and row["softlocks"] == []


def test_probe_command_finds_a_bypass_and_exits_1(env, tmp_path):
    level = corridor(["w_move"]).write(tmp_path)  # nothing stands in the way
    r = run(env, "probe", level)
    assert r.returncode == 1, r.stderr
    assert "bypass: wall_hug won at" in r.stdout and "without w_move" in r.stdout
    r = run(env, "probe", level, "--json", "--workers", "2")
    assert r.returncode == 1
    (row,) = json.loads(r.stdout)
    # straight may move along w (to a goal's w), so its win is no bypass of w_move
    assert {b["strategy"] for b in row["bypasses"]} == {"wall_hug", "jump_spam", "no_w_move"}


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["probe", "no_such_level"], "no level 'no_such_level'"),
        (["probe", "--workers", "0"], "--workers"),
    ],
)
def test_probe_command_refuses_bad_input_in_one_line(env, args, says):
    r = run(env, *args)
    assert r.returncode == 2 and r.stdout == ""
    assert says in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_probe_command_refuses_a_bad_level(env, tmp_path):
    r = run(env, "probe", corridor(["teleport"]).write(tmp_path))
    assert r.returncode == 2 and "got 'teleport'" in r.stderr


@pytest.mark.slow
def test_the_folded_stair_is_climbed_only_on_the_image_with_the_cameras_loot():
    """The full bot follows level 12's route (the camera's loot, then the stair's image) and
    wins; taking away the walk on the image, the loot or the orbit loses."""
    from across_dimensions.probe.route import load_route
    from across_dimensions.probe.runner import run_one
    from across_dimensions.world.level import load_level

    path = str(REPO / "levels" / "12_folded_stair.toml")
    route = load_route(load_level(path))
    assert [s.kind for s in route.steps if s.kind in ("camera_loot", "frustum_walk")] == ["camera_loot", "frustum_walk"]
    assert run_one(path, "no_enemies")["won"]  # no enemy to fight here: the full bot
    for name in ("no_frustum_walk", "no_camera_loot", "frustum_no_orbit"):
        r = run_one(path, name)
        assert not r["won"] and r["softlocks"] == [], name
