"""Lifting 3D solids into 4D (core.lift) and baking mesh assets (world.bake)."""

from __future__ import annotations

import io
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.core import TetMesh4, cross_section
from across_dimensions.core.fileio import FileProblem
from across_dimensions.core.lift import (
    HyperDepth,
    box_solid,
    extend_solid,
    extrude,
    profile_layers,
    profile_scales,
    tet_volumes3,
)
from across_dimensions.core.transform import translation
from across_dimensions.world import bake
from across_dimensions.world.assets import bake_cache
from across_dimensions.world.bake import AssetError, lift_asset, lift_to_file, load_surface

ASSETS = Path(__file__).resolve().parents[1] / "assets" / "meshes"
#: Coarse enough to keep a pytetwild run to a couple of seconds.
COARSE = 0.12


def slice_at(mesh: TetMesh4, w: float):
    pose = np.eye(5)
    pose[3, 4] = w
    return cross_section(mesh, pose)


def unit_cube():
    return box_solid([0.5, 0.5, 0.5], 1.0)


def signed_volume(vertices, faces) -> float:
    """Volume enclosed by a closed surface (negative when wound inward)."""
    p = np.asarray(vertices, np.float64)[np.asarray(faces)]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


# ----------------------------------------------------------------------- extrude
def test_box_solid_is_positive_kuhn_split():
    v, t = box_solid([1.0, 2.0, 3.0], [2.0, 3.0, 4.0])
    vol = tet_volumes3(v, t)
    assert (vol > 0).all()
    assert vol.sum() == pytest.approx(24.0)
    assert (t[:, 0] == 0).all() and (t[:, 3] == 7).all()


@pytest.mark.parametrize("depth", [0.5, 1.0, 3.0])
def test_prism_of_unit_cube_has_hypervolume_depth(depth):
    v, t = unit_cube()
    mesh = extrude(v, t, [-depth / 2, depth / 2]).validate()
    assert mesh.hypervolume() == pytest.approx(depth)
    # A tesseract's boundary: 6 walls of 1 x depth... plus two unit-cube caps.
    assert mesh.boundary_volume() == pytest.approx(2 + 6 * depth)


def test_extrude_accepts_either_3d_orientation():
    v, t = unit_cube()
    mesh = extrude(v, t[:, [1, 0, 2, 3]], [0.0, 2.0]).validate()
    assert mesh.hypervolume() == pytest.approx(2.0)


def test_scaled_layers_match_the_integral_of_scale_cubed():
    v, t = unit_cube()
    mesh = extrude(v, t, [0.0, 1.0, 2.0], [1.0, 2.0, 0.5]).validate()
    # Linear scale per interval: integral of s^3 = dw * (s0^4 - s1^4) / (4 (s0 - s1)).
    expect = (2**4 - 1) / (4 * 1) + (2**4 - 0.5**4) / (4 * 1.5)
    assert mesh.hypervolume() == pytest.approx(expect)


def test_tips_close_the_solid():
    v, t = unit_cube()
    mesh = extrude(v, t, [0.0, 1.0, 2.0], [0.0, 1.0, 0.0]).validate()
    assert mesh.hypervolume() == pytest.approx(0.5)  # two cones of height 1 over a unit cube: 1/4 each
    assert len(slice_at(mesh, 2.01)) == 0


@pytest.mark.parametrize(
    "layers, scales",
    [
        ([0.0], None),
        ([0.0, 0.0], None),
        ([1.0, 0.0], None),
        ([0, 1, 2], [1, 0, 1]),
        ([0, 1], [1, -1]),
        ([0, 1], [0, 0]),
    ],
)
def test_extrude_rejects_bad_layers(layers, scales):
    v, t = unit_cube()
    with pytest.raises(ValueError):
        extrude(v, t, layers, scales)


def test_walls_use_min_index_diagonals_consistently():
    # Two boxes side by side: if neighbouring prisms disagreed on a quad's
    # diagonal the mesh would have faces used once, and validate() would fail.
    v1, t1 = box_solid([0, 0, 0], 1.0)
    v2, t2 = box_solid([1, 0, 0], 1.0)
    v = np.concatenate([v1, v2])
    t = np.concatenate([t1, t2 + 8])
    # Weld the shared face's corners so the two boxes form one solid.
    q = np.round(v * 1e6).astype(np.int64)
    _, first, inv = np.unique(q, axis=0, return_index=True, return_inverse=True)
    mesh = extend_solid(v[first], inv.reshape(-1)[t], HyperDepth(0.0, 2.0, "taper", 5)).validate()
    assert mesh.hypervolume() > 0


def test_colors_follow_their_vertices():
    v, t = unit_cube()
    colors = np.c_[v, np.ones(8)]
    mesh = extrude(v, t, [0.0, 1.0, 2.0], colors=colors)
    xyz = mesh.vertices[:, :3]
    np.testing.assert_allclose(mesh.colors[:, :3], xyz, atol=1e-6)


# ---------------------------------------------------------------------- profiles
def test_profile_scales():
    w = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
    np.testing.assert_allclose(profile_scales(w, 0.0, 1.0, "prism"), 1.0)
    np.testing.assert_allclose(profile_scales(w, 0.0, 1.0, "taper"), [0, 0.5, 1, 0.5, 0])
    np.testing.assert_allclose(profile_scales(w, 0.0, 1.0, "round"), [0, np.sqrt(0.75), 1, np.sqrt(0.75), 0])
    np.testing.assert_allclose(profile_scales(w, 0.0, 1.0, "round", floor=0.02)[[0, -1]], 0.02)
    with pytest.raises(ValueError, match="unknown profile"):
        profile_scales(w, 0.0, 1.0, "wobbly")


def test_round_profile_sections_shrink_then_vanish():
    v, t = unit_cube()
    c, depth = 3.0, 2.0
    mesh = extend_solid(v, t, HyperDepth(c, depth, "round", layers=9)).validate()
    assert slice_at(mesh, c).volume() == pytest.approx(1.0)  # the full solid
    layers = profile_layers(c, depth, "round", 9)
    scales = profile_scales(layers, c, depth / 2, "round")
    for w in (c + 0.6, c + 0.93, c - 0.97):
        s = np.interp(w, layers, scales)  # the scale is linear between layers
        sec = slice_at(mesh, w)
        assert sec.volume() == pytest.approx(s**3, rel=1e-5)
        lo, hi = sec.bounds()
        assert hi - lo == pytest.approx(np.full(3, s), rel=1e-5)  # a scaled copy, about the centre
        assert (lo + hi) / 2 == pytest.approx(np.full(3, 0.5), abs=1e-5)
    for w in (c + 1.001, c - 1.001, c + 5):
        assert len(slice_at(mesh, w)) == 0


def test_thin_ends_validate_with_a_floor_or_tips():
    # validate() judges each tet against its own size, so a thin 2 % end layer
    # of a small part in a large mesh is not mistaken for a degenerate tet.
    v, t = box_solid([0, 1.5, 0], [0.05, 3.0, 0.05])
    floored = extend_solid(v, t, HyperDepth(0.0, 3.0, "round", floor=0.02)).validate()
    tipped = extend_solid(v, t, HyperDepth(0.0, 3.0, "round")).validate()
    # With tips the object vanishes exactly at the end; with a floor it pops out.
    end = translation((0, 0, 0, 1.5 - 1e-3))
    assert cross_section(tipped, end).volume() < cross_section(floored, end).volume()


# ------------------------------------------------------------------- load/repair
def write_obj(path: Path, vertices, faces) -> Path:
    lines = [f"v {x} {y} {z}" for x, y, z in vertices] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def cube_surface():
    v, _ = unit_cube()
    # Outward quads of the unit cube as corner ids (bit j = axis j).
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    f = [(a, b, c) for a, b, c, d in quads] + [(a, c, d) for a, b, c, d in quads]
    return v, np.array(f)


def test_assets_are_watertight_as_shipped():
    for path in sorted(ASSETS.glob("*.obj")):
        v, f = load_surface(path)
        assert len(f) <= 600, path.name
        assert signed_volume(v, f) > 0


def test_small_hole_and_flipped_faces_are_repaired(tmp_path):
    v, f = cube_surface()
    f = f.copy()
    f[3] = f[3, ::-1]  # one face wound backwards
    f = np.delete(f, [0, 6], axis=0)  # a missing quad: a 4-edge hole
    rv, rf = load_surface(write_obj(tmp_path / "holey.obj", v, f))
    assert len(rf) == 12
    assert signed_volume(rv, rf) == pytest.approx(1.0)


def test_a_repaired_surface_is_read_back_from_the_cache(tmp_path, monkeypatch):
    """The second load of a surface comes from the bake cache: the same arrays, without
    reading the file with trimesh again; a damaged entry is read and repaired anew."""
    import across_dimensions.world.bake as bake

    v, f = cube_surface()
    path = write_obj(tmp_path / "flipped.obj", v, np.concatenate([f[:3, ::-1], f[3:]]))
    cache = tmp_path / "cache"
    first = load_surface(path, cache_dir=cache)
    (entry,) = cache.glob("flipped-*.npz")

    def no_reading(*a):
        raise AssertionError("read the file again")

    monkeypatch.setattr(bake, "read_triangles", no_reading)
    again = load_surface(path, cache_dir=cache)
    assert all(np.array_equal(a, b) and a.dtype == b.dtype for a, b in zip(first, again))
    entry.write_bytes(b"not a zip")
    monkeypatch.undo()
    repaired = load_surface(path, cache_dir=cache)
    assert all(np.array_equal(a, b) for a, b in zip(first, repaired))
    assert signed_volume(*repaired) == pytest.approx(1.0)


def test_inside_out_surface_is_turned_outward(tmp_path):
    v, f = cube_surface()
    rv, rf = load_surface(write_obj(tmp_path / "inverted.obj", v, f[:, ::-1]))
    assert signed_volume(rv, rf) == pytest.approx(1.0)


def test_open_mesh_raises_asset_error_naming_the_file(tmp_path):
    v, f = cube_surface()
    f = np.delete(f, [0, 6, 2, 8], axis=0)  # two adjacent faces (z=0, y=0) gone: a 6-edge hole
    path = write_obj(tmp_path / "open_box.obj", v, f)
    with pytest.raises(AssetError, match=r"open_box\.obj.*6 open edges"):
        load_surface(path)


def test_single_triangle_strip_is_not_a_solid(tmp_path):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 2, 0]], float)
    path = write_obj(tmp_path / "strip.obj", v, [(0, 1, 2), (2, 1, 3), (2, 3, 4)])
    with pytest.raises(AssetError, match=r"strip\.obj.*open edges"):
        load_surface(path)


def test_garbage_bytes_raise_asset_error(tmp_path):
    path = tmp_path / "garbage.obj"
    path.write_bytes(np.random.default_rng(1).integers(0, 256, 4096, dtype=np.uint8).tobytes())
    with pytest.raises(AssetError, match=r"garbage\.obj"):
        load_surface(path)
    text = tmp_path / "words.obj"
    text.write_text("hello\nthis is not a mesh\n")
    with pytest.raises(AssetError, match=r"words\.obj: contains no triangles"):
        load_surface(text)


@pytest.mark.parametrize("name", ["model.fbx", "noext", "missing.obj"])
def test_unknown_format_or_missing_file_raise_asset_error(tmp_path, name):
    path = tmp_path / name
    if name != "missing.obj":
        path.write_text("x")
    with pytest.raises(AssetError, match=name.replace(".", r"\.")):
        load_surface(path)


def test_glb_scene_is_flattened_with_transforms(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box(), transform=trimesh.transformations.translation_matrix([3, 0, 0]))
    scene.add_geometry(trimesh.creation.box(), transform=trimesh.transformations.translation_matrix([-3, 0, 0]))
    path = tmp_path / "two.glb"
    scene.export(path)
    v, f = load_surface(path)
    assert v.min(axis=0) == pytest.approx([-3.5, -0.5, -0.5])
    assert v.max(axis=0) == pytest.approx([3.5, 0.5, 0.5])
    assert signed_volume(v, f) == pytest.approx(2.0)


# -------------------------------------------------------------- cache (no tetwild)
@pytest.fixture
def fake_tetwild(monkeypatch):
    """Replace pytetwild by the surface's bounding box split into 6 tets; counts calls."""
    calls = []

    def fake(vertices, faces, edge_length_fac=bake.DEFAULT_EDGE_LENGTH_FAC, **kw):
        calls.append(edge_length_fac)
        lo, hi = vertices.min(axis=0), vertices.max(axis=0)
        return box_solid((lo + hi) / 2, hi - lo)

    monkeypatch.setattr(bake, "tetrahedralize", fake)
    return calls


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_cache_hit_is_silent_and_skips_tetrahedralization(tmp_path, fake_tetwild, monkeypatch):
    asset = ASSETS / "crate.obj"
    monkeypatch.setattr(sys, "stderr", Terminal())
    first = lift_asset(asset, 2.0, cache_dir=tmp_path)
    err = sys.stderr.getvalue()
    assert "tetrahedralize" in err and "crate.obj" in err
    assert len(list(tmp_path.glob("crate-*.npz"))) == 1
    monkeypatch.setattr(sys, "stderr", Terminal())
    second = lift_asset(asset, 2.0, cache_dir=tmp_path)
    assert sys.stderr.getvalue() == ""
    assert len(fake_tetwild) == 1
    np.testing.assert_array_equal(first.tets, second.tets)
    # Depth, position and profile do not need a new bake; resolution does.
    lift_asset(asset, HyperDepth(2.0, 5.0, "round"), cache_dir=tmp_path, progress=False)
    assert len(fake_tetwild) == 1
    lift_asset(asset, 2.0, cache_dir=tmp_path, edge_length_fac=0.3, progress=False)
    assert len(fake_tetwild) == 2


def test_corrupt_cache_file_is_rebuilt(tmp_path, fake_tetwild):
    asset = ASSETS / "crate.obj"
    lift_asset(asset, 1.0, cache_dir=tmp_path, progress=False)
    (cached,) = tmp_path.glob("crate-*.npz")
    cached.write_bytes(b"PK\x03\x04 truncated")
    mesh = lift_asset(asset, 1.0, cache_dir=tmp_path, progress=False)
    assert len(fake_tetwild) == 2
    assert mesh.hypervolume() == pytest.approx(1.0)  # the crate's 1 m bounding box, 1 deep
    assert bake_cache.load_entry(cached) is not None
    assert not list(tmp_path.glob("*.tmp"))


def test_changed_file_bytes_miss_the_cache(tmp_path, fake_tetwild):
    v, f = cube_surface()
    path = write_obj(tmp_path / "cube.obj", v, f)
    lift_asset(path, 1.0, cache_dir=tmp_path / "c", progress=False)
    write_obj(path, v * 2, f)
    mesh = lift_asset(path, 1.0, cache_dir=tmp_path / "c", progress=False)
    assert len(fake_tetwild) == 2
    assert mesh.hypervolume() == pytest.approx(8.0)


def test_lift_to_file_writes_a_loadable_npz(tmp_path, fake_tetwild):
    out = lift_to_file(ASSETS / "pillar.obj", 2.0, tmp_path / "pillar.npz", cache_dir=tmp_path, progress=False)
    assert out == tmp_path / "pillar.npz"
    mesh = TetMesh4.load(out)
    assert mesh.hypervolume() == pytest.approx(0.8 * 0.8 * 3.0 * 2.0)


def test_lift_to_file_refuses_a_missing_folder(tmp_path, fake_tetwild):
    with pytest.raises(FileProblem, match=r"nowhere.*does not exist"):
        lift_to_file(ASSETS / "pillar.obj", 2.0, tmp_path / "nowhere" / "pillar.npz", cache_dir=tmp_path)
    assert not (tmp_path / "nowhere").exists()
    assert not fake_tetwild  # refused before any work


# --------------------------------------------------------------- real pytetwild
@pytest.fixture(scope="module")
def pillar_bake(tmp_path_factory):
    cache = tmp_path_factory.mktemp("bake-cache")
    t0 = time.perf_counter()
    mesh = lift_asset(
        ASSETS / "pillar.obj",
        HyperDepth(1.0, 2.0, "prism"),
        cache_dir=cache,
        edge_length_fac=COARSE,
        progress=False,
    )
    return mesh, cache, time.perf_counter() - t0


@pytest.mark.slow
def test_lifted_pillar_is_closed_and_oriented(pillar_bake):
    trimesh = pytest.importorskip("trimesh")
    mesh, _, _ = pillar_bake
    assert not mesh.problems()
    section = slice_at(mesh, 1.0)
    expect = trimesh.load(ASSETS / "pillar.obj").volume
    # fTetWild keeps the surface within its envelope (1e-3 of the bbox diagonal).
    assert section.volume() == pytest.approx(expect, rel=0.02)
    assert mesh.hypervolume() == pytest.approx(2.0 * section.volume(), rel=1e-4)
    assert len(slice_at(mesh, 2.1)) == 0 and len(slice_at(mesh, -0.1)) == 0


@pytest.mark.slow
def test_lifted_pillar_cache_hit(pillar_bake, monkeypatch):
    mesh, cache, bake_seconds = pillar_bake
    assert len(list(cache.glob("pillar-*.npz"))) == 1

    def no_tetwild(*a, **k):
        raise AssertionError("cache hit expected, but pytetwild was called")

    monkeypatch.setattr(bake, "tetrahedralize", no_tetwild)
    t0 = time.perf_counter()
    again = lift_asset(
        ASSETS / "pillar.obj", HyperDepth(1.0, 2.0, "prism"), cache_dir=cache, edge_length_fac=COARSE, progress=False
    )
    hit_seconds = time.perf_counter() - t0
    np.testing.assert_array_equal(again.tets, mesh.tets)
    assert hit_seconds * 10 < bake_seconds


@pytest.mark.slow
def test_tetrahedralize_orients_pytetwild_output_positively():
    v, f = load_surface(ASSETS / "crate.obj")
    tv, tt = bake.tetrahedralize(v, f, COARSE)
    vol = tet_volumes3(tv, tt)
    assert (vol > 0).all()
    assert vol.sum() == pytest.approx(signed_volume(v, f), rel=0.01)
    assert len(np.unique(tt)) == len(tv)  # no unreferenced vertices
