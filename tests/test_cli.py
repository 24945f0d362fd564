"""The ``across-dimensions`` command, run the way a user runs it.

Every test starts ``python -m across_dimensions ...`` in a subprocess and checks
what a user would see: the files written (loaded back with trimesh or
``TetMesh4.load``), the lines printed and the exit status. User errors must be
one line on stderr, a non-zero status and never a traceback.

numba compiles the projection kernels on first use; all subprocesses share one
``NUMBA_CACHE_DIR`` for the session so only the first call pays for it.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from across_dimensions.core.mesh import TetMesh4
from across_dimensions.core.shapes import SHAPES

REPO = Path(__file__).resolve().parents[1]
LEVEL = REPO / "levels" / "01_first_steps.toml"
SHIPPED_REPLAY = REPO / "levels" / "replays" / "01_first_steps.json"
#: The first call compiles numba kernels; later ones take about a second.
TIMEOUT = 240


# ----------------------------------------------------------------- helpers
@pytest.fixture(scope="session")
def cli_env(tmp_path_factory) -> dict:
    """Environment for the CLI: a session-wide numba cache, this checkout first on the path."""
    env = dict(os.environ)
    env["NUMBA_CACHE_DIR"] = str(tmp_path_factory.mktemp("numba-cache"))
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), env.get("PYTHONPATH")) if p)
    env.pop("PYTHONWARNINGS", None)
    return env


def run_cli(env: dict, cwd: Path, *args) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
        cwd=cwd,
        env=env,
    )


@pytest.fixture
def cli(cli_env, tmp_path):
    """``cli(*args, env=None)`` runs the command in ``tmp_path`` and returns the CompletedProcess."""

    def run(*args, env=None) -> subprocess.CompletedProcess:
        return run_cli(cli_env if env is None else env, tmp_path, *args)

    return run


def describe(r: subprocess.CompletedProcess) -> str:
    return f"exit {r.returncode}\n--- stdout\n{r.stdout}--- stderr\n{r.stderr}"


def ok(r: subprocess.CompletedProcess) -> str:
    """Assert success without a traceback; return stdout."""
    assert r.returncode == 0, describe(r)
    assert "Traceback" not in r.stderr + r.stdout, describe(r)
    return r.stdout


def user_error(r: subprocess.CompletedProcess, *needles: str, status: int | None = 2) -> str:
    """Assert a one-line error on stderr, a failing status and no traceback; return the line.

    ``needles`` must all appear in the line (case-insensitive).
    """
    assert r.returncode != 0, describe(r)
    if status is not None:
        assert r.returncode == status, describe(r)
    assert "Traceback" not in r.stderr + r.stdout, describe(r)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, f"expected exactly one line on stderr\n{describe(r)}"
    line = lines[0]
    for needle in needles:
        assert needle.lower() in line.lower(), f"{needle!r} missing from the error line\n{describe(r)}"
    return line


def load_tri(path: Path) -> trimesh.Trimesh:
    """A 3D mesh file as one Trimesh, exactly as written (the writers weld and index it)."""
    m = trimesh.load(str(path), force="mesh", process=False)
    assert isinstance(m, trimesh.Trimesh), type(m)
    return m


def no_temp_files(folder: Path) -> None:
    left = [p.name for p in folder.rglob("*") if p.name.endswith(".tmp")]
    assert not left, f"temporary files left behind: {left}"


def assert_box(m: trimesh.Trimesh, half_extents) -> None:
    h = np.asarray(half_extents, dtype=float)
    assert len(m.faces) > 0
    assert m.is_watertight, "section is not closed"
    assert m.is_winding_consistent
    np.testing.assert_allclose(m.bounds, [-h, h], atol=1e-5)
    # Signed volume: positive means the triangles face outwards.
    assert m.volume == pytest.approx(float(np.prod(2 * h)), rel=1e-4)


# ------------------------------------------------------------------- slice
def test_slice_tesseract_is_the_unit_cube(cli, tmp_path):
    out = ok(cli("slice", "tesseract", "-o", "out.obj"))
    assert "out.obj" in out and "triangles" in out
    assert_box(load_tri(tmp_path / "out.obj"), [0.5, 0.5, 0.5])


def test_slice_rotate_xw_stretches_x(cli, tmp_path):
    ok(cli("slice", "tesseract", "--rotate", "xw=30", "-o", "r.obj"))
    m = load_tri(tmp_path / "r.obj")
    stretch = 1 / math.cos(math.radians(30))
    extent = m.bounds[1] - m.bounds[0]
    assert extent[0] == pytest.approx(stretch, abs=1e-4)
    np.testing.assert_allclose(extent[1:], [1.0, 1.0], atol=1e-5)
    assert m.is_watertight
    assert m.volume == pytest.approx(stretch, rel=1e-4)


def test_slice_translate_within_and_beyond_the_tesseract(cli, tmp_path):
    ok(cli("slice", "tesseract", "--translate", "w=0.3", "-o", "near.obj"))
    assert_box(load_tri(tmp_path / "near.obj"), [0.5, 0.5, 0.5])

    out = ok(cli("slice", "tesseract", "--translate", "w=0.7", "-o", "far.obj"))
    assert "empty" in out.lower(), out
    text = (tmp_path / "far.obj").read_text()
    assert not re.search(r"^f ", text, re.M), "an empty section should write no faces"


@pytest.mark.parametrize("ext", [".ply", ".glb"])
def test_slice_other_formats_load_with_the_same_volume(cli, tmp_path, ext):
    ok(cli("slice", "tesseract", "-o", f"out{ext}"))
    assert_box(load_tri(tmp_path / f"out{ext}"), [0.5, 0.5, 0.5])


@pytest.mark.parametrize("fov, distance", [(60.0, 3.0), (90.0, 4.0)])
def test_slice_frustum_shows_the_inner_cube_smaller(cli, tmp_path, fov, distance):
    args = ["slice", "tesseract", "--mode", "frustum", "-o", "f.obj"]
    if (fov, distance) != (60.0, 3.0):  # the first case uses the defaults
        args += ["--fov", fov, "--distance", distance]
    out = ok(cli(*args))
    assert "frustum" in out
    m = trimesh.load(str(tmp_path / "f.obj"), force="mesh", process=False)
    radii = np.unique(np.round(np.abs(m.vertices).max(axis=1), 5))
    # The camera sits at w = -distance looking along +w: the cell at w = -0.5 is
    # the outer cube (depth distance - 0.5), the cell at w = +0.5 the inner one.
    f = 1 / math.tan(math.radians(fov) / 2)
    near, far = distance - 0.5, distance + 0.5
    assert len(radii) == 2, f"expected the vertices of exactly two cubes, got half-sizes {radii}"
    inner, outer = radii
    assert outer == pytest.approx(0.5 * f / near, abs=1e-4)
    assert inner == pytest.approx(0.5 * f / far, abs=1e-4)
    assert inner / outer == pytest.approx(near / far, abs=1e-4)
    # The 2-skeleton: 24 squares, two triangles each.
    assert len(m.faces) == 48


# ------------------------------------------------------------------- shape
def test_shape_120_cell_writes_a_valid_npz(cli, tmp_path):
    out = ok(cli("shape", "120-cell", "-o", "x.npz"))
    assert "600 vertices" in out
    with np.load(tmp_path / "x.npz") as data:
        assert data["vertices"].shape == (600, 4)
        assert data["tets"].ndim == 2 and data["tets"].shape[1] == 4
    mesh = TetMesh4.load(tmp_path / "x.npz")  # validates: closed, oriented, in range
    assert len(mesh.tets) > 0


def test_shape_list_names_every_shape(cli):
    out = ok(cli("shape", "--list"))
    assert out.split() == list(SHAPES)


def test_shape_with_a_parameter(cli, tmp_path):
    ok(cli("shape", "hypersphere", "--param", "subdivisions=1", "-o", "h.npz"))
    mesh = TetMesh4.load(tmp_path / "h.npz")
    assert mesh.vertices.shape[1] == 4 and len(mesh.tets) > 0
    # All vertices on the unit 3-sphere.
    np.testing.assert_allclose(np.linalg.norm(mesh.vertices, axis=1), 1.0, atol=1e-6)


# ------------------------------------------------------------------ errors
def test_unknown_shape_lists_known_names(cli):
    line = user_error(cli("slice", "nosuchshape", "-o", "a.obj"), "nosuchshape")
    for name in SHAPES:
        assert name in line, f"{name!r} not listed in: {line}"
    line = user_error(cli("shape", "nosuchshape", "-o", "a.npz"), "nosuchshape")
    assert all(name in line for name in SHAPES), line


def test_unknown_rotation_plane(cli, tmp_path):
    line = user_error(cli("slice", "tesseract", "--rotate", "xq=3", "-o", "a.obj"), "xq")
    assert all(p in line for p in ("xy", "xz", "yz", "xw", "yw", "zw")), line
    assert not (tmp_path / "a.obj").exists()


def test_rotation_angle_not_a_number(cli, tmp_path):
    user_error(cli("slice", "tesseract", "--rotate", "xw=abc", "-o", "a.obj"), "abc", "not a number")
    assert not (tmp_path / "a.obj").exists()


def test_bad_output_extension(cli, tmp_path):
    user_error(cli("slice", "tesseract", "-o", "out.stl"), "out.stl", ".obj")
    assert list(tmp_path.iterdir()) == [], "a failed slice left files behind"


def test_missing_output_option(cli):
    user_error(cli("slice", "tesseract"), "-o")
    user_error(cli("shape", "tesseract"), "-o")


def test_unknown_subcommand(cli):
    user_error(cli("frobnicate"), "frobnicate")


def test_lift_missing_file(cli, tmp_path):
    user_error(cli("lift", "missing.obj", "--depth", "1", "-o", "l.npz"), "missing.obj")
    assert not (tmp_path / "l.npz").exists()


def test_lift_negative_depth(cli, tmp_path):
    crate = REPO / "assets" / "meshes" / "crate.obj"
    user_error(cli("lift", crate, "--depth", "-1", "-o", "l.npz"), "depth", "-1")
    assert not (tmp_path / "l.npz").exists()


def test_replay_missing_file(cli):
    user_error(cli("replay", LEVEL, "nosuch.json"), "nosuch.json")


def test_replay_garbage_json(cli, tmp_path):
    (tmp_path / "garbage.json").write_text("{this is not json", encoding="utf-8")
    user_error(cli("replay", LEVEL, "garbage.json"), "garbage.json", "not a replay")


def test_slice_missing_npz(cli):
    user_error(cli("slice", "missing.npz", "-o", "a.obj"), "missing.npz")


def _random_bytes(n: int = 512) -> bytes:
    data = np.random.default_rng(1234).bytes(n)
    assert not data.startswith((b"PK", b"\x93NUMPY"))  # really not a zip or .npy
    return data


@pytest.fixture(scope="module")
def corrupt_npz_run(cli_env, tmp_path_factory):
    """``slice corrupt.npz`` (random bytes) once, for the two tests below."""
    where = tmp_path_factory.mktemp("corrupt")
    (where / "corrupt.npz").write_bytes(_random_bytes())
    return where, run_cli(cli_env, where, "slice", "corrupt.npz", "-o", "a.obj")


def test_slice_corrupt_npz(corrupt_npz_run):
    where, r = corrupt_npz_run
    user_error(r, "corrupt.npz")
    assert not (where / "a.obj").exists()


def test_corrupt_npz_message_does_not_advise_unpickling(corrupt_npz_run):
    line = user_error(corrupt_npz_run[1], "corrupt.npz")
    assert "pickle" not in line.lower(), line


@pytest.mark.parametrize(
    "arrays, needle",
    [
        pytest.param({"a": np.zeros(3)}, "vertices", id="missing-arrays"),
        pytest.param({"vertices": np.zeros((5, 3)), "tets": np.zeros((2, 4), np.int64)}, "vertices", id="3d-vertices"),
        pytest.param({"vertices": np.zeros((5, 4)), "tets": np.zeros((2, 4))}, "tets", id="float-tets"),
        pytest.param(
            {"vertices": np.zeros((5, 4)), "tets": np.array([[0, 1, 2, 9]])}, "index", id="index-out-of-range"
        ),
        pytest.param({"vertices": np.eye(5)[:, :4], "tets": np.array([[0, 1, 2, 3]])}, "tets", id="open-mesh"),
    ],
)
def test_slice_npz_with_wrong_arrays(cli, tmp_path, arrays, needle):
    np.savez(tmp_path / "wrong.npz", **arrays)
    user_error(cli("slice", "wrong.npz", "-o", "a.obj"), "wrong.npz", needle)
    assert not (tmp_path / "a.obj").exists()


def test_slice_npz_with_nan_vertices_is_one_line(cli, tmp_path):
    np.savez(tmp_path / "nan.npz", vertices=np.full((5, 4), np.nan), tets=np.array([[0, 1, 2, 3]]))
    user_error(cli("slice", "nan.npz", "-o", "a.obj"), "nan.npz", "finite")


def test_bad_shape_parameter_value_names_the_parameter(cli):
    user_error(cli("shape", "hypersphere", "--param", "subdivisions=abc", "-o", "h.npz"), "subdivisions", "abc")


def test_output_in_missing_folder_names_the_users_path(cli, tmp_path):
    line = user_error(cli("slice", "tesseract", "-o", tmp_path / "no" / "such" / "a.obj"), "a.obj")
    assert ".tmp" not in line, line


# ------------------------------------------------------------------ replay
def hash_line(out: str) -> str:
    m = re.search(r"^final state hash: (\S+)$", out, re.M)
    assert m, f"no 'final state hash:' line in\n{out}"
    return m.group(1)


def outcome_line(out: str) -> str:
    m = re.search(r"^level '.+': .+ after \d+ ticks", out, re.M)
    assert m, f"no outcome line in\n{out}"
    return m.group(0)


@pytest.mark.slow
@pytest.mark.skipif(not SHIPPED_REPLAY.exists(), reason="levels/replays/01_first_steps.json has not been recorded yet")
def test_shipped_replay_is_deterministic(cli):
    first = ok(cli("replay", LEVEL, SHIPPED_REPLAY))
    second = ok(cli("replay", LEVEL, SHIPPED_REPLAY))
    outcome_line(first)
    assert hash_line(first) == hash_line(second)
    assert first == second


def synthetic_replay(path: Path, final_hash: str = "") -> Path:
    """A short hand-written replay of the first level: walk, strafe, turn, move in w, jump."""
    data = {
        "format": "across-dimensions-replay",
        "version": 1,
        "level": "01_first_steps",
        "level_hash": hashlib.sha256(LEVEL.read_bytes()).hexdigest(),
        "seed": 0,
        "tick_rate": 60,
        "hash_every": 60,
        "actions": [
            [45, [1.0, 0.0, 0.0, 0.0, 0.0, 0]],
            [30, [0.5, 0.3, 0.02, 0.0, 0.5, 0]],
            [45, [1.0, 0.0, 0.0, 0.0, -1.0, 1]],
        ],
        "hashes": {},
        "final": {"ticks": 120, "hash": final_hash, "outcome": None},
    }
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


def test_replay_is_deterministic_across_processes(cli, tmp_path):
    rep = synthetic_replay(tmp_path / "walk.json")
    first, second = ok(cli("replay", LEVEL, rep)), ok(cli("replay", LEVEL, rep))
    assert "after 120 ticks" in outcome_line(first)
    assert re.fullmatch(r"[0-9a-f]{8,}", hash_line(first)), hash_line(first)
    assert hash_line(first) == hash_line(second)


def test_replay_reports_divergence(cli, tmp_path):
    rep = synthetic_replay(tmp_path / "walk.json", final_hash="0" * 16)
    r = cli("replay", LEVEL, rep)
    assert r.returncode == 3, describe(r)
    assert "Traceback" not in r.stderr, describe(r)
    hash_line(r.stdout)
    assert "diverges" in r.stderr, describe(r)


# ------------------------------------------------------------------- play
@pytest.mark.parametrize("args", [[], ["play"]], ids=["bare", "play"])
def test_play_without_a_display(cli, cli_env, args):
    env = {k: v for k, v in cli_env.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    r = cli(*args, env=env)
    line = user_error(r, "display", "demo", status=None)
    assert r.stdout == "", describe(r)
    assert line.startswith("across-dimensions"), line


# ------------------------------------------------------------------ bench
@pytest.mark.slow
def test_bench_quick_prints_throughput_and_copy_baseline(cli):
    out = ok(cli("bench", "--quick", "--no-physics"))
    lines = out.splitlines()
    # Which code the kernels' figures time: a player's shipped kernels or this processor's own.
    assert re.match(r"Kernels: (the shipped kernels, compiled for x86-64-v2|kernels compiled for .+)\.$", lines[0]), out
    header = next((i for i, line in enumerate(lines) if "Mtets/s" in line), None)
    assert header is not None, out
    assert "copy" in lines[header], lines[header]
    rows = [line for line in lines[header + 1 :] if re.search(r"\s\d+\s+[\d.]+\s+\d+\s+[\d.]+\s+[\d.]+$", line)]
    assert len(rows) >= 2, out
    # The game's own figures, each next to its baseline from the same run.
    assert re.search(r"Game\.step:\s+[\d.]+ ms per tick\s+\(baseline, no entities: [\d.]+ ms", out), out
    assert re.search(r"1000 crystals .*Game\.step [\d.]+ ms per tick\s+\(baseline, the path without them", out), out
    assert re.search(r"64 enemies on their own .*Game\.step [\d.]+ ms\s+\(baseline, the hall without them", out), out
    # The held enemies' line says what their frame costs most: the triangles their sections hold.
    assert re.search(r"Enemies: 10 animated in view .*sections, [\d,]+ triangles per frame", out), out
    # A PASS or FAIL line for each CPU target, after the figures.
    for target in ("Game.frame, 200 entities <= 2 ms", "Game.step, 10 enemies in view <= 1 ms",
                   "Game.frame, 10 enemies in view <= 2 ms", "Game.step, 64 enemies <= 4 ms",
                   "Game.step, 1000 crystals <= 2 ms"):  # fmt: skip
        assert re.search(rf"\[(PASS|FAIL)\] {re.escape(target)}: [\d.]+ ms \(baseline", out), (target, out)
    # The 4D camera's modes, next to cross-section on the same scene.
    modes = r"cross-section [\d.]+ ms\s+frustum, camera still [\d.]+ ms\s+frustum, orbiting [\d.]+ ms"
    assert re.search(modes, out), out
    assert re.search(r"200 radar pins: HUD with energy bar and radar [\d.]+ ms\s+\(baseline, HUD alone", out) or (
        "HUD and radar: skipped" in out
    ), out
    # The sci-fi look next to the flat look, per shipped level.
    assert re.search(r"01_first_steps\.toml\s+sci-fi\s+[\d.]+ ms .*\(baseline, flat look: ", out) or (
        "HUD and radar: skipped" in out
    ), out


# ------------------------------------------------------- welded exports
@pytest.mark.parametrize("ext", [".obj", ".ply", ".glb"])
def test_slice_exports_a_welded_closed_cube(cli, tmp_path, ext):
    ok(cli("slice", "tesseract", "-o", f"cube{ext}"))
    m = load_tri(tmp_path / f"cube{ext}")  # no merge_vertices: the file itself must be indexed
    assert (len(m.vertices), len(m.faces)) == (8, 12)
    assert_box(m, [0.5, 0.5, 0.5])
    # Per-vertex colours survive: the tesseract's palette shades the cube from bottom to top.
    colors = np.asarray(m.visual.vertex_colors)[:, :3].astype(int)
    assert len(np.unique(colors, axis=0)) == 2, colors
    top = m.vertices[:, 1] > 0
    assert (colors[top].sum(axis=1) > colors[~top].sum(axis=1).max()).all()
    no_temp_files(tmp_path)


def test_slice_obj_text_is_indexed(cli, tmp_path):
    out = ok(cli("slice", "tesseract", "-o", "cube.obj"))
    assert "cube.obj: 12 triangles, 8 vertices" in out, out
    lines = (tmp_path / "cube.obj").read_text(encoding="ascii").splitlines()
    assert sum(line.startswith("v ") for line in lines) == 8
    assert sum(line.startswith("f ") for line in lines) == 12


def test_slice_welded_hypersphere_is_watertight(cli, tmp_path):
    ok(cli("slice", "hypersphere", "--translate", "w=0.3", "--rotate", "xw=20", "-o", "s.obj"))
    m = load_tri(tmp_path / "s.obj")
    assert m.is_watertight and m.is_winding_consistent and m.volume > 0


@pytest.mark.parametrize("ext", [".obj", ".ply", ".glb"])
def test_slice_empty_section_writes_a_valid_empty_file(cli, tmp_path, ext):
    out = ok(cli("slice", "tesseract", "--translate", "w=5", "-o", f"empty{ext}"))
    assert "empty" in out
    loaded = trimesh.load(str(tmp_path / f"empty{ext}"), process=False)
    if isinstance(loaded, trimesh.Scene):
        assert len(loaded.geometry) == 0
    else:
        assert len(loaded.faces) == 0
    no_temp_files(tmp_path)


# ----------------------------------------------------------------- lift
def test_lift_writes_a_valid_tetmesh(cli, cli_env, tmp_path):
    env = dict(cli_env, XDG_CACHE_HOME=str(tmp_path / "cache"))  # a fresh bake, not the user's cache
    out = ok(cli("lift", REPO / "assets" / "meshes" / "crate.obj", "--depth", "1", "-o", "crate.npz", env=env))
    mesh = TetMesh4.load(tmp_path / "crate.npz")  # validates: closed, oriented, in range
    assert f"{len(mesh.vertices)} vertices, {len(mesh.tets)} tets" in out, out
    lo, hi = mesh.bounds()
    assert hi[3] - lo[3] == pytest.approx(1.0, rel=1e-5)
    assert mesh.hypervolume() > 0
    no_temp_files(tmp_path)


def test_lift_refuses_a_missing_output_folder_before_baking(cli, tmp_path):
    crate = REPO / "assets" / "meshes" / "crate.obj"
    user_error(cli("lift", crate, "--depth", "1", "-o", "no/such/l.npz"), "no/such", "does not exist")
    assert not (tmp_path / "no").exists()


# -------------------------------------------------------- option limits
@pytest.mark.parametrize(
    "args, needles",
    [
        (["--rotate", "xw=nan"], ["--rotate", "xw", "finite"]),
        (["--rotate", "xw=inf"], ["--rotate", "finite"]),
        (["--translate", "w=nan"], ["--translate", "w", "finite"]),
        (["--translate", "w=-inf"], ["--translate", "finite"]),
        (["--translate", "w=1e300"], ["--translate", "1e+06"]),
        (["--mode", "frustum", "--fov", "0"], ["--fov", "between 0 and 180"]),
        (["--mode", "frustum", "--fov", "180"], ["--fov", "180"]),
        (["--mode", "frustum", "--fov", "nan"], ["--fov", "finite"]),
        (["--mode", "frustum", "--fov", "1e-300"], ["--fov"]),
        (["--mode", "frustum", "--distance", "0"], ["--distance", "positive"]),
        (["--mode", "frustum", "--distance", "inf"], ["--distance", "finite"]),
    ],
    ids=lambda v: "_".join(v) if isinstance(v, list) else None,
)
def test_slice_refuses_bad_numbers_naming_the_option(cli, tmp_path, args, needles):
    user_error(cli("slice", "tesseract", *args, "-o", "a.obj"), *needles)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "param, needles",
    [
        ("subdivisions=50", ["subdivisions", "0 to 3", "50"]),
        ("subdivisions=1.5", ["subdivisions", "whole"]),
        ("radius=inf", ["radius", "finite"]),
        ("radius=nan", ["radius"]),
        ("radius=0", ["radius", "0.001"]),
        ("radius=1e9", ["radius", "1000"]),
    ],
)
def test_shape_parameters_are_bounded_before_any_work(cli, tmp_path, param, needles):
    r = cli("shape", "hypersphere", "--param", param, "-o", "h.npz")
    user_error(r, *needles)
    assert list(tmp_path.iterdir()) == []


def test_shape_duoprism_sides_are_bounded(cli, tmp_path):
    user_error(cli("shape", "duoprism", "--param", "p=100000", "-o", "d.npz"), "'p'", "3 to 128")


def test_numpy_warnings_never_reach_the_user(cli, cli_env, tmp_path):
    env = dict(cli_env, PYTHONWARNINGS="error::RuntimeWarning")  # a warning would become an internal error
    for args in (
        ["slice", "tesseract", "--mode", "frustum", "--fov", "0.001", "--distance", "1e6", "-o", "a.obj"],
        ["slice", "24-cell", "--mode", "frustum", "--fov", "179.999", "--distance", "1e-300", "-o", "a.ply"],
        ["slice", "hypersphere", "--rotate", "xw=1e6", "--translate", "w=0.999", "-o", "a.glb"],
    ):
        ok(cli(*args, env=env))


# --------------------------------------------------- special and hostile files
@pytest.fixture
def special_files(tmp_path):
    os.mkfifo(tmp_path / "fifo.npz")
    os.symlink("/dev/zero", tmp_path / "zero.npz")
    (tmp_path / "folder.npz").mkdir()
    return tmp_path


@pytest.mark.parametrize("name, needle", [("fifo.npz", "FIFO"), ("zero.npz", "device"), ("folder.npz", "folder")])
def test_slice_special_files_give_one_line(cli, special_files, name, needle):
    r = cli("slice", name, "-o", "a.obj")  # a FIFO must not block, /dev/zero must not be read
    user_error(r, name, needle)


def _zip_bomb(path: Path, member_mib: int = 400) -> None:
    """A .npz whose 'vertices' member inflates from a few hundred kB to ``member_mib`` MiB of zeros."""
    import io
    import zipfile

    header = io.BytesIO()
    n = member_mib * (1 << 20) // 32
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (n, 4)})
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=9) as z:
        with z.open("vertices.npy", "w", force_zip64=True) as f:
            f.write(header.getvalue())
            chunk = bytes(1 << 20)
            for _ in range(member_mib):
                f.write(chunk)
        z.writestr("tets.npy", b"")


def test_slice_refuses_a_zip_bomb_without_inflating_it(cli, tmp_path):
    _zip_bomb(tmp_path / "bomb.npz")
    assert (tmp_path / "bomb.npz").stat().st_size < 1 << 20
    r = cli("slice", "bomb.npz", "-o", "a.obj")
    line = user_error(r, "bomb.npz", "vertices")
    assert "rows" in line
    assert not (tmp_path / "a.obj").exists()


def test_slice_refuses_a_header_promising_a_huge_array(cli, tmp_path):
    import io
    import zipfile

    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (10**12, 4)})
    with zipfile.ZipFile(tmp_path / "liar.npz", "w") as z:
        z.writestr("vertices.npy", header.getvalue() + bytes(64))
        z.writestr("tets.npy", header.getvalue())
    user_error(cli("slice", "liar.npz", "-o", "a.obj"), "liar.npz", "at most 1000000")


@pytest.mark.parametrize(
    "arrays, needles",
    [
        pytest.param(
            {"vertices": np.eye(5)[:, :4], "tets": np.array([[0, 1, 2, 2**32 + 3]], np.uint64)},
            ["tets", "4294967299"],
            id="uint64-above-2^32",
        ),
        pytest.param(
            {"vertices": np.array([["a"] * 4] * 5), "tets": np.array([[0, 1, 2, 3]])},
            ["vertices", "real numbers"],
            id="string-vertices",
        ),
        pytest.param(
            {"vertices": np.eye(5)[:, :4], "tets": np.array([["0"] * 4])}, ["tets", "integers"], id="string-tets"
        ),
        pytest.param(
            {"vertices": np.eye(5)[:, :4], "tets": np.array([[0, 1, 2, 3]]), "colors": np.float32(1)},
            ["colors", "shape ()"],
            id="scalar-colors",
        ),
        pytest.param(
            {"vertices": np.eye(5)[:, :4], "tets": np.array([[0, 1, 2, 3]]), "colors": np.ones((5, 7))},
            ["colors", "(5, 7)"],
            id="wide-colors",
        ),
        pytest.param(
            {"vertices": np.eye(5)[:, :4], "tets": np.array([[0, 1, 2, 3]]), "colors": np.ones((4, 3))},
            ["colors", "4 rows"],
            id="too-few-colors",
        ),
        pytest.param(
            {"vertices": np.full((5, 4), np.inf), "tets": np.array([[0, 1, 2, 3]])},
            ["vertices", "finite"],
            id="inf-vertices",
        ),
        pytest.param(
            {"vertices": np.full((5, 4), 1e30), "tets": np.array([[0, 1, 2, 3]])},
            ["vertices", "1e+06"],
            id="huge-vertices",
        ),
        pytest.param(
            {"vertices": np.eye(5)[:, :4], "tets": np.array([[0, 1, 2, -3]])}, ["tets", "negative"], id="negative-index"
        ),
    ],
)
def test_slice_npz_hostile_arrays_give_one_line(cli, tmp_path, arrays, needles):
    np.savez(tmp_path / "bad.npz", **arrays)
    user_error(cli("slice", "bad.npz", "-o", "a.obj"), "bad.npz", *needles)
    assert not (tmp_path / "a.obj").exists()


def test_slice_refuses_a_nested_zip(cli, tmp_path):
    import zipfile

    np.savez(tmp_path / "inner.npz", vertices=np.eye(5)[:, :4], tets=np.array([[0, 1, 2, 3]]))
    with zipfile.ZipFile(tmp_path / "nested.npz", "w") as z:
        z.write(tmp_path / "inner.npz", "vertices.npy")
        z.write(tmp_path / "inner.npz", "tets.npy")
    user_error(cli("slice", "nested.npz", "-o", "a.obj"), "nested.npz", "nested zip")


# ------------------------------------------------------ atomic writes
def test_two_concurrent_slices_to_one_file_leave_a_whole_file(cli_env, tmp_path):
    cmd = [sys.executable, "-m", "across_dimensions", "slice"]
    runs = [
        subprocess.Popen(
            [*cmd, shape, "-o", "same.obj"],
            cwd=tmp_path,
            env=cli_env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for shape in ("hypersphere", "tesseract")
    ]
    for p in runs:
        _, err = p.communicate(timeout=TIMEOUT)
        assert p.returncode == 0, err
    m = load_tri(tmp_path / "same.obj")
    assert m.is_watertight and m.is_winding_consistent
    assert len(m.vertices) == 8 or len(m.vertices) > 100  # one whole run's file, never a mix
    no_temp_files(tmp_path)


def test_output_in_missing_folder_is_refused_before_any_work(cli, tmp_path):
    for args in (["slice", "tesseract"], ["shape", "tesseract"]):
        ext = ".obj" if args[0] == "slice" else ".npz"
        line = user_error(cli(*args, "-o", f"missing/out{ext}"), "missing", "does not exist")
        assert ".tmp" not in line
    assert list(tmp_path.iterdir()) == []


def test_killed_write_leaves_no_temporary_file(cli_env, tmp_path):
    """SIGTERM arriving in the middle of writing the .npz: no output, no temporary file."""
    script = (
        "import os, signal, sys, numpy as np\n"
        "real = np.savez_compressed\n"
        "def dying(f, **arrays):\n"
        "    f.write(b'PK half a file')\n"
        "    os.kill(os.getpid(), signal.SIGTERM)\n"
        "    real(f, **arrays)\n"
        "np.savez_compressed = dying\n"
        "from across_dimensions.app.cli import main\n"
        "sys.exit(main(['shape', 'tesseract', '-o', 'x.npz']))\n"
    )
    r = subprocess.run(
        [sys.executable, "-c", script], cwd=tmp_path, env=cli_env, capture_output=True, text=True, timeout=TIMEOUT
    )
    assert r.returncode == 128 + 15, describe(r)
    assert "Traceback" not in r.stderr, describe(r)
    assert list(tmp_path.iterdir()) == []


def test_a_signal_caught_inside_a_library_still_ends_as_stopped_not_internal_error(cli_env, tmp_path):
    """numba's compiler turns an exception raised inside it into a RuntimeError: SIGTERM during
    a first run's kernel compile must still read as stopped, with the signal's exit status."""
    script = (
        "import os, signal, sys\n"
        "from across_dimensions.app import commands\n"
        "def compiling(args):\n"
        "    try:\n"
        "        os.kill(os.getpid(), signal.SIGTERM)\n"
        "    except SystemExit as e:\n"
        "        raise RuntimeError('no compiled object yet') from e\n"
        "commands.shape = compiling\n"
        "from across_dimensions.app.cli import main\n"
        "sys.exit(main(['shape', 'tesseract', '-o', 'x.npz']))\n"
    )
    r = subprocess.run(
        [sys.executable, "-c", script], cwd=tmp_path, env=cli_env, capture_output=True, text=True, timeout=TIMEOUT
    )
    assert r.returncode == 128 + 15, describe(r)
    assert r.stderr.strip() == "across-dimensions: stopped by SIGTERM", describe(r)


# ------------------------------------------------------------- errors
def test_internal_errors_are_not_reported_as_user_errors(cli_env, tmp_path):
    script = (
        "import sys\n"
        "from across_dimensions.app import commands\n"
        "def broken(args):\n"
        "    raise ValueError('a bug, not bad input')\n"
        "commands.shape = broken\n"
        "from across_dimensions.app.cli import main\n"
        "sys.exit(main(['shape', 'tesseract', '-o', 'x.npz']))\n"
    )
    r = subprocess.run(
        [sys.executable, "-c", script], cwd=tmp_path, env=cli_env, capture_output=True, text=True, timeout=TIMEOUT
    )
    assert r.returncode == 1, describe(r)
    assert "internal error: ValueError" in r.stderr, describe(r)


def test_play_with_a_display_that_does_not_answer(cli, cli_env):
    env = {k: v for k, v in cli_env.items() if k != "WAYLAND_DISPLAY"}
    env["DISPLAY"] = ":917"  # an unusual number: no X server listens there
    r = cli("play", env=env)
    line = user_error(r, "DISPLAY=:917", "demo", status=1)
    assert "internal error" not in line


def test_play_unknown_level_is_a_user_error(cli):
    user_error(cli("play", "no_such_level"), "no_such_level", "shipped levels")


def test_a_reader_that_goes_away_ends_the_command_quietly(cli_env, tmp_path):
    # `across-dimensions ... | head`: the pipe is closed before the command writes to it.
    p = subprocess.Popen(
        [sys.executable, "-m", "across_dimensions", "replay", LEVEL, SHIPPED_REPLAY, "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=tmp_path,
        env=cli_env,
    )
    p.stdout.close()
    err = p.stderr.read().decode()
    assert p.wait(timeout=TIMEOUT) == 141, err  # 128 + SIGPIPE, as a shell reports it
    assert err == ""
