"""Walking on frustum images: ``walkable_in_frustum`` objects collide as their image while the
frustum view holds, the entry is reported, and the end of the view never leaves the player
inside geometry."""

from __future__ import annotations

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import Actions
from across_dimensions.game.events import EnteredFrustumObject, MovedToSafety
from across_dimensions.game.frustum_walk import overlaps
from across_dimensions.game.player import HALF_WIDTH, SKIN
from across_dimensions.game.sim import Game
from across_dimensions.world.level import LevelError, load_level

SWITCH = Actions(presses=(("switch_camera", 1),))


def _barrier_level(tmp_path, walkable=True, frustum=True):
    """A barrier across the hall at z = 6, solid in the slice; the frustum camera orbits at
    90 degrees a second, its focus 4 m ahead."""
    return (
        LevelBuilder("walk", goal=(0.0, 1.0, 10.0), floor=(16.0, 1.0, 30.0))
        .table("camera", turn=False, frustum=frustum, frustum_cost=0.0, orbit_speed=90.0, focus_distance=4.0)
        .object(
            [0.0, 1.5, 6.0, 0.0],
            name="barrier",
            scale=[4.0, 3.0, 0.4, 0.4],
            solid=True,
            walkable_in_frustum=walkable,
        )
        .load(tmp_path)
    )


def _run(game, ticks, actions=None):
    actions = Actions() if actions is None else actions
    seen = []
    for _ in range(ticks):
        game.step(actions)
        seen += game.events
    return seen


def _orbited(game):
    """Switch to the frustum view and orbit it a quarter turn (60 ticks at 90 degrees a second)."""
    seen = _run(game, 1, SWITCH)
    seen += _run(game, 60, Actions(orbit_right=True))
    assert game.camera.orbit == pytest.approx(np.pi / 2)
    return seen


def test_the_barrier_stops_the_walker_in_the_slice(tmp_path):
    game = Game(_barrier_level(tmp_path))
    _run(game, 240, Actions(forward=1.0))
    z = game.player.position[2]
    assert z == pytest.approx(6.0 - 0.2 - HALF_WIDTH, abs=1e-3)  # its section's near face


def test_in_the_frustum_view_the_walker_meets_the_image_and_enters_it(tmp_path):
    game = Game(_barrier_level(tmp_path))
    _orbited(game)
    e = game.entities.named("barrier")
    tris = game.image_triangles(e)
    lo, hi = tris.min(axis=(0, 1)), tris.max(axis=(0, 1))
    # Orbited a quarter turn, the barrier's image is half its size, 4 m nearer (z about 1.9).
    assert hi[2] < 3.0 and lo[1] < 1.0 and lo[0] > -1.5 and hi[0] < 1.5
    seen = _run(game, 240, Actions(forward=1.0))
    entered = [ev for ev in seen if isinstance(ev, EnteredFrustumObject)]
    assert [(ev.entity, ev.name) for ev in entered] == [(e.id, "barrier")]
    # Stopped by the image's nearest face, not by the barrier's section 4 m on.
    z = game.player.position[2] + HALF_WIDTH
    assert z == pytest.approx(lo[2], abs=2 * SKIN)


def test_the_end_of_the_view_puts_the_player_somewhere_safe(tmp_path):
    game = Game(_barrier_level(tmp_path))
    _orbited(game)
    inside = np.array([0.0, 0.0, 6.0, 0.0])  # where the barrier's section is: free in the image
    assert not overlaps(game, inside)
    game.place_player(inside)
    seen = _run(game, 1, SWITCH)
    moved = [ev for ev in seen if isinstance(ev, MovedToSafety)]
    assert len(moved) == 1 and np.allclose(moved[0].position, game.player.position)
    assert not overlaps(game, game.player.position)  # never inside geometry
    # The nearest free spot: just clear of the barrier's section (0.2 thick), on a 0.25 m ring.
    assert abs(game.player.position[2] - 6.0) >= 0.2 + HALF_WIDTH
    assert np.linalg.norm(game.player.position[[0, 2]] - inside[[0, 2]]) <= 0.75
    # Many ticks later the player is still clear of everything.
    _run(game, 120)
    assert not overlaps(game, game.player.position)


def test_a_player_clear_of_geometry_stays_where_they_are(tmp_path):
    game = Game(_barrier_level(tmp_path))
    _orbited(game)
    game.place_player([1.0, 0.0, 3.0, 0.0])
    seen = _run(game, 1, SWITCH)
    assert not [ev for ev in seen if isinstance(ev, MovedToSafety)]
    assert game.player.position[[0, 2]] == pytest.approx([1.0, 3.0])


def test_unmarked_objects_keep_their_sections_in_the_frustum_view(tmp_path):
    game = Game(_barrier_level(tmp_path, walkable=False))
    _orbited(game)
    seen = _run(game, 240, Actions(forward=1.0))
    assert not [ev for ev in seen if isinstance(ev, EnteredFrustumObject)]
    assert game.player.position[2] == pytest.approx(6.0 - 0.2 - HALF_WIDTH, abs=1e-3)


def test_the_level_reader_checks_the_field(tmp_path):
    with pytest.raises(LevelError, match="walkable_in_frustum.*frustum = true"):
        _barrier_level(tmp_path, frustum=False)
    path = (
        LevelBuilder("walk")
        .table("camera", frustum=True)
        .object([0.0, 1.0, 3.0, 0.0], name="crate", body="hypercube", walkable_in_frustum=True)
        .write(tmp_path)
    )
    with pytest.raises(LevelError, match="crate.*walkable_in_frustum.*body = 'none'"):
        load_level(path)
    path = (
        LevelBuilder("walk")
        .table("camera", frustum=True)
        .object([0.0, 1.0, 3.0, 0.0], walkable_in_frustum=1)
        .write(tmp_path)
    )
    with pytest.raises(LevelError, match="walkable_in_frustum"):
        load_level(path)


@pytest.mark.slow
def test_the_folded_stairs_replay_climbs_the_image_and_frees_the_loot_with_the_camera():
    """Level 12's shipped replay, through the command a player types: the stair is walked as an
    image and the crystal for the climb came out for the camera."""
    import json
    import subprocess
    import sys
    from pathlib import Path

    levels = Path(__file__).resolve().parents[1] / "levels"
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "replay", str(levels / "12_folded_stair.toml"),
         str(levels / "replays" / "12_folded_stair.json"), "--json"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    out = json.loads(r.stdout)
    assert out["outcome"] == "complete" and out["divergence"] is None
    assert out["events"]["entered_frustum_object"] >= 1
    assert out["causes"] == {"loot_released:camera": 1}
    assert out["events"]["crystal_collected"] == 1
