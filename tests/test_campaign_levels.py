"""Levels 4 and 5 of the campaign: the Armory asks for a push, Blast and Field for the blast
and the field; and saves written before the levels were renumbered keep their progress."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.app.saves import RENAMED, Progress, load_progress
from across_dimensions.game.actions import Actions
from across_dimensions.game.playback import play
from across_dimensions.game.player import JUMP_SPEED, STEP_HEIGHT
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import Game
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

ARMORY = levels_dir() / "04_armory.toml"
ARMORY_REPLAY = levels_dir() / "replays" / "04_armory.json"
BLAST_FIELD = levels_dir() / "05_blast_and_field.toml"
BLAST_FIELD_REPLAY = levels_dir() / "replays" / "05_blast_and_field.json"
G = 9.81


def _replay_cli(level, replay) -> dict:
    out = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "replay", str(level), str(replay), "--json"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def _without(replay: Replay, *presses: str) -> Replay:
    """The replay with the named one-shot presses taken out (and no hashes to check)."""
    acts = [dataclasses.replace(a, presses=tuple(p for p in a.presses if p[0] not in presses)) for a in replay.actions]
    return dataclasses.replace(replay, actions=acts, hashes={}, final_hash="")


# ---------------------------------------------------------------- 4: the Armory (gun and push)
def test_armory_has_only_the_gun_and_its_ledge_is_beyond_any_jump():
    level = load_level(ARMORY)
    assert [w.kind for w in level.weapons] == ["gun"] and level.arsenal == ()  # the gun lies in the level
    assert [p.weapon for p in level.pickups] == ["gun"]
    jump = JUMP_SPEED**2 / (2 * G)  # how high the feet rise
    ledge = 2.2  # the ledge's top (levels/04_armory.toml)
    assert jump + STEP_HEIGHT < ledge, "the ledge must not be reached from the floor"
    crate = next(o for o in level.objects if o.name == "crate")
    top = crate.position[1] + 0.5 * float(np.max(crate.scale))
    assert top < jump and ledge - top < jump, "from the floor onto the crate, from the crate onto the ledge"
    assert level.goal.center[1] - level.goal.size[1] / 2 >= ledge - 1e-9  # the goal is up on the ledge


def test_armory_replay_finishes_by_a_shot_and_a_push():
    summary = _replay_cli(ARMORY, ARMORY_REPLAY)
    assert summary["outcome"] == "complete" and summary["divergence"] is None
    ev = summary["events"]
    assert ev["shot_fired"] >= 2 and ev["target_hit"] == 1 and ev["blast"] == 0 and ev["field"] == 0
    assert ev["slab_knocked"] >= 1  # the hidden block round the switch was knocked off its post first
    assert summary["position"][1] > 2.2  # finished up on the ledge


def _armory_variant(tmp_path, shield: str) -> Path:
    """The Armory with its hidden block round the switch as it ships (``"body"``), fixed in place
    (``"fixed"``: a solid slab no bullet can knock) or taken out (``"none"``)."""
    text = ARMORY.read_text(encoding="utf-8")
    body = 'body = "hypercube"\nmass = 2.5\n'
    assert text.count(body) == 1
    if shield == "fixed":
        text = text.replace(body, "")
    elif shield == "none":
        cut = text.index('name = "shield"')
        text = text[: text.rindex("[[object]]", 0, cut)] + text[text.index("\n\n", cut) + 2 :]
    path = tmp_path / f"04_armory_{shield}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _switch_hits(level: Path, spots) -> int:
    """How many of single shots at the switch, one from each feet position ``(x, z, w)``, hit it."""
    hits = 0
    for x, z, w in spots:
        game = Game(load_level(level, arsenal=["gun"]))
        game.player.position = np.array([x, 0.0, z, w])
        game.step(Actions())
        aim = game.entities.named("ana switch").center(game)[:3] - game.player.eye()[:3]
        yaw, pitch = np.arctan2(aim[0], aim[2]), np.arctan2(aim[1], np.hypot(aim[0], aim[2]))
        game.step(Actions(yaw=float(yaw), pitch=float(pitch)))
        game.step(Actions(presses=(("fire", 1),)))
        for _ in range(90):
            game.step(Actions())
        hits += game.event_counts.get("target_hit", 0)
    return hits


@pytest.mark.slow
def test_armory_switch_is_reached_only_by_knocking_its_hidden_block(tmp_path):
    # Shots from near and far, either side, in front of the switch and beside it, at every w
    # the player can take: without the block some hit the switch; with the block fixed in place
    # none does (so the shipped block, a body, must be knocked first), and the shipped route,
    # played against the fixed block, never opens the door.
    spots = [
        (x, z, w)
        for x, z in ((0.0, -13.0), (-3.0, -11.0), (3.5, -12.0), (2.5, -10.0), (0.0, -4.6))
        for w in (-0.4, 0.0, 0.4)
    ]
    assert _switch_hits(_armory_variant(tmp_path, "none"), spots) >= 3
    assert _switch_hits(_armory_variant(tmp_path, "fixed"), spots) == 0
    replay = Replay.load(ARMORY_REPLAY)
    game = Game(load_level(_armory_variant(tmp_path, "fixed")), seed=replay.seed)
    result = play(replay, game, check=False)
    assert result.outcome is None and game.entities.named("door A") is not None


def test_armory_replay_pushes_the_crate_and_without_the_crate_does_not_finish(tmp_path):
    replay = Replay.load(ARMORY_REPLAY)
    game = Game(load_level(ARMORY), seed=replay.seed)
    start = game.entities.named("crate").center(game).copy()
    result = play(replay, game)
    assert result.divergence is None and result.outcome == "complete"
    moved = game.entities.named("crate").center(game) - start
    assert moved[2] > 5.0, "the crate was pushed most of the way to the ledge"
    # The same inputs with nothing to push: the ledge stays out of reach.
    text = ARMORY.read_text(encoding="utf-8")
    cut = text.index('[[object]]\nname = "crate"')
    end = text.index("\n\n", cut)
    no_crate = tmp_path / "04_armory.toml"
    text = text[:cut] + text[end:]
    cut = text.index("[[beacon]]")  # and the crate's beacon with it
    text = text[:cut] + text[text.index("\n\n", cut) :]
    no_crate.write_text(text, encoding="utf-8")
    game = Game(load_level(no_crate), seed=replay.seed)
    assert game.entities.named("crate") is None
    result = play(replay, game, check=False)
    assert result.outcome is None
    assert game.player.position[1] < 1.5  # on the floor, or in a jump from it: never up on the ledge (2.2)
    for _ in range(600):  # and jumping at the ledge for ten more seconds does not get there either
        game.step(Actions(forward=1.0, jump=True))
    assert game.outcome is None


@pytest.mark.slow
# ---------------------------------------------------------------- 5: Blast and Field
def test_blast_and_field_replay_finishes_with_both_new_weapons():
    summary = _replay_cli(BLAST_FIELD, BLAST_FIELD_REPLAY)
    assert summary["outcome"] == "complete" and summary["divergence"] is None
    ev = summary["events"]
    assert ev["blast"] >= 1 and ev["field"] >= 1 and ev["target_hit"] == 2


@pytest.mark.slow
def test_without_the_blast_the_kata_switch_is_never_hit(tmp_path):
    replay = Replay.load(BLAST_FIELD_REPLAY)
    text = BLAST_FIELD.read_text(encoding="utf-8")
    cut = text.index("[[pickup]]   # before the blue door")
    no_blast = tmp_path / "no_blast.toml"  # the blast's pickup taken out: the same clicks fire the gun
    no_blast.write_text(text[:cut] + text[text.index("\n\n", cut) :], encoding="utf-8")
    game = Game(load_level(no_blast, arsenal=["gun"]), seed=replay.seed)
    result = play(replay, game, check=False)
    assert result.outcome is None
    assert game.event_counts["blast"] == 0
    assert game.entities.named("door B") is not None
    switch = game.entities.named("kata switch")
    assert not switch.data.hit and switch.center(game)[3] == pytest.approx(-3.0)


def _shelf_looks(game):
    """The odd crate's look and its radar pin, and the level's plain crates' colour."""
    crate = game.entities.named("odd crate")
    pins = [p for p in game.frame().radar.pins if p.kind == "target"]
    return crate.style, crate.mesh.colors[0, :3].tolist(), len(pins)


@pytest.mark.slow
def test_the_odd_crate_looks_like_the_others_until_the_field_shows_it():
    level = load_level(BLAST_FIELD)
    plain = {tuple(np.round(b.color[:3], 6)) for b in level.boxes if np.allclose(b.size, 0.8)}
    assert len(plain) == 1  # four plain crates, one colour
    replay = Replay.load(BLAST_FIELD_REPLAY)
    game = Game(level, seed=replay.seed)
    looks = []
    for a in replay.actions:
        game.step(a)
        if any(p[0] == "fire" for p in a.presses) and game.states.weapons.current.kind == "field":
            looks.append(("field", game.entities.named("odd crate").style))
        if game.tick == 10:
            style, color, pins = _shelf_looks(game)
            assert style == "solid" and tuple(np.round(color, 6)) in plain
            # a disguised target gets no pin: the radar (16 m) shows only the kata switch
            assert pins == 1
    assert looks == [("field", "wire")]


# ---------------------------------------------------------------- saves across the renumbering
def test_progress_saved_under_the_old_level_names_survives_the_renumbering(tmp_path):
    old = {
        "format": "across-dimensions-progress",
        "version": 1,
        "finished": {"04_armory": 80.0, "05_bridge": 61.5, "06_orthogonal_worlds": 90.0, "07_around_the_corner": 70.0},
        "crystals": {"08_hive": [2, 5]},
        "current": {"level": "08_hive", "checkpoint": 1},
    }
    path = tmp_path / "progress.json"
    path.write_text(json.dumps(old), encoding="utf-8")
    progress, warnings = load_progress(path)
    assert warnings == []
    assert progress.finished == {
        "04_armory": 80.0,
        "06_bridge": 61.5,
        "07_orthogonal_worlds": 90.0,
        "08_around_the_corner": 70.0,
    }
    assert progress.crystals == {"09_hive": (2, 5)}
    assert (progress.current, progress.checkpoint) == ("09_hive", 1)
    # Every new name is a shipped level; every old one is gone.
    shipped = {p.stem for p in levels_dir().glob("*.toml")}
    assert set(RENAMED.values()) <= shipped and not set(RENAMED) & shipped
    # Written back, the file holds only the new names, and reads the same again.
    again = Progress.from_json(progress.to_json())
    assert again.finished == progress.finished and again.current == "09_hive"
    # The level after the Armory is the new one, unlocked by the Armory's finish.
    stems = [p.stem for p in sorted(levels_dir().glob("[0-9][0-9]_*.toml"))]
    assert stems.index("05_blast_and_field") == stems.index("04_armory") + 1
    assert progress.unlocked(stems)[stems.index("05_blast_and_field")]
