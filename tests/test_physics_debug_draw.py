"""Debug drawing: what the physics reports to a drawer, and the GL overlay that draws it."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from across_dimensions.core import transform
from across_dimensions.physics import BodyDef, DebugDrawOptions, PhysicsWorld
from across_dimensions.physics.debug_draw import box_section_edges


class RecordingDrawer:
    """A drawer that only remembers the calls."""

    def __init__(self):
        self.calls = []

    def draw_sphere(self, body_id, center, radius, color):
        self.calls.append(("sphere", body_id, np.array(center), radius, color))

    def draw_section(self, body_id, edges, color):
        self.calls.append(("section", body_id, np.array(edges), color))

    def draw_contact(self, point, normal, color):
        self.calls.append(("contact", np.array(point), np.array(normal), color))

    def draw_box(self, center, half_extents, color):
        self.calls.append(("box", np.array(center), np.array(half_extents), color))

    def of(self, kind):
        return [c for c in self.calls if c[0] == kind]


def _scene():
    """Two boxes and a ball resting apart on the ground; the second box asleep, the others awake."""
    world = PhysicsWorld()
    world.set_static_boxes([((5.0, 1.0, 0.0), (0.5, 1.0, 0.5))])
    near = world.add_body(BodyDef("hypercube", size=1.0, position=(0.0, 0.5, 0.0, 0.1)))
    far = world.add_body(BodyDef("hypercube", size=(1.0, 1.0, 1.0, 0.6), position=(-3.0, 0.5, 0.0, 0.0)))
    ball = world.add_body(BodyDef("hypersphere", radius=0.5, position=(3.0, 0.5, 0.0, 0.3)))
    for _ in range(90):
        world.step(1 / 60)
    assert all(world.is_sleeping(b) for b in (near, far, ball))
    world.wake(near)
    world.wake(ball)
    world.tick()
    return world, near, far, ball


def test_recording_drawer_gets_the_known_scene():
    world, near, far, ball = _scene()
    opt = DebugDrawOptions()
    player = (np.array([1.5, 0.9, 0.0, 0.0]), np.array([0.3, 0.9, 0.3, 0.05]))
    rec = RecordingDrawer()
    world.debug_draw(rec, 0.0, opt, boxes=[player])

    # The ball: a sphere of radius sqrt(r^2 - dw^2) in the slice, awake colour.
    (sphere,) = rec.of("sphere")
    assert sphere[1] == ball and sphere[4] == opt.dynamic_color
    np.testing.assert_allclose(sphere[2], world.body_position(ball)[:3])
    assert sphere[3] == pytest.approx(np.sqrt(0.5**2 - 0.3**2), abs=1e-6)

    # The boxes: axis-aligned, so their sections are unit cubes (12 edges each).
    sections = {c[1]: c for c in rec.of("section")}
    assert set(sections) == {near, far}
    assert sections[near][3] == opt.dynamic_color
    assert sections[far][3] == opt.sleeping_color != opt.dynamic_color
    for b, (_, _, edges, _) in sections.items():
        assert edges.shape == (12, 2, 3)
        pts = edges.reshape(-1, 3)
        # (settling leaves a tilt of a few micro-radians)
        np.testing.assert_allclose(pts.min(0), world.body_position(b)[:3] - 0.5, atol=1e-3)
        np.testing.assert_allclose(pts.max(0), world.body_position(b)[:3] + 0.5, atol=1e-3)

    # The world box and the player's box, in their colours and in that order.
    boxes = rec.of("box")
    assert len(boxes) == 2
    np.testing.assert_allclose(boxes[0][1], (5.0, 1.0, 0.0))
    np.testing.assert_allclose(boxes[0][2], (0.5, 1.0, 0.5))
    assert boxes[0][3] == opt.static_color
    np.testing.assert_allclose(boxes[1][1], player[0][:3])
    np.testing.assert_allclose(boxes[1][2], player[1][:3])
    assert boxes[1][3] == opt.box_color

    # Contacts: only the awake bodies have them, on the ground, normal into it.
    contacts = rec.of("contact")
    assert contacts
    for _, p, n, color in contacts:
        assert color == opt.contact_color
        assert abs(p[1]) < 0.05
        np.testing.assert_allclose(n, (0.0, -1.0, 0.0), atol=1e-6)
        assert min(np.linalg.norm(p[[0, 2]] - world.body_position(b)[[0, 2]]) for b in (near, ball)) < 0.75


def test_the_slice_decides_what_is_reported():
    world, near, far, ball = _scene()
    rec = RecordingDrawer()
    # At w = 0.45 the ball (w 0.3, r 0.5) and the near box (w 0.1 +- 0.5) are
    # cut; the far box (w +- 0.3) is not.
    world.debug_draw(rec, 0.45, DebugDrawOptions(contacts=False))
    assert {c[1] for c in rec.of("section")} == {near}
    assert [c[1] for c in rec.of("sphere")] == [ball]
    assert rec.of("contact") == []
    rec = RecordingDrawer()
    world.debug_draw(rec, 5.0, DebugDrawOptions(shapes=False))
    assert rec.calls == []  # nothing at w = 5, no shapes asked for


def test_rotated_box_section_lies_in_the_box_and_is_closed():
    rot = transform.angles_to_rotation({"xw": 0.5, "yw": 0.3, "xy": 0.2})
    pos = np.array([1.0, 2.0, 3.0, 0.2])
    half = np.array([0.5, 0.4, 0.3, 0.6])
    edges = box_section_edges(pos, rot, half, 0.35)
    assert edges.shape[0] >= 6
    pts = edges.reshape(-1, 3)
    local = (np.column_stack([pts, np.full(len(pts), 0.35)]) - pos) @ rot
    assert (np.abs(local) <= half + 1e-9).all()
    # A closed polytope: every vertex meets at least three edges.
    _, counts = np.unique(np.round(pts, 9), axis=0, return_counts=True)
    assert counts.min() >= 3
    assert box_section_edges(pos, rot, half, 3.0).shape == (0, 2, 3)


def test_game_hook_reports_the_player_box_without_physics():
    from across_dimensions.game.player import HALF_WIDTH, HEIGHT
    from across_dimensions.game.player_bodies import debug_draw_game

    game = SimpleNamespace(physics=None, player=SimpleNamespace(position=np.array([1.0, 0.0, 2.0, 0.5])))
    rec = RecordingDrawer()
    debug_draw_game(game, rec)
    ((_, center, half, _),) = rec.calls
    np.testing.assert_allclose(center, (1.0, 0.5 * HEIGHT, 2.0))
    np.testing.assert_allclose(half, (HALF_WIDTH, 0.5 * HEIGHT, HALF_WIDTH))


def test_debug_draw_has_a_default_key():
    from across_dimensions.app.settings import default_settings

    assert default_settings().action_for_key("F4") == "debug_draw"


@pytest.mark.gl
def test_overlay_draws_lines_over_a_frame(gl_ctx):
    from across_dimensions.game.frame import Camera3
    from across_dimensions.render.context import Offscreen
    from across_dimensions.render.debug_draw import DebugOverlay, LineDrawer

    world, near, far, ball = _scene()
    target = Offscreen(gl_ctx, 160, 90)
    overlay = DebugOverlay(gl_ctx)
    try:
        target.use()
        gl_ctx.clear(0.0, 0.0, 0.0, 1.0)
        before = target.read_rgb()
        assert before.max() == 0
        # The camera 4 m in front of the near box, looking at it along +z.
        cam = Camera3(position=np.array([0.0, 0.5, -4.0]))
        drawer = LineDrawer()
        world.debug_draw(drawer, 0.0, DebugDrawOptions(contacts=False))
        n = overlay.draw(drawer, cam, target.viewport)
        assert n > 12
        img = target.read_rgb().astype(int)
        green = np.round(np.array(DebugDrawOptions().dynamic_color[:3]) * 255).astype(int)
        hit = (np.abs(img - green) <= 2).all(axis=2)
        assert hit.sum() > 20
        # The near box is in the middle of the picture: its lines are there.
        ys, xs = np.nonzero(hit)
        assert 50 < xs.mean() < 110
        assert gl_ctx.error == "GL_NO_ERROR"
        # Nothing to draw leaves the image alone.
        gl_ctx.clear(0.0, 0.0, 0.0, 1.0)
        assert overlay.draw(LineDrawer(), cam, target.viewport) == 0
        assert target.read_rgb().max() == 0
        # The window's hook: the player's box is drawn in its (half transparent) colour too.
        game = SimpleNamespace(physics=world, player=SimpleNamespace(position=np.array([0.0, 0.0, -1.0, 0.0])))
        assert overlay.draw_game(game, cam, target.viewport) > n
        c = DebugDrawOptions().box_color
        expected = np.round(np.array(c[:3]) * c[3] * 255).astype(int)  # blended over black
        box_px = (np.abs(target.read_rgb().astype(int) - expected) <= 2).all(axis=2)
        assert box_px.sum() > 10
    finally:
        overlay.release()
        target.release()
