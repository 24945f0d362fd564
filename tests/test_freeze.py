"""The standalone build: ``python -m across_dimensions.app.freeze`` and the folder it makes.

The build tests are slow (a PyInstaller build, then a cold compile of the kernels inside the
frozen game: about four minutes on two cores), and skipped when PyInstaller
(the ``standalone`` extra) is not installed. Run them with::

    pip install -e '.[standalone]'
    python -m pytest tests/test_freeze.py -m slow -v -p no:cacheprovider

With ``DISPLAY`` set (``Xvfb :1 & DISPLAY=:1 python -m pytest ...``) it also
opens the game in a window.

The frozen executable runs with an empty environment and a PATH that holds no
Python, in a fresh home folder, so it can only use what the folder carries and
the system's base libraries (which ``ldd`` checks for every library in it).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tarfile
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
REPLAYS = sorted((ROOT / "levels" / "replays").glob("*.json"))
#: Where the base system's shared libraries live (glibc, libGL/libEGL, X11).
SYSTEM_LIBS = ("/lib/", "/lib64/", "/usr/lib/", "/usr/lib64/", "/usr/local/lib/")


def _freeze(*args, blocked_pyinstaller=False):
    code = "import runpy, sys\n"
    if blocked_pyinstaller:
        code += "sys.modules['PyInstaller'] = None  # import PyInstaller now raises ImportError\n"
    code += "runpy.run_module('across_dimensions.app.freeze', run_name='__main__')\n"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-c", code, *args], env=env, capture_output=True, text=True, timeout=120)


def test_freeze_help():
    done = _freeze("--help")
    assert done.returncode == 0, done.stderr
    assert "--no-archive" in done.stdout


def test_freeze_without_pyinstaller_says_which_extra_to_install():
    done = _freeze("--dist", "unused", blocked_pyinstaller=True)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and "pip install -e '.[standalone]'" in done.stderr


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """Build once: (folder, archive, player home)."""
    pytest.importorskip("PyInstaller", reason="the standalone extra (PyInstaller) is not installed")
    tmp = tmp_path_factory.mktemp("freeze")
    cmd = [sys.executable, "-m", "across_dimensions.app.freeze"]
    cmd += ["--dist", str(tmp / "dist"), "--work", str(tmp / "work")]
    done = subprocess.run(
        cmd,
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    archives = list((tmp / "dist").glob("across-dimensions-*.tar.gz"))
    assert len(archives) == 1, done.stdout
    home = tmp / "home"
    (home / "bin").mkdir(parents=True)  # the player's PATH: no python, no compiler
    return tmp / "dist" / "across-dimensions", archives[0], home


def _player_env(home: Path) -> dict[str, str]:
    env = {"HOME": str(home), "PATH": str(home / "bin"), "LANG": "C.UTF-8"}
    for name in ("DISPLAY", "XDG_RUNTIME_DIR"):  # a desktop session's, not Python's
        if name in os.environ:
            env[name] = os.environ[name]
    return env


def _run(built, *args, timeout=900):
    folder, _, home = built
    return subprocess.run(
        [str(folder / "across-dimensions"), *args],
        env=_player_env(home),
        cwd=home,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _installed(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "across_dimensions", *args], env=env, capture_output=True, text=True)


@pytest.mark.slow
def test_folder_holds_the_game_levels_assets_and_desktop_entry(built):
    folder, archive, _ = built
    data = folder / "_internal"
    assert os.access(folder / "across-dimensions", os.X_OK)
    shipped = sorted(p.name for p in (ROOT / "levels").glob("*.toml"))
    assert sorted(p.name for p in (data / "levels").glob("*.toml")) == shipped
    assert sorted(p.name for p in (data / "levels" / "replays").glob("*.json")) == [p.name for p in REPLAYS]
    assert (data / "assets" / "meshes" / "crate.obj").is_file()
    entry = (folder / "across-dimensions.desktop").read_text()
    assert "Type=Application" in entry and "Exec=across-dimensions" in entry and "Icon=across-dimensions" in entry
    assert (folder / "across-dimensions.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # What the game does not use is left out.
    for unused in ("pytest", "_pytest", "hypothesis", "scipy", "IPython", "tkinter", "setuptools", "pygments"):
        assert not (data / unused).exists(), unused
    with tarfile.open(archive) as tar:
        names = set(tar.getnames())
        assert "across-dimensions/across-dimensions" in names
        assert tar.getmember("across-dimensions/across-dimensions").mode & 0o111
        assert "across-dimensions/_internal/levels/01_first_steps.toml" in names


@pytest.mark.slow
def test_libraries_resolve_inside_the_folder_or_the_base_system(built):
    folder, _, _ = built
    outside = []
    libs = [folder / "across-dimensions", *folder.rglob("*.so*")]
    for lib in libs:
        done = subprocess.run(["ldd", str(lib)], capture_output=True, text=True, env={"PATH": "/usr/bin:/bin"})
        for line in done.stdout.splitlines():
            if "=>" not in line:
                continue
            target = line.split("=>")[1].split("(")[0].strip()
            if target == "not found" or not (target.startswith(str(folder)) or target.startswith(SYSTEM_LIBS)):
                outside.append(f"{lib.name}: {line.strip()}")
    # The base system's libraries are searched after the folder's, so only
    # libraries PyInstaller leaves to the system (libc, libGL, X11) come from it.
    assert not [o for o in outside if "not found" not in o], outside
    assert not [o for o in outside if "not found" in o and "tbb" not in o], outside


@pytest.mark.slow
def test_help_and_errors_match_the_installed_command(built):
    frozen, installed = _run(built, "--help"), _installed("--help")
    assert frozen.returncode == 0 == installed.returncode
    assert frozen.stdout == installed.stdout
    for args in (["no-such-command"], ["check-level", "/no/such/level.toml"], ["replay", "nowhere", "x.json"]):
        frozen, installed = _run(built, *args), _installed(*args)
        assert frozen.returncode == installed.returncode == 2, (args, frozen.stderr)
        assert frozen.stderr == installed.stderr


@pytest.mark.slow
@pytest.mark.skipif(not os.environ.get("DISPLAY"), reason="needs an X display (Xvfb is enough)")
def test_game_opens_in_a_window(built):
    # Runs before the other game commands, so this is the first start: the
    # kernels compile behind the notice window, then the game's window opens.
    _, _, home = built
    done = _run(built, "play", "--screenshot-after", "0.001", "--quit-after", "1")
    assert done.returncode == 0, done.stderr
    shots = list((home / "Pictures" / "Across Dimensions").glob("across-dimensions_*.png"))  # platformdirs
    assert len(shots) == 1 and shots[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
@pytest.mark.parametrize("replay", REPLAYS, ids=[p.stem for p in REPLAYS])
def test_every_shipped_replay_reaches_its_recorded_hashes(built, replay):
    folder, _, _ = built
    shipped = folder / "_internal" / "levels" / "replays" / replay.name
    done = _run(built, "replay", replay.stem, str(shipped), "--json")
    assert done.returncode == 0, done.stderr  # 3 would mean a divergence from the recorded hashes
    result = json.loads(done.stdout)
    assert result["divergence"] is None
    final = json.loads(replay.read_text())["final"]
    assert (result["hash"], result["ticks"], result["outcome"]) == (final["hash"], final["ticks"], final["outcome"])


@pytest.mark.slow
def test_demo_writes_screenshots_and_kernels_cache_in_the_players_folder(built, tmp_path):
    _, _, home = built
    shots = tmp_path / "shots"
    done = _run(built, "demo", "--screenshots", str(shots), "--every", "120")
    if done.returncode != 0 and "EGL" in done.stderr:
        pytest.skip(f"no offscreen OpenGL here: {done.stderr.strip()}")
    assert done.returncode == 0, done.stderr
    pngs = sorted(shots.glob("*.png"))
    assert len(pngs) >= 3
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in pngs)
    caches = list((home / ".cache" / "across-dimensions").glob("numba-*"))
    assert len(caches) == 1 and any(caches[0].rglob("*.nbi")), "kernels were not cached in the player's folder"


@pytest.mark.slow
def test_desktop_entry_installs_for_this_user_and_is_removed(built, tmp_path):
    folder, _, _ = built
    env = {"HOME": str(tmp_path), "XDG_DATA_HOME": str(tmp_path / "share"), "PATH": "/usr/bin:/bin"}
    script = str(folder / "install-desktop-entry.sh")
    done = subprocess.run([script], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    entry = tmp_path / "share" / "applications" / "across-dimensions.desktop"
    lines = entry.read_text().splitlines()
    assert f'Exec="{folder / "across-dimensions"}"' in lines
    icon = next(line.split("=", 1)[1] for line in lines if line.startswith("Icon="))
    assert Path(icon).read_bytes() == (folder / "across-dimensions.png").read_bytes()
    done = subprocess.run([script, "--remove"], env=env, capture_output=True, text=True)
    assert done.returncode == 0 and not entry.exists() and not Path(icon).exists()


@pytest.mark.slow
def test_lift_runs_the_tetrahedralizer_child_inside_the_frozen_game(built, tmp_path):
    # A frozen executable is no Python: the tetrahedralizer's child process
    # (sys.executable -c WORKER) must still be served by the game itself.
    folder, _, _ = built
    out = tmp_path / "crate.npz"
    crate = folder / "_internal" / "assets" / "meshes" / "crate.obj"
    done = _run(built, "lift", str(crate), "--depth", "0.5", "-o", str(out))
    assert done.returncode == 0, done.stderr
    with np.load(out) as d:
        assert d["vertices"].shape[1] == 4 and d["tets"].shape[1] == 4 and len(d["tets"]) > 0
        assert d["tets"].max() < len(d["vertices"])
