"""Seek: a key that moves the player along w to the nearest thing of interest (issue 18, point 3)."""

from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import Actions
from across_dimensions.game.events import EnergySpent, SeekArrived, SeekBlocked, SeekStarted
from across_dimensions.game.frame import Radar, RadarPin
from across_dimensions.game.sim import Game
from across_dimensions.game.systems import seek
from across_dimensions.render.radar import SOUGHT_COLOR, radar_geometry
from across_dimensions.world.level import load_level

DATA = Path(__file__).parent / "data"
SEEK = Actions(presses=(("seek", 1),))
JUMP = Actions(presses=(("seek_jump", 1),))


@pytest.fixture(scope="module")
def crystal_level():
    return load_level(DATA / "crystals.toml")


def run(game, first, ticks=240):
    """Press once, then idle until the seek ends; returns the events."""
    game.step(first)
    seen = list(game.events)
    for _ in range(ticks):
        if not game.states.seek.active:
            break
        game.step(Actions())
        seen += game.events
    return seen


def spent(events):
    return sum(e.milli for e in events if isinstance(e, EnergySpent) and e.reason == "w_move")


def test_seek_lands_exactly_on_the_nearest_things_w(crystal_level):
    game = Game(crystal_level)
    game.energy.gain(10_000)
    # "here" is in the slice already (w = 0): the nearest thing needing a move along w is
    # "regrows" (3 m away, w = -0.4) before "ana" (3 m away, w = 0.8).
    assert seek.candidates(game)[0] == game.entities.named("here").id
    seen = run(game, SEEK)
    target = game.entities.named("regrows")
    started = [e for e in seen if isinstance(e, SeekStarted)]
    assert [e.entity for e in started] == [target.id]
    assert [e.entity for e in seen if isinstance(e, SeekArrived)] == [target.id]
    assert game.player.position[3] == target.center(game)[3] == -0.4  # exactly, not approximately
    assert game.player.velocity[3] == 0.0, "nothing left to drift past it"
    # It glided: more than one tick, never past the target.
    assert 10 < sum(1 for e in seen if isinstance(e, EnergySpent)) < 60


def test_seek_costs_what_walking_there_along_w_costs(crystal_level):
    cost = crystal_level.energy.w_cost_milli  # 5000 milli per unit of w
    game = Game(crystal_level)
    game.energy.gain(10_000)
    events = run(game, SEEK)
    w = float(game.player.position[3])
    seek_paid = spent(events)
    ticks = sum(1 for e in events if isinstance(e, EnergySpent))
    # Both pay through one formula: ceil(travelled * cost) each tick, so the bill is the
    # distance's price plus under one milli of round-up per tick.
    assert abs(w) * cost <= seek_paid <= abs(w) * cost + ticks

    walker = Game(crystal_level)
    walker.energy.gain(10_000)
    walked, n = [], 0
    while walker.player.position[3] > w:
        walker.step(Actions(w=-1.0))
        walked += walker.events
        n += 1
    over = abs(float(walker.player.position[3]) - w)  # the walker cannot stop exactly: its overshoot
    walk_paid = spent(walked)
    assert abs(w) * cost <= walk_paid <= (abs(w) + over) * cost + n
    # Per unit of w the two prices agree to the round-up of one milli a tick.
    assert seek_paid / abs(w) == pytest.approx(walk_paid / (abs(w) + over), abs=(n + ticks) / abs(w))


def test_second_press_cycles_to_the_next_thing(crystal_level):
    game = Game(crystal_level)
    game.energy.gain(10_000)
    run(game, SEEK)
    first = game.entities.named("regrows").id
    assert seek.sought_id(game) == first
    events = run(game, SEEK)
    started = [e.entity for e in events if isinstance(e, SeekStarted)]
    assert started == [game.entities.named("ana").id]
    assert game.player.position[3] == 0.8
    # The radar highlights the pin being sought, and only that one.
    frame = game.frame()
    sought = [p for p in frame.radar.pins if p.sought]
    assert len(sought) == 1 and sought[0].kind == "crystal" and sought[0].height == pytest.approx(0.0)


def test_held_w_key_takes_over(crystal_level):
    game = Game(crystal_level)
    game.energy.gain(10_000)
    game.step(SEEK)
    game.step(Actions())
    game.step(Actions(w=1.0))
    assert not game.states.seek.active


def test_seek_jump_lands_in_one_tick_for_the_same_price(crystal_level):
    game = Game(crystal_level)
    game.energy.gain(10_000)
    before = game.energy.milli
    events = run(game, JUMP)
    assert game.player.position[3] == -0.4
    assert sum(1 for e in events if isinstance(e, EnergySpent)) == 1
    assert before - game.energy.milli == round(0.4 * crystal_level.energy.w_cost_milli)


def test_seek_stops_at_the_nearest_reachable_w_when_out_of_energy(crystal_level):
    game = Game(crystal_level)  # starts with 1.0 energy: 0.2 units of w at 5 per unit
    events = run(game, SEEK)
    blocked = [e for e in events if isinstance(e, SeekBlocked)]
    assert [e.reason for e in blocked] == ["energy"]
    assert game.energy.milli == 0
    # 1.0 energy buys 0.2 of w, less the round-up of under a milli per tick (about 12 ticks, 5000 a unit).
    assert -0.2 <= game.player.position[3] < -0.2 + 15 / crystal_level.energy.w_cost_milli
    assert "not enough energy" in game.frame().hud.message


def walled(crystal=(0.0, 1.0, 6.0, 1.0), name: str | None = "beyond") -> LevelBuilder:
    """A block round the player that exists only for w in (0.5, 1.5), the goal at w >= 1 and a
    crystal (named ``name``, by default past the block)."""
    block = {"center": [0.0, 1.0, 0.0], "size": [2.0, 2.0, 2.0]}
    level = LevelBuilder(
        "Seek wall",
        w_range=(-1.0, 1.5),
        goal=(0.0, 1.0, 40.0),
        goal_size=(2.0, 2.0, 2.0),
        goal_w=(1.0, 1.5),
        floor=(40.0, 1.0, 100.0),
    ).world(1.0, 1.0, name="block", profile="prism", boxes=[block])
    return level.crystal(crystal, **({} if name is None else {"name": name}))


def test_seek_blocked_by_a_wall_stops_just_short_and_says_so(tmp_path):
    path = walled().write(tmp_path, "walled.toml")
    for press in (SEEK, JUMP):
        game = Game(load_level(path))
        events = run(game, press)
        blocked = [e for e in events if isinstance(e, SeekBlocked)]
        assert [e.reason for e in blocked] == ["wall"]
        w = game.player.position[3]
        # The block appears past w = 0.5; a glide tick moves at most SEEK_SPEED / 60.
        assert 0.5 - 0.05 < w <= 0.5
        assert blocked[0].w == w
        assert "wall" in game.frame().hud.message


def test_seek_goes_to_the_goals_w(tmp_path):
    game = Game(walled([0, 1, 90, 0], name=None).load(tmp_path, "goal.toml"))
    game.player.position[:3] = [0.0, 0.0, 30.0]  # out of the block, near the goal
    events = run(game, SEEK)
    assert [e.entity for e in events if isinstance(e, SeekArrived)] == [-1]
    assert game.player.position[3] == 1.0


def test_level_can_disable_seek(tmp_path):
    game = Game(walled().table("seek", enabled=False).load(tmp_path, "noseek.toml"))
    game.step(SEEK)
    assert not game.states.seek.active and game.player.position[3] == 0.0
    assert "off in this level" in game.frame().hud.message


def test_seek_replays_identically(crystal_level):
    from across_dimensions.game.playback import play
    from across_dimensions.game.replay import ActionRuns, Replay

    frames = [Actions()] * 5 + [SEEK] + [Actions()] * 60 + [JUMP] + [Actions(forward=1.0)] * 30
    game = Game(crystal_level)
    for a in frames:
        game.step(a)
    rows = [Actions.from_row(a.to_row()) for a in frames]
    assert rows == frames
    runs = ActionRuns()
    for a in rows:
        runs.append(a)
    replay = Replay("crystals", crystal_level.source_hash, actions=runs)
    again = Game(crystal_level)
    play(replay, again, check=False)
    assert again.state_hash() == game.state_hash()


def test_radar_draws_rings_round_the_sought_pin():
    pins = [RadarPin("crystal", 0.2, 0.3, 0.4, False), RadarPin("body", -0.2, 0.1, 0.0, True, sought=True)]
    rings = radar_geometry(Radar(20.0, 1.0, pins)).instances["seen_ring"]
    bright = rings[np.all(np.abs(rings[:, 6:9] - SOUGHT_COLOR) < 1e-6, axis=1)]
    assert len(bright) == 2  # round the head and round the foot
    assert np.allclose(bright[:, 0], -0.2) and np.allclose(bright[:, 2], 0.1)
    plain = radar_geometry(Radar(20.0, 1.0, pins[:1])).instances.get("seen_ring")
    assert plain is None
