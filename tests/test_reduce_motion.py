"""Reduce motion: every glide snaps and every held turn jumps, counted in ticks with the setting
off and on (issue 35, point 1). The setting reaches the simulation as a flag of each tick's
actions, so replays record it; with it off the simulation is exactly what it was."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.game.actions import Actions
from across_dimensions.game.motion import JUMP_DEG, JUMP_SECONDS
from across_dimensions.game.sim import Game
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

LEVELS = levels_dir()
DATA = Path(__file__).parent / "data"
JUMP_TICKS = round(JUMP_SECONDS * 60)


def _a(reduced: bool, **kw) -> Actions:
    return Actions(reduced_motion=reduced, **kw)


def _ticks_until(game, reduced: bool, done, limit: int = 600, **held) -> int:
    """Ticks (held actions each tick) until ``done(game)``; the limit if never."""
    for n in range(1, limit + 1):
        game.step(_a(reduced, **held))
        if done(game):
            return n
    return limit


@pytest.fixture(scope="module")
def orthogonal():
    """Orthogonal Worlds with its slice turns free (what they cost is tests/test_slice_cost.py's)."""
    level = load_level(LEVELS / "07_orthogonal_worlds.toml")
    return replace(level, energy=replace(level.energy, slice_cost=0.0))


@pytest.fixture(scope="module")
def corner():
    return load_level(LEVELS / "08_around_the_corner.toml")


@pytest.mark.parametrize("reduced", [False, True])
def test_a_90_degree_step_glides_only_without_the_setting(orthogonal, reduced):
    game = Game(orthogonal)
    game.step(_a(reduced, presses=(("step_zw_pos", 1),)))
    ticks = 1 + (
        0
        if game.event_counts["slice_aligned"]
        else _ticks_until(game, reduced, lambda g: g.event_counts["slice_aligned"])
    )
    assert game.camera.angles_deg() == pytest.approx((0.0, 0.0, 90.0))
    # Off: at twice the turning speed, a little over the 45 ticks of a constant-speed turn.
    assert (ticks == 1) if reduced else 45 <= ticks <= 60


@pytest.mark.parametrize("reduced", [False, True])
def test_the_snap_glides_only_without_the_setting(orthogonal, reduced):
    game = Game(orthogonal)
    for _ in range(12):
        game.step(Actions(turn_xw_pos=True))  # 12 smooth ticks off the axes (the setting off)
    assert game.camera.angles_deg()[0] > 5
    game.step(_a(reduced, presses=(("snap_slice", 1),)))
    ticks = 1 + (
        0
        if game.event_counts["slice_aligned"]
        else _ticks_until(game, reduced, lambda g: g.event_counts["slice_aligned"])
    )
    assert game.camera.angles_deg() == pytest.approx((0.0, 0.0, 0.0), abs=1e-9)
    assert (ticks == 1) if reduced else ticks > 3


def _angles(game, reduced, n, **held) -> list[float]:
    out = []
    for _ in range(n):
        game.step(_a(reduced, **held))
        out.append(game.camera.angles_deg()[0])
    return out


def test_a_held_slice_turn_jumps_with_the_setting_and_turns_smoothly_without(orthogonal):
    smooth = _angles(Game(orthogonal), False, 2 * JUMP_TICKS, turn_xw_pos=True)
    assert len(set(np.round(smooth, 9))) == len(smooth), "off: a new angle every tick"
    jumps = _angles(Game(orthogonal), True, 2 * JUMP_TICKS, turn_xw_pos=True)
    # On: JUMP_DEG on the tick the key goes down, the next JUMP_TICKS later, nothing between.
    assert jumps[0] == pytest.approx(JUMP_DEG)
    assert jumps[JUMP_TICKS - 1] == pytest.approx(JUMP_DEG) and jumps[JUMP_TICKS] == pytest.approx(2 * JUMP_DEG)
    assert len(set(np.round(jumps, 9))) == 2


def test_the_orbit_jumps_and_the_return_only_fades_with_the_setting(corner):
    total = round(corner.camera.return_time * 60)
    result = {}
    for reduced in (False, True):
        game = Game(corner)
        game.step(_a(reduced, presses=(("switch_camera", 1),)))
        orbit = []
        for _ in range(JUMP_TICKS + 1):
            game.step(_a(reduced, orbit_right=True))
            orbit.append(np.degrees(game.camera.orbit))
        game.step(_a(reduced, presses=(("switch_camera", 1),)))
        assert game.camera.mode == "returning"
        back = _ticks_until(game, reduced, lambda g: g.camera.mode == "synced")
        result[reduced] = orbit, back
    smooth, back_off = result[False]
    assert np.all(np.diff(smooth) > 0) and back_off == total
    jumps, back_on = result[True]
    assert jumps[0] == pytest.approx(JUMP_DEG) and jumps[-1] == pytest.approx(2 * JUMP_DEG)
    assert len(set(np.round(jumps, 9))) == 2
    # The glide back (GLIDE_SHARE of the return) is skipped: only the fade is left.
    assert back_on == total - int(np.ceil(0.7 * total))


def test_a_returning_camera_is_already_back_in_place_with_the_setting(corner):
    game = Game(corner)
    game.step(_a(True, presses=(("switch_camera", 1),)))
    for _ in range(40):
        game.step(_a(True, orbit_right=True))
    game.step(_a(True, presses=(("switch_camera", 1),)))
    game.step(_a(True))
    assert game.camera.mode == "returning" and game.camera.return_progress(round(corner.camera.return_time * 60)) == 1


@pytest.mark.parametrize("reduced", [False, True])
def test_seek_lands_in_one_tick_only_with_the_setting(reduced):
    game = Game(load_level(DATA / "crystals.toml"))
    game.energy.gain(10_000)
    game.step(_a(reduced, presses=(("seek", 1),)))
    ticks = 1 + (0 if not game.states.seek.active else _ticks_until(game, reduced, lambda g: not g.states.seek.active))
    assert game.player.position[3] == -0.4
    assert (ticks == 1) if reduced else ticks > 10


def test_a_manipulated_object_turns_a_whole_step_at_once_with_the_setting():
    game = Game(load_level(LEVELS / "06_bridge.toml"))
    for _ in range(60):
        game.step(Actions(forward=1.0))
    for _ in range(20):  # look down until the crosshair is on the slab
        if game.states.manipulation.aimed == game.entities.named("slab").id:
            break
        game.step(Actions(pitch=-0.015))
    assert game.states.manipulation.aimed == game.entities.named("slab").id
    slab = game.entities.named("slab").data
    step = round(slab.spec.step * 1000)
    seen = []
    for _ in range(JUMP_TICKS + 1):
        game.step(_a(True, manipulate=True, right=1.0))
        seen.append(slab.offsets["zw"])
    assert seen[0] == step and seen[JUMP_TICKS - 1] == step and seen[JUMP_TICKS] == 2 * step


def test_replays_record_the_setting_and_default_frames_are_unchanged():
    on = _a(True, forward=1.0)
    assert Actions.from_row(on.to_row()) == on
    assert Actions(forward=1.0).to_row() == [1.0, 0.0, 0.0, 0.0, 0.0, 0]  # no bit set when off
    assert replace(on, reduced_motion=False).to_row()[5] == 0


def test_a_replay_recorded_with_the_setting_plays_back_with_it(orthogonal, tmp_path):
    from across_dimensions.game.playback import play
    from across_dimensions.game.replay import Recorder, Replay

    script = (
        [_a(True, turn_xw_pos=True)] * 20
        + [_a(True, presses=(("snap_slice", 1),))]
        + [_a(True, presses=(("step_zw_pos", 1),))]
        + [_a(True, forward=1.0)] * 30
    )
    game = Game(orthogonal)
    rec = Recorder(game, "07_orthogonal_worlds")
    for a in script:
        game.step(a)
        rec.record(a)
    path = tmp_path / "reduced.json"
    rec.finish().save(path)
    loaded = Replay.load(path)
    assert all(a.reduced_motion for a in loaded.actions)
    result = play(loaded, Game(orthogonal))
    assert result.divergence is None and result.final_hash == game.state_hash()
    # The same keys without the setting glide, so the game ends elsewhere.
    plain = Game(orthogonal)
    for a in script:
        plain.step(replace(a, reduced_motion=False))
    assert plain.state_hash() != game.state_hash()
