"""The cross-section kernel's inner paths and scratch memory (issue 10, point 4).

The kernel takes different paths for the same slice (camera space for every
vertex or only the cut tets' vertices; each section point per tet or once per
edge) and reuses memory between calls. None of that may show in the output:
these tests check that every path gives the same bits, and that reused memory
never overwrites a section someone still holds. Speed is in ``across-dimensions
bench`` (``core/bench.py``), not here.
"""

from __future__ import annotations

import threading

import numpy as np
import pytest

from across_dimensions.core import section as S
from across_dimensions.core import shapes
from across_dimensions.core import transform as T
from across_dimensions.core.bench import tiled_scene
from across_dimensions.core.mesh import TetMesh4, cross4


def arrays(tri):
    return tri.vertices.copy(), tri.normals.copy(), tri.colors.copy()


def same_bits(a, b):
    return all(np.array_equal(x, y) for x, y in zip(arrays(a), arrays(b)))


def coloured(mesh):
    """``mesh`` with random vertex colours, so colour interpolation is checked too."""
    rng = np.random.default_rng(3)
    return TetMesh4(mesh.vertices, mesh.tets, rng.uniform(0, 1, (len(mesh.vertices), 4)).astype(np.float32))


@pytest.fixture(scope="module")
def dense():
    """Every copy of the 600-cell cut: the edge path, camera space for every vertex."""
    return coloured(tiled_scene(shapes.cell600(), 6_000))


def test_edge_path_and_tet_path_give_the_same_bits(dense, monkeypatch):
    cam = T.translation((0, 0, 0, 0.013))
    by_edge = S.cross_section(dense, cam)
    assert S._workspace(dense, S.mesh_clusters(dense)).edges is not None  # the edge path ran
    fresh = coloured(tiled_scene(shapes.cell600(), 6_000))
    monkeypatch.setattr(S, "EDGE_TABLE_FRACTION", 0)  # never the edge path
    by_tet = S.cross_section(fresh, cam)
    assert S._workspace(fresh, S.mesh_clusters(fresh)).edges is None
    assert len(by_edge) > 1000 and same_bits(by_edge, by_tet)


@pytest.mark.parametrize("by_edge", [False, True])
def test_camera_space_of_every_vertex_or_only_the_cut_ones_gives_the_same_bits(dense, monkeypatch, by_edge):
    cam = T.translation((0, 0, 0, 0.013))
    monkeypatch.setattr(S, "EDGE_TABLE_FRACTION", 16 if by_edge else 0)
    monkeypatch.setattr(S, "EVERY_VERTEX_FRACTION", 10**9)
    every = S.cross_section(dense, cam)
    monkeypatch.setattr(S, "EVERY_VERTEX_FRACTION", 0)
    only_cut = S.cross_section(dense, cam)
    assert len(every) > 1000 and same_bits(every, only_cut)


def test_culling_changes_no_bit():
    # Copies spread along w: few tets cut among many vertices.
    scene = coloured(tiled_scene(shapes.cell600(), 30_000, spread_w=20.0))
    cam = T.translation((0, 0, 0, 0.3))
    culled, full = S.cross_section(scene, cam), S.cross_section(scene, cam, cull=False)
    assert 0 < 4 * len(full) < len(scene.vertices)
    assert same_bits(culled, full)


def test_a_held_section_is_never_overwritten(dense):
    held = S.cross_section(dense, T.translation((0, 0, 0, 0.013)))
    before = arrays(held)
    for w in (-0.4, 0.2, 0.013, 0.6):  # more sections than output blocks are kept
        S.cross_section(dense, T.translation((0, 0, 0, w)))
    assert all(np.array_equal(x, y) for x, y in zip(arrays(held), before))
    # A dropped section's memory is reused, and the new section is still right.
    again = S.cross_section(dense, T.translation((0, 0, 0, 0.013)))
    del held
    assert same_bits(again, S.cross_section(dense, T.translation((0, 0, 0, 0.013))))


def test_a_view_of_a_section_keeps_it_alive(dense):
    view = S.cross_section(dense, T.translation((0, 0, 0, 0.013))).colors[:10]  # the section itself is dropped
    before = view.copy()
    for w in (-0.4, 0.2, 0.5, 0.6, 0.7):
        S.cross_section(dense, T.translation((0, 0, 0, w)))
    np.testing.assert_array_equal(view, before)


def test_faces_are_the_unwelded_numbering_and_read_only():
    tri = S.cross_section(shapes.cell600(), T.translation((0, 0, 0, 0.1)))
    np.testing.assert_array_equal(tri.faces, np.arange(3 * len(tri), dtype=np.uint32).reshape(-1, 3))
    assert tri.faces.dtype == np.uint32 and not tri.faces.flags.writeable
    assert tri.vertices.flags.c_contiguous and tri.normals.flags.c_contiguous and tri.colors.flags.c_contiguous


def test_threads_slicing_one_mesh_take_turns(dense):
    poses = [T.translation((0, 0, 0, w)) for w in (-0.3, 0.013, 0.25, 0.5)]
    expected = [arrays(S.cross_section(dense, p)) for p in poses]
    results = {}

    def work(k):
        for _ in range(5):
            results[k] = arrays(S.cross_section(dense, poses[k]))

    threads = [threading.Thread(target=work, args=(k,)) for k in range(len(poses))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k, exp in enumerate(expected):
        assert all(np.array_equal(x, y) for x, y in zip(results[k], exp))


def test_padded_case_table_repeats_a_triangles_last_edge():
    for mask in range(16):
        k = S.CASE_COUNT[mask]
        np.testing.assert_array_equal(S.CASE_EDGES_PADDED[mask, :k], S.CASE_EDGES[mask, :k])
        if k == 3:
            np.testing.assert_array_equal(S.CASE_EDGES_PADDED[mask, 3], S.CASE_EDGES[mask, 2])
        for e in range(k):
            a, b = sorted(S.CASE_EDGES[mask, e])
            assert tuple(S.TET_EDGE_PAIRS[S.CASE_LOCAL_EDGES[mask, e]]) == (a, b)


def test_a_cases_winding_is_the_same_for_every_tet():
    """CASE_REVERSED against the winding measured from each polygon's own corners."""
    rng = np.random.default_rng(11)
    seen = set()
    for _ in range(3000):
        p = rng.normal(size=(4, 4))
        mask = int(sum((p[i, 3] > 0) << i for i in range(4)))
        k = S.CASE_COUNT[mask]
        if k == 0:
            continue
        pts = []
        for a, b in S.CASE_EDGES[mask, :k]:
            s = p[a, 3] / (p[a, 3] - p[b, 3])
            pts.append(p[a, :3] + s * (p[b, :3] - p[a, :3]))
        normal = cross4(p[1] - p[0], p[2] - p[0], p[3] - p[0])[:3]
        # Both diagonals of a quad (robust to slivers), two edges of a triangle.
        if k == 4:
            poly = np.cross(pts[2] - pts[0], pts[3] - pts[1])
        else:
            poly = np.cross(pts[1] - pts[0], pts[2] - pts[0])
        assert (poly @ normal < 0) == bool(S.CASE_REVERSED[0, mask]), mask
        assert S.CASE_REVERSED[1, mask] == 1 - S.CASE_REVERSED[0, mask]
        seen.add(mask)
    assert seen == set(range(1, 15))


def _sheared_mirror():
    m = np.eye(5)
    m[:4, :4] = [[-1.3, 0.4, 0.0, 0.2], [0.1, 0.8, 0.3, 0.0], [0.0, -0.5, 1.1, 0.3], [0.2, 0.0, 0.4, 0.9]]
    return m


@pytest.mark.parametrize("mirror", [False, True])
def test_normals_turned_from_object_space_are_the_camera_space_normals(mirror):
    """Under a shear (and a mirror), each triangle's normal is the camera-space tet's and the winding agrees."""
    mesh = shapes.cell600()
    model = _sheared_mirror() if mirror else T.pose((0.1, 0, 0, 0.05), {"xw": 0.4, "yz": 0.3}, (1.0, 1.5, 0.7, 1.2))
    assert (np.linalg.det(model[:4, :4]) < 0) == mirror
    cam = T.translation((0, 0, 0, 0.013))  # off any vertex
    fast, slow = S.cross_section(mesh, cam, model), S.cross_section_reference(mesh, cam, model)
    assert len(fast) == len(slow) > 100
    key = lambda tri: np.lexsort(np.round(tri.vertices[tri.faces].reshape(len(tri), 9), 4).T)  # noqa: E731
    f, s = key(fast), key(slow)
    np.testing.assert_allclose(fast.vertices[fast.faces][f], slow.vertices[slow.faces][s], atol=1e-5)
    np.testing.assert_allclose(fast.normals[::3][f], slow.normals[::3][s], atol=1e-5)
    # Counter-clockwise seen from outside: the face's own normal along the outward one.
    v = fast.vertices.astype(np.float64)[fast.faces]
    own = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    big = np.linalg.norm(own, axis=1) > 1e-6
    assert ((own * fast.normals[::3]).sum(axis=1)[big] > 0).all()


def test_a_flattened_object_is_sliced_without_error():
    """A singular model (scale 0 along x): normals are the flat space's, no exception."""
    model = np.diag([0.0, 1.0, 1.0, 1.0, 1.0])
    tri = S.cross_section(shapes.cell600(), T.translation((0, 0, 0, 0.013)), model=model)
    assert len(tri) > 0 and np.isfinite(tri.normals).all()


@pytest.mark.parametrize("seed", range(4))
def test_the_normal_transform_turns_object_normals_like_the_camera_space_cross_product(seed):
    rng = np.random.default_rng(seed)
    mv = np.eye(5)
    mv[:4] = rng.normal(size=(4, 5))
    if seed == 3:
        mv[:4, 1] = 0.0  # singular: flattened along y
    det = np.linalg.det(mv[:4, :4])
    flip = 1.0 if det > 0 else -1.0
    g = np.empty(12)
    S.normal_transform(mv, flip, g)
    a = mv[:4, :4]
    u, v, t = rng.normal(size=(3, 4))
    np.testing.assert_allclose(g.reshape(3, 4) @ cross4(u, v, t), flip * cross4(a @ u, a @ v, a @ t)[:3], atol=1e-9)
    if seed < 3:  # the inverse transpose, up to the positive factor |det|
        np.testing.assert_allclose(g.reshape(3, 4), abs(det) * np.linalg.inv(a).T[:3], atol=1e-9)


def test_edge_scan_and_numbering_by_tets_give_the_same_bits(dense, monkeypatch):
    # One workspace for both: the scan must leave every edge unnumbered for the next section.
    cam = T.translation((0, 0, 0, 0.013))
    modes = []
    emit = S._emit
    monkeypatch.setattr(S, "_emit", lambda *args: modes.append(args[5]) or emit(*args))
    monkeypatch.setattr(S, "EDGE_SCAN_FRACTION", 10**9)  # every edge-path section scans
    scanned = S.cross_section(dense, cam)
    monkeypatch.setattr(S, "EDGE_SCAN_FRACTION", 0)  # never
    numbered = S.cross_section(dense, cam)
    assert modes == [S.POINTS_BY_EDGE_SCAN, S.POINTS_BY_EDGE]
    assert len(scanned) > 1000 and same_bits(scanned, numbered)


@pytest.mark.parametrize("scale", [1e-6, 1e-3, 1e3, 1e6])
def test_normals_are_unit_at_any_scale_a_model_may_have(scale):
    # Normals are made unit in float32: their squared length (which goes as the scale's
    # sixth power) must neither underflow nor overflow. The section of the scaled mesh
    # is the unscaled one's, scaled: the same tets in the same order, the same normals.
    mesh = shapes.cell600()
    unit = S.cross_section(mesh, T.translation((0, 0, 0, 0.013)))
    tri = S.cross_section(mesh, T.translation((0, 0, 0, 0.013 * scale)), model=T.scaling((scale,) * 4))
    assert len(tri) == len(unit) > 100
    np.testing.assert_allclose(np.linalg.norm(tri.normals, axis=1), 1.0, atol=3e-7)
    np.testing.assert_allclose(tri.normals, unit.normals, atol=3e-7)
