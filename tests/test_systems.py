"""The game's systems through play: crystals, energy, w movement, the radar, entities."""

from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import Actions
from across_dimensions.game.entities import Placed
from across_dimensions.game.events import CrystalCollected, EnergyEmpty, EnergySpent, WBlocked
from across_dimensions.game.sim import TICK_RATE, Game
from across_dimensions.world.level import load_level

DATA = Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def crystal_level():
    return load_level(DATA / "crystals.toml")


def walk_to(game, x, z, w_axis=0.0, ticks=600):
    """Steer towards (x, z) at the current w; returns the events seen on the way."""
    seen = []
    for _ in range(ticks):
        p = game.player.position
        d = np.array([x - p[0], z - p[2]])
        if np.hypot(*d) < 0.05:
            break
        want = np.arctan2(d[0], d[1])
        turn = (want - game.player.yaw + np.pi) % (2 * np.pi) - np.pi
        game.step(Actions(forward=float(min(1.0, np.hypot(*d))), yaw=float(turn), w=w_axis))
        seen += game.events
    return seen


def hold_w(game, direction, ticks):
    seen = []
    for _ in range(ticks):
        game.step(Actions(w=direction))
        seen += game.events
    return seen


def kinds(events):
    return [e.kind for e in events]


def test_crystal_is_collected_only_where_it_is_visible(crystal_level):
    game = Game(crystal_level)
    ana = game.entities.named("ana")
    # Walk right through it at w = 0: it lies at w = 0.8, out of the slice, so nothing happens.
    seen = walk_to(game, 3.0, 0.0)
    assert game.entities.get(ana.id) is ana
    assert not any(isinstance(e, CrystalCollected) and e.entity == ana.id for e in seen)
    # Same place, near its w: taken, once, for its energy.
    game.energy.gain(10_000)
    seen = hold_w(game, 1.0, 60)
    got = [e for e in seen if isinstance(e, CrystalCollected)]
    assert [e.entity for e in got] == [ana.id]
    assert got[0].milli == 5000
    assert game.entities.get(ana.id) is None
    # Standing there for longer never collects it again.
    seen = hold_w(game, 0.0, 120)
    assert not any(isinstance(e, CrystalCollected) and e.entity == ana.id for e in seen)


def test_w_movement_stops_at_zero_energy_and_resumes_after_a_pickup(crystal_level):
    game = Game(crystal_level)
    assert game.energy.milli == 1000  # start = 1, w_cost = 5: 0.2 of w
    seen = hold_w(game, 1.0, 120)
    assert game.energy.milli == 0
    assert game.player.position[3] == pytest.approx(0.2, abs=1e-3)
    assert kinds(seen).count("energy_empty") == 1
    blocked = [e for e in seen if isinstance(e, WBlocked)]
    assert [(e.reason, e.direction) for e in blocked] == [("energy", 1)]
    w_stuck = game.player.position[3]
    hold_w(game, 1.0, 60)
    assert game.player.position[3] == w_stuck  # still stuck
    assert game.frame().hud.energy.empty
    # The crystal at w = 0 (0.35 across in w) is visible from w = 0.2: take it and move on.
    seen = walk_to(game, 0.0, 3.0)
    assert "crystal_collected" in kinds(seen) and game.energy.milli == 3000
    assert not game.frame().hud.energy.empty
    hold_w(game, 1.0, 60)
    assert game.player.position[3] > w_stuck + 0.3


def test_energy_accounting_is_exact_over_a_long_random_run(crystal_level):
    game = Game(crystal_level)
    rng = np.random.default_rng(7)
    start = game.energy.milli
    gained = spent = empties = 0
    for t in range(4000):
        if t % 30 == 0:
            a = Actions(
                forward=float(rng.uniform(-1, 1)),
                right=float(rng.uniform(-1, 1)),
                yaw=float(rng.normal(0, 0.2)),
                w=float(rng.choice([-1.0, 0.0, 1.0])),
            )
        game.step(a)
        for e in game.events:
            if isinstance(e, CrystalCollected):
                gained += e.gained_milli
            elif isinstance(e, EnergySpent):
                assert e.milli > 0
                spent += e.milli
            elif isinstance(e, EnergyEmpty):
                empties += 1
        assert 0 <= game.energy.milli <= game.energy.maximum_milli
    assert start + gained - spent == game.energy.milli
    assert spent > 0 and gained > 0, "the run should both spend and collect"
    assert game.event_counts["energy_spent"] > 0


def test_regrowing_crystal_comes_back_as_a_new_entity(crystal_level):
    game = Game(crystal_level)
    game.energy.gain(10_000)
    hold_w(game, -1.0, 25)  # to about w = -0.4
    first = game.entities.named("regrows")
    seen = walk_to(game, -3.0, 0.0)
    assert first.id in [e.entity for e in seen if isinstance(e, CrystalCollected)]
    walk_to(game, 0.0, 0.0)
    hold_w(game, 0.0, TICK_RATE)  # respawn = 1 s
    again = game.entities.named("regrows")
    assert again is not None and again.id != first.id


def test_radar_pin_height_is_w_offset_times_scale(crystal_level):
    game = Game(crystal_level)
    game.energy.gain(10_000)
    hold_w(game, 1.0, 10)
    frame = game.frame()
    radar = frame.radar
    assert radar.range == 25.0 and radar.w_scale == 0.75
    w = game.player.position[3]
    crystals = game.entities.of_kind("crystal")
    assert len(radar.pins) == len(crystals) == 3
    want = sorted((e.model(game)[3, 4] - w) * 0.75 for e in crystals)
    assert sorted(p.height for p in radar.pins) == pytest.approx(want)
    # "here" is straight ahead of the player at w = 0: on the disc's forward axis, visible now.
    here = next(p for p in radar.pins if p.visible)
    assert here.x == pytest.approx(0.0, abs=1e-9) and here.z == pytest.approx(3.0 / 25.0, abs=1e-6)


def test_radar_turns_with_the_player(crystal_level):
    game = Game(crystal_level)
    game.step(Actions(yaw=np.pi / 2))  # face +x: the crystal at +x ("ana") is now ahead
    pins = game.frame().radar.pins
    ana_pin = max(pins, key=lambda p: p.height)
    assert ana_pin.z == pytest.approx(3.0 / 25.0, abs=1e-6) and abs(ana_pin.x) < 1e-6


def test_entity_ids_are_stable_and_never_reused(crystal_level):
    game = Game(crystal_level)
    ids = [e.id for e in game.entities]
    extra = [game.entities.spawn("marker", motion=Placed(np.eye(5))).id for _ in range(5)]
    game.remove(extra[1])
    game.remove(ids[0])
    assert game.entities.get(extra[1]) is None and game.entities.get(ids[0]) is None
    assert [e.id for e in game.entities] == ids[1:] + extra[:1] + extra[2:]
    newer = game.entities.spawn("marker").id
    assert newer > max(extra)


def test_state_hash_covers_entities_energy_and_rng(crystal_level):
    a, b = Game(crystal_level), Game(crystal_level)
    assert a.state_hash() == b.state_hash()
    b.energy.gain(1)
    assert a.state_hash() != b.state_hash()
    c = Game(crystal_level)
    c.remove(c.entities.named("here").id)
    assert a.state_hash() != c.state_hash()
    d = Game(crystal_level)
    d.rng.random()
    assert a.state_hash() != d.state_hash()


def test_levels_without_energy_move_freely(level_path=None):
    from across_dimensions.world.resources import levels_dir

    game = Game(load_level(levels_dir() / "01_first_steps.toml"))
    assert game.energy is None and game.frame().hud.energy is None
    hold_w(game, 1.0, 30)
    assert game.player.position[3] > 0.2


# ---- the shipped crystal level ------------------------------------------------
def crystal_cache():
    from across_dimensions.world.resources import levels_dir

    return Game(load_level(levels_dir() / "02_crystal_cache.toml"))


def test_crystal_cache_needs_the_hidden_crystal():
    game = crystal_cache()
    walk_to(game, 0.0, -5.5)  # the crystal in plain sight: 2 energy, half a unit of w
    assert game.energy.value == 2.0
    hold_w(game, 1.0, 120)
    assert game.player.position[3] < 0.8  # not enough to get past the blue wall
    walk_to(game, 0.0, 12.0, ticks=600)
    assert game.outcome is None and game.player.position[2] < 3.0  # stopped at the wall
    # The visible crystal grows back, but the bar holds 3, less than the 3.2 the wall's end costs.
    game = crystal_cache()
    walk_to(game, 0.0, -5.5)
    for _ in range(16 * TICK_RATE):  # standing where it grows back takes it again
        game.step(Actions())
    assert game.energy.value == 3.0 and game.event_counts["crystal_collected"] == 2
    hold_w(game, 1.0, 120)
    assert game.player.position[3] == pytest.approx(0.75, abs=0.01)  # 3 / 4, short of 0.8
    walk_to(game, 0.0, 12.0, ticks=600)
    assert game.outcome is None and game.player.position[2] < 3.0


def test_crystal_cache_route_by_the_radar():
    game = crystal_cache()
    walk_to(game, 0.0, -5.5)
    ana = max(game.frame().radar.pins, key=lambda p: p.height)
    assert ana.kind == "crystal" and ana.height > 0 and not ana.visible  # a pin above the disc: go ana
    hold_w(game, 1.0, 11)
    walk_to(game, -3.0, -3.0)
    assert game.energy.value == 3.0  # the cache fills the bar: 1.2 of it takes the player on to w = 0.8
    walk_to(game, 0.0, 0.0)
    hold_w(game, 1.0, 60)
    walk_to(game, 0.0, 12.0, ticks=900)
    assert game.outcome == "complete"


def test_crystal_cache_running_dry_is_recoverable():
    game = crystal_cache()
    walk_to(game, 0.0, -5.5)
    hold_w(game, -1.0, 120)  # the wrong way: spend it all going kata
    assert game.energy.milli == 0 and game.event_counts["energy_empty"] == 1
    walk_to(game, 3.0, -3.0)  # the kata crystal is visible from here
    assert game.energy.milli > 0
    hold_w(game, 1.0, 120)  # back towards ana as far as it pays
    walk_to(game, -3.0, -3.0)
    walk_to(game, 0.0, -5.5)  # "first light" has grown back meanwhile, or will
    for _ in range(20 * TICK_RATE):
        if game.entities.named("first light") is None:
            game.step(Actions())
        else:
            break
    walk_to(game, 0.0, -5.5)
    hold_w(game, 1.0, 120)
    walk_to(game, 0.0, 12.0, ticks=900)
    assert game.outcome == "complete", (game.player.position, game.energy.value)


# ---- the format-2 example in levels/README.md ----------------------------------
def test_readme_energy_example_plays_to_the_exit(tmp_path):
    import re

    readme = (Path(__file__).parent.parent / "levels" / "README.md").read_text(encoding="utf-8")
    (block,) = [b for b in re.findall(r"^```toml\n(.*?)^```", readme, re.S | re.M) if "Energy example" in b]
    path = tmp_path / "energy_example.toml"
    path.write_text(block, encoding="utf-8")
    game = Game(load_level(path))
    assert game.energy.milli == 0 and game.frame().radar.range == 12.0
    hold_w(game, 1.0, 60)
    assert game.player.position[3] == 0.0  # no energy: no w
    walk_to(game, 0.0, -2.0)  # the crystal in sight
    assert game.energy.value == 3.0
    hold_w(game, 1.0, 40)  # to w = 0.6 and a bit: 0.75 of w affordable
    walk_to(game, 0.0, 2.0)  # the ana crystal, visible now
    assert game.event_counts["crystal_collected"] == 2
    walk_to(game, 0.0, 6.0)
    assert game.outcome == "complete"


def test_player_settings_scale_and_hide_the_radar(crystal_level):
    from across_dimensions.game.sim import RadarView

    game = Game(crystal_level)
    game.energy.gain(10_000)
    hold_w(game, 1.0, 10)
    base = game.frame().radar
    game.radar_view = RadarView(True, range_scale=2.0, height_scale=0.5)
    scaled = game.frame().radar
    assert scaled.range == 2 * base.range and scaled.w_scale == 0.5 * base.w_scale
    assert sorted(p.height for p in scaled.pins) == pytest.approx(sorted(0.5 * p.height for p in base.pins))
    assert sorted(p.z for p in scaled.pins) == pytest.approx(sorted(0.5 * p.z for p in base.pins))
    game.radar_view = RadarView(False)
    assert game.frame().radar is None


def test_ten_thousand_spawned_and_removed_entities_leave_the_physics_arrays_bounded():
    """Entities come and go all game long (bullets, crystals growing back): removing one frees
    its rigid body's slot, so the physics arrays stop growing."""
    from across_dimensions.game.entities import Rigid
    from across_dimensions.physics import BodyDef
    from across_dimensions.world.resources import levels_dir

    game = Game(load_level(levels_dir() / "03_tumbling_hall.toml"))
    start_capacity = game.physics.bodies.alive.shape[0]
    live = []
    for k in range(10_000):
        body = game.physics.add_body(BodyDef("hypersphere", radius=0.1, position=(k % 7 - 3.0, 3.0, 0.0, 0.0)))
        e = game.entities.spawn("bullet", motion=Rigid(body, np.ones(4)))
        game.entity_of_body[body] = e.id
        live.append(e.id)
        if len(live) > 5:  # a few live at a time, as a gun's bullets are
            game.remove(live.pop(0))
        if k % 50 == 0:
            game.step(Actions())
    assert game.physics.bodies.alive.shape[0] <= max(start_capacity, 64)
    assert len(game.entities) < 40 and game.entities.next_id > 10_000


def test_a_bad_crystal_reports_every_problem_at_once(tmp_path):
    from across_dimensions.world.level import LevelError

    level = LevelBuilder(w_range=None, spawn=(0, 0, 0, 0), goal=(0, 1, 5), goal_size=(1, 1, 1), floor=None)
    path = level.table("radar", range=0).crystal([0, 1, 2, 9.0], energy=-1).write(tmp_path, "bad.toml")
    with pytest.raises(LevelError) as e:
        load_level(path)
    problems = e.value.problems
    assert len(problems) == 3 and all(p.startswith(f"{path}: ") for p in problems)
    assert any("[radar]: field 'range'" in p for p in problems)
    assert any("'energy': expected a number > 0" in p for p in problems)
    assert any("w = 9 is outside the level's w_range [-1, 1]" in p for p in problems)
