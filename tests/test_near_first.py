"""The scenery drawn nearest piece first, with no depth pre-pass of its own: the order against
distances worked out by hand, the index buffer rewritten only when the order changes, and the
picture the same as the pre-pass drew."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import standing_frames

from across_dimensions.game.frame import Camera3, Drawable, Frame, Hud
from across_dimensions.render.context import Offscreen, RenderError
from across_dimensions.render.demo import box_mesh
from across_dimensions.render.near_first import faces_in_order, nearest_first, piece_boxes
from across_dimensions.render.renderer import Renderer
from across_dimensions.world.geometry import face_runs, merge_trimeshes

#: Three boxes along -z: 2, 6 and 12 m in front of an eye at the origin looking down -z.
CENTRES = [(0.0, 1.0, -12.0), (0.0, 1.0, -2.0), (0.0, 1.0, -6.0)]


def _boxes():
    parts = [box_mesh(c, (1.0, 2.0, 1.0), (0.5, 0.5 + 0.1 * i, 0.6, 1.0)) for i, c in enumerate(CENTRES)]
    return merge_trimeshes(parts), face_runs(parts)


def test_pieces_are_ordered_by_the_distance_from_the_eye_to_their_boxes():
    mesh, parts = _boxes()
    assert parts.tolist() == [0, 12, 24, 36]
    boxes = piece_boxes(mesh.vertices, mesh.faces, parts)
    assert np.allclose(boxes[1], [[-0.5, 0.0, -2.5], [0.5, 2.0, -1.5]])
    assert nearest_first(boxes, np.zeros(3)).tolist() == [1, 2, 0]
    assert nearest_first(boxes, np.array([0.0, 1.0, -20.0])).tolist() == [0, 2, 1]
    # Inside the farthest box: at distance 0, first; the two others by their gaps (3.5, 7.5 m).
    assert nearest_first(boxes, np.array([0.2, 1.0, -11.8])).tolist() == [0, 2, 1]
    # Beside the boxes, level with the middle one: its gap is the x distance alone.
    assert nearest_first(boxes, np.array([5.0, 1.0, -6.0])).tolist() == [2, 1, 0]


def test_faces_in_order_moves_whole_runs():
    parts = np.array([0, 2, 5, 6])  # runs of 2, 3 and 1 faces
    assert faces_in_order(parts, np.array([2, 0, 1])).tolist() == [5, 0, 1, 2, 3, 4]
    assert faces_in_order(parts, np.array([1, 2, 0])).tolist() == [2, 3, 4, 5, 0, 1]
    rng = np.random.default_rng(3)
    parts = np.concatenate([[0], np.cumsum(rng.integers(1, 13, 40))])
    order = rng.permutation(40)
    faces = faces_in_order(parts, order)
    assert sorted(faces.tolist()) == list(range(parts[-1]))
    runs = np.split(faces, np.cumsum(np.diff(parts)[order])[:-1])
    for run, j in zip(runs, order):
        assert run.tolist() == list(range(parts[j], parts[j + 1]))


@pytest.mark.gl
def test_the_index_buffer_holds_the_nearest_piece_first_and_is_rewritten_only_when_the_order_changes(gl_ctx):
    mesh, parts = _boxes()
    target = Offscreen(gl_ctx, 160, 90)
    r = Renderer(gl_ctx)
    try:

        def draw(z, yaw=np.pi):
            target.use()
            cam = Camera3(position=np.array([0.0, 1.0, z]), yaw=yaw)
            frame = Frame(cam, [Drawable("s", 0, mesh, parts=parts)], hud=Hud())
            r.draw(frame, hud=False)
            gm = r.meshes.meshes["s"]
            first = np.frombuffer(gm.ibo.read(size=12 * 3 * 4), np.uint32).reshape(12, 3)
            return first, r.stats.upload_bytes, r.stats.depth_calls  # this frame's

        first, _, depth_calls = draw(0.0)
        assert np.array_equal(first, mesh.faces[12:24]) and depth_calls == 0  # the nearest box, no pre-pass
        _, uploaded, _ = draw(0.5)  # the same order: nothing written
        assert uploaded == 0
        first, uploaded, _ = draw(-20.0, 0.0)  # past them all: the farthest-listed box is now nearest
        assert np.array_equal(first, mesh.faces[0:12]) and uploaded == mesh.faces.nbytes
    finally:
        r.release()
        target.release()


@pytest.mark.gl
def test_parts_that_do_not_cover_the_faces_are_refused(gl_ctx):
    mesh, _ = _boxes()
    target = Offscreen(gl_ctx, 64, 36)
    target.use()
    r = Renderer(gl_ctx)
    try:
        for parts in ([0, 12, 30], [0, 12, 12, 36], [1, 36]):
            frame = Frame(Camera3(position=np.zeros(3)), [Drawable("s", 0, mesh, parts=np.array(parts))], hud=Hud())
            with pytest.raises(RenderError, match="'s': parts must rise strictly from 0 to the face count 36"):
                r.draw(frame, hud=False)
        # A level without walls: no faces, in no parts.
        empty = Drawable("none", 0, merge_trimeshes([]), parts=face_runs([]))
        r.draw(Frame(Camera3(position=np.zeros(3)), [empty], hud=Hud()), hud=False)
    finally:
        r.release()
        target.release()


def test_the_levels_scenery_comes_in_pieces_one_a_box():
    from across_dimensions.world.level import load_level
    from across_dimensions.world.resources import resolve_level
    from across_dimensions.world.scene import build_scene

    scene = build_scene(load_level(resolve_level("10_cloister")))
    for mesh, parts in ((scene.static_mesh, scene.static_parts), (scene.floor_mesh, scene.floor_parts)):
        assert parts[-1] == len(mesh.faces) and set(np.diff(parts)) == {12}
    assert len(scene.static_parts) - 1 + len(scene.floor_parts) - 1 == len(scene.level.boxes)
    assert scene.open_parts[-1] == len(scene.open_mesh.faces) and len(scene.open_parts) - 1 == len(scene.level.meshes)


@pytest.mark.gl
def test_the_levels_drawn_in_pieces_look_as_with_the_pre_pass(gl_ctx):
    """The Cloister (arches before walls), Crossfire and the Tumbling Hall from standing points
    over their floors, drawn in pieces nearest first and, as before, with the whole scenery in
    the depth pre-pass: the same picture but for a few pixels where two faces meet at the same
    depth (the order decides which is drawn)."""
    target = Offscreen(gl_ctx, 320, 180)
    r = Renderer(gl_ctx)
    try:
        for level, pose, frame in standing_frames(("10_cloister", "11_crossfire", "03_tumbling_hall")):
            target.use()
            r.draw(frame, hud=False)
            pieces = {key: gm.parts for key, gm in r.meshes.meshes.items() if gm.parts is not None}
            assert {"static", "floor"} <= set(pieces)
            in_pieces = target.read_rgb().astype(int)
            for key in pieces:
                r.meshes.meshes[key].parts = None
            r.draw(frame, hud=False)
            for key, parts in pieces.items():
                r.meshes.meshes[key].parts = parts
            diff = np.abs(in_pieces - target.read_rgb()).max(axis=2)
            assert (diff > 2).mean() < 1e-3, (level, pose, (diff > 2).sum())
    finally:
        r.release()
        target.release()
