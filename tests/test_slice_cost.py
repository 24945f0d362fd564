"""What 4D actions cost: the slice turn paid through the energy bar (``[energy] slice_cost``),
the grace before a w move's first payment, and exact accounting of both."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import Actions
from across_dimensions.game.events import EnergySpent, SliceTurnUnpaid
from across_dimensions.game.sim import Game
from across_dimensions.game.slice_pay import step_price
from across_dimensions.game.systems.energy import cost_line
from across_dimensions.game.systems.player import W_GRACE
from across_dimensions.world.level import LevelError, load_level

ROOT = Path(__file__).resolve().parents[1]
STEP = Actions(presses=(("step_zw_pos", 1),))


@pytest.fixture(scope="module")
def turn_level(tmp_path_factory):
    """A room whose slice turns at 60 degrees/s for 0.05 a degree (4.5 a step), w costs 2 a unit."""
    return (
        LevelBuilder(w_range=(-0.5, 0.5))
        .table("energy", start=0.0, max=10.0, w_cost=2.0, slice_cost=0.05)
        .table("camera", turn=True, turn_speed=60.0)
        .load(tmp_path_factory.mktemp("turn"))
    )


def _run(game: Game, n: int, **kw) -> list:
    seen = []
    for _ in range(n):
        game.step(Actions(**kw))
        seen += game.events
    return seen


def _spent(events) -> int:
    return sum(e.milli for e in events if isinstance(e, EnergySpent))


def test_a_slice_turn_with_an_empty_bar_does_not_turn(turn_level):
    game = Game(turn_level)
    assert game.energy.milli == 0
    game.step(STEP)
    seen = list(game.events) + _run(game, 90)
    seen += _run(game, 60, turn_zw_pos=True)
    assert game.camera.aligned and game.camera.angles_deg() == (0.0, 0.0, 0.0)
    unpaid = [e for e in seen if isinstance(e, SliceTurnUnpaid)]
    assert [(e.need, e.have) for e in unpaid] == [(4500, 0), (4500, 0)]  # the step, then the held key once
    assert "costs 4.5 energy" in game.frame().hud.message


def test_a_step_costs_its_price_exactly_and_one_short_of_it_is_refused(turn_level):
    game = Game(turn_level)
    game.energy.gain(4499)
    game.step(STEP)
    _run(game, 60)
    assert game.camera.aligned and game.energy.milli == 4499  # refused whole, nothing paid
    game.energy.gain(1)
    game.step(STEP)
    seen = list(game.events) + _run(game, 60)
    assert game.camera.angles_deg() == pytest.approx((0.0, 0.0, 90.0))
    assert _spent(seen) == 4500 == step_price(50) and game.energy.milli == 0
    assert {e.reason for e in seen if isinstance(e, EnergySpent)} == {"slice_turn"}


def test_a_held_turn_stops_where_the_bar_runs_dry_and_turning_back_is_free(turn_level):
    game = Game(turn_level)
    game.energy.gain(1000)  # 20 degrees' worth
    seen = _run(game, 60, turn_zw_pos=True)  # a second held: 60 degrees wanted
    assert game.camera.angles_deg()[2] == pytest.approx(20.0, abs=1e-6)
    assert game.energy.milli == 0 and _spent(seen) == 1000
    # Back to where the slice rested costs nothing, and lands it there exactly with a snap.
    _run(game, 15, turn_zw_neg=True)
    game.step(Actions(presses=(("snap_slice", 1),)))
    _run(game, 30)
    assert game.camera.aligned and game.energy.milli == 0
    # Landing on the rest starts the count over: turning away again is paid again.
    game.energy.gain(500)
    _run(game, 60, turn_zw_neg=True)
    assert game.camera.angles_deg()[2] == pytest.approx(-10.0, abs=1e-6) and game.energy.milli == 0


def test_the_accounting_stays_exact_over_random_turns_and_w_moves(turn_level):
    """start + gained - spent == the bar, to the thousandth, whatever the keys do."""
    game = Game(turn_level)
    rng = np.random.default_rng(3)
    start, gained, spent = game.energy.milli, 0, 0
    keys = ("turn_zw_pos", "turn_zw_neg", "turn_xw_pos", None, None)
    for t in range(3000):
        if t % 200 == 0:
            gained += game.energy.gain(int(rng.integers(0, 4000)))
        if t % 20 == 0:
            key = keys[int(rng.integers(len(keys)))]
            kw = {key: True} if key else {}
            w = float(rng.choice([-1.0, 0.0, 0.0, 1.0]))
            r = rng.random()
            presses = (("step_zw_pos", 1),) if r < 0.1 else (("snap_slice", 1),) if r < 0.3 else ()
        a = Actions(w=w, presses=presses if t % 20 == 0 else (), **kw)
        game.step(a)
        spent += _spent(game.events)
        assert 0 <= game.energy.milli <= game.energy.maximum_milli
    assert start + gained - spent == game.energy.milli
    assert spent > 0


# ---------------------------------------------------------------- the w grace
def test_a_short_w_hold_does_not_touch_the_bar(turn_level):
    game = Game(turn_level)
    game.energy.gain(5000)
    seen = _run(game, 6, w=1.0) + _run(game, 30)  # a tenth of a second held, then let go
    assert 0.0 < game.player.position[3] < W_GRACE
    assert game.energy.milli == 5000 and _spent(seen) == 0


def test_a_w_move_past_the_grace_pays_the_whole_way_and_the_grace_never_adds_up(turn_level):
    game = Game(turn_level)
    game.energy.gain(5000)
    seen = _run(game, 15, w=1.0) + _run(game, 30)
    w = game.player.position[3]
    assert 2 * W_GRACE < w < 0.4
    # The whole way paid (each tick rounded up to the thousandth, never down).
    assert 2000 * w <= _spent(seen) <= 2000 * w + 40
    # Taps that stay in the grace are free; taps that add up past it pay for all of it.
    paid_before, at = game.energy.milli, game.player.position[3]
    for _ in range(8):
        _run(game, 4, w=-1.0)
        _run(game, 20)
    moved = at - game.player.position[3]
    assert moved > W_GRACE
    unpaid = game.states.player.w_unpaid
    assert abs(unpaid) <= W_GRACE
    assert paid_before - game.energy.milli >= int(2000 * (moved - abs(unpaid)))


def test_the_grace_never_lets_the_player_go_farther_than_the_bar_pays(turn_level):
    game = Game(turn_level)
    game.energy.gain(100)  # 0.05 of w, less than the grace
    _run(game, 120, w=1.0)
    _run(game, 30)
    _run(game, 120, w=1.0)
    assert game.player.position[3] == pytest.approx(0.05, abs=1e-9)


# ---------------------------------------------------------------- the level file and the HUD
def test_slice_cost_needs_a_turning_slice(tmp_path):
    path = LevelBuilder().table("energy", max=10.0, slice_cost=0.1).write(tmp_path)
    with pytest.raises(LevelError) as e:
        load_level(path)
    assert "[energy]" in str(e.value) and "slice_cost" in str(e.value) and "turn = true" in str(e.value)
    cmd = [sys.executable, "-m", "across_dimensions", "check-level", str(path)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert done.returncode != 0 and "slice_cost" in done.stdout + done.stderr
    assert "Traceback" not in done.stdout + done.stderr


def test_the_hud_prices_the_slice_turn_in_orthogonal_worlds():
    level = load_level(ROOT / "levels" / "07_orthogonal_worlds.toml")
    assert "SLICE 4.5/90DEG" in cost_line(level) and "W 2/UNIT" in cost_line(level)
    assert Game(level).frame().hud.energy.costs == cost_line(level)
