"""TetMesh4's arrays are read-only, its .npz files are read as hostile, and 3D exports are welded.

In-process tests of ``core.mesh`` and ``core.meshio``; the same cases are run
through the command line in ``test_cli.py``.
"""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest
import trimesh

from across_dimensions.core import cross_section
from across_dimensions.core.errors import InputError
from across_dimensions.core.fileio import FileProblem
from across_dimensions.core.mesh import NPZ_MAX_VERTICES, MeshError, TetMesh4, TriMesh3
from across_dimensions.core.meshio import COLOR_TOL, indexed_mesh
from across_dimensions.core.shapes import SHAPE_PARAM_RULES, make_shape, shape_param_problem


# ----------------------------------------------------------- read-only arrays
def test_mesh_arrays_are_read_only():
    mesh = make_shape("tesseract")
    for name in ("vertices", "tets", "colors"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(mesh, name)[0] = 0


def test_construction_copies_the_callers_writeable_arrays():
    base = make_shape("5-cell")
    v = np.array(base.vertices)  # writeable copy
    mesh = TetMesh4(v, np.array(base.tets))
    faces_before = mesh.unique_faces()[0].copy()
    v[:] = 0  # the caller keeps editing its own array...
    assert np.abs(mesh.vertices).max() > 0  # ...which the mesh does not share
    np.testing.assert_array_equal(mesh.unique_faces()[0], faces_before)
    assert v.flags.writeable


def test_read_only_arrays_are_shared_not_copied():
    mesh = make_shape("16-cell")
    moved = TetMesh4(mesh.vertices, mesh.tets, mesh.colors, mesh.name)
    assert np.shares_memory(moved.vertices, mesh.vertices)
    assert np.shares_memory(moved.tets, mesh.tets)


def test_assigning_new_arrays_clears_the_cache():
    mesh = make_shape("tesseract")
    cross_section(mesh)
    assert mesh._cache
    mesh.vertices = mesh.vertices * 2.0
    assert not mesh._cache
    assert not mesh.vertices.flags.writeable
    assert mesh.hypervolume() == pytest.approx(16.0)


def test_tets_out_of_uint32_range_do_not_wrap():
    v = np.eye(5)[:, :4]
    with pytest.raises(MeshError, match="uint32"):
        TetMesh4(v, np.array([[0, 1, 2, 2**32 + 1]], np.uint64))
    with pytest.raises(MeshError, match="negative"):
        TetMesh4(v, np.array([[0, 1, 2, -1]]))


# ------------------------------------------------------------ .npz loading
def test_save_and_load_round_trip(tmp_path):
    mesh = make_shape("24-cell")
    mesh.save(tmp_path / "m.npz")
    back = TetMesh4.load(tmp_path / "m.npz")
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    np.testing.assert_array_equal(back.tets, mesh.tets)
    np.testing.assert_array_equal(back.colors, mesh.colors)
    assert [p.name for p in tmp_path.iterdir()] == ["m.npz"]


def test_save_refuses_a_missing_folder(tmp_path):
    with pytest.raises(FileProblem, match="does not exist"):
        make_shape("5-cell").save(tmp_path / "nope" / "m.npz")
    assert list(tmp_path.iterdir()) == []


def test_fortran_ordered_arrays_load_the_same(tmp_path):
    mesh = make_shape("16-cell")
    np.savez(tmp_path / "f.npz", vertices=np.asfortranarray(mesh.vertices), tets=np.asfortranarray(mesh.tets))
    back = TetMesh4.load(tmp_path / "f.npz")
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    np.testing.assert_array_equal(back.tets, mesh.tets)


def _npy_header(shape, descr="<f8") -> bytes:
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": descr, "fortran_order": False, "shape": shape})
    return buf.getvalue()


def test_member_sizes_are_checked_before_decompressing(tmp_path, monkeypatch):
    path = tmp_path / "bomb.npz"
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as z:
        z.writestr("vertices.npy", _npy_header((10**7, 4)) + bytes(8 * 4 * 10**7))
        z.writestr("tets.npy", _npy_header((1, 4), "<i8") + bytes(32))
    assert path.stat().st_size < 2 << 20

    def no_reading(*args, **kwargs):
        raise AssertionError("the member was decompressed")

    monkeypatch.setattr(zipfile.ZipFile, "read", no_reading)
    with pytest.raises(MeshError, match=f"{NPZ_MAX_VERTICES} rows"):
        TetMesh4.load(path)


@pytest.mark.parametrize(
    "vertices, needle",
    [
        (_npy_header((5, 4)) + bytes(8), "promises"),  # truncated data
        (_npy_header((5, 4), "|O"), "object"),
        (_npy_header((5, 4), "<c16") + bytes(16 * 20), "complex"),
        (b"not a numpy array at all", "not a numpy array"),
    ],
)
def test_malformed_members_are_refused(tmp_path, vertices, needle):
    path = tmp_path / "bad.npz"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("vertices.npy", vertices)
        z.writestr("tets.npy", _npy_header((1, 4), "<i8") + bytes(32))
    with pytest.raises(MeshError) as err:
        TetMesh4.load(path)
    msg = str(err.value)
    assert str(path) in msg and needle in msg and "\n" not in msg


def test_every_loader_error_is_an_input_error(tmp_path):
    (tmp_path / "text.npz").write_text("hello", encoding="utf-8")
    for name in ("text.npz", "missing.npz"):
        with pytest.raises(InputError):
            TetMesh4.load(tmp_path / name)


# ------------------------------------------------------------ shape limits
def test_every_shape_parameter_has_a_rule():
    import inspect

    from across_dimensions.core.shapes import SHAPES

    for builder in SHAPES.values():
        for name in inspect.signature(builder).parameters:
            assert name == "color" or name in SHAPE_PARAM_RULES, name


@pytest.mark.parametrize(
    "name, value",
    [
        ("subdivisions", 4),
        ("subdivisions", -1),
        ("subdivisions", True),
        ("p", 2),
        ("p", 129),
        ("segments", 3.5),
        ("radius", float("nan")),
        ("radius", float("inf")),
        ("radius", 0.0),
        ("height", 1e4),
        ("r1", "1"),
    ],
)
def test_shape_param_problem_refuses(name, value):
    problem = shape_param_problem(name, value)
    assert problem and name in problem


@pytest.mark.parametrize(
    "name, value",
    [
        ("subdivisions", 3),
        ("subdivisions", 0),
        ("p", 128),
        ("segments", 3.0),
        ("radius", 1e-3),
        ("size", 1000),
        ("r2", np.float32(0.5)),
    ],
)
def test_shape_param_problem_accepts(name, value):
    assert shape_param_problem(name, value) is None


def test_make_shape_refuses_before_building(monkeypatch):
    from across_dimensions.core import shapes

    monkeypatch.setitem(shapes.SHAPES, "hypersphere", lambda radius=1.0, subdivisions=1, color=None: 1 / 0)
    with pytest.raises(InputError, match="subdivisions"):
        shapes.make_shape("hypersphere", subdivisions=50)


# ------------------------------------------------------------ welded export
def test_indexed_mesh_welds_and_merges_flat_faces():
    tri = cross_section(make_shape("tesseract"))
    assert len(tri.faces) == 48
    v, f, c = indexed_mesh(tri)
    assert (len(v), len(f), len(c)) == (8, 12, 8)
    m = trimesh.Trimesh(v, f, process=False)
    assert m.is_watertight and m.is_winding_consistent
    assert m.volume == pytest.approx(1.0)


def test_indexed_mesh_splits_vertices_only_where_colours_differ():
    # Two triangles sharing an edge, the shared corners coloured differently on each side.
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    c = np.ones((6, 4), np.float32)
    faces = np.arange(6, dtype=np.uint32).reshape(2, 3)
    same = indexed_mesh(TriMesh3(v, faces, np.zeros_like(v), c))
    assert len(same[0]) == 4
    c[3:, :3] = 0.2
    split = indexed_mesh(TriMesh3(v, faces, np.zeros_like(v), c))
    assert len(split[0]) == 6
    np.testing.assert_array_equal(np.unique(split[2][:, 0]), np.float32([0.2, 1.0]))


def test_collapse_keeps_colours_within_tolerance():
    tri = cross_section(make_shape("hypersphere"))
    v, f, c = indexed_mesh(tri)
    # Every original corner's colour is reproduced at its position by the welded mesh.
    assert len(f) < len(tri.faces)
    pts = tri.vertices.astype(np.float64)
    a, b, d = (v.astype(np.float64)[f[:, k]] for k in range(3))
    n = np.cross(b - a, d - a)
    area = (n * n).sum(axis=1)
    worst = 0.0
    for p, color in zip(pts, tri.colors):
        # Barycentric coordinates of p in every welded triangle; keep the one p lies in.
        w = (
            np.stack(
                [
                    (np.cross(d - b, p - b) * n).sum(1),
                    (np.cross(a - d, p - d) * n).sum(1),
                    (np.cross(b - a, p - a) * n).sum(1),
                ],
                axis=1,
            )
            / area[:, None]
        )
        off_plane = np.abs(((p - a) * n).sum(1)) / np.sqrt(area)
        inside = np.flatnonzero((w >= -1e-6).all(axis=1) & (off_plane < 1e-5))
        assert len(inside), f"{p} is on no welded triangle"
        k = inside[0]
        worst = max(worst, float(np.abs(w[k] @ c[f[k]] - color).max()))
    assert worst <= COLOR_TOL + 1e-5


def test_empty_export_is_a_valid_glb(tmp_path):
    TriMesh3.empty().save(tmp_path / "e.glb")
    scene = trimesh.load(str(tmp_path / "e.glb"))
    assert len(scene.geometry) == 0


# ------------------------------------------------------------------ fuzzing
def _mutations(rng, mesh):
    """Arrays derived from a valid mesh by one random, plausible mistake each."""
    v, t, c = np.array(mesh.vertices, np.float64), np.array(mesh.tets, np.int64), np.array(mesh.colors)
    kind = rng.integers(9)
    if kind == 0:
        v[rng.integers(len(v)), rng.integers(4)] = rng.choice([np.nan, np.inf, -np.inf, 1e30, -1e7])
    elif kind == 1:
        t[rng.integers(len(t)), rng.integers(4)] = rng.choice([-1, len(v), 2**32 + 1, 2**40])
    elif kind == 2:
        v *= rng.choice([1e-30, 1e-6, 1e5, -1.0])
    elif kind == 3:
        t = t[: rng.integers(1, len(t))]  # an open mesh
    elif kind == 4:
        t[:, [0, 1]] = t[:, [1, 0]]  # inside out
    elif kind == 5:
        c = c[:, : rng.integers(0, 5)] if rng.random() < 0.5 else c[: rng.integers(len(c))]
    elif kind == 6:
        v = v.astype(rng.choice([np.float16, np.float32, np.int32]))
    elif kind == 7:
        t = t.astype(rng.choice([np.uint8, np.uint64, np.int16, np.float64]))
    else:
        v[rng.integers(len(v))] = v[rng.integers(len(v))]  # two vertices made one: degenerate tets
    return {"vertices": v, "tets": t, "colors": c}


def test_mutated_npz_meshes_load_or_refuse_cleanly(tmp_path):
    """A fixed-seed fuzz: every mutated file either slices and exports, or raises one InputError line."""
    import warnings

    rng = np.random.default_rng(20261201)
    bases = [make_shape(n) for n in ("5-cell", "tesseract", "24-cell")]
    outcomes = {"ok": 0, "refused": 0}
    for i in range(60):
        path = tmp_path / f"m{i}.npz"
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", RuntimeWarning)
                np.savez(path, **_mutations(rng, bases[i % len(bases)]))
        except (ValueError, RuntimeWarning, OverflowError):
            continue  # numpy itself could not make that array (e.g. 2**40 in uint8); not the loader's business
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            try:
                mesh = TetMesh4.load(path)
                tri = cross_section(mesh)
                tri.save(tmp_path / "out.obj")
                outcomes["ok"] += 1
            except InputError as e:
                assert str(path) in str(e) and "\n" not in str(e), str(e)
                outcomes["refused"] += 1
    assert outcomes["ok"] > 0 and outcomes["refused"] > 10, outcomes
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
