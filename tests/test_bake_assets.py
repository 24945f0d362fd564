"""Asset baking (world.bake and world.assets): repair, confinement, bounds, cache, progress.

The repair tests pin what the hand-written repair this project used before
trimesh's produced (recorded at commit da20a67): the same vertices, faces and
volumes, bit for bit, on every shipped asset, and the same counts and volumes
on the hole and flip cases.
"""

from __future__ import annotations

import base64
import hashlib
import io
import json
import os
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
import trimesh

from across_dimensions.core.lift import box_solid
from across_dimensions.world import bake
from across_dimensions.world.assets import bake_cache, confine, limits, mesh_files, tetwild
from across_dimensions.world.assets.progress import BakeProgress
from across_dimensions.world.bake import AssetError, cache_key, lift_asset, load_surface

REPO = Path(__file__).resolve().parents[1]
ASSETS = REPO / "assets" / "meshes"


def signed_volume(vertices, faces) -> float:
    p = np.asarray(vertices, np.float64)[np.asarray(faces)]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def digest(a: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()[:16]


def cube_surface(offset=0.0):
    v, _ = box_solid([0.5, 0.5, 0.5], 1.0)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    f = [(a, b, c) for a, b, c, d in quads] + [(a, c, d) for a, b, c, d in quads]
    return v + offset, np.array(f)


def one_line_error(excinfo, *needles: str) -> str:
    msg = str(excinfo.value)
    assert "\n" not in msg, msg
    for n in needles:
        assert n in msg, msg
    return msg


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


# ------------------------------------------------------------------ repair
#: name: (vertices, faces, volume, sha256[:16] of vertices float64, of faces int64),
#: from the hand-written repair (merge, fill, fix_winding, fix_inversion) of commit da20a67.
SHIPPED = {
    "arch.obj": (100, 196, 2.1705411970279997, "1f2b0d198214e8e7", "05fe198157523d91"),
    "crate.obj": (24, 44, 0.9907413333333336, "c7395286d534c0eb", "5dbda67784f18158"),
    "pillar.obj": (194, 384, 0.6839831799600201, "2312ae30c71f282d", "52d0c16b198da31a"),
    "tree.obj": (182, 360, 2.2545978362538666, "e52c7ec84326df39", "3c0099a7d2ca35eb"),
    # The props, as make_assets.py writes them.
    "console.obj": (12, 20, 0.6504300000000001, "6ed9a3198333d1ab", "6bbabd1e0fbe10e3"),
    "door.obj": (40, 76, 1.548, "4e4a728ce0eb2b6d", "d0e526c8671ecb98"),
    "plant.obj": (162, 320, 0.3592172678790333, "c22582e267a06fcc", "6256de4092dcde07"),
}


def test_every_shipped_asset_is_pinned():
    assert {p.name for p in ASSETS.glob("*.obj")} == set(SHIPPED)


@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_trimesh_repair_gives_the_old_surfaces_bit_for_bit(name):
    n_v, n_f, volume, hv, hf = SHIPPED[name]
    v, f = load_surface(ASSETS / name)
    assert (len(v), len(f)) == (n_v, n_f)
    assert signed_volume(v, f) == pytest.approx(volume, rel=1e-12)
    # Same arrays, so the tetrahedralizer gets exactly the input it got before.
    assert (digest(v.astype(np.float64)), digest(f.astype(np.int64))) == (hv, hf)


def _holey():
    v, f = cube_surface()
    f = f.copy()
    f[3] = f[3, ::-1]
    return v, np.delete(f, [0, 6], axis=0)


def _three_flipped():
    v, f = cube_surface()
    f = f.copy()
    f[[1, 4, 9]] = f[[1, 4, 9], ::-1]
    return v, f


def _two_bodies_one_inside_out():
    (v1, f1), (v2, f2) = cube_surface(), cube_surface(3.0)
    return np.r_[v1, v2], np.r_[f1, (f2 + 8)[:, ::-1]]


def _unwelded_copy():
    v, f = cube_surface()
    return np.r_[v, v], np.r_[f, f + 8]


#: case: (vertices, faces, volume) the old repair gave.
REPAIR_CASES = {
    "quad_hole_and_a_flipped_face": (_holey, 8, 12, 1.0),
    "inside_out": (lambda: (cube_surface()[0], cube_surface()[1][:, ::-1]), 8, 12, 1.0),
    "three_flipped_faces": (_three_flipped, 8, 12, 1.0),
    "triangle_hole": (lambda: (cube_surface()[0], np.delete(cube_surface()[1], [0], axis=0)), 8, 12, 1.0),
    "two_bodies_one_inside_out": (_two_bodies_one_inside_out, 16, 24, 2.0),
    "duplicated_unwelded_copy": (_unwelded_copy, 8, 12, 1.0),
}


@pytest.mark.parametrize("case", sorted(REPAIR_CASES))
def test_trimesh_repair_matches_the_old_counts_and_volumes(case):
    make, n_v, n_f, volume = REPAIR_CASES[case]
    v, f = bake.repair_surface(*make(), case)
    assert (len(v), len(f)) == (n_v, n_f)
    assert signed_volume(v, f) == pytest.approx(volume, rel=1e-12)
    mesh = trimesh.Trimesh(v, f, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent


def test_a_big_hole_is_reported_not_guessed():
    v, f = cube_surface()
    with pytest.raises(AssetError) as e:
        bake.repair_surface(v, np.delete(f, [0, 6, 2, 8], axis=0), "open_box.obj")
    one_line_error(e, "open_box.obj", "6 open edges", "not watertight")


def test_faces_out_of_range_are_refused():
    v, f = cube_surface()
    with pytest.raises(AssetError) as e:
        bake.repair_surface(v, f + 5, "bad.obj")
    one_line_error(e, "bad.obj", "do not exist")


# ------------------------------------------------------------ confinement
def write_gltf(folder: Path, name="box.gltf") -> Path:
    """A unit box as .gltf plus its .bin buffer in ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    scene = trimesh.Scene(trimesh.creation.box())
    path = folder / name
    scene.export(path)
    return path


def set_uri(gltf: Path, uri: str, key="buffers") -> None:
    doc = json.loads(gltf.read_text())
    if key == "images":
        doc["images"] = [{"uri": uri}]
    else:
        doc["buffers"][0]["uri"] = uri
    gltf.write_text(json.dumps(doc))


def test_a_gltf_in_its_folder_loads(tmp_path):
    v, f = load_surface(write_gltf(tmp_path / "asset"))
    assert len(f) == 12 and signed_volume(v, f) == pytest.approx(1.0)


@pytest.mark.parametrize(
    "uri",
    [
        "/etc/hostname",
        "../../x.bin",
        "../secret.bin",
        "sub/../../secret.bin",
        "..%2Fsecret.bin",
        "file:///etc/hostname",
        "C:/Windows/x.bin",
        "\\\\host\\x.bin",
    ],
)
def test_gltf_buffer_uri_outside_the_folder_is_refused(tmp_path, uri, fake_tetwild):
    (tmp_path / "secret.bin").write_bytes(b"\0" * 1024)
    gltf = write_gltf(tmp_path / "asset")
    set_uri(gltf, uri)
    for call in (
        lambda: load_surface(gltf),
        lambda: cache_key(gltf),
        lambda: lift_asset(gltf, 1.0, cache_dir=tmp_path / "cache", progress=False),
    ):
        with pytest.raises(AssetError) as e:
            call()
        one_line_error(e, "box.gltf", repr(uri), "buffer 0 URI")
    assert not fake_tetwild
    assert not (tmp_path / "cache").exists()


def test_gltf_image_uri_outside_the_folder_is_refused(tmp_path):
    gltf = write_gltf(tmp_path / "asset")
    set_uri(gltf, "/etc/passwd", key="images")
    with pytest.raises(AssetError) as e:
        cache_key(gltf)
    one_line_error(e, "box.gltf", "'/etc/passwd'", "image 0 URI")


def test_symlink_out_of_the_folder_is_refused(tmp_path):
    gltf = write_gltf(tmp_path / "asset")
    bin_name = json.loads(gltf.read_text())["buffers"][0]["uri"]
    os.replace(gltf.parent / bin_name, tmp_path / "outside.bin")
    (gltf.parent / bin_name).symlink_to(tmp_path / "outside.bin")
    with pytest.raises(AssetError) as e:
        load_surface(gltf)
    one_line_error(e, "box.gltf", "leaves the asset's folder")


def test_subfolders_and_data_uris_are_fine_and_hashed(tmp_path):
    gltf = write_gltf(tmp_path / "asset")
    bin_name = json.loads(gltf.read_text())["buffers"][0]["uri"]
    (gltf.parent / "buffers").mkdir()
    os.replace(gltf.parent / bin_name, gltf.parent / "buffers" / "box.bin")
    set_uri(gltf, "buffers/box.bin")
    assert len(load_surface(gltf)[1]) == 12
    key = cache_key(gltf)
    data = (gltf.parent / "buffers" / "box.bin").read_bytes()
    (gltf.parent / "buffers" / "box.bin").write_bytes(data[::-1])
    assert cache_key(gltf) != key  # the referenced buffer is part of the key
    set_uri(gltf, "data:application/octet-stream;base64," + base64.b64encode(data).decode())
    assert len(load_surface(gltf)[1]) == 12


def test_a_fifo_outside_the_folder_is_never_opened(tmp_path):
    fifo = tmp_path / "pipe.bin"
    os.mkfifo(fifo)
    gltf = write_gltf(tmp_path / "asset")
    set_uri(gltf, str(fifo))
    with pytest.raises(AssetError, match="is absolute"):
        load_surface(gltf)  # opening the FIFO would block forever


def test_an_obj_material_library_is_never_opened(tmp_path):
    fifo = tmp_path / "materials.mtl"
    os.mkfifo(fifo)  # opening it would block forever
    text = (ASSETS / "crate.obj").read_text()
    for ref in (str(fifo), "../materials.mtl"):
        (tmp_path / "asset").mkdir(exist_ok=True)
        path = tmp_path / "asset" / "crate.obj"
        path.write_text(f"mtllib {ref}\nusemtl wood\n{text}")
        assert len(load_surface(path)[1]) == SHIPPED["crate.obj"][1]


def test_a_malformed_glb_is_named(tmp_path):
    for data, why in ((b"glTF" + b"\0" * 30, "no complete JSON chunk"), (b"nope" * 10, "expected the 'glTF' header")):
        path = tmp_path / "bad.glb"
        path.write_bytes(data)
        with pytest.raises(AssetError) as e:
            load_surface(path)
        one_line_error(e, "bad.glb", why)


def test_the_resolver_serves_only_its_folder(tmp_path):
    (tmp_path / "asset" / "sub").mkdir(parents=True)
    (tmp_path / "asset" / "sub" / "a.bin").write_bytes(b"abc")
    (tmp_path / "b.bin").write_bytes(b"outside")
    root = (tmp_path / "asset").resolve()
    res = confine.ConfinedResolver(root, root / "m.gltf", confine.Budget(7))
    assert res["sub/a.bin"] == b"abc"
    assert res.namespaced("sub").get("a.bin") == b"abc"
    assert "sub/a.bin" in res and "../b.bin" not in res
    assert list(res.keys()) == []
    with pytest.raises(AssetError, match="leaves"):
        res.get("../b.bin")
    with pytest.raises(AssetError, match="leaves"):
        res.namespaced("..").get("b.bin")
    with pytest.raises(AssetError, match="more than the 1 bytes left of the 7 bytes"):
        res.get("sub/a.bin")  # 6 of the 7 bytes are spent
    with pytest.raises(AssetError, match="never writes"):
        res.write("x.bin", b"")


def test_gltf_accessor_counts_are_bounded_together(tmp_path):
    gltf = write_gltf(tmp_path / "asset")
    doc = json.loads(gltf.read_text())
    doc["accessors"][0]["count"] = 10**12
    gltf.write_text(json.dumps(doc))
    with pytest.raises(AssetError) as e:
        load_surface(gltf)
    one_line_error(e, "box.gltf", "accessor 0", str(10**12), f"more than the {limits.MAX_GLTF_ELEMENTS}")
    # Many accessors without buffers, each small, add up: the loader would allocate them all.
    doc["accessors"] = [{"componentType": 5126, "type": "VEC3", "count": 100_000}] * 1000
    gltf.write_text(json.dumps(doc))
    with pytest.raises(AssetError) as e:
        load_surface(gltf)
    one_line_error(e, "box.gltf", f"accessor {limits.MAX_GLTF_ELEMENTS // 100_000}")


# ------------------------------------------------------------------ bounds
def test_file_larger_than_the_limit_is_refused_without_reading(tmp_path):
    big = tmp_path / "big.obj"
    with open(big, "wb") as f:
        f.truncate(bake.MAX_ASSET_BYTES + 1)  # sparse: no disk used
    with pytest.raises(AssetError) as e:
        load_surface(big)
    one_line_error(e, "big.obj", "larger than the 32 MiB")


def test_fifo_and_dev_zero_give_one_line(tmp_path):
    fifo = tmp_path / "pipe.obj"
    os.mkfifo(fifo)
    with pytest.raises(AssetError) as e:
        load_surface(fifo)
    one_line_error(e, "pipe.obj", "pipe (FIFO)")
    zero = tmp_path / "zero.stl"
    zero.symlink_to("/dev/zero")
    with pytest.raises(AssetError) as e:
        bake.bake_solid(zero, cache_dir=tmp_path / "c", progress=False)
    one_line_error(e, "zero.stl", "device")


def test_triangle_limit(tmp_path, monkeypatch):
    monkeypatch.setattr(mesh_files, "MAX_TRIANGLES", 10)
    # Text formats are counted before trimesh parses them...
    with pytest.raises(AssetError) as e:
        load_surface(ASSETS / "crate.obj")
    one_line_error(e, "crate.obj", "44 faces", "more than the 10 triangles")
    stl = tmp_path / "box.stl"
    stl.write_bytes(box_stl(False).encode())
    with pytest.raises(AssetError) as e:
        load_surface(stl)
    one_line_error(e, "box.stl", "12 faces", "more than the 10 triangles")
    # ... and everything once loaded.
    with pytest.raises(AssetError) as e:
        load_surface(write_gltf(tmp_path / "asset"))
    one_line_error(e, "box.gltf", "12 triangles", "more than the 10")


def test_unsupported_format_is_refused_before_reading(tmp_path):
    fifo = tmp_path / "model.fbx"
    os.mkfifo(fifo)
    for call in (lambda: load_surface(fifo), lambda: bake.bake_solid(fifo, cache_dir=tmp_path, progress=False)):
        with pytest.raises(AssetError) as e:
            call()
        one_line_error(e, "model.fbx", "unsupported mesh format '.fbx'")


def test_tet_limit(tmp_path, monkeypatch, fake_tetwild):
    monkeypatch.setattr(bake, "MAX_TETS", 5)
    with pytest.raises(AssetError) as e:
        lift_asset(ASSETS / "crate.obj", 1.0, cache_dir=tmp_path, progress=False)
    one_line_error(e, "crate.obj", "6 tets", "more than the 5")
    assert not list(tmp_path.iterdir())  # nothing cached


def box_stl(binary: bool) -> bytes:
    return trimesh.creation.box().export(file_type="stl" if binary else "stl_ascii")


def test_stl_binary_and_ascii_load(tmp_path):
    for binary in (True, False):
        path = tmp_path / f"box{int(binary)}.stl"
        data = box_stl(binary)
        path.write_bytes(data if isinstance(data, bytes) else data.encode())
        v, f = load_surface(path)
        assert len(f) == 12 and signed_volume(v, f) == pytest.approx(1.0)


@pytest.mark.parametrize("damage", ["truncated", "header_count", "garbage", "tiny"])
def test_corrupt_stl_gives_one_clear_line(tmp_path, damage):
    good = box_stl(True)
    data = {
        "truncated": good[:-7],
        "header_count": good[:80] + struct.pack("<I", 10**9) + good[84:],
        "garbage": np.random.default_rng(3).integers(0, 256, 1000, dtype=np.uint8).tobytes(),
        "tiny": b"\x00\xff\x10",
    }[damage]
    path = tmp_path / "broken.stl"
    path.write_bytes(data)
    with pytest.raises(AssetError) as e:
        load_surface(path)
    msg = one_line_error(e, "broken.stl")
    assert "charset" not in msg and "module" not in msg
    if damage in ("truncated", "header_count"):
        assert "corrupt binary STL" in msg


def test_binary_stl_header_beyond_the_triangle_limit(tmp_path, monkeypatch):
    monkeypatch.setattr(mesh_files, "MAX_TRIANGLES", 5)
    path = tmp_path / "box.stl"
    path.write_bytes(box_stl(True))
    with pytest.raises(AssetError) as e:
        load_surface(path)
    one_line_error(e, "box.stl", "12 triangles", "more than the 5")


# ------------------------------------------------------------------- cache
def test_interrupted_save_leaves_nothing(tmp_path, monkeypatch, fake_tetwild):
    def half_then_interrupt(archive, *args, **kw):
        archive.fp.write(b"PK\x03\x04 half an archive")
        raise KeyboardInterrupt

    monkeypatch.setattr(bake_cache.zipfile.ZipFile, "writestr", half_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        lift_asset(ASSETS / "crate.obj", 1.0, cache_dir=tmp_path, progress=False)
    assert list(tmp_path.iterdir()) == []


def test_interrupted_tetrahedralization_leaves_nothing(tmp_path, monkeypatch):
    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(bake, "tetrahedralize", interrupted)
    with pytest.raises(KeyboardInterrupt):
        lift_asset(ASSETS / "crate.obj", 1.0, cache_dir=tmp_path, progress=False)
    assert list(tmp_path.iterdir()) == []


def test_interrupting_the_tetwild_child_kills_it_and_cleans_up(tmp_path, monkeypatch):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    v, f = load_surface(ASSETS / "crate.obj")
    waits = []

    def interrupt():
        waits.append(1)
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        tetwild.tetrahedralize(v, f, 0.01, on_wait=interrupt)  # fine enough to take more than 0.1 s
    assert waits == [1]
    assert list(tmp_path.iterdir()) == []  # the child's folder is gone with its files


def test_an_oversized_or_planted_cache_entry_is_rebuilt(tmp_path, fake_tetwild):
    lift_asset(ASSETS / "crate.obj", 1.0, cache_dir=tmp_path, progress=False)
    (entry,) = tmp_path.glob("crate-*.npz")
    buf = io.BytesIO()
    np.savez_compressed(
        buf, vertices=np.zeros((8, 3)), tets=np.zeros((bake.MAX_TETS + 1, 4), np.int32), bake_version=bake.BAKE_VERSION
    )
    entry.write_bytes(buf.getvalue())
    assert bake_cache.load_entry(entry) is None
    lift_asset(ASSETS / "crate.obj", 1.0, cache_dir=tmp_path, progress=False)
    assert len(fake_tetwild) == 2
    assert bake_cache.load_entry(entry) is not None


# ---------------------------------------------------------------- progress
class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_on_a_terminal_redraws_one_line_then_summarises():
    out = Terminal()
    bar = BakeProgress("pillar.obj", True, out)
    assert bar.shown
    bar.stage("tetrahedralize 384 triangles")
    bar.tick()
    bar.done("1857 tets")
    text = out.getvalue()
    assert "\rbake pillar.obj: tetrahedralize 384 triangles" in text
    last = text.rsplit("\r", 1)[-1]
    assert last.startswith("bake pillar.obj: 1857 tets in ") and last.endswith(" s\n")
    assert text.count("\n") == 1


def test_progress_of_a_failed_bake_is_cleared():
    out = Terminal()
    bar = BakeProgress("pillar.obj", True, out)
    bar.stage("load")
    bar.close()
    assert "\n" not in out.getvalue() and out.getvalue().endswith("\r")


def test_progress_prints_nothing_off_a_terminal_or_when_disabled():
    for stream, enabled in ((io.StringIO(), True), (Terminal(), False)):
        bar = BakeProgress("pillar.obj", enabled, stream)
        assert not bar.shown
        bar.stage("load")
        bar.tick()
        bar.done("12 tets")
        assert stream.getvalue() == ""


# -------------------------------------------------------- the command line
@pytest.fixture(scope="module")
def lift_env(tmp_path_factory) -> dict:
    env = dict(os.environ)
    env["NUMBA_CACHE_DIR"] = os.environ.get("NUMBA_CACHE_DIR") or str(tmp_path_factory.mktemp("numba"))
    env["XDG_CACHE_HOME"] = str(tmp_path_factory.mktemp("xdg-cache"))
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), env.get("PYTHONPATH")) if p)
    return env


def lift_cli(env, cwd, mesh) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", "lift", str(mesh), "--depth", "1", "-o", "out.npz"],
        capture_output=True,
        text=True,
        timeout=240,
        cwd=cwd,
        env=env,
    )


def assert_user_error(r: subprocess.CompletedProcess, *needles: str) -> None:
    detail = f"exit {r.returncode}\n{r.stdout}{r.stderr}"
    assert r.returncode == 2, detail
    assert "Traceback" not in r.stderr and "internal error" not in r.stderr, detail
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, detail
    for n in needles:
        assert n in lines[0], detail
    assert not (Path(r.args[-1]).exists())


def test_lift_refuses_an_escaping_gltf_a_fifo_and_a_corrupt_stl(lift_env, tmp_path):
    fifo = tmp_path / "outside.fifo"
    os.mkfifo(fifo)
    gltf = write_gltf(tmp_path / "asset")
    set_uri(gltf, str(fifo))
    assert_user_error(lift_cli(lift_env, tmp_path, gltf), "box.gltf", repr(str(fifo)))
    set_uri(gltf, "../../x.bin")
    assert_user_error(lift_cli(lift_env, tmp_path, gltf), "box.gltf", "'../../x.bin'")
    pipe = tmp_path / "pipe.obj"
    os.mkfifo(pipe)
    assert_user_error(lift_cli(lift_env, tmp_path, pipe), "pipe.obj", "FIFO")
    stl = tmp_path / "broken.stl"
    stl.write_bytes(box_stl(True)[:-7])
    assert_user_error(lift_cli(lift_env, tmp_path, stl), "broken.stl", "corrupt binary STL")
    assert not list(tmp_path.glob("*.tmp")) and not list(tmp_path.glob(".*.tmp"))
