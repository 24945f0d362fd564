"""Enemies that hide along w: bodies, animation, the state machine, combat, weak spots, loot, health."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.core.section import cross_section
from across_dimensions.core.transform import rotation, scaling, translation
from across_dimensions.game import enemies as en
from across_dimensions.game import health as hp
from across_dimensions.game.actions import Actions
from across_dimensions.game.events import EnemyHit, LootReleased
from across_dimensions.game.frame import HealthGauge, Hud
from across_dimensions.game.sim import TICK_RATE, Game
from across_dimensions.game.systems import enemies as enemy_system
from across_dimensions.world.level import LevelError, load_level
from across_dimensions.world.resources import levels_dir, resolve_level

ROOT = Path(__file__).resolve().parents[1]
HIVE = levels_dir() / "09_hive.toml"


def hall() -> LevelBuilder:
    """A long hall from w = -3 to 3, the goal far ahead."""
    return LevelBuilder(
        "enemy test", w_range=(-3.0, 3.0), goal=(0.0, 1.0, 40.0), goal_size=(1.0, 1.0, 1.0), floor=(40.0, 1.0, 90.0)
    )


GUN = """
[[weapon]]
kind = "gun"
cost = 0.0
cooldown = 0.05
speed = 12.0
amplitude = 0.01
size = 0.15
lifetime = 2.0
"""


def enemy(game, name=None):
    found = game.entities.of_kind("enemy")
    return found[0] if name is None else next(e for e in found if e.name == name)


def run(game, ticks, actions=None):
    seen = []
    for _ in range(ticks):
        game.step(actions or Actions())
        seen += game.events
    return seen


def fire(game, ticks=40):
    """One shot straight ahead, then wait ``ticks`` ticks; returns the events."""
    return run(game, 1, Actions(presses=(("fire", 1),))) + run(game, ticks)


@pytest.fixture
def frozen(monkeypatch):
    """Enemies that stay at their post: the tests of hits are about geometry, not behaviour."""
    monkeypatch.setattr(enemy_system, "_think", lambda game, foe, moves: None)


# ------------------------------------------------------------------ bodies and animation
def test_section_at_time_t_is_the_lifted_mesh_cut_after_its_animation_pose(tmp_path):
    lv = hall().load(
        tmp_path,
        extra="""
[[enemy]]
name = "tree"
kind = "morph"
position = [0.0, 1.6, 30.0, 2.0]
size = 1.0
depth = 1.2
sight = 1.0
animation = "turn"
[[animation]]
name = "turn"
time = 0.0
[[animation]]
name = "turn"
time = 1.0
offset = [0.0, 0.0, 0.0, 0.5]
rotation = { yw = 90.0 }
[[animation]]
name = "turn"
time = 2.0
""",
    )
    game = Game(lv)
    run(game, TICK_RATE)  # the pose set on the 60th tick is the one for t = 1.0 s: the second key
    e = enemy(game)
    foe = e.data
    # The truth, built independently: the tree lifted (its vertices' box middle to the origin,
    # space scaled so its largest half extent is the size, w as deep as the level says),
    # turned 90 degrees in yw and moved 0.5 ana, at the enemy's centre.
    v = e.mesh.vertices.astype(np.float64)
    lo, hi = v.min(axis=0), v.max(axis=0)
    assert hi[3] - lo[3] == pytest.approx(1.2, abs=1e-6)  # lifted 1.2 deep
    assert np.ptp(v[:, 1]) == pytest.approx(3.4, abs=1e-6)  # the tree asset is 3.4 m tall
    s = 1.0 / (np.max(hi[:3] - lo[:3]) / 2)
    want = (
        translation(foe.centre + [0.0, 0.0, 0.0, 0.5])
        @ rotation("yw", np.pi / 2)
        @ scaling([s, s, s, 1.0])
        @ translation(-(lo + hi) / 2)
    )
    # 1/60 s ticks summed 60 times land within float rounding of 1.0; the smoothstep is flat there.
    np.testing.assert_allclose(e.model(game), want, atol=1e-9)
    w = float(foe.centre[3]) + 0.45
    got = cross_section(e.mesh, translation((0, 0, 0, w)), e.model(game))
    ref = cross_section(e.mesh, translation((0, 0, 0, w)), want)
    assert len(got.faces) == len(ref.faces) > 0
    np.testing.assert_allclose(np.sort(got.vertices, axis=0), np.sort(ref.vertices, axis=0), atol=1e-4)
    # Halfway between keys the smoothstep is exactly one half: 45 degrees and 0.25 ana.
    half = en.animation_pose(foe.keys, 0.5)
    np.testing.assert_allclose(half, translation([0, 0, 0, 0.25]) @ rotation("yw", np.pi / 4), atol=1e-12)
    # And the drawn section (alpha 1) is that same cut, once the player stands at its w.
    game.player.position[3] = w
    frame = game.frame(1.0)
    assert any(f"entity:{e.id}" in b.members for b in frame.batches)  # sliced with the others, in a batch
    _, rows = game.entity_sections.batches[e.style].instance_rows(e.id)
    # Three rows a triangle: every one facing the eye, at most all (the batch leaves out those
    # clearly facing away, which the renderer skips anyway).
    facing = ((np.asarray(frame.camera.position) - ref.vertices[::3]) * ref.normals[::3]).sum(axis=1) > 0.0
    assert 0 < facing.sum() <= rows // 3 <= len(ref.faces)


def test_swarm_is_ten_hyperspheres_and_its_section_changes_as_it_turns_in_zw():
    game = Game(load_level(HIVE))
    run(game, 1)
    e = enemy(game, "drone")
    assert len(e.mesh.tets) == 10 * 600  # ten hyperspheres of 600 tetrahedra
    w = float(e.data.centre[3])
    counts = []
    for t in (0.0, 1.5, 2.25, 3.0):
        model = en.body_model(e.data.body, e.data.keys, e.data.centre, t)
        counts.append(len(cross_section(e.mesh, translation((0, 0, 0, w)), model).faces))
    assert len(set(counts)) > 1  # translated along w and turned in zw, the slice shows another shape


def test_body_models_pose_every_foe_as_body_model_does_bit_for_bit():
    """The one-pass poses (:class:`Track`) against each foe's own: keys of both kinds, a still
    animation, planes one key leaves out, integer degrees, negative zero, times past the loop."""
    from types import SimpleNamespace

    from across_dimensions.world.enemy_tables import KeySpec

    rng = np.random.default_rng(7)
    body = SimpleNamespace(scale=np.array([0.5, 0.7, 0.5, 0.4]), pivot=np.array([0.1, -0.2, 0.0, 0.05]))
    tracks = [
        en.default_keys("swarm"),
        en.default_keys("morph"),
        [KeySpec(0.0, np.array([-0.0, 0.2, 0.0, -0.0]), {"xw": 30})],  # still
        [KeySpec(0.0, np.zeros(4), {"xy": 10}), KeySpec(1.0, np.ones(4), {"zw": -45.5}), KeySpec(1.0, np.ones(4), {})],
    ]
    foes, times, grows = [], [], []
    for i in range(40):
        keys = tracks[i % len(tracks)]
        foes.append(SimpleNamespace(keys=keys, track=en.Track(keys), body=body, centre=rng.normal(size=4)))
        times.append(float(rng.uniform(-3.0, 20.0)) if i % 5 else 1.0 * (i // 5))
        grows.append(1.0 if i % 3 else float(rng.uniform(1.0, 2.5)))
    models = en.body_models(foes, times, grows)
    for foe, t, g, m in zip(foes, times, grows, models):
        one = en.body_model(foe.body, foe.keys, foe.centre, t, g)
        assert one.tobytes() == m.tobytes(), (t, foe.keys)


# ------------------------------------------------------------------ the state machine
def scout(level: LevelBuilder) -> LevelBuilder:
    """``level`` with a swarm posted 10 m ahead, 1.6 ana, that sees the player within 10 m."""
    return level.enemy("scout", [0.0, 1.5, 10.0, 1.6], kind="swarm", health=3, sight=10.0, reach=8.0)


def test_state_machine_follows_the_players_position(tmp_path):
    game = Game(scout(hall()).load(tmp_path))
    game.player.position[:] = [0.0, 0.0, -20.0, 0.0]  # 30 m from its post: out of sight
    states = set()
    for _ in range(3 * TICK_RATE):
        game.step(Actions())
        states.add(enemy(game).data.state)
        assert abs(enemy(game).data.centre[3]) >= en.HIDE_W - 0.3  # drifting, never in the slice
    assert states == {"hidden"}
    game.player.position[:] = [0.0, 0.0, 4.0, 0.0]  # within sight of its post
    run(game, 1)
    assert enemy(game).data.state == "approaching"
    for _ in range(6 * TICK_RATE):
        game.step(Actions())
        if enemy(game).data.state == "attacking":
            break
    foe = enemy(game).data
    assert foe.state == "attacking"
    assert abs(foe.centre[3] - 0.0) <= en.IN_SLICE  # in the player's slice
    assert np.linalg.norm(foe.centre[[0, 2]] - [0.0, 4.0]) <= 8.0  # within its reach
    # The player runs up to it: it backs off out of the slice, then hides.
    game.player.position[:] = [foe.centre[0], 0.0, foe.centre[2] - 1.0, 0.0]
    run(game, 1)
    assert enemy(game).data.state == "fleeing"
    for _ in range(4 * TICK_RATE):
        game.step(Actions())
        if enemy(game).data.state == "hidden":
            break
    assert enemy(game).data.state == "hidden"
    assert abs(enemy(game).data.centre[3]) >= en.HIDE_W


def test_an_attack_is_announced_and_can_be_dodged_along_w(tmp_path):
    game = Game(scout(hall()).load(tmp_path))
    game.player.position[:] = [0.0, 0.0, 4.0, 0.0]
    seen, looks = [], []
    for _ in range(8 * TICK_RATE):
        game.step(Actions())
        seen += game.events
        looks.append(enemy(game).style)
        if game.states.enemies.shots:
            break
    assert game.states.enemies.shots, "no shot within 8 s"
    # The wind-up: the body flickered between glowing and solid in the second before the shot.
    warning = looks[-TICK_RATE:]
    assert "glow" in warning and "solid" in warning
    assert "glow" not in looks[:-TICK_RATE]
    assert not any(ev.kind == "player_hit" for ev in seen)
    # Stepping along w out of the shot's slice dodges it; standing still does not.
    dodger = Game(scout(hall()).load(tmp_path))
    dodger.player.position[:] = [0.0, 0.0, 4.0, 0.0]
    dodger.step(Actions())
    while not dodger.states.enemies.shots:
        dodger.step(Actions())
    hits = [ev for ev in run(dodger, 90, Actions(w=1.0)) if ev.kind == "player_hit"]
    assert hits == []
    hits = [ev for ev in run(game, 90) if ev.kind == "player_hit"]
    assert len(hits) == 1 and hits[0].damage == 15.0
    assert game.states.health.value == 85.0
    # The cue points at the enemy (ahead of the player: straight up on the HUD).
    frame = game.frame()
    assert frame.hud.damage_dir == pytest.approx(0.0, abs=0.2)
    assert frame.hud.health == HealthGauge(85.0, 100.0, frame.hud.health.flash, False)


def test_enemies_never_move_through_the_3d_world(tmp_path):
    wall = hall().box([0.0, 2.0, 6.0], [40.0, 4.0, 0.5])
    game = Game(scout(wall).load(tmp_path))
    game.player.position[:] = [0.0, 0.0, 2.0, 0.0]  # the wall is between the post and the player
    for _ in range(6 * TICK_RATE):
        game.step(Actions())
        assert enemy(game).data.centre[2] - 0.3 >= 6.25 - 1e-9


# ------------------------------------------------------------------ combat, weak spots, loot
WARDEN = """
[[enemy]]
name = "warden"
kind = "morph"
position = [0.0, 1.6, 6.0, 1.0]
health = 2
weak_spot = [0.0, 0.0, 0.0, 0.9]
"""


def test_a_weak_spot_takes_damage_only_from_a_hit_at_its_own_w(tmp_path, frozen):
    game = Game(hall().load(tmp_path, extra=WARDEN + GUN))
    run(game, 1)
    foe = enemy(game).data
    game.player.position[1] = 0.0
    game.player.position[3] = 1.0  # the body's w: the bullet strikes the armour
    seen = fire(game)
    hits = [ev for ev in seen if isinstance(ev, EnemyHit)]
    assert [(h.damage, h.weak_spot) for h in hits] == [(0, False)]
    assert foe.health == 2
    assert game.frame().hud.message.startswith("Armoured")
    game.player.position[3] = 0.0  # a whole unit kata of it: the bullet passes by
    assert not [ev for ev in fire(game) if isinstance(ev, EnemyHit)]
    assert foe.health == 2
    game.player.position[3] = 1.9  # the weak spot's w: hurt
    hits = [ev for ev in fire(game) if isinstance(ev, EnemyHit)]
    assert [(h.damage, h.weak_spot) for h in hits] == [(1, True)]
    assert foe.health == 1


def test_a_swinging_bullet_reaches_the_weak_spot_from_the_right_distance(tmp_path, frozen):
    swing = GUN.replace("amplitude = 0.01", "amplitude = 0.8\nperiod = 2.0")
    game = Game(hall().load(tmp_path, extra=WARDEN + swing))
    run(game, 1)
    game.player.position[:] = [0.0, 0.0, 1.5, 1.0]  # 4.5 m away at the body's w: the swing reaches ana 0.74
    hits = [ev for ev in fire(game, 60) if isinstance(ev, EnemyHit)]
    assert [(h.damage, h.weak_spot) for h in hits] == [(1, True)]
    game.player.position[:] = [0.0, 0.0, 5.0, 1.0]  # 1 m away: the bullet is still near the body's w
    hits = [ev for ev in fire(game, 60) if isinstance(ev, EnemyHit)]
    assert [(h.damage, h.weak_spot) for h in hits] == [(0, False)]


def test_loot_appears_exactly_once_when_defeated(tmp_path, frozen):
    body = """
[[enemy]]
name = "carrier"
kind = "swarm"
position = [0.0, 1.5, 6.0, 0.0]
health = 2
loot = 5.0
[energy]
start = 0.0
max = 20.0
"""
    game = Game(hall().load(tmp_path, extra=body + GUN))
    run(game, 1)
    eid = enemy(game).id
    assert len(game.entities.of_kind("loot")) == 1
    seen = fire(game) + fire(game) + fire(game) + run(game, 120)
    assert [ev.kind for ev in seen if ev.kind in ("enemy_defeated", "loot_released")] == [
        "enemy_defeated",
        "loot_released",
    ]
    assert game.entities.get(eid) is None  # the defeat burst is over
    assert game.entities.of_kind("loot") == []
    crystals = [c for c in game.entities.of_kind("crystal") if c.name == "carrier loot"]
    assert len(crystals) == 1
    assert crystals[0].data.milli == 5000


def test_blast_drags_an_enemy_into_the_slice_and_shakes_its_loot_out_once(tmp_path, monkeypatch):
    monkeypatch.setattr(en, "DRIFT", np.zeros(4))
    body = """
[[enemy]]
name = "carrier"
kind = "morph"
position = [0.0, 1.6, 4.0, 1.6]
health = 1
loot = 5.0
sight = 1.0
[[weapon]]
kind = "blast"
cost = 0.0
radius = 7.0
duration = 0.6
"""
    game = Game(hall().load(tmp_path, extra=body + GUN))
    run(game, 29)
    run(game, 1, Actions(presses=(("weapon_2", 1),)))  # the blast's key
    foe = enemy(game).data
    assert foe.state == "hidden" and foe.centre[3] == pytest.approx(1.6)
    seen = fire(game, 45)
    loot = [ev for ev in seen if isinstance(ev, LootReleased)]
    assert [ev.reason for ev in loot] == ["forced"]
    assert foe.state == "stunned" and foe.centre[3] == pytest.approx(0.0, abs=1e-9)
    crystal = game.entities.get(loot[0].crystal)
    assert crystal.center(game)[3] == 0.0  # in the player's slice, where it can be taken
    # Defeated afterwards, it has nothing left to give.
    seen = run(game, 1, Actions(presses=(("weapon_1", 1),))) + fire(game)  # the gun's key
    assert [ev.kind for ev in seen if ev.kind in ("enemy_defeated", "loot_released")] == ["enemy_defeated"]


def test_the_frustum_camera_holds_an_enemy_in_view_and_its_loot_comes_out_once(tmp_path, monkeypatch):
    monkeypatch.setattr(en, "DRIFT", np.zeros(4))
    body = """
[camera]
frustum = true
frustum_cost = 0.0
[[enemy]]
name = "carrier"
kind = "morph"
position = [0.0, 1.6, 4.0, 1.6]
health = 1
loot = 5.0
sight = 1.0
[[enemy]]
name = "behind"
kind = "morph"
position = [0.0, 1.6, -6.0, 1.6]
health = 1
loot = 5.0
sight = 1.0
"""
    game = Game(hall().load(tmp_path, extra=body + GUN))
    run(game, 30)
    ahead, behind = enemy(game, "carrier").data, enemy(game, "behind").data
    assert ahead.state == behind.state == "hidden"
    seen = run(game, 1, Actions(presses=(("switch_camera", 1),))) + run(game, 60)
    assert [ev.mode for ev in seen if ev.kind == "camera_switched"] == ["frustum"]
    loot = [ev for ev in seen if isinstance(ev, LootReleased)]
    assert [(ev.entity, ev.reason) for ev in loot] == [(enemy(game, "carrier").id, "camera")]
    assert game.entities.get(loot[0].crystal).center(game)[3] == 0.0  # at the player's w: in reach
    assert ahead.centre[3] == pytest.approx(0.0, abs=1e-9)  # held in the player's slice
    assert behind.centre[3] == pytest.approx(1.6)  # behind the player: the camera does not see it
    # Switching again (back, then to the frustum view once more) gives nothing more.
    seen = run(game, 1, Actions(presses=(("switch_camera", 1),))) + run(game, 90)
    seen += run(game, 1, Actions(presses=(("switch_camera", 1),))) + run(game, 60)
    assert not [ev for ev in seen if isinstance(ev, LootReleased) and ev.entity == enemy(game, "carrier").id]


@pytest.mark.parametrize("z, freed", [(11.5, True), (12.5, False)])
def test_the_camera_frees_loot_exactly_when_its_rule_says(tmp_path, monkeypatch, z, freed):
    """The rule (:func:`enemy_system._frustum_holds`): ahead of the player and within 12 m of
    the eye; then the crystal comes out on the tick its w first comes within its size of the
    player's slice, never earlier."""
    monkeypatch.setattr(en, "DRIFT", np.zeros(4))
    body = f"""
[camera]
frustum = true
frustum_cost = 0.0
[[enemy]]
name = "carrier"
kind = "morph"
position = [0.0, 1.6, {z}, 1.6]
health = 1
loot = 5.0
sight = 1.0
"""
    game = Game(hall().load(tmp_path, extra=body + GUN))
    run(game, 30)
    foe = enemy(game, "carrier").data
    eid = enemy(game, "carrier").id
    seen = run(game, 1, Actions(presses=(("switch_camera", 1),)))
    released_at = None
    for _ in range(80):
        off = foe.loot_point()[3] - game.player.position[3]
        events = run(game, 1)
        if any(isinstance(ev, LootReleased) for ev in events):
            released_at = (off, foe.loot_point()[3] - game.player.position[3])
        seen += events
    loot = [ev for ev in seen if isinstance(ev, LootReleased)]
    if not freed:
        assert loot == [] and foe.centre[3] == pytest.approx(1.6)
        return
    assert [(ev.entity, ev.reason) for ev in loot] == [(eid, "camera")]
    before, now = released_at
    # The release tick: outside the crystal's size before it, within it (or across) after.
    assert abs(before) > en.LOOT_SIZE and (abs(now) <= en.LOOT_SIZE or before * now < 0)


# ------------------------------------------------------------------ health, death, determinism
def test_a_player_who_stands_still_dies_and_comes_back_at_the_start():
    game = Game(load_level(HIVE))
    seen = run(game, 60 * TICK_RATE)
    kinds = [ev.kind for ev in seen]
    assert kinds.count("player_hit") >= 7
    assert kinds.count("player_died") >= 1
    # Died at the spawn point and came back there (no checkpoint touched).
    assert game.states.health.deaths == kinds.count("player_died")
    assert game.player.position[2] == pytest.approx(-20.0, abs=0.01)


def test_death_restarts_at_the_last_checkpoint_and_keeps_progress():
    game = Game(load_level(HIVE))
    run(game, 1)
    game.player.position[:] = [0.0, 0.0, -1.0, 0.0]  # on the checkpoint pad
    seen = run(game, 1)
    assert [ev.name for ev in seen if ev.kind == "checkpoint_reached"] == ["midway"]
    drone = enemy(game, "drone")
    enemy_system._defeat(game, drone)
    run(game, 60)
    game.energy.gain(7000)
    energy = game.energy.milli
    game.player.position[:] = [2.0, 0.0, 8.0, 0.3]
    game.states.health.value = 10.0
    assert hp.damage(game, 15.0, [2.0, 12.0], -1)
    assert game.event_counts["player_died"] == 1
    assert list(game.player.position) == [0.0, 0.0, -1.0, 0.0]
    assert game.states.health.value == 100.0
    assert game.energy.milli == energy  # nothing won is lost
    assert game.states.enemies.defeated == 1 and game.entities.get(drone.id) is None
    assert not hp.damage(game, 15.0, [0.0, 5.0], -1)  # safe for a moment after coming back
    frame = game.frame()
    assert "checkpoint 'midway'" in frame.hud.message
    assert frame.hud.health.safe


def test_continuing_a_save_starts_at_its_checkpoint_and_refuses_one_the_level_lacks():
    game = Game(load_level(HIVE))
    assert game.checkpoint is None  # nothing reached yet: a save continues at the start
    game.restart_at_checkpoint(0)
    assert game.checkpoint == 0 and list(game.player.position) == [0.0, 0.0, -1.0, 0.0]
    with pytest.raises(IndexError):
        game.restart_at_checkpoint(len(game.level.checkpoints))
    plain = Game(load_level(resolve_level("01_first_steps")))
    assert plain.checkpoint is None
    with pytest.raises(ValueError):
        plain.restart_at_checkpoint(0)


def test_falling_out_of_the_level_comes_back_at_the_last_checkpoint():
    game = Game(load_level(HIVE))
    run(game, 1)
    game.player.position[:] = [0.0, 0.0, -1.0, 0.0]  # on the checkpoint pad
    run(game, 1)
    game.player.position[:] = [0.0, -60.0, 5.0, 0.0]  # far below every floor
    seen = run(game, 1)
    assert [ev.kind for ev in seen if ev.kind == "respawned"] == ["respawned"]
    assert list(game.player.position) == [0.0, 0.0, -1.0, 0.0]


def test_enemies_rng_draws_are_in_the_state_hash_and_runs_repeat():
    lv = load_level(HIVE)
    a, b, c = Game(lv, seed=3), Game(lv, seed=3), Game(lv, seed=4)
    for _ in range(4 * TICK_RATE):
        for g in (a, b, c):
            g.step(Actions())
    assert a.state_hash() == b.state_hash()
    pa = [e.data.centre for e in a.entities.of_kind("enemy")]
    pc = [e.data.centre for e in c.entities.of_kind("enemy")]
    assert not all(np.array_equal(x, y) for x, y in zip(pa, pc))  # the drift comes from the seed
    # One extra draw by an enemy changes the hash; so does any change to an enemy's state.
    b.rng.uniform()
    assert a.state_hash() != b.state_hash()
    b2 = Game(lv, seed=3)
    for _ in range(4 * TICK_RATE):
        b2.step(Actions())
    assert b2.state_hash() == a.state_hash()
    enemy(b2).data.next_shot += 1
    assert b2.state_hash() != a.state_hash()


def test_levels_without_enemies_have_no_hive_and_no_health():
    game = Game(load_level(levels_dir() / "04_armory.toml"))
    run(game, 5)
    assert game.states.enemies is None and game.states.health is None
    assert not game.entities.of_kind("enemy") and game.frame().hud.health is None


# ------------------------------------------------------------------ level entries and HUD
BAD = [
    ('kind = "dragon"\nposition = [0, 1, 5, 0]', "field 'kind': expected one of swarm, morph, got 'dragon'"),
    ('kind = "swarm"\nposition = [0, 1, 5, 0]\nhealth = 0', "field 'health': expected a number > 0, got 0"),
    ('kind = "swarm"\nposition = [0, 1, 5, 0]\nanimation = "wave"', "field 'animation': 'wave' has no keyframes"),
    ('kind = "morph"\nposition = [0, 1, 5, 0]\nasset = "../levels/01_first_steps.toml"', "field 'asset':"),
]


@pytest.mark.parametrize(("entry", "message"), BAD)
def test_bad_enemy_entries_are_one_line_each(tmp_path, entry, message):
    path = hall().write(tmp_path, "bad.toml", extra=f'[[enemy]]\nname = "x"\n{entry}\n')
    with pytest.raises(LevelError) as err:
        load_level(path)
    lines = err.value.problems
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"{path}: [[enemy]] #1 'x': ")
    assert message in lines[0]


def test_hud_draws_health_flash_and_the_damage_direction():
    from across_dimensions.render.hud import HudMetrics, damage_cue_points, health_bar_rect, hud_quads

    base = hud_quads(Hud(), 640, 360)
    hurt = hud_quads(Hud(health=HealthGauge(40.0, 100.0, 1.0), damage_flash=1.0, damage_dir=np.pi / 2), 640, 360)
    assert len(hurt) > len(base)
    # A red frame round the view, drawn first: its outer band touches every edge, its centre is clear.
    from across_dimensions.render.hud import DAMAGE_FLASH_COLOR

    red = hurt[np.isclose(hurt[:, 8], DAMAGE_FLASH_COLOR[0]) & np.isclose(hurt[:, 9], DAMAGE_FLASH_COLOR[1])]
    assert len(red) and red[:, 0].min() == 0 and red[:, 1].min() == 0
    assert (red[:, 0] + red[:, 2]).max() == 640 and (red[:, 1] + red[:, 3]).max() == 360
    centre = (red[:, 0] <= 320) & (red[:, 0] + red[:, 2] >= 320) & (red[:, 1] <= 180) & (red[:, 1] + red[:, 3] >= 180)
    assert not centre.any()
    assert red[:, 2:4].prod(axis=1).sum() < 0.35 * 640 * 360  # a frame, not a wash
    x, y, w, h = health_bar_rect(HudMetrics(640, 360))
    assert any(r[0] == x - 1 and r[1] == y - 1 for r in hurt)  # the bar's outline
    right = damage_cue_points(np.pi / 2, HudMetrics(640, 360))
    assert all(px > 320 for px, _ in right)  # a hit from the right is marked right of the crosshair
    behind = damage_cue_points(np.pi, HudMetrics(640, 360))
    assert all(py > 180 for _, py in behind)  # from behind: below it


def test_hive_replay_finishes_with_enemies_defeated():
    replay = levels_dir() / "replays" / "09_hive.json"
    if not replay.exists():
        pytest.skip("the Hive's replay is recorded in the window")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "replay", str(HIVE), str(replay), "--json"],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout)
    assert summary["outcome"] == "complete"
    assert summary["divergence"] is None
    assert summary["events"]["enemy_defeated"] >= 3
    assert summary["events"]["enemy_hit"] >= summary["events"]["enemy_defeated"]


def test_the_level_readme_example_loads_and_plays(tmp_path):
    import re

    text = (ROOT / "levels" / "README.md").read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"^```toml\n(.*?)^```", text, re.S | re.M) if 'name = "Warden"' in b)
    path = tmp_path / "warden.toml"
    path.write_text(block, encoding="utf-8")
    game = Game(load_level(path))
    run(game, 2)
    warden = enemy(game)
    assert warden.data.spec.weak_spot is not None and [k.time for k in warden.data.keys] == [0.0, 2.0, 4.0]
    assert [c.name for c in game.level.checkpoints] == ["midway"]


def test_enemy_shots_stop_at_the_gate_a_solid_4d_object():
    game = Game(load_level(HIVE))
    game.step(Actions())
    # The gate spans x in [-4.5, 4.5], z in [15.8, 16.2] at every w of the level.
    assert enemy_system._through_solid(game, np.array([0.0, 1.5, 15.0, 0.0]), np.array([0.0, 1.5, 17.0, 0.0]))
    assert not enemy_system._through_solid(game, np.array([0.0, 1.5, 12.0, 0.0]), np.array([0.0, 1.5, 14.0, 0.0]))
