"""Weapons found in the world (``[[pickup]]``) and carried along the campaign."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from levels_builder import LevelBuilder

from across_dimensions.app.saves import Progress, load_progress, save_progress
from across_dimensions.game.actions import Actions
from across_dimensions.game.replay import Recorder, Replay
from across_dimensions.game.sim import Game
from across_dimensions.world.level import LevelError, load_level
from across_dimensions.world.pickups import campaign_arsenal

REPO = Path(__file__).resolve().parents[1]
LEVELS = REPO / "levels"
ARMORY = LEVELS / "04_armory.toml"
FORWARD = Actions(forward=1.0)
FIRE = Actions(presses=(("fire", 1),))


def walk_until(game, kind: str, ticks: int = 300) -> int:
    """Walk forward until an event of ``kind``; returns how many came."""
    for _ in range(ticks):
        game.step(FORWARD)
        if game.event_counts[kind]:
            break
    return game.event_counts[kind]


# ------------------------------------------------------------------ a pickup teaches itself
def test_the_armory_gun_is_found_on_the_way_and_taught_by_the_notice():
    game = Game(load_level(ARMORY))
    game.step(FIRE)  # nothing owned yet: nothing fires, no panel
    assert game.event_counts["shot_fired"] == 0 and game.frame().hud.weapon is None
    assert walk_until(game, "weapon_acquired") == 1
    (ev,) = [e for e in game.events if e.kind == "weapon_acquired"]
    assert ev.weapon == "gun" and game.entities.of_kind("pickup") == []
    hud = game.frame().hud
    assert hud.weapon.name == "120-cell gun" and (hud.weapon.slot, hud.weapon.count) == (1, 1)
    # The notice names its key and what a shot costs; the window fills in the player's keys.
    assert "{weapon_1}" in hud.message and "{fire}" in hud.message and "costs 1 energy" in hud.message
    assert hud.energy.costs.endswith("GUN 1")
    game.step(FIRE)
    assert game.event_counts["shot_fired"] == 1


def test_the_hud_shows_owned_weapons_only_and_keys_reach_only_those(tmp_path):
    level = load_level(LEVELS / "05_blast_and_field.toml")
    assert level.arsenal == ("gun",) and [w.kind for w in level.weapons] == ["gun", "blast", "field"]
    game = Game(level)
    game.step(Actions(presses=(("weapon_3", 1), ("next_weapon", 1))))  # the field is not owned yet
    panel = game.frame().hud.weapon
    assert (panel.name, panel.slot, panel.count) == ("120-cell gun", 1, 1)
    assert game.frame().hud.energy.costs == "W 2/UNIT  GUN 1"  # the level's w moves are paid too
    assert walk_until(game, "weapon_acquired") == 1  # the blast floats ahead of the start
    panel = game.frame().hud.weapon
    assert (panel.name, panel.slot, panel.count) == ("w-pull blast", 2, 2)  # taken in hand
    assert game.frame().hud.energy.costs == "W 2/UNIT  GUN 1  BLAST 5"
    game.step(Actions(presses=(("weapon_3", 1),)))
    assert game.states.weapons.current.kind == "blast"


def test_a_pickup_off_the_players_w_is_not_taken(tmp_path):
    build = LevelBuilder("off", spawn=(0.0, 0.0, -3.0, 0.0), goal=(0.0, 1.0, 9.0), floor=(10.0, 1.0, 30.0))
    level = build.pickup("gun", [0.0, 1.0, 0.0, 0.9]).load(tmp_path, arsenal=())
    game = Game(level)
    for _ in range(90):  # walks through its x, y, z at w = 0: it is 0.9 away along w
        game.step(FORWARD)
    assert game.event_counts["weapon_acquired"] == 0
    for _ in range(120):
        game.step(Actions(forward=-1.0, w=1.0))  # back, and along w to it
    assert walk_until(game, "weapon_acquired") == 1


# ------------------------------------------------------------------ bad entries
BAD = [
    (
        '[[pickup]]\nweapon = "laser"\nposition = [0.0, 1.0, 0.0, 0.0]\n',
        "[[pickup]] #1: field 'weapon': expected one of gun, blast, field, got 'laser'",
    ),
    ('[[pickup]]\nweapon = "gun"\n', "[[pickup]] #1: missing field 'position'"),
    (
        '[[pickup]]\nweapon = "gun"\nposition = [0.0, 1.0, 0.0, 3.0]\n',
        "[[pickup]] #1 '120-cell gun': field 'position': w = 3 is outside the level's w_range",
    ),
    (
        '[[pickup]]\nweapon = "gun"\nposition = [0.0, 1.0, 0.0, 0.0]\ncolour = "red"\n',
        "[[pickup]] #1: unknown field 'colour'",
    ),
    (
        '[[pickup]]\nweapon = "blast"\nposition = [0.0, 1.0, 0.0, 0.0]\n'
        '[[pickup]]\nweapon = "blast"\nposition = [0.0, 1.0, 2.0, 0.0]\n',
        "[[pickup]] #2 'w-pull blast': field 'weapon': the blast already lies in [[pickup]] #1 (one per weapon)",
    ),
    (
        '[[weapon]]\nkind = "gun"\ncost = 1.0\n[[weapon]]\nkind = "gun"\ncost = 2.0\n',
        "[[weapon]] #2: field 'kind': the gun is already tuned by [[weapon]] #1 (one per kind)",
    ),
]


@pytest.mark.parametrize(("entry", "message"), BAD)
def test_a_bad_pickup_is_one_line_naming_the_file_and_the_entry(tmp_path, entry, message):
    path = LevelBuilder("bad").write(tmp_path, "bad.toml", extra=entry)
    with pytest.raises(LevelError) as err:
        load_level(path)
    (line,) = err.value.problems
    assert line.startswith(f"{path}: ") and message in line


def test_check_level_names_a_bad_pickup_without_a_traceback(tmp_path):
    path = LevelBuilder("bad").write(tmp_path, "bad.toml", extra=BAD[0][0])
    out = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "check-level", str(path)], capture_output=True, text=True
    )
    assert out.returncode != 0
    text = out.stdout + out.stderr
    assert "[[pickup]] #1" in text and str(path) in text and "Traceback" not in text


# ------------------------------------------------------------------ carried along the campaign
def test_the_shipped_campaign_gives_each_weapon_from_the_level_that_lays_it():
    assert campaign_arsenal(LEVELS / "00_arrival.toml") == ()
    assert campaign_arsenal(ARMORY) == ()  # the gun lies in the Armory itself
    assert campaign_arsenal(LEVELS / "05_blast_and_field.toml") == ("gun",)
    for later in ("06_bridge", "08_around_the_corner", "09_hive"):
        assert campaign_arsenal(LEVELS / f"{later}.toml") == ("gun", "blast", "field")
        assert load_level(LEVELS / f"{later}.toml").arsenal == ("gun", "blast", "field")


def _campaign(folder: Path, order: list[str]) -> None:
    """A campaign in ``folder``: a level laying the gun, then one laying nothing, in ``order``."""
    base = LevelBuilder("x", spawn=(0.0, 0.0, -3.0, 0.0), goal=(0.0, 1.0, 6.0), floor=(10.0, 1.0, 30.0))
    base.pickup("gun", [0.0, 1.0, -1.5, 0.0]).write(folder, "armoury.toml")
    LevelBuilder("y", goal=(0.0, 1.0, 6.0)).write(folder, "after.toml")
    text = "".join(f'[[level]]\nfile = "{stem}"\ntitle = "{stem}"\n\n' for stem in order)
    (folder / "campaign.toml").write_text(text, encoding="utf-8")


def test_a_weapon_found_in_one_level_is_owned_at_the_start_of_the_next(tmp_path):
    _campaign(tmp_path, ["armoury", "after"])
    after = load_level(tmp_path / "after.toml")
    assert after.arsenal == ("gun",)
    game = Game(after)
    game.step(FIRE)
    assert game.event_counts["shot_fired"] == 1  # owned from the first tick
    _campaign(tmp_path, ["after", "armoury"])  # before the armoury, the same level has nothing
    assert load_level(tmp_path / "after.toml").arsenal == ()
    assert load_level(tmp_path / "after.toml", arsenal=["gun"]).arsenal == ("gun",)  # unless told


def test_a_replay_records_its_arsenal_and_replays_alike_after_the_campaign_changes(tmp_path):
    _campaign(tmp_path, ["armoury", "after"])
    game = Game(load_level(tmp_path / "after.toml"))
    rec = Recorder(game, "after")
    for a in [FIRE] + [FORWARD] * 60 + [FIRE] * 3:
        game.step(a)
        rec.record(a)
    path = tmp_path / "after.json"
    rec.finish().save(path)
    header = json.loads(path.read_text(encoding="utf-8"))
    assert header["version"] == 4 and header["arsenal"] == ["gun"]
    _campaign(tmp_path, ["after", "armoury"])  # today's campaign gives nothing before it
    cmd = [sys.executable, "-m", "across_dimensions", "replay", str(tmp_path / "after.toml"), str(path), "--json"]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout)
    assert summary["divergence"] is None and summary["events"]["shot_fired"] >= 2


def test_a_replay_without_an_arsenal_plays_with_the_campaigns(tmp_path):
    shipped = json.loads((LEVELS / "replays" / "06_bridge.json").read_text(encoding="utf-8"))
    assert shipped["arsenal"] == ["gun", "blast", "field"]
    old = {k: v for k, v in shipped.items() if k != "arsenal"} | {"version": 3}
    path = tmp_path / "06_bridge.json"
    path.write_text(json.dumps(old), encoding="utf-8")
    assert Replay.load(path).arsenal is None
    cmd = [sys.executable, "-m", "across_dimensions", "replay", "06_bridge", str(path)]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr  # the same hashes: the campaign gives what was recorded


def test_a_replay_naming_an_unknown_weapon_is_one_line(tmp_path):
    shipped = json.loads((LEVELS / "replays" / "06_bridge.json").read_text(encoding="utf-8"))
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(shipped | {"arsenal": ["gun", "laser"]}), encoding="utf-8")
    cmd = [sys.executable, "-m", "across_dimensions", "replay", "06_bridge", str(path)]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert out.returncode != 0 and "Traceback" not in out.stderr
    assert f"{path}: entry 'arsenal': unknown weapon 'laser'" in out.stderr


# ------------------------------------------------------------------ progress
def test_the_weapons_found_are_saved_merged_and_checked(tmp_path):
    path = tmp_path / "progress.json"
    mine = Progress(arsenal={"gun"})
    save_progress(mine, path)
    other = Progress(arsenal={"blast"})
    save_progress(other, path)  # another game in the same folder: nothing is lost
    loaded, warnings = load_progress(path)
    assert loaded.arsenal == {"gun", "blast"} and warnings == []
    assert json.loads(path.read_text(encoding="utf-8"))["arsenal"] == ["gun", "blast"]  # key order
    data = json.loads(path.read_text(encoding="utf-8")) | {"arsenal": ["gun", "gun"]}
    path.write_text(json.dumps(data), encoding="utf-8")
    fresh, warnings = load_progress(path)
    assert fresh.arsenal == set() and len(warnings) == 1 and "arsenal" in warnings[0]
    assert (tmp_path / "progress.corrupt-1.json").exists()


def test_an_old_progress_file_has_found_no_weapon(tmp_path):
    path = tmp_path / "progress.json"
    old = {"format": "across-dimensions-progress", "version": 1, "finished": {"04_armory": 30.0}}
    path.write_text(json.dumps(old), encoding="utf-8")
    loaded, warnings = load_progress(path)
    assert warnings == [] and loaded.arsenal == set() and loaded.finished == {"04_armory": 30.0}


def test_shipped_levels_copied_elsewhere_keep_their_campaign_arsenal(tmp_path):
    copy = tmp_path / "08_around_the_corner.toml"
    shutil.copy(LEVELS / "08_around_the_corner.toml", copy)
    assert load_level(copy).arsenal == ("gun", "blast", "field")  # no campaign beside it: the shipped one
