"""Things hidden behind a box are neither sliced nor drawn (game/occlusion.py).

What must hold: a ball called hidden is hidden from every point of it (each segment from the
eye to a point of the ball crosses the box), a box the eye stands in hides nothing, and in a
level the picture is the one drawn with nothing left out, while the radar still says the
hidden things reach the slice. Where the sky is left out, every ray meets a box before the far
plane, and the picture is the one with the sky drawn everywhere.
"""

from __future__ import annotations

import numpy as np
import pytest

from across_dimensions.game.actions import Actions
from across_dimensions.game.occlusion import BIG, EYE_MARGIN, SKY_ROWS, box_sections, hidden, open_rectangles
from across_dimensions.game.sim import Game
from across_dimensions.game.systems import sections
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import resolve_level


def _segment_hits(eye, p, lo, hi) -> bool:
    """Does the segment from ``eye`` to ``p`` meet the box ``[lo, hi]``? (Slab test.)"""
    d = p - eye
    t0, t1 = 0.0, 1.0
    for a in range(3):
        if abs(d[a]) < 1e-12:
            if not lo[a] <= eye[a] <= hi[a]:
                return False
            continue
        u, v = sorted(((lo[a] - eye[a]) / d[a], (hi[a] - eye[a]) / d[a]))
        t0, t1 = max(t0, u), min(t1, v)
    return t0 <= t1


def test_a_ball_behind_a_wall_is_hidden_and_one_past_its_edge_is_not():
    wall = np.array([[[-2.0, 0.0, 4.0], [2.0, 3.0, 4.5]]])
    eye = [0.0, 1.5, 0.0]
    centers = [[0.0, 1.5, 8.0], [3.5, 1.5, 8.0], [0.0, 1.5, 4.2], [0.0, 1.5, -3.0]]
    assert hidden(eye, centers, [0.5, 0.5, 0.5, 0.5], wall).tolist() == [True, False, False, False]
    # From inside the wall, or next to it, it hides nothing: its faces are culled from inside.
    assert not hidden([0.0, 1.5, 4.2], [[0.0, 1.5, 8.0]], [0.5], wall).any()
    assert not hidden([0.0, 1.5, 4.0 - 0.5 * EYE_MARGIN], [[0.0, 1.5, 8.0]], [0.5], wall).any()
    # A box absent from the slice (NaN) hides nothing.
    assert not hidden(eye, [[0.0, 1.5, 8.0]], [0.5], np.full((1, 2, 3), np.nan)).any()


def test_a_ball_reaching_into_a_box_is_hidden_when_the_rest_is_behind_one():
    wall = [[-2.0, 0.0, 4.0], [2.0, 3.0, 4.5]]
    floor = [[-10.0, -1.0, -10.0], [10.0, 0.0, 10.0]]
    eye = [0.0, 1.5, 0.0]
    # Sunk in the floor behind the wall: the floor hides nothing its bottom would show.
    assert hidden(eye, [[0.0, 0.0, 6.0]], [0.5], [wall, floor]).all()
    assert hidden(eye, [[0.0, 0.0, 6.0]], [0.5], [wall]).all()
    # Pressed into the wall from behind: hidden when big enough to be worth the test; poking
    # out of its front: not.
    assert hidden(eye, [[0.0, 1.5, 5.4]], [BIG], [wall]).all()
    assert not hidden(eye, [[0.0, 1.5, 4.2]], [BIG], [wall]).any()


def _inside(p, boxes) -> bool:
    return any(np.all((lo <= p) & (p <= hi)) for lo, hi in boxes)


def test_whatever_is_called_hidden_is_hidden_from_every_point_of_its_ball():
    rng = np.random.default_rng(7)
    called = 0
    for _ in range(300):
        lo = rng.uniform(-3, 3, (2, 3))
        boxes = np.stack([lo, lo + rng.uniform(0.2, 4.0, (2, 3))], axis=1)
        eye = rng.uniform(-8, 8, 3)
        centers = rng.uniform(-6, 6, (20, 3))
        radii = rng.uniform(0.1, 1.5, 20)
        said = hidden(eye, centers, radii, boxes)
        for c, r in zip(centers[said], radii[said]):
            called += 1
            d = rng.normal(size=(300, 3))
            pts = c + r * d / np.linalg.norm(d, axis=1, keepdims=True) * rng.uniform(0, 1, (300, 1)) ** (1 / 3)
            pts = np.concatenate([pts, c + r * np.eye(3), c - r * np.eye(3)])
            # Each point lies inside a box (hidden by its faces) or behind one.
            assert all(_inside(p, boxes) or any(_segment_hits(eye, p, *b) for b in boxes) for p in pts)
    assert called > 20  # the test saw hidden balls


def _crossfire_from_the_vault(w: float = 0.0):
    """Crossfire, the eye in the vault at ``w`` facing the closed arena gate (the arena's enemies
    and crystals behind it)."""
    game = Game(load_level(resolve_level("11_crossfire")))
    game.step(Actions())
    game.place_player((0.0, float(game.player.position[1]), 17.0, w), np.pi, 0.0)
    return game


def _drawn_without_occlusion(game, monkeypatch):
    """The frame and the radar's sections as they were before occlusion: nothing left out."""
    from across_dimensions.game.systems import ghosts

    with monkeypatch.context() as m:
        for system in (sections, ghosts):
            m.setattr(system, "hidden_rows", lambda game, *_: np.zeros(len(game.entity_models.entities), bool))
        frame = game.frame()
        return frame, {e.id: game.entity_sections.has_section(e.id) for e in game.entity_models.entities}


def test_the_closed_gate_hides_the_arena_and_the_radar_still_knows_it(monkeypatch):
    game = _crossfire_from_the_vault(w=0.6)  # the sapling (ana) reaches this slice
    frame = game.frame()
    table = game.entity_models
    gate = box_sections(table, table.models(game, 1.0), frame.camera.w)
    assert np.allclose(gate[1], [[-6.25, 0.0, 11.8], [6.25, 4.0, 12.2]])
    # Shown as a wireframe (the field weapon), it hides nothing: neither what is behind it nor the sky.
    wired = next(e for e in table.entities if e.name == "arena gate")
    wired.style = "wire"
    assert len(box_sections(table, table.models(game, 1.0), frame.camera.w)) == len(gate) - 1
    wired.style = "solid"
    members = {m for b in frame.batches for m in b.members}
    enemies = [e for e in table.entities if e.kind == "enemy"]
    assert enemies and not any(f"entity:{e.id}" in members for e in enemies)
    # Hidden, not gone: the radar's "in the slice" is what slicing them finds.
    said = {e.id: game.entity_sections.has_section(e.id) for e in table.entities}
    sapling = next(e for e in table.entities if e.name == "sapling")
    assert said[sapling.id]
    assert said == _drawn_without_occlusion(game, monkeypatch)[1]


def test_what_is_left_out_changes_no_pixel(gl_ctx, monkeypatch):
    from tests.test_batch import _image

    game = _crossfire_from_the_vault()
    for yaw in (np.pi, 0.75 * np.pi):
        game.place_player((0.0, float(game.player.position[1]), 17.0, 0.0), yaw, 0.0)
        culled = game.frame()
        everything, _ = _drawn_without_occlusion(game, monkeypatch)
        drawn = sum(len(b.members) for b in everything.batches)
        assert drawn > sum(len(b.members) for b in culled.batches)
        assert np.array_equal(_image(gl_ctx, culled), _image(gl_ctx, everything))


def test_an_open_gate_hides_nothing():
    game = _crossfire_from_the_vault()
    gate = next(e for e in game.entities if e.name == "arena gate")
    game.remove(gate.id)
    frame = game.frame()
    members = {m for b in frame.batches for m in b.members}
    enemies = [e for e in game.entity_models.entities if e.kind == "enemy"]
    assert any(f"entity:{e.id}" in members for e in enemies)


def _covered_area(rects) -> float:
    """How much of a 16:9 view ``rects`` (the view's units) leave to the sky, as a fraction."""
    r = np.asarray(rects).reshape(-1, 4)
    aspect = 16 / 9
    width = np.clip(r[:, 2], -aspect, aspect) - np.clip(r[:, 0], -aspect, aspect)
    return float((width * (r[:, 3] - r[:, 1])).sum() / (4 * aspect))


def test_where_the_sky_is_left_out_every_ray_meets_a_box_before_the_far_plane():
    rng = np.random.default_rng(3)
    eye = np.array([0.0, 1.5, 0.0])
    yaw = 0.4
    axes = np.array([[np.cos(yaw), 0.0, -np.sin(yaw)], [0.0, 1.0, 0.0], [np.sin(yaw), 0.0, np.cos(yaw)]])
    t, far = np.tan(np.radians(37.5)), 60.0
    # A room's walls seen from inside, a pillar, and a wall beyond the far plane (hides nothing).
    boxes = np.array([
        [[-8.0, -1.0, 6.0], [8.0, 3.0, 7.0]], [[6.0, -1.0, -8.0], [7.0, 3.0, 7.0]],
        [[-8.0, -1.0, -1.0], [8.0, 0.0, 7.0]], [[-0.5, 0.0, 3.0], [0.5, 5.0, 3.5]],
        [[-500.0, 3.0, 200.0], [500.0, 500.0, 201.0]],
    ])  # fmt: skip
    rects = open_rectangles(eye, axes, t, far, boxes)
    assert rects is not None and 0.05 < _covered_area(rects) < 0.95  # some of the view, not all
    # Rays through random points of the view: inside a rectangle, or meeting a box before the far plane.
    pts = rng.uniform([-3.0, -1.0], [3.0, 1.0], (4000, 2))
    inside = np.zeros(len(pts), bool)
    for x0, y0, x1, y1 in rects:
        inside |= (x0 <= pts[:, 0]) & (pts[:, 0] <= x1) & (y0 <= pts[:, 1]) & (pts[:, 1] <= y1)
    ends = eye + far * (np.column_stack([pts * t, np.ones(len(pts))]) @ axes)
    for p in ends[~inside]:
        assert any(_segment_hits(eye, p, lo, hi) for lo, hi in boxes)
    assert (~inside).sum() > 1000
    # And the rectangles leave out every cell that one box covers: a cell none covers stays.
    assert open_rectangles(eye, axes, t, far, boxes[4:]) is None  # beyond the far plane: no help
    assert open_rectangles(eye, axes, t, far, boxes[:0]) is None


def test_the_sky_cells_are_square_and_tile_the_view():
    eye, axes = np.zeros(3), np.eye(3)
    wall = np.array([[[-1.0, -100.0, 5.0], [100.0, 100.0, 6.0]]])  # the right half of the view, and more
    rects = open_rectangles(eye, axes, 1.0, 100.0, wall)
    cell = 2.0 / SKY_ROWS
    # The open run of every row is the same: one rectangle, the view's height, from its left
    # edge to the first cell wholly right of the wall's edge (x = -1/5 in the view).
    assert len(rects) == 1
    x0, y0, x1, y1 = rects[0]
    assert (x0, y0, y1) == (-3.0, -1.0, 1.0) and -0.2 <= x1 < -0.2 + cell
    assert np.isclose((x1 + 3.0) / cell % 1.0, 0.0) or np.isclose((x1 + 3.0) / cell % 1.0, 1.0)  # on the grid
    # A wall over the lower half of the view only: open rows above it, the same across.
    floor_wall = np.array([[[-100.0, -100.0, 5.0], [100.0, -1.0, 6.0]]])
    rects = open_rectangles(eye, axes, 1.0, 100.0, floor_wall)
    assert len(rects) == 1 and tuple(rects[0]) == (-3.0, rects[0, 1], 3.0, 1.0)
    assert -0.2 <= rects[0, 1] < -0.2 + cell  # the wall's top edge is at y = -1/5


@pytest.mark.parametrize(
    "level, pose, covered",
    [
        ("11_crossfire", (-7.0, -17.0, 90.0), True),  # outside the armoury, facing its wall
        ("10_cloister", (0.0, 10.333, 180.0), True),  # against the veil
        ("11_crossfire", (0.0, 0.0, 0.0), False),  # the arena, the sky over its walls
        ("04_armory", (3.3, 0.0, 225.0), False),  # a room's corner: sky only where the walls meet
    ],
)
def test_a_box_covering_the_view_hides_the_sky_and_no_pixel_changes(gl_ctx, monkeypatch, level, pose, covered):
    from across_dimensions.render import sky
    from tests.test_batch import _image

    game = Game(load_level(resolve_level(level)))
    game.step(Actions())
    x, z, yaw = pose
    game.place_player((x, float(game.player.position[1]), z, 0.0), np.radians(yaw), 0.0)
    frame = game.frame()
    assert frame.sky_boxes is not None
    left = _covered_area(sky.open_sky(frame, 1280, 720))
    assert left == 0.0 if covered else 0.0 < left < 1.0
    for fine in (0, sky.FINE_CELLS_PIXELS):  # the small test image in fine cells, then in three
        monkeypatch.setattr(sky, "FINE_CELLS_PIXELS", fine)
        drawn = _image(gl_ctx, frame)
        boxes, frame.sky_boxes = frame.sky_boxes, None  # the sky over the whole view
        whole = _image(gl_ctx, frame)
        frame.sky_boxes = boxes
        # The same picture: nothing left unwritten (the target starts black, the sky never is),
        # and at most a few sky pixels a star's texel apart (the sky's direction is interpolated
        # over other triangles: a last-bit difference can pick the texel next door).
        assert not (drawn == 0).all(axis=2).any() and not (whole == 0).all(axis=2).any()
        assert (drawn != whole).any(axis=2).sum() <= 0.001 * drawn.shape[0] * drawn.shape[1]
