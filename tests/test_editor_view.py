"""What the editor shows, headless: picking, outlines, previews along w, frustum view, play from here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from across_dimensions.app.editor import view
from across_dimensions.game.actions import Actions
from across_dimensions.game.sim import Game
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import resolve_level
from across_dimensions.world.scene import SectionCache

ALL = [("level",), ("spawn",), ("goal",)] + [("box", i) for i in range(6)]
ALL += [("world", 0), ("world", 0, "box", 0), ("crystal", 0), ("crystal", 1), ("crystal", 2), ("object", 0)]


@pytest.fixture(scope="module")
def cache_level():
    return load_level(resolve_level("02_crystal_cache"))


@pytest.fixture
def game(cache_level):
    return Game(cache_level)


def _aimed_at(target, eye, w) -> view.EditorCamera:
    """A camera at ``eye`` looking straight at ``target`` (both (3,)), slicing at ``w``."""
    d = np.asarray(target, float) - np.asarray(eye, float)
    yaw = math.atan2(d[0], d[2])
    pitch = math.atan2(d[1], math.hypot(d[0], d[2]))
    return view.EditorCamera(np.asarray(eye, float), yaw, pitch, w)


def test_the_ray_through_the_centre_is_the_view_direction():
    cam = view.EditorCamera(np.array([1.0, 2.0, 3.0]), 0.4, -0.3, 0.0)
    o, d = view.ray(cam, 0.0, 0.0, 16 / 9)
    np.testing.assert_allclose(d, cam.camera3().forward(), atol=1e-9)  # matrix inverse round-off
    np.testing.assert_allclose(o, cam.position + cam.camera3().near * cam.camera3().forward(), atol=1e-6)


def test_click_selects_what_is_visible_at_the_slice(game):
    # Level with "first light" (a crystal of radius 0.35 at w = 0, 3.5 m ahead), then the blue world's
    # wall (z = 2.7 to 3.3, present for |w| < 0.8), the goal and the far wall (z = 14).
    cam = view.EditorCamera(np.array([0.0, 1.0, -9.0]), 0.0, 0.0, 0.0)
    assert view.pick(game, cam, 0.0, 0.0, 16 / 9, ALL) == ("crystal", 0)
    cam.w = 0.6  # the crystal's section is empty; the world's wall is there (a prism: full size)
    assert view.pick(game, cam, 0.0, 0.0, 16 / 9, ALL) == ("world", 0, "box", 0)
    cam.w = 0.9  # the world is gone too: the goal's box (z = 11 to 13) is next
    assert view.pick(game, cam, 0.0, 0.0, 16 / 9, ALL) == ("goal",)
    # The wall is picked only where it is: off to the side, at w = 0.6 it hides what is behind it,
    # at w = 0.9 it does not.
    right = view.EditorCamera(np.array([3.0, 1.0, -9.0]), 0.0, 0.0, 0.6)
    assert view.pick(game, right, 0.0, 0.0, 16 / 9, ALL) == ("world", 0, "box", 0)
    right.w = 0.9
    assert view.pick(game, right, 0.0, 0.0, 16 / 9, ALL) == ("box", 4)
    # Looking up at the empty sky picks nothing.
    sky = view.EditorCamera(np.array([0.0, 2.0, 0.0]), 0.0, 1.2, 0.0)
    assert view.pick(game, sky, 0.0, 0.0, 16 / 9, ALL) is None


def test_the_spawn_is_picked_from_outside_not_from_within(game):
    eye = np.array([0.0, 1.0, -5.0])
    cam = _aimed_at(game.level.spawn[:3] + [0.0, 0.8, 0.0], eye, 0.0)
    assert view.pick(game, cam, 0.0, 0.0, 1.0, [("spawn",), ("box", 0)]) == ("spawn",)
    inside = view.EditorCamera(game.level.spawn[:3] + [0.0, 0.8, 0.0], 0.0, -1.0, 0.0)
    assert view.pick(game, inside, 0.0, 0.0, 1.0, [("spawn",), ("box", 0)]) == ("box", 0)


def test_editor_frame_is_seen_from_the_camera_at_its_slice(game):
    cam = view.EditorCamera(np.array([0.0, 2.0, -6.0]), 0.1, -0.2, 0.9)
    frame = view.editor_frame(game, cam, ("object", 0))
    np.testing.assert_allclose(frame.camera.position, cam.position, atol=1e-12)
    assert frame.hud.w == pytest.approx(0.9)
    keys = [d.key for d in frame.drawables] + [k for b in frame.batches for k in b.members]
    beacon = view.entity_of(game, ("object", 0))
    assert f"entity:{beacon.id}" in keys  # the beacon at w = 0.9 is in the slice
    first_light = view.entity_of(game, ("crystal", 0))
    assert f"entity:{first_light.id}" not in keys  # a crystal at w = 0 is not
    outline = [d for d in frame.drawables if d.key == "editor:outline"]
    assert len(outline) == 1 and outline[0].style == "wire" and len(outline[0].mesh.faces) > 0
    assert frame.radar is not None and frame.radar.pins  # the radar works in the editor too


def test_a_box_outline_is_its_bounds(game):
    (d,) = view.outline(game, ("box", 5), 0.0)
    lo, hi = d.mesh.vertices.min(0), d.mesh.vertices.max(0)
    b = game.level.boxes[5]
    np.testing.assert_allclose((lo + hi) / 2, b.center, atol=1e-5)  # float32 vertices
    np.testing.assert_allclose(hi - lo, b.size * view.OUTLINE_GROW, atol=1e-5)


def test_previews_show_the_section_shrinking_away_from_the_objects_w(game):
    step = 0.25
    frames = view.preview_frames(game, ("crystal", 1), 0.5, [-2 * step, -step, 0.0, step, 2 * step], SectionCache())
    assert [w for w, _ in frames] == pytest.approx([0.0, 0.25, 0.5, 0.75, 1.0])
    extents = []
    for _, f in frames:
        (d,) = f.drawables
        v = d.mesh.vertices
        extents.append(float(np.ptp(v, axis=0).max()) if len(v) else 0.0)
    # The crystal (radius 0.35) is at w = 0.5: biggest there, smaller at +-0.25, absent at +-0.5.
    assert extents[2] > extents[1] > 0 and extents[2] > extents[3] > 0
    assert extents[0] == 0.0 and extents[4] == 0.0
    assert view.preview_frames(game, ("box", 0), 0.0, [0.0], SectionCache()) == []  # boxes are the same at every w


def test_world_previews_follow_the_profile(game):
    frames = view.preview_frames(game, ("world", 0), 0.0, [0.0, 0.6, 0.9], SectionCache())
    sizes = [
        float(np.ptp(f.drawables[0].mesh.vertices[:, 0])) if len(f.drawables[0].mesh.vertices) else 0.0
        for _, f in frames
    ]
    assert sizes[0] == pytest.approx(9.0, rel=1e-4)  # the wall's full 9 m at the world's w
    assert sizes[1] == sizes[0] and sizes[2] == 0.0  # a prism over depth 1.6: full size, gone at |w| >= 0.8


def test_frustum_view_keeps_the_slice_size_and_shrinks_ana(game):
    by_name = {}
    for d in view.frustum_drawables(game, 0.0):
        assert d.style == "ghost" and d.mesh.depth is not None
        by_name[d.key] = d
    first = view.entity_of(game, ("crystal", 0))  # w = 0, on the slice
    ana = view.entity_of(game, ("crystal", 1))  # w = 0.5, ana
    kata = view.entity_of(game, ("crystal", 2))  # w = -0.5, kata
    size = {e.id: float(np.ptp(by_name[f"frustum:{e.id}"].mesh.vertices, axis=0).max()) for e in (first, ana, kata)}
    assert size[ana.id] < size[first.id] < size[kata.id]
    # Placed at the entity's own xyz.
    d = by_name[f"frustum:{first.id}"]
    np.testing.assert_allclose(d.model[:3, 3], game.level.crystals[0].position[:3])


def test_the_frustum_view_lets_the_sky_show_wherever_the_slice_did_not_hide_it(game):
    """The frustum view takes the 4D entities' sections out of the frame: a door's box, gone from
    where it stood, must not keep the sky out there (the renderer would leave those pixels unwritten)."""
    cam = view.EditorCamera(np.array([0.0, 1.6, -6.0]), 0.0, 0.1, 0.0)
    assert view.editor_frame(game, cam).sky_boxes is not None
    assert view.editor_frame(game, cam, frustum=True).sky_boxes is None


def test_play_from_here_starts_at_the_camera_and_plays(cache_level):
    cam = view.EditorCamera(np.array([2.0, 1.6 + 0.5, -2.0]), 0.7, 0.2, 0.4)
    game = view.game_at(cache_level, cam)
    p = game.player
    np.testing.assert_allclose(p.eye(), cam.position)
    assert p.position[3] == 0.4 and p.yaw == 0.7
    frame = game.frame()
    np.testing.assert_allclose(frame.camera.position, cam.position)  # no interpolation from the spawn
    for _ in range(60):
        game.step(Actions())
    assert game.player.position[1] == pytest.approx(0.0, abs=0.05)  # fell 0.5 m onto the floor
    # w is kept inside the level's range.
    far = view.EditorCamera(cam.position, 0.0, 0.0, 5.0)
    assert view.game_at(cache_level, far).player.position[3] == cache_level.w_range[1]
    # Without a camera: the spawn, like a new game.
    assert view.game_at(cache_level).state_hash() == Game(cache_level).state_hash()
