"""Cross-section and frustum projection against analytic geometry and the oracles."""

import numpy as np
import pytest

from across_dimensions.core import (
    cross_section,
    cross_section_reference,
    frustum_project,
    frustum_project_reference,
    shapes,
)
from across_dimensions.core import transform as T
from across_dimensions.core.bench import tiled_scene
from across_dimensions.core.frustum import focal_length
from across_dimensions.core.mesh import TetMesh4, concatenate


def closed_and_outward(tri):
    """Every directed edge once and its reverse once; positive volume."""
    v, f = tri.welded()
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    directed = {tuple(e) for e in edges.tolist()}
    assert len(directed) == len(edges), "a directed edge is used twice: orientation flips"
    assert all((b, a) in directed for a, b in directed), "an edge has no partner: the section is open"
    return True


def canonical(tri, decimals=5):
    """Triangles as a sorted array, each rotated to start at its smallest vertex."""
    p = np.round(tri.vertices.astype(np.float64)[tri.faces], decimals)
    keys = [tuple(map(tuple, t)) for t in p]
    out = []
    for k in keys:
        i = min(range(3), key=lambda j: k[j])
        out.append(k[i:] + k[:i])
    return sorted(out)


def test_tesseract_at_w0_is_the_unit_cube():
    tri = cross_section(shapes.tesseract())
    assert tri.area() == pytest.approx(6.0, abs=1e-6)
    assert tri.volume() == pytest.approx(1.0, abs=1e-6)
    lo, hi = tri.bounds()
    assert np.allclose(lo, -0.5) and np.allclose(hi, 0.5)
    assert closed_and_outward(tri)


@pytest.mark.parametrize("deg", [10.0, 30.0, 45.0])
def test_xw_rotation_stretches_the_section_by_one_over_cos(deg):
    a = np.radians(deg)
    tri = cross_section(shapes.tesseract(), model=T.rotation("xw", a))
    lo, hi = tri.bounds()
    assert hi[0] - lo[0] == pytest.approx(1.0 / np.cos(a), rel=1e-5)
    assert hi[1] - lo[1] == pytest.approx(1.0, rel=1e-6)
    # A slanted prism of height 1 and cross-section area 1 x 1/cos(a): volume 1/cos(a).
    assert tri.volume() == pytest.approx(1.0 / np.cos(a), rel=1e-5)


def test_nothing_cut_gives_an_empty_mesh():
    tri = cross_section(shapes.tesseract(), model=T.translation((0, 0, 0, 3.0)))
    assert tri.is_empty and tri.vertices.shape == (0, 3) and tri.faces.shape == (0, 3)


def test_hyper_depth_makes_sections_persist():
    mesh = shapes.tesseract()
    at = T.translation((0, 0, 0, 0.9))
    assert cross_section(mesh, model=at).is_empty
    deep = T.compose(at, T.scaling([1, 1, 1, 2.0]))
    assert cross_section(mesh, model=deep).volume() == pytest.approx(1.0, abs=1e-6)


def test_camera_pose_is_the_inverse_of_moving_the_object():
    rng = np.random.default_rng(3)
    mesh = shapes.cell24()
    cam = T.pose(rng.normal(size=4) * 0.2, {p: rng.uniform(-1, 1) for p in T.PLANES})
    a = cross_section(mesh, camera_pose=cam)
    b = cross_section(mesh, model=T.inverse(cam))
    assert canonical(a) == canonical(b)


def test_mirrored_object_still_has_outward_sections():
    tri = cross_section(shapes.cell600(), model=T.scaling([-1, 1, 1, 1.3]))
    assert tri.volume() > 0
    assert closed_and_outward(tri)


@pytest.mark.parametrize("seed", range(8))
def test_numba_kernel_agrees_with_numpy_oracle(seed):
    rng = np.random.default_rng(seed)
    mesh = shapes.hypersphere(subdivisions=1)  # 4800 tets
    model = T.pose(
        rng.normal(size=4) * 0.3, {p: rng.uniform(-np.pi, np.pi) for p in T.PLANES}, rng.uniform(0.5, 2.0, size=4)
    )
    fast = cross_section(mesh, model=model)
    slow = cross_section_reference(mesh, model=model)
    assert len(fast) == len(slow) > 0
    assert canonical(fast) == canonical(slow)
    assert np.allclose(np.sort(fast.normals, axis=0), np.sort(slow.normals, axis=0), atol=1e-5)


def test_cluster_culling_changes_nothing():
    scene = tiled_scene(shapes.cell600(), 60_000, spread_w=5.0)
    for w in (-0.7, 0.013, 1.9):
        cam = T.translation((0, 0, 0, w))
        culled = cross_section(scene, cam)
        full = cross_section(scene, cam, cull=False)
        assert len(culled) == len(full) > 0
        assert canonical(culled) == canonical(full)


def test_union_of_solids_slices_into_closed_pieces():
    mesh = concatenate([shapes.tesseract(), shapes.cell16().transformed(T.translation((3, 0, 0, 0.2)))])
    tri = cross_section(mesh)
    assert closed_and_outward(tri)
    assert tri.volume() > 1.0


def test_colors_are_interpolated():
    mesh = shapes.tesseract()
    colors = np.zeros((len(mesh.vertices), 4), np.float32)
    colors[:, 0] = mesh.vertices[:, 3] + 0.5  # red = w in [0, 1]
    colors[:, 3] = 1
    mesh = TetMesh4(mesh.vertices, mesh.tets, colors)
    tri = cross_section(mesh, T.translation((0, 0, 0, 0.25)))
    assert np.allclose(tri.colors[:, 0], 0.75, atol=1e-6)


# ------------------------------------------------------------------ frustum
def test_frustum_tesseract_shows_a_smaller_inner_cube():
    f = focal_length(60.0)
    tri = frustum_project(shapes.tesseract(), T.translation((0, 0, 0, -3.0)), fov_deg=60.0)
    assert np.isfinite(tri.vertices).all()
    used = np.unique(tri.faces)
    depth, verts = tri.depth[used], tri.vertices[used]
    assert depth.min() == pytest.approx(2.5) and depth.max() == pytest.approx(3.5)
    near = np.isclose(depth, 2.5)
    far = np.isclose(depth, 3.5)
    # Corners of the near cube at +-0.5 f / 2.5, of the far cube at +-0.5 f / 3.5.
    assert np.abs(verts[near]).max() == pytest.approx(0.5 * f / 2.5, rel=1e-5)
    assert np.abs(verts[far]).max() == pytest.approx(0.5 * f / 3.5, rel=1e-5)
    # The 24 square faces of the tesseract, two triangles each; no triangles inside cubes.
    assert len(tri) == 48


def test_frustum_farther_objects_look_smaller():
    mesh = shapes.cell24()
    sizes = []
    for d in (3.0, 5.0, 9.0):
        tri = frustum_project(mesh, T.translation((0, 0, 0, -d)))
        sizes.append(np.ptp(tri.vertices[np.unique(tri.faces), 0]))
    assert sizes[0] > sizes[1] > sizes[2]


def test_frustum_clips_at_the_near_hyperplane():
    # The camera sits inside the tesseract: half of it is behind the near hyperplane.
    tri = frustum_project(shapes.tesseract(), T.translation((0, 0, 0, 0.1)), near=0.05)
    assert len(tri) > 0
    assert np.isfinite(tri.vertices).all() and np.isfinite(tri.normals).all() and np.isfinite(tri.depth).all()
    assert tri.depth[np.unique(tri.faces)].min() >= 0.05 - 1e-6


def test_frustum_behind_the_camera_is_empty():
    tri = frustum_project(shapes.tesseract(), T.translation((0, 0, 0, 5.0)))
    assert tri.is_empty and tri.depth.shape == (0,)


@pytest.mark.parametrize("seed", range(4))
def test_frustum_kernel_agrees_with_oracle(seed):
    rng = np.random.default_rng(seed)
    mesh = shapes.cell120()
    cam = T.pose((0, 0, 0, -rng.uniform(0.8, 3.0)), {p: rng.uniform(-0.5, 0.5) for p in T.PLANES})
    fast = frustum_project(mesh, cam, near=0.1)
    slow = frustum_project_reference(mesh, cam, near=0.1)
    assert len(fast) == len(slow) > 0
    assert canonical(fast) == canonical(slow)
    assert np.allclose(np.sort(fast.depth[fast.faces].ravel()), np.sort(slow.depth[slow.faces].ravel()), atol=1e-5)


def test_frustum_rejects_bad_parameters():
    with pytest.raises(ValueError, match="near"):
        frustum_project(shapes.tesseract(), near=0.0)
    with pytest.raises(ValueError, match="field of view"):
        frustum_project(shapes.tesseract(), fov_deg=180.0)


# ------------------------------------------------------------- validation
def test_validation_names_each_problem():
    good = shapes.tesseract()
    with pytest.raises(Exception, match="past the end"):
        TetMesh4(good.vertices, np.vstack([good.tets, [[0, 1, 2, 99]]])).validate()
    flipped = good.tets.copy()
    flipped[3] = flipped[3, [0, 2, 1, 3]]
    with pytest.raises(Exception, match="same orientation"):
        TetMesh4(good.vertices, flipped).validate()
    with pytest.raises(Exception, match="not shared by exactly two"):
        TetMesh4(good.vertices, good.tets[:-1]).validate()
    with pytest.raises(Exception, match="inside out"):
        TetMesh4(good.vertices, good.tets[:, [0, 2, 1, 3]]).validate()
    degenerate = np.vstack([good.tets, [[0, 0, 1, 2]]])
    with pytest.raises(Exception, match="degenerate"):
        TetMesh4(good.vertices, degenerate).validate(check_closed=False)


def test_npz_round_trip(tmp_path):
    mesh = shapes.cell16()
    mesh.save(tmp_path / "m.npz")
    back = TetMesh4.load(tmp_path / "m.npz")
    assert np.array_equal(back.vertices, mesh.vertices) and np.array_equal(back.tets, mesh.tets)
    assert np.array_equal(back.colors, mesh.colors)
    assert not list(tmp_path.glob("*.tmp"))
