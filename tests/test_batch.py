"""The batched path: many objects sliced in one kernel call and drawn with one call per style.

What batching must not change: the triangles of each object (bit-identical to
the per-object slicer), the picture (a batched game frame against the
per-object frame it replaces, within the golden-image tolerance), and what is
visible (culling never drops an object that has a triangle in view). What it
must keep bounded: the renderer's GPU buffers over many spawn/remove cycles.
No timing here: speed is in ``across-dimensions bench scene`` / ``bench levels``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.core.cells import mesh_cells
from across_dimensions.core.frustum import frustum_project
from across_dimensions.core.frustum_batch import FrustumBatch, solid_edges
from across_dimensions.core.section import cross_section
from across_dimensions.core.section_batch import SHRINK_AFTER, SectionBatch, pool_part
from across_dimensions.core.shapes import make_shape
from across_dimensions.core.transform import PLANES, inverse, pose, translation
from across_dimensions.game.actions import Actions
from across_dimensions.game.entity_sections import view_planes
from across_dimensions.game.frame import Camera3, Frame, TriangleBatch
from across_dimensions.game.sim import Game
from across_dimensions.game.systems import sections
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import level_files

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def meshes():
    return [make_shape("120-cell"), make_shape("tesseract"), make_shape("5-cell")]


def random_models(rng, n, spread=4.0, w_spread=1.5):
    out = []
    for _ in range(n):
        angles = {p: rng.uniform(-np.pi, np.pi) for p in PLANES}
        pos = (*rng.uniform(-spread, spread, 3), rng.uniform(-w_spread, w_spread))
        out.append(pose(pos, angles, scale=rng.uniform(0.5, 1.5)))
    return np.array(out)


def rows_of(batch, key):
    start, count = batch.instance_rows(key)
    return batch.vertices[start : start + count]


def assert_same_triangles(rows, tri):
    """The batch's interleaved rows are exactly the per-object slicer's vertices, normals and colours."""
    assert len(rows) == len(tri.vertices)
    np.testing.assert_array_equal(rows[:, 0:3], tri.vertices)
    np.testing.assert_array_equal(rows[:, 3:6], tri.normals)
    np.testing.assert_array_equal(rows[:, 6:10], tri.colors)


def _area_vectors(positions):
    """Area-weighted normal ``(t, 3)`` of each triangle of ``(3t, 3)`` positions."""
    v = positions.astype(np.float64).reshape(-1, 3, 3)
    return 0.5 * np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])


def assert_same_section(rows, tri, mesh):
    """The batch's rows draw the per-object slicer's section.

    A mesh sliced tet by tet gives the very same triangles. A mesh sliced by
    cells (see core.cells) covers the same polygons with fewer triangles: same
    area and area-weighted normal, corners among the slicer's own points (to
    the bit), each triangle wound along its flat outward normal.
    """
    if mesh_cells(mesh) is None:
        assert_same_triangles(rows, tri)
        return
    if tri.is_empty:
        assert len(rows) == 0
        return
    got, want = _area_vectors(rows[:, 0:3]), _area_vectors(tri.vertices[tri.faces.ravel()])
    area = np.linalg.norm(want, axis=1).sum()
    assert np.linalg.norm(got, axis=1).sum() == pytest.approx(area, rel=1e-5)
    np.testing.assert_allclose(got.sum(axis=0), want.sum(axis=0), atol=1e-5 * area)
    assert len(rows) < len(tri.vertices)
    points = {tuple(p) for p in tri.vertices}
    assert all(tuple(p) in points for p in rows[:, 0:3])
    flat = rows[0::3, 3:6].astype(np.float64)
    assert (np.einsum("ij,ij->i", got, flat) >= -1e-7 * area).all()
    np.testing.assert_allclose(np.linalg.norm(flat, axis=1), 1.0, atol=1e-5)


def test_one_kernel_call_gives_each_objects_own_section(meshes):
    rng = np.random.default_rng(4)
    n = 40
    keys = [f"o{i}" for i in range(n)]
    ms = [meshes[i % 3] for i in range(n)]
    models = random_models(rng, n)
    camera = translation((0.0, 0.0, 0.0, 0.2))
    batch = SectionBatch(capacity_rows=3)  # tiny: the output must grow on the way
    assert batch.update(keys, ms, models, camera)
    total = 0
    for k, m, model in zip(keys, ms, models):
        tri = cross_section(m, camera, model)
        assert_same_section(rows_of(batch, k), tri, m)
        total += len(rows_of(batch, k))
    assert len(batch.vertices) == total > 0


def test_only_changed_instances_are_resliced_and_the_rest_kept(meshes):
    rng = np.random.default_rng(5)
    keys = list(range(12))
    ms = [meshes[i % 3] for i in keys]
    models = random_models(rng, 12, w_spread=0.3)
    batch = SectionBatch()
    batch.update(keys, ms, models)
    assert not batch.update(keys, ms, models)  # nothing moved: nothing to do
    assert batch.sliced == 0 and batch.changed_from == len(batch.vertices)
    models[3] = models[3] @ translation((0.0, 0.0, 0.0, 0.05))
    batch.update(keys, ms, models)
    assert batch.sliced < len(keys)
    models[3] = models[3] @ translation((0.0, 0.0, 0.0, -0.02))
    batch.update(keys, ms, models)
    # A moving instance has drifted to the back: only it is sliced and uploaded again.
    assert batch.sliced == 1
    start, count = batch.instance_rows(3)
    assert batch.changed_from == start and start + count == len(batch.vertices)
    for k in keys:
        assert_same_section(rows_of(batch, k), cross_section(ms[k], None, models[k]), ms[k])
    # Removing one keeps the others' triangles.
    batch.update(keys[1:], ms[1:], models[1:])
    for k in keys[1:]:
        assert_same_section(rows_of(batch, k), cross_section(ms[k], None, models[k]), ms[k])


def test_a_deferred_update_slices_when_finished_or_read(meshes):
    rng = np.random.default_rng(9)
    keys = list(range(9))
    ms = [meshes[i % 3] for i in keys]
    models = random_models(rng, 9, w_spread=0.3)
    now, later = SectionBatch(), SectionBatch()
    now.update(keys, ms, models)
    later.update(keys, ms, models, defer=True)
    assert later._pending is not None  # nothing sliced yet
    assert later.revision == now.revision and later.changed_from == now.changed_from
    assert np.array_equal(later.vertices, now.vertices)  # reading the rows slices them
    # A second update finishes the first before it starts from its rows.
    models[4] = models[4] @ translation((0.0, 0.0, 0.0, 0.05))
    now.update(keys, ms, models)
    later.update(keys, ms, models, defer=True)
    models[5] = models[5] @ translation((0.0, 0.0, 0.0, -0.05))
    now.update(keys, ms, models)
    later.update(keys, ms, models, defer=True)
    later.finish()
    assert later._pending is None and later.changed_from == now.changed_from
    assert np.array_equal(later.vertices, now.vertices)
    assert np.array_equal(later.cut_counts, now.cut_counts)
    for k in keys:
        assert_same_section(rows_of(later, k), cross_section(ms[k], None, models[k]), ms[k])


def test_meshes_no_longer_drawn_are_let_go():
    """Objects of ever new shapes spawned and removed: the batch does not keep every mesh it saw."""
    batch = SectionBatch()
    for i in range(60):
        mesh = make_shape("5-cell").with_color((0.1 * (i % 10), 0.5, 0.5, 1.0))  # a new mesh each time
        batch.update([i], [mesh], [pose((0.0, 0.0, 0.0, 0.05))])
        assert_same_triangles(rows_of(batch, i), cross_section(mesh, None, pose((0.0, 0.0, 0.0, 0.05))))
        # One start per instance and one past the last, after the pool starts again too (the
        # kernel does not check bounds: a start array left one entry long was written past).
        assert len(batch.instances()[1]) == 2
    assert len(batch._pool.meshes) <= 17


def test_a_mesh_met_again_by_another_batch_brings_what_it_brought_the_first(meshes):
    """A mesh's pooled arrays are made once and kept on it (for another batch, a pool started
    again, or made at a level's start ahead of play); the sections are the same either way,
    and a mesh of other colours brings its own."""
    mesh = make_shape("16-cell")
    first = SectionBatch()
    first.update([0], [mesh], [pose((0.0, 0.0, 0.0, 0.05))])
    part = pool_part(mesh)
    second = SectionBatch()
    second.update([0], [mesh], [pose((0.0, 0.0, 0.0, 0.05))])
    assert pool_part(mesh) is part
    assert np.array_equal(second.vertices, first.vertices)
    tinted = mesh.with_color((0.9, 0.2, 0.1, 1.0))
    assert pool_part(tinted).colors[0].tolist() == pytest.approx([0.9, 0.2, 0.1, 1.0])
    third = SectionBatch()
    third.update([0], [tinted], [pose((0.0, 0.0, 0.0, 0.05))])
    assert_same_section(rows_of(third, 0), cross_section(tinted, None, pose((0.0, 0.0, 0.0, 0.05))), tinted)


@pytest.mark.parametrize("with_states", [True, False])
def test_a_level_start_readies_the_meshes_of_things_spawned_later(monkeypatch, with_states):
    """The gun's first bullet (a 120-cell) and an enemy's first shot each cost a frame 20-30 ms
    when their meshes were first cut mid-level. Made ready at the level's start with the
    entities' (the systems' states hold them), play makes none; from the entities alone, it
    makes them on the frames they first appear."""
    from across_dimensions.core import section_batch
    from across_dimensions.game.replay import Replay
    from across_dimensions.world.resources import levels_dir, resolve_level

    rep = Replay.load(levels_dir() / "replays" / "09_hive.json")
    game = Game(load_level(resolve_level("09_hive"), arsenal=rep.arsenal), seed=rep.seed)
    game.entity_sections.prepare(game.entities, game.states if with_states else ())
    made, real = [], section_batch._chunks
    monkeypatch.setattr(section_batch, "_chunks", lambda layout: made.append(game.tick) or real(layout))
    kinds = set()
    for a, _ in zip(rep.actions, range(240)):
        game.step(a)
        game.frame()
        kinds |= {e.kind for e in game.entities}
    assert {"bullet", "enemy_shot"} <= kinds  # both spawned within these ticks
    assert (made == []) == with_states, made


def test_culling_never_drops_an_object_with_a_triangle_in_view(meshes):
    """Random poses around a camera: every culled object's full section lies outside the view."""
    rng = np.random.default_rng(6)
    cam = Camera3(np.array([0.0, 1.0, 0.0]), yaw=0.4, pitch=-0.1, fov_y_deg=70.0, far=40.0)
    planes = view_planes(cam, aspect=16 / 9)
    checked = 0
    for trial in range(6):
        n = 60
        keys = list(range(n))
        ms = [meshes[i % 3] for i in keys]
        models = random_models(rng, n, spread=12.0, w_spread=2.0)
        w = rng.uniform(-0.5, 0.5)
        camera = translation((0.0, 0.0, 0.0, w))
        culled = SectionBatch()
        culled.update(keys, ms, models, camera, planes)
        assert culled.culled > 0
        for k in keys:
            tri = cross_section(ms[k], camera, models[k])
            got = rows_of(culled, k)
            if len(got):
                assert_same_section(got, tri, ms[k])
                continue
            if tri.is_empty:
                continue
            # Culled by the view: no vertex of the section may be inside all six planes.
            v = tri.vertices.astype(np.float64)
            inside = (v @ planes[:, :3].T + planes[:, 3] >= 0).all(axis=1)
            assert not inside.any(), f"trial {trial}: object {k} was culled but has a vertex in view"
            checked += 1
    assert checked > 0  # the view test did cull objects whose sections exist


def test_frustum_batch_projects_like_the_per_object_projection(meshes):
    rng = np.random.default_rng(7)
    n = 6
    cam4 = translation((0.0, 0.0, 0.0, -3.0))
    models = random_models(rng, n, spread=0.3, w_spread=0.3)
    mvs = np.array([inverse(cam4) @ m for m in models])
    place = np.array([[1.0 + i, i, -i, 2.0] for i in range(n)])
    ms = [meshes[i % 3] for i in range(n)]
    batch = FrustumBatch()
    batch.update(ms, mvs, place, fov_deg=60.0, silhouette=False)
    faces = batch.faces
    done = 0
    for i in range(n):
        ref = frustum_project(ms[i], cam4, 60.0, model=models[i])
        got = batch.vertices[faces[done : done + len(ref.faces)]][..., 0:3]
        want = ref.vertices[ref.faces] * place[i, 0] + place[i, 1:]
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-5)
        done += len(ref.faces)
    assert done == len(faces)
    # The 120-cell's drawn edges are the polytope's 1200, not the triangulation's diagonals.
    assert len(solid_edges(meshes[0])) == 1200 and len(solid_edges(meshes[1])) == 32


def test_frustum_silhouette_drops_only_hidden_faces(gl_ctx, meshes):
    """Drawn opaque, the outline faces alone give the picture all faces give, with far fewer triangles."""
    from across_dimensions.bench.scene import FRUSTUM_FOV, _Scene, spin

    pictures, counts = {}, {}
    for how in ("all", "outline", "facing"):
        scene = _Scene("frustum", 6, meshes[0])
        b = scene.batch
        eye = scene.camera.position if how == "facing" else None
        b.update(scene.meshes, scene.cam4 @ spin(6, 0.4), scene.place, FRUSTUM_FOV, silhouette=how != "all", eye=eye)
        tb = TriangleBatch("f", 1, b.vertices, "solid", 0, b.faces, b.edges, b.topology_revision)
        pictures[how] = _image(gl_ctx, Frame(scene.camera, batches=[tb]), (480, 270))
        counts[how] = len(b.faces), len(b.edges)
    assert counts["outline"][0] < 0.4 * counts["all"][0]
    assert _within_golden_tolerance(pictures["outline"], pictures["all"])
    # The outline is closed: its side facing away from the 3D eye is hidden by the other.
    assert 0.3 * counts["outline"][0] < counts["facing"][0] < 0.6 * counts["outline"][0]
    assert counts["facing"][1] < 0.8 * counts["outline"][1]
    assert _within_golden_tolerance(pictures["facing"], pictures["outline"])
    assert (pictures["facing"] != pictures["facing"][0, 0]).any()
    # An eye inside a projection's box may see its inside: every outline face is kept.
    scene = _Scene("frustum", 1, meshes[0])
    b = scene.batch
    b.update(scene.meshes, scene.cam4, scene.place, FRUSTUM_FOV)
    outline = len(b.faces)
    b.update(scene.meshes, scene.cam4, scene.place, FRUSTUM_FOV, eye=scene.place[0, 1:])
    assert len(b.faces) == outline
    # A camera inside the near hyperplane of an object sees into it: every face is kept.
    b = FrustumBatch()
    b.update([meshes[0]], [translation((0.0, 0.0, 0.0, 0.5))], [[1.0, 0.0, 0.0, 0.0]], 60.0)
    full = FrustumBatch()
    full.update([meshes[0]], [translation((0.0, 0.0, 0.0, 0.5))], [[1.0, 0.0, 0.0, 0.0]], 60.0, silhouette=False)
    assert len(b.faces) == len(full.faces) > 0


def _image(ctx, frame, size=(320, 180)):
    from across_dimensions.render.context import Offscreen
    from across_dimensions.render.renderer import Renderer

    with Offscreen(ctx, *size) as target:
        target.use()
        renderer = Renderer(ctx)
        renderer.draw(frame, target.viewport)
        img = target.read_rgb()
        renderer.release()
    return img


def _within_golden_tolerance(a, b):
    # The golden-image rule of tests/conftest.py: mean abs diff < 2/255 and < 1% of pixels off by > 32.
    diff = np.abs(a.astype(int) - b.astype(int))
    return diff.mean() < 2.0 and (diff.max(axis=2) > 32).mean() < 0.01


@pytest.mark.parametrize("name", ["02_crystal_cache", "03_tumbling_hall", "04_armory"])
def test_batched_game_frame_matches_the_per_object_frame(gl_ctx, name):
    path = next(p for p in level_files() if p.stem == name)
    game = Game(load_level(path))
    for _ in range(40):
        game.step(Actions(forward=0.4, yaw=0.03))
    batched = game.frame()
    assert batched.batches, "the level's entities should be drawn as batches"
    per_object = game.frame()
    per_object.batches = []
    sections.draw_per_object(game, per_object, 1.0)
    assert any(d.key.startswith("entity:") for d in per_object.drawables)
    a, b = _image(gl_ctx, batched), _image(gl_ctx, per_object)
    assert _within_golden_tolerance(a, b)
    assert (a != a[0, 0]).any()  # not a blank picture


def test_gpu_buffers_end_where_they_began_after_spawn_and_remove_cycles(gl_ctx, meshes):
    """Objects spawned and removed many times: the renderer ends with the bytes it started with."""
    from across_dimensions.render.context import Offscreen
    from across_dimensions.render.renderer import Renderer

    rng = np.random.default_rng(8)
    cam = Camera3(np.array([0.0, 0.0, -12.0]))
    batch = SectionBatch()
    with Offscreen(gl_ctx, 64, 36) as target:
        target.use()
        renderer = Renderer(gl_ctx)

        def frame_with(n, t):
            keys = list(range(n))
            models = random_models(np.random.default_rng(t), n, spread=3.0, w_spread=0.2)
            batch.update(keys, [meshes[0]] * n, models)
            tb = TriangleBatch("objects", batch.revision, batch.vertices, "solid", batch.changed_from)
            renderer.draw(Frame(cam, batches=[tb]), target.viewport, hud=False)

        frame_with(1, 0)
        start_gpu, start_cpu = renderer.gpu_bytes(), batch.capacity_bytes
        peak = start_gpu
        for cycle in range(12):
            for n in (5, 40, int(rng.integers(60, 120)), 20, 2):
                frame_with(n, cycle * 10 + n)
                peak = max(peak, renderer.gpu_bytes())
            frame_with(1, 0)
        for _ in range(SHRINK_AFTER):  # the scene settles
            frame_with(1, 0)
        assert peak > 4 * start_gpu  # the scene did grow the buffers
        assert renderer.gpu_bytes() == start_gpu
        assert batch.capacity_bytes == start_cpu
        # Leaving the frame altogether frees the batch's buffers.
        renderer.draw(Frame(cam), target.viewport, hud=False)
        assert renderer.gpu_bytes() == 0
        renderer.release()


def test_render_scale_default_follows_the_gl_renderer():
    from across_dimensions.render.scale import SOFTWARE_SCALE, default_render_scale

    assert default_render_scale("llvmpipe (LLVM 15.0.6, 256 bits)") == SOFTWARE_SCALE < 1.0
    assert default_render_scale("softpipe") == SOFTWARE_SCALE
    assert default_render_scale("NVIDIA GeForce RTX 3060/PCIe/SSE2") == 1.0


def test_scaled_target_upscales_the_scene(gl_ctx):
    """A frame drawn at scale 0.5 and upscaled looks like the full-size frame (blurred edges aside)."""
    from across_dimensions.render.context import Offscreen
    from across_dimensions.render.renderer import Renderer
    from across_dimensions.render.scale import ScaledTarget

    game = Game(load_level(next(p for p in level_files() if p.stem == "03_tumbling_hall")))
    frame = game.frame()
    full = _image(gl_ctx, frame, (320, 180))
    renderer = Renderer(gl_ctx)
    scaled = ScaledTarget(gl_ctx, 0.5)
    with Offscreen(gl_ctx, 320, 180) as screen:
        assert scaled.begin(screen.size) and scaled.viewport == (0, 0, 160, 90)
        renderer.draw(frame, scaled.viewport, hud=False)
        scaled.present(screen.fbo, screen.viewport)
        renderer.draw_overlay(frame, screen.viewport)
        img = screen.read_rgb()
    scaled.release()
    renderer.release()
    diff = np.abs(img.astype(int) - full.astype(int))
    assert diff.mean() < 12  # same picture, softer
    assert (diff > 0).any()  # but not the full-size one


def _run(*args, timeout=600):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), env.get("PYTHONPATH")) if p)
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", *args], capture_output=True, text=True, timeout=timeout, env=env
    )


def test_bench_scene_prints_rows_as_json():
    r = _run("bench", "scene", "--n", "1,2", "--frames", "2", "--json")
    assert r.returncode == 0, r.stderr
    rows = json.loads(r.stdout)
    keys = {"mode", "n", "fps", "projection_ms", "submit_ms", "raster_ms", "baseline_fps"}
    assert [(row["mode"], row["n"]) for row in rows] == [("section", 1), ("section", 2), ("frustum", 1), ("frustum", 2)]
    for row in rows:
        assert keys <= set(row)
        assert row["fps"] > 0 and row["baseline_fps"] > 0 and row["triangles"] > 0
    assert "Targets" in r.stderr and "per-object CPU overhead" in r.stderr


def test_bench_scene_writes_a_plot_or_says_what_it_needs(tmp_path):
    out = tmp_path / "fps.png"
    r = _run("bench", "scene", "--n", "1", "--frames", "1", "--modes", "section", "--out", str(out))
    assert r.returncode == 0, r.stderr
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        assert "pip install across-dimensions[plot]" in r.stdout
    else:
        assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bench_scene_refuses_bad_options():
    r = _run("bench", "scene", "--n", "0")
    assert r.returncode == 2 and "--n" in r.stderr and "Traceback" not in r.stderr
    r = _run("bench", "scene", "--render-scale", "2")
    assert r.returncode == 2 and "--render-scale" in r.stderr


def test_bench_levels_reports_the_worst_frame_of_a_level():
    r = _run("bench", "levels", "--level", "06_bridge", "--grid", "1", "--frames", "1", "--json", "--no-memory")
    assert r.returncode == 0, r.stderr
    (row,) = json.loads(r.stdout)
    assert row["level"] == "06_bridge" and row["poses"] == 8
    assert row["worst_ms"] >= row["median_ms"] > 0
    assert row["full_worst_cpu_ms"] > 0 and row["geometry"] > 0
    # Where the worst full-size frame's time goes: the scenery is drawn, and the scenery, the 4D
    # matter and the sky behind them shade about the view once (the worst pose may face the sky).
    passes = {p["pass"]: p for p in row["passes"]}
    assert passes["scenery"]["triangles"] > 0
    assert 0.8 < sum(passes[k]["overdraw"] for k in ("scenery", "matter", "sky")) < 3.0, passes
    # At a render scale below 1 (llvmpipe's default), the same for its worst frame: the scene at
    # that scale, then the upscale, a full-size pass of its own.
    scaled = {p["pass"]: p for p in row["passes_at_scale"]}
    if row["render_scale"] < 1.0:
        assert scaled["scenery"]["triangles"] > 0 and scaled["upscale"]["ms"] > 0.0, scaled
        assert 0.8 < sum(scaled[k]["overdraw"] for k in ("scenery", "matter", "sky")) < 3.0, scaled
        assert f"render scale {row['render_scale']:g}, worst pose, CPU ms per pass" in r.stderr
    else:
        assert not scaled
    assert "[PASS]" in r.stderr or "[FAIL]" in r.stderr
    assert "full size" in r.stderr and "Peak memory" not in r.stderr


def test_bench_play_draws_every_frame_of_a_replay_and_lists_the_longest():
    r = _run("bench", "play", "--level", "00_arrival", "--json")
    assert r.returncode == 0, r.stderr
    (row,) = json.loads(r.stdout)
    replay = json.loads((REPO / "levels" / "replays" / "00_arrival.json").read_text())
    assert row["level"] == "00_arrival" and row["outcome"] == "complete"
    assert row["frames"] == replay["final"]["ticks"]  # one frame a tick, as the game at 60 Hz
    assert row["first_ms"] > row["median_ms"] > 0  # the first frame builds the shaders
    longest = [f["ms"] for f in row["longest"]]
    assert longest == sorted(longest, reverse=True) and longest[0] >= row["p99_ms"] >= row["median_ms"]
    assert "stutters" in r.stderr and "median is each row's baseline" in r.stderr
    r = _run("bench", "play", "--level", "no_such_level")
    assert r.returncode == 2 and "--level" in r.stderr and "Traceback" not in r.stderr
    r = _run("bench", "play", "--level", "prologue")  # a level without a 4D replay to draw
    assert r.returncode == 2 and "not a shipped 4D level with a replay" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.slow
def test_bench_levels_measures_the_peak_memory_of_play():
    """The memory target: ``play`` in a child process on its own display, its peak resident set."""
    r = _run("bench", "levels", "--level", "00_arrival", "--grid", "1", "--frames", "1", timeout=1800)
    assert r.returncode == 0, r.stderr
    line = next(x for x in r.stdout.splitlines() if "peak memory of play" in x)
    assert "00_arrival" in line and "MB" in line and ("[PASS]" in line or "[FAIL]" in line), line


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="reads /proc")
def test_a_childs_peak_memory_is_its_own_not_its_parents():
    """Started by a process holding 300 MB, a child that holds 60 MB peaks at about 60 MB. The
    kernel's figure at its exit (``ru_maxrss``) says 300: Linux carries the parent's peak
    across ``exec``, which is how ``bench levels`` once measured itself after every level."""
    from across_dimensions.bench.memory import _wait_watching

    ballast = np.ones(300 * 2**20 // 8)  # 300 MB, every page touched
    code = "import time; b = bytearray(60 * 2**20); time.sleep(0.6)"
    child = subprocess.Popen([sys.executable, "-c", code])
    status, usage, peak_kb = _wait_watching(child.pid)
    child.returncode = 0  # reaped
    assert os.waitstatus_to_exitcode(status) == 0
    assert 60 <= peak_kb / 1024 < 150, peak_kb
    assert usage.ru_maxrss / 1024 >= 300, usage.ru_maxrss  # what it measured before
    del ballast


def test_render_scale_setting_is_checked(tmp_path):
    from across_dimensions.app.settings import Settings, load_settings

    assert Settings().render_scale == "auto"
    assert Settings(render_scale=0.75).render_scale == 0.75
    assert Settings(render_scale="AUTO").render_scale == "auto"
    for bad in (0.3, 1.5, "half", True):
        with pytest.raises(ValueError, match="render_scale"):
            Settings(render_scale=bad)
    path = tmp_path / "settings.toml"
    path.write_text("render_scale = 2.0\n")
    settings, warnings = load_settings(path)
    assert settings.render_scale == "auto"
    (line,) = [w for w in warnings if "render_scale" in w]
    assert str(path) in line and "0.5 to 1.0" in line


def test_wire_entities_stay_single_drawables(gl_ctx):
    """Outlined entities (the field weapon's wireframes) keep their own drawable: edges are derived per mesh."""
    path = next(p for p in level_files() if p.stem == "03_tumbling_hall")
    game = Game(load_level(path))
    game.step(Actions())
    w = float(game.player.position[3])
    shown = game.entity_table().reaching(w)
    assert shown
    shown[0].style = "wire"
    frame = game.frame()
    wires = [d for d in frame.drawables if d.style == "wire" and d.key == f"entity:{shown[0].id}"]
    assert len(wires) == 1
    assert all(f"entity:{shown[0].id}" not in b.members for b in frame.batches)
    assert any(f"entity:{e.id}" in b.members for b in frame.batches for e in shown[1:])
    _image(gl_ctx, frame)  # draws without complaint


def _boxes_extruded(centers):
    """Unit boxes at ``centers`` (sharing faces) swept along w into one 4D solid."""
    from across_dimensions.core.lift import box_solid, extrude

    verts, tets = [], []
    for c in centers:
        v, t = box_solid(c, 1.0)
        tets.append(t + sum(len(x) for x in verts))
        verts.append(v)
    v = np.concatenate(verts)
    uniq, inv = np.unique(np.round(v, 6), axis=0, return_inverse=True)
    return extrude(uniq, inv.reshape(-1)[np.concatenate(tets)], [-0.5, 0.5])


def test_cells_are_found_from_the_tets_alone():
    """Polychora split into their convex cells; meshes whose cells are tets, or not convex, are sliced by tets."""
    for name, cells, edges in (("120-cell", 120, 30), ("tesseract", 8, 12), ("24-cell", 24, 12)):
        c = mesh_cells(make_shape(name))
        assert len(c.radii) == cells and (np.diff(c.edge_start) == edges).all(), name
        assert (c.edges[:, 0] < c.edges[:, 1]).all()
    for name in ("5-cell", "16-cell", "600-cell"):
        assert mesh_cells(make_shape(name)) is None, name  # each tet is a cell already
    # Swept boxes: a convex block is sliced by cells; an L-shaped one has a non-convex cell (its
    # 3D caps), so the whole mesh is sliced tet by tet.
    block = mesh_cells(_boxes_extruded([(0, 0, 0), (1, 0, 0)]))
    assert block is not None and len(block.radii) == 8  # a 4D box: 2 caps and 6 sides
    assert mesh_cells(_boxes_extruded([(0, 0, 0), (1, 0, 0), (0, 1, 0)])) is None


def test_slicing_by_tets_stays_the_per_object_slicer(meshes):
    rng = np.random.default_rng(9)
    models = random_models(rng, 9, w_spread=0.4)
    batch = SectionBatch(by_cells=False)
    batch.update(range(9), [meshes[i % 3] for i in range(9)], models)
    for k in range(9):
        assert_same_triangles(rows_of(batch, k), cross_section(meshes[k % 3], None, models[k]))


def test_cells_draw_the_picture_tets_draw_with_far_fewer_triangles(gl_ctx, meshes):
    """Rotating 120-cells and tesseracts filling the view, sliced by cells and by tets."""
    from across_dimensions.bench.scene import grid, spin

    n = 24
    centers, dist = grid(n)
    models = spin(n, 0.7)
    models[:, :3, 4] = centers
    ms = [meshes[i % 2] for i in range(n)]
    cam = Camera3(np.zeros(3), fov_y_deg=75.0, far=4 * dist)
    pictures, rows = {}, {}
    for by_cells in (True, False):
        batch = SectionBatch(by_cells=by_cells)
        batch.update(range(n), ms, models)
        tb = TriangleBatch("objects", 1, batch.vertices, "solid", 0)
        pictures[by_cells] = _image(gl_ctx, Frame(cam, batches=[tb]), (640, 360))
        rows[by_cells] = len(batch.vertices)
    assert rows[True] < 0.3 * rows[False]
    assert _within_golden_tolerance(pictures[True], pictures[False])
    diff = np.abs(pictures[True].astype(int) - pictures[False].astype(int)).max(axis=2)
    assert (diff > 8).mean() < 0.002  # a few edge pixels at most: the colours agree too
    assert (pictures[True] != pictures[True][0, 0]).any(axis=2).mean() > 0.1  # objects fill the view


def test_cells_facing_away_from_the_eye_are_left_out_and_the_picture_stays(gl_ctx, meshes):
    """With an eye, a convex section's far half is not written (the rasterizer would cull it,
    drawing outside only): about half the rows, and not one pixel changes, mirrored instances
    and an eye off the axis included."""
    from across_dimensions.bench.scene import grid, spin

    n = 24
    centers, dist = grid(n)
    models = spin(n, 1.3)
    models[:, :3, 4] = centers
    models[::5] = models[::5] @ np.diag([-1.0, 1.0, 1.0, 1.0, 1.0])  # some mirrored
    ms = [meshes[i % 2] for i in range(n)]
    for eye in (np.zeros(3), np.array([1.5, -0.8, 0.4])):
        cam = Camera3(eye, fov_y_deg=75.0, far=4 * dist)
        pictures, rows = {}, {}
        for seen_from in (None, eye):
            batch = SectionBatch()
            batch.update(range(n), ms, models, eye=seen_from)
            tb = TriangleBatch("objects", 1, batch.vertices, "solid", 0, outside_only=True)
            pictures[seen_from is None] = _image(gl_ctx, Frame(cam, batches=[tb]), (640, 360))
            rows[seen_from is None] = len(batch.vertices)
            assert (batch.cut_counts > 0).all()  # every one still has its section
        assert 0.35 * rows[True] < rows[False] < 0.65 * rows[True], rows
        np.testing.assert_array_equal(pictures[True], pictures[False])


def test_cells_keep_winding_under_mirrors_and_slices_through_vertices(meshes):
    rng = np.random.default_rng(10)
    models = random_models(rng, 6, spread=1.0, w_spread=0.4) @ np.diag([-1.0, 1.0, 1.0, 1.0, 1.0])  # mirrored
    models = np.concatenate([models, [translation((0.0, 0.0, 0.0, 0.5))] * 2])  # w = 0 through a tesseract's cell
    ms = [meshes[i % 2] for i in range(8)]
    batch = SectionBatch()
    batch.update(range(8), ms, models)
    for k in range(8):
        assert_same_section(rows_of(batch, k), cross_section(ms[k], None, models[k]), ms[k])
