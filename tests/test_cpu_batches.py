"""Per-entity work done as arrays: each batched path against the per-entity result it replaces.

The frame's entity batches find which instances meet the slice and the view, how far each reaches
along the slice's normal (the w cue) and which instances changed, for all instances at once; the
ghost layers test every entity for a ghost that would be the slice itself at once. Each must give
what the one-by-one code gives. No timing here: speed is in ``across-dimensions bench``.
"""

from __future__ import annotations

import numpy as np
import pytest

from across_dimensions.core.section import cross_section
from across_dimensions.core.section_batch import SectionBatch
from across_dimensions.core.section_batch_kernels import _instances_in_view
from across_dimensions.core.shapes import make_shape, tesseract
from across_dimensions.core.transform import PLANES, pose, rotation, scaling, translation
from across_dimensions.game.entity_sections import ALPHA, w_offset
from across_dimensions.game.systems import ghosts


@pytest.fixture(scope="module")
def meshes():
    return [make_shape("tesseract"), make_shape("5-cell"), make_shape("16-cell")]


def random_models(rng, n, spread=3.0, w_spread=1.0):
    out = []
    for _ in range(n):
        angles = {p: rng.uniform(-np.pi, np.pi) for p in PLANES}
        pos = (*rng.uniform(-spread, spread, 3), rng.uniform(-w_spread, w_spread))
        out.append(pose(pos, angles, scale=rng.uniform(0.5, 1.5)))
    return np.array(out)


def visible_per_instance(mv, center, radius, planes):
    """The test of one instance as the batch made it with numpy, one by one."""
    a = mv[:4, :4]
    stretch = np.sqrt(np.abs(a.T @ a).sum(axis=1).max())
    c = a @ center + mv[:4, 4]
    r = radius * stretch * (1.0 + 1e-6) + 1e-6
    in_slice = abs(c[3]) <= r
    r3 = np.sqrt(max(r * r - c[3] ** 2, 0.0))
    dist = planes[:, :3] @ c[:3] + planes[:, 3]
    return in_slice, in_slice and bool((dist >= -r3 * np.linalg.norm(planes[:, :3], axis=1)).all())


def test_instances_meet_the_slice_and_the_view_as_tested_one_by_one_and_have_det_s_orientation():
    rng = np.random.default_rng(3)
    mvs = random_models(rng, 400, spread=6.0, w_spread=2.0)
    mvs[::7] = mvs[::7] @ scaling((1.0, 3.0, 0.2, 1.5))  # stretched: the bound, not the exact radius
    centers, radii = rng.uniform(-0.5, 0.5, (400, 4)), rng.uniform(0.2, 1.5, 400)
    planes = np.array([[1.0, 0.0, 0.3, 2.0], [-0.5, 0.2, 1.0, 1.0], [0.0, -2.0, 0.0, 3.0]])
    mvs[::5] = mvs[::5] @ scaling((1.0, -1.0, 1.0, 1.0))  # mirrored: the other winding
    mvs[3] = mvs[3] @ scaling((1.0, 1.0, 0.0, 1.0))  # flat: too close to call, numpy's det decides
    in_slice, visible, flips = np.empty(400, bool), np.empty(400, bool), np.empty(400)
    unsure = _instances_in_view(mvs, centers, radii, planes, in_slice, visible, flips)
    want = np.array([visible_per_instance(m, c, r, planes) for m, c, r in zip(mvs, centers, radii)])
    np.testing.assert_array_equal(in_slice, want[:, 0])
    np.testing.assert_array_equal(visible, want[:, 1])
    assert 0 < visible.sum() < in_slice.sum() < 400  # every outcome occurs
    det = np.linalg.det(mvs[:, :4, :4])  # the orientation the per-object slicer takes
    assert unsure == 1 and flips[3] == 0.0
    sure = np.arange(400) != 3
    np.testing.assert_array_equal(flips[sure], np.where(det[sure] > 0, 1.0, -1.0))
    assert (flips < 0).sum() >= 60  # both orientations occur


def test_w_cue_in_each_instances_rows_is_the_one_made_per_entity(meshes):
    rng = np.random.default_rng(5)
    models = random_models(rng, 30)
    picks = [meshes[i % 3] for i in range(30)]
    camera = pose((0.3, 0.0, -1.0, 0.2), {"xw": 0.4, "yz": 0.1})
    batch, plain = SectionBatch(), SectionBatch()
    batch.update(range(30), picks, models, camera, w_cue=True)
    plain.update(range(30), picks, models, camera)
    keys, start, count, _ = batch.instances()
    cues = []
    for i, k in enumerate(keys):
        rows = batch.vertices[start[i] : start[i] + count[i]]
        cue = w_offset(picks[k], models[k], camera)
        np.testing.assert_allclose(rows[:, ALPHA], cue, atol=1e-5)
        np.testing.assert_array_equal(rows[:, :ALPHA], plain.vertices[slice(*_span(plain, k))][:, :ALPHA])
        cues += [cue] if count[i] else []
    assert len(cues) > 5 and max(map(abs, cues)) > 0.3
    assert (plain.vertices[:, ALPHA] == 1.0).all()  # without the cue: the colours' own alpha


def _span(batch, key):
    start, count = batch.instance_rows(key)
    return start, start + count


def test_changed_instances_move_back_and_the_rest_keep_their_triangles(meshes):
    """Updates that add, drop, move and reorder instances leave every instance with the
    triangles a fresh slice gives it."""
    rng = np.random.default_rng(11)
    models = random_models(rng, 40, spread=2.0, w_spread=0.5)
    mesh_of = {k: meshes[k % 3] for k in range(40)}
    camera = translation((0.0, 0.0, 0.0, 0.05))
    batch = SectionBatch(by_cells=False)
    live = list(range(25))
    for step in range(12):
        if step % 3 == 1:
            live = [k for k in live if rng.random() > 0.2] + [int(k) for k in rng.choice(40, 4)]
            live = list(dict.fromkeys(live))
        if step % 4 == 2:
            rng.shuffle(live)
        moved = rng.choice(40, 5)
        models[moved] = models[moved] @ translation((0.0, 0.0, 0.0, 0.01))
        batch.update(live, [mesh_of[k] for k in live], models[live], camera)
        keys, start, count, _ = batch.instances()
        assert sorted(keys) == sorted(live)
        assert start[-1] == len(batch.vertices)
        for i, k in enumerate(keys):
            tri = cross_section(mesh_of[k], camera, models[k])
            rows = batch.vertices[start[i] : start[i] + count[i]]
            np.testing.assert_array_equal(rows[:, 0:3], tri.vertices)
            assert batch.instance_rows(k) == (start[i], count[i])


def test_an_instance_cut_for_the_eye_is_cut_whole_again_once_the_eye_moves(meshes):
    """Changed instances leave out the triangles facing away from the eye; when the eye moves,
    those (and only those) are sliced again, whole, and stay so while they keep still."""
    rng = np.random.default_rng(7)
    models = random_models(rng, 12, spread=2.0, w_spread=0.3)
    picks = [meshes[k % 3] for k in range(12)]
    camera = translation((0.0, 0.0, 0.0, 0.05))
    whole = {k: len(cross_section(picks[k], camera, models[k]).vertices) for k in range(12)}
    batch = SectionBatch(by_cells=False)

    def rows():
        keys, _, count, _ = batch.instances()
        return dict(zip(keys, count.tolist()))

    eye = np.array([0.5, 1.0, -9.0])
    batch.update(range(12), picks, models, camera, eye=eye)  # all new: cut for this eye
    cut_for_eye = rows()
    assert all(cut_for_eye[k] <= whole[k] for k in range(12))
    assert sum(cut_for_eye.values()) < 0.7 * sum(whole.values())
    assert dict(zip(batch.instances()[0], batch.cut_counts > 0)) == {k: whole[k] > 0 for k in range(12)}
    batch.update(range(12), picks, models, camera, eye=eye)  # nothing changed
    assert batch.sliced == 0 and rows() == cut_for_eye
    models[3] = models[3] @ translation((0.0, 0.0, 0.0, 0.01))  # one moved, and the eye too
    batch.update(range(12), picks, models, camera, eye=eye + 1.0)
    assert batch.sliced == 12 and rows() == {**whole, 3: rows()[3]}  # the others whole again
    assert rows()[3] < len(cross_section(picks[3], camera, models[3]).vertices)  # it, for the new eye
    batch.update(range(12), picks, models, camera, eye=eye + 2.0)  # only it is cut again: whole
    assert batch.sliced < 12 and rows() == whole
    batch.update(range(12), picks, models, camera, eye=eye + 3.0)  # all whole: the eye is no matter
    assert batch.sliced == 0


def test_ghost_spans_say_what_same_as_slice_says_for_each_entity():
    rng = np.random.default_rng(2)
    slab, cell = tesseract(1.0), make_shape("24-cell")
    cases = []
    for i in range(60):
        deep = translation((*rng.uniform(-2, 2, 3), rng.uniform(-1, 1))) @ scaling((2.0, 1.0, 0.5, rng.uniform(0.2, 3)))
        if i % 4 == 1:
            deep = deep @ rotation("xw", 0.2)  # turned into w: never the same slice
        if i % 4 == 2:
            deep = deep @ rotation("xy", 0.7)  # turned in space only: still a prism along w
        cases.append((cell if i % 5 == 0 else slab, deep))
    caps = np.array([ghosts._caps(m) for m, _ in cases])
    models = np.array([m for _, m in cases])
    spans = ghosts.slice_spans(caps, models)
    for w, wg in [(0.0, 0.3), (0.5, -0.4), (-1.0, 1.2), (0.2, 0.25)]:
        same = (spans[:, 0] < min(w, wg)) & (max(w, wg) < spans[:, 1])
        want = [ghosts.same_as_slice(m, model, w, wg) for m, model in cases]
        np.testing.assert_array_equal(same, want)
    assert same.any() and not same.all()


@pytest.mark.slow
def test_animated_enemies_in_the_frames_batches_are_each_enemys_own_sections(tmp_path):
    """Ten held enemies (lifted trees and swarms of hyperspheres) at several animation poses: the
    frame's batches (the slice, and the ghost layers on either side) hold for each enemy the
    section the per-object slicer gives its posed mesh, and the w cue made for it alone, less
    the triangles that face away from the eye (the renderer skips those: the batches are drawn
    with inner faces culled), and say it has a section."""
    from across_dimensions.bench.systems import enemy_level_text
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game
    from across_dimensions.game.systems import enemies
    from across_dimensions.world.level import load_level

    path = tmp_path / "enemies.toml"
    path.write_text(enemy_level_text(10), encoding="utf-8")
    game = Game(load_level(path))
    game.step(Actions())
    enemies.hold(game, 0.0, 10**9)
    foes = [e for e in game.entities.of_kind("enemy")]
    kept = dropped = 0
    for ticks in (30, 95, 130, 200):  # poses across both kinds' keyframes (4.5 s and 6 s loops)
        for _ in range(ticks):
            game.step(Actions())
        game.frame(0.5)  # the ghost layers take turns: after two frames of one tick, each had its turn
        frame = game.frame(0.5)
        eye = np.asarray(frame.camera.position, np.float64)
        table = game.entity_models
        models = dict(zip((e.id for e in table.entities), table.models(game, 0.5)))
        es = game.entity_sections
        slices = [(es.batches["solid"], game.camera.slice_pose(0.0), True)]
        slices += [(batch, translation((0.0, 0.0, 0.0, w)), False) for batch, w in _ghost_batches(game)]
        for batch, camera, cue in slices:
            cuts = dict(zip(batch.instances()[0], batch.cut_counts))
            for e in foes:
                assert not batch.culled_by_view(e.id)  # all ten stand in front of the player
                start, count = batch.instance_rows(e.id)
                rows = batch.vertices[start : start + count]
                tri = cross_section(e.mesh, camera, models[e.id])
                alpha = w_offset(e.mesh, models[e.id], camera) if cue else tri.colors[:, 3]
                alpha = np.broadcast_to(alpha, len(tri.vertices))
                want = np.column_stack([tri.vertices, tri.normals, tri.colors[:, :3], alpha])
                front = _rows_in_order(rows, want)
                away = ((eye - tri.vertices[::3]) * tri.normals[::3]).sum(axis=1) < 0.0
                assert not (~front & ~away).any(), "a triangle facing the eye was left out"
                assert (cuts[e.id] > 0) == (len(tri.vertices) > 0)  # it has a section, faces away or not
                if cue:  # the slice's batch: what the radar asks
                    assert es.has_section(e.id) == (len(tri.vertices) > 0)
                kept, dropped = kept + front.sum(), dropped + (~front).sum()
    assert kept > 10_000 and dropped > 0.3 * (kept + dropped)  # most enemies are cut; about half faces away


def _rows_in_order(rows: np.ndarray, want: np.ndarray) -> np.ndarray:
    """Which triangles of ``want`` ``(3 t, 10)`` the ``rows`` ``(3 r, 10)`` hold, in order and none
    else: ``(t,) bool``."""
    held = np.zeros(len(want) // 3, bool)
    r = 0
    for i in range(len(held)):
        if r < len(rows) and np.allclose(rows[r : r + 3], want[3 * i : 3 * i + 3], atol=1e-5):
            held[i] = True
            r += 3
    assert r == len(rows), "the batch holds a triangle the per-object slicer does not give"
    return held


def _ghost_batches(game):
    """``(batch, w)`` of each ghost layer drawn in the last frame."""
    layers = ghosts.layers_of(game, game.player.position[3])
    assert len(layers) == 2
    return [(game.entity_sections.ghost_batches[layer.tag], layer.w) for layer in layers]
