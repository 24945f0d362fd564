"""Weapons through play: the 120-cell gun's bullets, the blast, the field, targets, and their level tables."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import Actions
from across_dimensions.game.events import BulletHit, WeaponRefused
from across_dimensions.game.sim import Game
from across_dimensions.physics import BodyDef, PhysicsWorld
from across_dimensions.render.hud import hud_quads
from across_dimensions.world.level import LevelError, load_level

REPO = Path(__file__).resolve().parents[1]
ARMORY = REPO / "levels" / "04_armory.toml"
BLAST_FIELD = REPO / "levels" / "05_blast_and_field.toml"  # the gun, the blast and the field

GRAVITY = (0.0, -9.81, 0.0, 0.0)


def hall(gravity=GRAVITY) -> LevelBuilder:
    """A range 80 m long, the player 8 m behind the middle."""
    return LevelBuilder(
        "range", spawn=(0.0, 0.0, -8.0, 0.0), goal=(0.0, 1.0, 30.0), goal_size=(2.0, 2.0, 2.0), floor=(20.0, 1.0, 80.0)
    ).table("physics", gravity=list(gravity))


def gun(cooldown=0.0, amplitude=0.6, period=2.0, lifetime=6.0, max_live=8, cost=0.0, **more) -> dict:
    """The fields of a ``[[weapon]]`` gun."""
    return dict(
        cost=cost,
        cooldown=cooldown,
        speed=10.0,
        amplitude=amplitude,
        period=period,
        size=0.15,
        mass=0.5,
        lifetime=lifetime,
        max_live=max_live,
        **more,
    )


def level(tmp_path, extra="", gravity=GRAVITY, name="range.toml", **fields):
    """The range with a gun of ``fields`` and ``extra`` (entries as TOML), loaded."""
    return hall(gravity).weapon("gun", **gun(**fields)).load(tmp_path, name, extra=extra)


FIRE = Actions(presses=(("fire", 1),))


def bullet_of(game):
    (eid,) = game.states.weapons.bullets
    return game.entities.get(eid)


# ------------------------------------------------------------------ the gun
def test_bullet_w_follows_the_sine_until_its_first_contact(tmp_path):
    # A hypercube 6 m ahead stops the bullet; until then its w is the weapon's sine about the
    # player's w at firing, to rounding (the steering cancels the in-tick gravity drop exactly).
    cube = """
[[object]]
name = "cube"
shape = "tesseract"
position = [0.0, 1.0, 0.0, 0.0]
scale = 2.0
body = "hypercube"
mass = 3.0
"""
    game = Game(level(tmp_path, cube, amplitude=0.3, period=1.5))
    game.step(Actions())
    game.step(FIRE)
    e = bullet_of(game)
    b = e.data
    checked = 0
    for _ in range(120):
        if b.contacted:
            break
        k = game.tick - b.born
        w = game.physics.body_position(e.motion.body)[3]
        want = b.w0 + 0.3 * np.sin(2 * np.pi * k * game.dt / 1.5)
        assert w == pytest.approx(want, abs=1e-9)  # rounding of a few hundred float ops
        checked += 1
        game.step(Actions())
    assert checked > 30


def test_bullet_hitting_a_resting_hypercube_off_centre_turns_it_in_a_w_plane(tmp_path):
    # The cube rests on the floor at w = -0.3; the bullet reaches it near w = 0 (amplitude 0.02),
    # so the contact is 0.3 off the cube's centre along w and the push turns it in xw, yw or zw.
    cube = """
[[object]]
name = "cube"
shape = "tesseract"
position = [0.0, 1.0, -3.0, -0.3]
scale = 2.0
body = "hypercube"
mass = 3.0
"""
    game = Game(level(tmp_path, cube, amplitude=0.02, period=4.0))
    for _ in range(60):  # let it settle and sleep
        game.step(Actions())
    target = game.entities.named("cube")
    game.step(FIRE)
    hit = []
    for _ in range(120):
        game.step(Actions())
        hit += [ev for ev in game.events if isinstance(ev, BulletHit) and ev.what == "body"]
        if hit:
            break
    assert hit and hit[0].other == target.id
    game.step(Actions())
    _, omega = game.physics.body_velocity(target.motion.body)
    w_planes = np.abs(omega[3:]).max()  # xw, yw, zw
    assert w_planes > 0.05, omega


def test_momentum_is_conserved_in_a_bullet_body_collision(tmp_path):
    # Zero gravity, a cube floating in the bullet's path: the bullet's commanded momentum plus
    # the cube's before the contact tick equals both after it.
    cube = """
[[object]]
name = "cube"
shape = "tesseract"
position = [0.1, 1.6, -3.0, 0.05]
scale = 0.8
body = "hypercube"
mass = 2.0
"""
    game = Game(level(tmp_path, cube, gravity=(0.0, 0.0, 0.0, 0.0), amplitude=0.1, period=3.0))
    game.step(Actions())
    game.step(FIRE)
    e = bullet_of(game)
    c = game.entities.named("cube")
    phys = game.physics
    for _ in range(120):
        b = e.data
        k = game.tick - b.born + 1
        v_cmd = (b.planned(k, game.dt) - phys.body_position(e.motion.body)) / game.dt
        before = b.spec.mass * v_cmd + phys.body_mass(c.motion.body) * phys.body_velocity(c.motion.body)[0]
        game.step(Actions())
        if b.contacted:
            break
    assert b.contacted
    after = b.spec.mass * phys.body_velocity(e.motion.body)[0]
    after = after + phys.body_mass(c.motion.body) * phys.body_velocity(c.motion.body)[0]
    # The solver exchanges equal and opposite impulses; only rounding separates the sums.
    assert np.allclose(after, before, atol=1e-9 * np.abs(before).max() + 1e-12)
    assert np.linalg.norm(phys.body_velocity(c.motion.body)[0]) > 0.1  # and it did push


def test_bullet_cap_and_lifetime_hold_with_bounded_memory(tmp_path):
    # Fire every tick for a simulated minute (the 10-minute run is the slow test below):
    # never more than max_live, none older than its lifetime, physics arrays bounded.
    game = Game(level(tmp_path, max_live=5, lifetime=1.0))
    caps = set()
    for _ in range(60 * 60):
        game.step(FIRE)
        live = [game.entities.get(i) for i in game.states.weapons.bullets]
        assert len(live) <= 5
        assert all((game.tick - b.data.born) * game.dt <= 1.0 + 1e-9 for b in live)
        caps.add(game.physics.bodies.alive.shape[0])
    assert game.physics.bodies.count <= 16 and caps == {16}
    assert len(game.entities) <= 5 + 1  # the bullets and nothing left behind


@pytest.mark.slow
def test_ten_minutes_of_firing_keep_arrays_bounded(tmp_path):
    game = Game(level(tmp_path, max_live=8, lifetime=2.0, cooldown=0.1))
    for _ in range(10 * 60 * 60):
        game.step(FIRE)
        assert len(game.states.weapons.bullets) <= 8
    assert game.physics.bodies.alive.shape[0] == 16
    assert game.physics.warm.key.shape[0] <= 1024


def test_firing_is_deterministic():
    lv = load_level(ARMORY)
    script = [
        Actions(forward=0.5, yaw=0.003 * (i % 7), presses=(("fire", 1),) if i % 20 == 0 else ()) for i in range(400)
    ]

    def run():
        g = Game(lv)
        hashes = []
        for a in script:
            g.step(a)
            hashes.append(g.state_hash())
        return hashes, dict(g.event_counts)

    assert run() == run()


def test_not_enough_energy_is_a_visible_cue_not_silence():
    game = Game(load_level(ARMORY, arsenal=["gun"]))
    game.energy.milli = 500  # half a unit; a shot costs 1
    game.step(FIRE)
    refused = [e for e in game.events if isinstance(e, WeaponRefused)]
    assert [(e.weapon, e.reason) for e in refused] == [("gun", "energy")]
    assert game.states.weapons.bullets == []
    assert game.frame().hud.weapon.refused == "NOT ENOUGH ENERGY"


def test_weapons_switch_by_next_previous_and_number_keys():
    game = Game(load_level(BLAST_FIELD, arsenal=["gun", "blast", "field"]))
    slots = []
    for p in ("next_weapon", "next_weapon", "next_weapon", "previous_weapon", "weapon_3", "weapon_1"):
        game.step(Actions(presses=((p, 1),)))
        slots.append(game.states.weapons.slot)
    assert slots == [1, 2, 0, 2, 2, 0]
    assert game.frame().hud.weapon.name == "120-cell gun"


def test_hud_draws_the_weapon_panel():
    game = Game(load_level(ARMORY, arsenal=["gun"]))
    game.step(FIRE)
    hud = game.frame().hud
    assert hud.weapon.cooldown == pytest.approx(1.0 - 1 / round(0.35 * 60), abs=1e-9)
    with_panel = hud_quads(hud, 1280, 720)
    hud.weapon = None
    assert len(with_panel) > len(hud_quads(hud, 1280, 720))


# ------------------------------------------------------------------ blast and field
SCATTER = """
[[weapon]]
kind = "blast"
cost = 0.0
radius = 5.0
duration = 0.5

[[weapon]]
kind = "field"
cost = 0.0
radius = 5.0
duration = 2.0

[[object]]
name = "near spinning"
shape = "24-cell"
position = [2.0, 1.5, -6.0, 0.7]
scale = 0.4
spin = {{ xw = 40.0 }}
solid = false

[[object]]
name = "near kata"
shape = "5-cell"
position = [-1.0, 1.0, -4.5, -0.8]
scale = 0.4
solid = false

[[object]]
name = "near body"
shape = "tesseract"
position = [0.0, 0.36, -5.0, 0.6]
scale = 0.7
body = "hypercube"

[[object]]
name = "far"
shape = "5-cell"
position = [0.0, 1.0, 2.0, 0.5]
scale = 0.4
solid = false

[[object]]
name = "far body"
shape = "tesseract"
position = [3.0, 0.36, 1.0, -0.5]
scale = 0.7
body = "hypercube"
"""


def scatter(tmp_path):
    # No gun: the physics world is the level's own (two bodies).
    return Game(hall().load(tmp_path, "scatter.toml", extra=SCATTER.format()))


def test_blast_brings_everything_in_its_radius_to_the_players_w_and_nothing_else(tmp_path):
    game = scatter(tmp_path)
    for _ in range(30):
        game.step(Actions(w=0.5))  # the player moves to w = 0.25 and stays
    for _ in range(60):
        game.step(Actions())
    w = float(game.player.position[3])
    assert w > 0.2
    far = {n: game.entities.named(n).center(game).copy() for n in ("far", "far body")}
    before = {n: game.entities.named(n).center(game)[3] for n in ("near spinning", "near kata", "near body")}
    game.step(Actions(presses=(("fire", 1),)))
    (blast,) = [e for e in game.events if e.kind == "blast"]
    assert {game.entities.get(i).name for i in blast.moved} == set(before)
    # Smooth, not a teleport: after one tick nothing has arrived.
    for n, w0 in before.items():
        assert abs(game.entities.named(n).center(game)[3] - w) > 0.5 * abs(w0 - w)
    for _ in range(90):
        game.step(Actions())
    for n in before:
        assert game.entities.named(n).center(game)[3] == pytest.approx(w, abs=0.01), n  # 1 cm
    for n, c in far.items():
        assert np.array_equal(game.entities.named(n).center(game), c), n
    # The body was moved, not frozen: it still rests under gravity with its physics running.
    body = game.entities.named("near body")
    assert game.physics.body_kind(body.motion.body) == "dynamic"
    assert game.physics.body_position(body.motion.body)[1] == pytest.approx(0.35, abs=0.03)


def test_what_the_blast_brings_is_drawn_as_soon_as_it_reaches_the_slice():
    """Blast and Field: the kata switch pulled to the player's w shows at once, before anything
    else comes or goes (nothing is fired at it yet)."""
    game = Game(load_level(BLAST_FIELD))
    for _ in range(120):
        game.step(Actions(forward=1.0))  # to the blue door; the switch is 1.5 m behind
    switch = game.entities.named("kata switch")

    def drawn() -> bool:
        return any(f"entity:{switch.id}" in b.members for b in game.frame().batches)

    assert not drawn()  # far kata
    game.step(Actions(presses=(("weapon_2", 1),)))
    game.step(Actions(presses=(("fire", 1),)))
    version = game.entities.version
    for _ in range(60):
        game.step(Actions())
    assert switch.center(game)[3] == pytest.approx(0.0, abs=0.01)
    assert game.entities.version == version and drawn()


def test_field_turns_exactly_the_objects_in_its_radius_to_wireframe_and_back(tmp_path):
    game = scatter(tmp_path)
    styles = {e.name: e.style for e in game.entities}
    game.step(Actions(presses=(("weapon_3", 1),)))  # the field's key, whatever else is owned
    game.step(Actions(presses=(("fire", 1),)))
    (field,) = [e for e in game.events if e.kind == "field"]
    wired = {e.name for e in game.entities if e.style == "wire"}
    assert wired == {"near spinning", "near kata", "near body"}
    assert {game.entities.get(i).name for i in field.shown} == wired
    for _ in range(field.ticks - 1):
        game.step(Actions())
    assert {e.name for e in game.entities if e.style == "wire"} == wired  # still on at its last tick
    game.step(Actions())
    assert {e.name: e.style for e in game.entities} == styles


# ------------------------------------------------------------------ targets and the level
def test_target_out_of_reach_is_hit_only_by_the_bullets_swing(tmp_path):
    target = """
[[target]]
name = "switch"
position = [0.0, 1.6, -3.0, 0.6]
size = 0.3
opens = "door"

[[object]]
name = "door"
shape = "tesseract"
position = [0.0, 2.0, 5.0, 0.0]
scale = [9.0, 4.0, 0.4, 3.0]
"""
    # Amplitude 0.6 at a period of 2 s and 10 m/s: the bullet is at w = 0.6 five metres out, so
    # the switch 4.35 m from the muzzle (w 0.58) is hit; with amplitude 0.1 it never is.
    for amplitude, hits in ((0.6, 1), (0.1, 0)):
        game = Game(level(tmp_path, target, amplitude=amplitude, period=2.0, name=f"t{amplitude}.toml"))
        game.step(FIRE)
        counts = []
        for _ in range(120):
            game.step(Actions())
            counts += [e for e in game.events if e.kind == "target_hit"]
        assert len(counts) == hits
        assert (game.entities.named("door") is None) == bool(hits)


@pytest.mark.slow
def test_blast_and_field_replay_finishes_with_every_weapon_used():
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "across_dimensions",
            "replay",
            str(BLAST_FIELD),
            str(REPO / "levels" / "replays" / "05_blast_and_field.json"),
            "--json",
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout)
    assert summary["outcome"] == "complete"
    ev = summary["events"]
    assert ev["shot_fired"] >= 2 and ev["target_hit"] == 2 and ev["blast"] >= 1 and ev["field"] >= 1
    assert ev["weapon_acquired"] == 2  # the blast and the field, found on the way; the gun came from level 4


BAD = [
    ('[[weapon]]\nkind = "blast"\nradius = -2.0\n', "[[weapon]] #1: field 'radius': expected a number > 0, got -2.0"),
    ('[[weapon]]\nkind = "gun"\nperiod = 0\n', "[[weapon]] #1: field 'period': expected a number > 0, got 0"),
    ('[[weapon]]\nkind = "laser"\n', "[[weapon]] #1: field 'kind': expected one of gun, blast, field, got 'laser'"),
    ('[[weapon]]\nkind = "field"\nspeed = 3.0\n', "[[weapon]] #1: field 'speed' does not apply to a field"),
    (
        '[[target]]\nname = "s"\nposition = [0.0, 1.0, 0.0, 2.0]\nopens = "nothing"\n',
        "[[target]] #1 's': field 'opens': no [[object]] is named 'nothing'",
    ),
]


@pytest.mark.parametrize(("entry", "message"), BAD)
def test_bad_weapon_and_target_entries_are_one_line_each(tmp_path, entry, message):
    path = hall().write(tmp_path, "bad.toml", extra=entry)
    with pytest.raises(LevelError) as err:
        load_level(path)
    assert len(err.value.problems) == 1
    (line,) = err.value.problems
    assert line.startswith(f"{path}: ") and message in line


def test_check_level_reports_a_bad_weapon(tmp_path):
    path = hall().write(tmp_path, "bad.toml", extra=BAD[1][0] + BAD[0][0])
    out = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "check-level", str(path)], capture_output=True, text=True
    )
    assert out.returncode != 0
    text = out.stdout + out.stderr
    assert "[[weapon]] #1" in text and "[[weapon]] #2" in text


# ------------------------------------------------------------------ physics slot reuse
def test_removed_bodies_free_their_slots_lowest_first_without_stale_warm_starts():
    world = PhysicsWorld()
    ids = [world.add_body(BodyDef("hypersphere", radius=0.2, position=(i, 0.2, 0, 0))) for i in range(6)]
    for _ in range(30):
        world.tick()  # they rest on the ground: warm-start entries for each
    world.remove_body(ids[4])
    world.remove_body(ids[1])
    c = int(world.warm.count[0])
    pairs = world.warm.key[:c]
    assert not np.any((pairs >> 32) == 1) and not np.any((pairs >> 32) == 4)
    # A newcomer in the freed slot, exactly where the old ball rested: its touch is new
    # (``began``), not the old ball's touch carried on.
    assert world.add_body(BodyDef("hypersphere", radius=0.2, position=(1, 0.2, 0, 0))) == 1
    world.tick()
    mine = [e for e in world.events if e.a == 1]
    assert mine and mine[0].began
    assert world.add_body(BodyDef("hypersphere", radius=0.2, position=(-9, 2, 0, 0))) == 4
    assert world.add_body(BodyDef("hypersphere", radius=0.2, position=(9, 2, 0, 0))) == 6
    for _ in range(1000):
        b = world.add_body(BodyDef("hypersphere", radius=0.1, position=(0, 5, 0, 0)))
        world.tick()
        world.remove_body(b)
    assert b == 7 and world.bodies.count == 8 and world.bodies.alive.shape[0] == 16


def test_a_gun_with_ammunition_fires_rounds_and_crystals_refill_them(tmp_path):
    ammo = gun(amplitude=0.5, lifetime=1.0, cost=1.0, ammo=2, max_ammo=4, refill=3)
    level = hall().weapon("gun", **ammo).table("energy", start=5.0)
    game = Game(level.crystal([0.0, 1.0, -6.0, 0.0], name="refill", energy=1.0).load(tmp_path, "ammo.toml"))
    seen = []
    for _ in range(3):
        game.step(FIRE)
        seen += game.events
    assert [e.kind for e in seen if e.kind in ("shot_fired", "weapon_refused")] == [
        "shot_fired",
        "shot_fired",
        "weapon_refused",
    ]
    assert game.energy.milli == 5000  # rounds, not energy
    assert game.frame().hud.weapon.refused == "OUT OF AMMO"
    for _ in range(40):  # walk into the crystal 2 m ahead
        game.step(Actions(forward=1.0))
    assert game.event_counts["crystal_collected"] == 1
    game.step(Actions())
    assert game.states.weapons.rounds == [3]  # 0 + 3, at most 4
    assert game.frame().hud.weapon.ammo == 3
