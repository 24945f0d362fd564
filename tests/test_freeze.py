"""The standalone build: ``python -m across_dimensions.app.freeze`` and the folder it makes.

The build tests are slow (a PyInstaller build, then the kernels compiled for the baseline CPU
inside the frozen game: five to seven minutes on two cores), and skipped when PyInstaller
(the ``standalone`` extra) is not installed. Run them with::

    pip install -e '.[standalone]'
    python -m pytest tests/test_freeze.py -m slow -v -p no:cacheprovider

or, on a folder built beforehand (CI builds it in Debian 11 with packaging/build-debian11.sh),
with ``ACROSS_DIMENSIONS_FROZEN_DIST=dist`` (the folder holding ``across-dimensions/`` and its
archive). Where Xvfb is installed the game's window, the title and the editor open on a
virtual display; where strace is, start-up is traced for programs it runs; as root, with the
Debian 11 root made by that script present, the folder also plays replays inside it.

The frozen executable runs with an empty environment and a PATH that holds no
Python, in a fresh home folder, so it can only use what the folder carries and
the system's base libraries (which ``ldd`` checks for every library in it).
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import xvfb_display

from across_dimensions._shipped_kernels import for_child
from across_dimensions.app.freeze import elf_facts, required_glibc, unshipped_kernels

ROOT = Path(__file__).resolve().parents[1]
REPLAYS = sorted((ROOT / "levels" / "replays").glob("*.json"))
#: A folder built beforehand: the dist folder holding across-dimensions/ and its archive.
PREBUILT_ENV = "ACROSS_DIMENSIONS_FROZEN_DIST"
#: The Debian 11 root packaging/build-debian11.sh makes (its --root).
DEBIAN11_ENV = "ACROSS_DIMENSIONS_DEBIAN11_ROOT"
DEBIAN11 = Path(os.environ.get(DEBIAN11_ENV, "/var/cache/across-dimensions/debian11"))
#: Seconds from start to the first level frame, kernels shipped. About 2.5 s on a quiet 2-core
#: machine (README); the bound leaves room for a machine shared with other work.
FIRST_FRAME_LIMIT = 20.0
#: Where the base system's shared libraries live (glibc, libGL/libEGL, X11).
SYSTEM_LIBS = ("/lib/", "/lib64/", "/usr/lib/", "/usr/lib64/", "/usr/local/lib/")


def _freeze(*args, blocked_pyinstaller=False):
    code = "import runpy, sys\n"
    if blocked_pyinstaller:
        code += "sys.modules['PyInstaller'] = None  # import PyInstaller now raises ImportError\n"
    code += "runpy.run_module('across_dimensions.app.freeze', run_name='__main__')\n"
    env = dict(for_child(), PYTHONPATH=str(ROOT))
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
    """Build once, or take the folder built beforehand: (folder, archive, player home)."""
    tmp = tmp_path_factory.mktemp("freeze")
    dist = Path(os.environ.get(PREBUILT_ENV) or tmp / "dist").resolve()
    if not os.environ.get(PREBUILT_ENV):
        pytest.importorskip("PyInstaller", reason="the standalone extra (PyInstaller) is not installed")
        cmd = [sys.executable, "-m", "across_dimensions.app.freeze", "--dist", str(dist), "--work", str(tmp / "work")]
        done = subprocess.run(cmd, cwd=ROOT, env=for_child(), capture_output=True, text=True, timeout=3600)
        assert done.returncode == 0, done.stdout + done.stderr
    archives = list(dist.glob("across-dimensions-*.tar.gz"))
    assert len(archives) == 1, archives
    home = tmp / "home"
    (home / "bin").mkdir(parents=True)  # the player's PATH: no python, no compiler
    return dist / "across-dimensions", archives[0], home


@pytest.fixture(scope="module")
def display():
    """An X display for the game's window: Xvfb where it is installed."""
    with xvfb_display(78, "ACROSS_DIMENSIONS_FREEZE_TEST_DISPLAY") as name:
        yield name


def _player_env(home: Path, **more: str) -> dict[str, str]:
    env = {"HOME": str(home), "PATH": str(home / "bin"), "LANG": "C.UTF-8"}
    if "XDG_RUNTIME_DIR" in os.environ:  # a desktop session's, not Python's
        env["XDG_RUNTIME_DIR"] = os.environ["XDG_RUNTIME_DIR"]
    return env | more


def _run(built, *args, timeout=900, home=None, cwd=None, prefix=(), **env):
    folder, _, player = built
    home = home or player
    home.mkdir(parents=True, exist_ok=True)
    return subprocess.run(
        [*prefix, str(folder / "across-dimensions"), *args],
        env=_player_env(home, **env),
        cwd=cwd or home,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _pngs(home: Path) -> list[Path]:
    """The PNG files the game wrote anywhere in the player's home (screenshots)."""
    return sorted(p for p in home.rglob("*.png") if ".cache" not in p.parts)


def _installed(*args):
    env = dict(for_child(), PYTHONPATH=str(ROOT))
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
        # The loader's path as the bootloader sets it: the bundle first.
        env = {"PATH": "/usr/bin:/bin", "LD_LIBRARY_PATH": str(folder / "_internal")}
        done = subprocess.run(["ldd", str(lib)], capture_output=True, text=True, env=env)
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
def test_first_start_opens_a_level_in_seconds_with_the_shipped_kernels(built, display, tmp_path):
    # The first start of this player: the kernels come from the folder, so the level's first
    # frame follows within seconds and nothing is compiled into the player's cache.
    home = tmp_path / "home"
    args = ("play", "01_first_steps", "--screenshot-after", "0.001", "--quit-after", "1")
    done = _run(built, *args, home=home, DISPLAY=display, ACROSS_DIMENSIONS_TIMING="1")
    assert done.returncode == 0, done.stderr
    frame = next(line for line in done.stdout.splitlines() if line.startswith("timing: first level frame"))
    assert float(frame.split(" at ")[1].split()[0]) < FIRST_FRAME_LIMIT, done.stdout  # seconds from the start
    assert not list(home.rglob("*.nbi")), "kernels were compiled on a processor that runs the shipped ones"
    shots = list((home / "Pictures" / "Across Dimensions").glob("across-dimensions_*.png"))  # platformdirs
    assert len(shots) == 1 and shots[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_started_from_its_folder_the_game_writes_nothing_there(built, display, tmp_path):
    # README.txt says to start it from its folder, which may be read-only: screenshots go to
    # the player's pictures folder (platformdirs, frozen in), settings to the config folder.
    if importlib.util.find_spec("across_dimensions.app.screenshots") is None:
        pytest.skip("screenshots still go to the working folder in this version of the game")
    folder, _, _ = built
    home = tmp_path / "home"
    before = sorted(p.relative_to(folder) for p in folder.rglob("*"))
    args = ("play", "01_first_steps", "--screenshot-after", "0.001", "--quit-after", "1")
    done = _run(built, *args, home=home, cwd=folder, DISPLAY=display)
    assert done.returncode == 0, done.stderr
    assert sorted(p.relative_to(folder) for p in folder.rglob("*")) == before, "the game wrote into its folder"
    shots = _pngs(home)
    assert len(shots) == 1 and (home / "Pictures") in shots[0].parents, shots


@pytest.mark.slow
def test_title_screen_opens(built, display, tmp_path):
    # play with no level named is what a double-click starts: the title screen.
    done = _run(built, "play", "--screenshot-after", "1.5", "--quit-after", "3", home=tmp_path, DISPLAY=display)
    assert done.returncode == 0, done.stderr
    assert len(_pngs(tmp_path)) == 1, done.stdout


@pytest.mark.slow
def test_editor_opens_in_the_frozen_game(built, display, tmp_path):
    level = tmp_path / "mine.toml"
    shutil.copy(ROOT / "levels" / "02_crystal_cache.toml", level)
    done = _run(
        built, "edit", str(level), "--screenshot-after", "2", "--quit-after", "4", home=tmp_path, DISPLAY=display
    )
    assert done.returncode == 0, done.stderr
    assert "pip install" not in done.stdout + done.stderr
    shots = _pngs(tmp_path)
    assert len(shots) == 1, done.stdout
    from across_dimensions.render.png import read_png

    bar = read_png(shots[0])[2:17, :, :3].astype(int)  # ImGui's menu bar: its dark grey, 36 in 8 bits
    assert np.mean(np.abs(bar - 36) <= 3) > 0.8


@pytest.mark.slow
def test_the_editor_key_in_the_frozen_game(built, display, tmp_path):
    if shutil.which("xdotool") is None:
        pytest.skip("xdotool is not installed")
    folder, _, _ = built
    env = _player_env(tmp_path, DISPLAY=display)
    game = subprocess.Popen(
        [str(folder / "across-dimensions"), "play", "02_crystal_cache"], env=env, cwd=tmp_path, text=True,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )  # fmt: skip
    xdo = dict(os.environ, DISPLAY=display)
    try:
        for _ in range(300):
            if subprocess.run(
                ["xdotool", "search", "--name", "Across Dimensions"], env=xdo, capture_output=True
            ).stdout:
                break
            time.sleep(0.2)
        for _ in range(60):  # F12 until the level shows: then play has begun
            subprocess.run(["xdotool", "key", "F12"], env=xdo, check=True)
            time.sleep(1.0)
            if _pngs(tmp_path):
                break
        time.sleep(3.0)  # the first shot may show the kernels loading, before the level
        for key in ("F2", "F12"):  # to the editor, then a screenshot of it
            subprocess.run(["xdotool", "key", key], env=xdo, check=True)
            time.sleep(2.0)
    finally:
        game.terminate()
        out, err = game.communicate(timeout=30)
    assert "pip install" not in out + err
    shots = _pngs(tmp_path)
    assert len(shots) >= 2, out + err
    from across_dimensions.render.png import read_png

    bar = read_png(shots[-1])[2:17, :, :3].astype(int)
    assert np.mean(np.abs(bar - 36) <= 3) > 0.8, "F2 did not open the editor"


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
def test_demo_writes_screenshots_with_the_shipped_kernels(built, tmp_path):
    shots = tmp_path / "shots"
    done = _run(built, "demo", "--screenshots", str(shots), "--every", "120", home=tmp_path / "home")
    if done.returncode != 0 and "EGL" in done.stderr:
        pytest.skip(f"no offscreen OpenGL here: {done.stderr.strip()}")
    assert done.returncode == 0, done.stderr
    pngs = sorted(shots.glob("*.png"))
    assert len(pngs) >= 3
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in pngs)
    assert not list((tmp_path / "home").rglob("*.nbi")), "kernels were compiled although the folder ships them"


@pytest.mark.slow
def test_every_kernel_is_shipped_read_only_for_the_baseline_cpu(built):
    folder, _, _ = built
    shipped = folder / "_internal" / "numba_cache"
    assert unshipped_kernels(shipped) == []
    files = [p for p in shipped.rglob("*") if p.is_file()]
    assert len([p for p in files if p.suffix == ".nbi"]) >= 50
    assert all(p.stat().st_mode & 0o222 == 0 for p in files)


@pytest.mark.slow
def test_another_cpu_target_compiles_into_the_players_cache(built, tmp_path):
    # A processor without the baseline's features is met the same way: a CPU target the
    # shipped kernels were not compiled for. They compile into the player's cache, not the folder.
    folder, _, _ = built
    before = sorted(p.name for p in (folder / "_internal" / "numba_cache").rglob("*"))
    home, out = tmp_path / "home", tmp_path / "slice.obj"
    done = _run(built, "slice", "tesseract", "--rotate", "xw=30", "-o", str(out), home=home, NUMBA_CPU_NAME="generic")
    assert done.returncode == 0, done.stderr
    assert out.is_file()
    assert list((home / ".cache" / "across-dimensions").rglob("*.nbi"))
    assert sorted(p.name for p in (folder / "_internal" / "numba_cache").rglob("*")) == before


@pytest.mark.slow
def test_no_library_names_a_build_machine_path(built):
    folder, _, _ = built
    named = {}
    for path in folder.rglob("*"):
        facts = elf_facts(path) if path.is_file() and not path.is_symlink() else None
        if facts is not None and any(not p.startswith("$ORIGIN") for p in facts.search_paths):
            named[str(path.relative_to(folder))] = facts.search_paths
    assert not named


def _programs_run(built, tmp_path, *args, **env) -> list[str]:
    """The programs ``across-dimensions ARGS`` runs, traced with strace (skips without it)."""
    strace = shutil.which("strace")
    if strace is None:
        pytest.skip("strace is not installed")
    log = tmp_path / "execve.log"
    prefix = (strace, "-f", "-qq", "-e", "trace=execve", "-o", str(log))
    done = _run(built, *args, home=tmp_path / "home", prefix=prefix, **env)
    assert done.returncode == 0, done.stderr
    return [line.split('"')[1] for line in log.read_text().splitlines() if "execve(" in line]


@pytest.mark.slow
def test_a_headless_replay_runs_no_other_program(built, tmp_path):
    # ctypes' library lookup runs ldconfig, gcc and objdump; the frozen game must run nothing.
    folder, _, _ = built
    replay = folder / "_internal" / "levels" / "replays" / "02_crystal_cache.json"
    programs = _programs_run(built, tmp_path, "replay", "02_crystal_cache", str(replay))
    assert programs and set(programs) == {str(folder / "across-dimensions")}, programs


@pytest.mark.slow
def test_the_window_and_its_sound_run_no_other_program(built, display, tmp_path):
    # pyglet looks up GL, X11, fonts and each audio driver's library as the window opens.
    folder, _, _ = built
    programs = _programs_run(built, tmp_path, "play", "01_first_steps", "--quit-after", "1", DISPLAY=display)
    assert programs and set(programs) == {str(folder / "across-dimensions")}, programs


@pytest.mark.slow
def test_plays_replays_in_a_debian_11_root(built, tmp_path):
    """The folder built for glibc 2.31 plays every shipped replay inside Debian 11 (made by
    packaging/build-debian11.sh) with its hashes: the C library's maths must agree with the
    newer glibc the replays were recorded on (its ``hypot`` did not, for Crossfire)."""
    if os.geteuid() != 0 or not (DEBIAN11 / "lib" / "x86_64-linux-gnu" / "libc-2.31.so").exists():
        pytest.skip(f"needs root and the Debian 11 root ({DEBIAN11_ENV}, made by packaging/build-debian11.sh)")
    folder, _, _ = built
    assert required_glibc(folder) <= (2, 31)
    player = Path(tempfile.mkdtemp(prefix="player-", dir=DEBIAN11 / "tmp"))
    try:
        shutil.copytree(folder, player / "across-dimensions", symlinks=True)
        (player / "home").mkdir()
        inside = "/" + str(player.relative_to(DEBIAN11))
        env = ["env", "-i", f"HOME={inside}/home", "PATH=/nonexistent", "LANG=C.UTF-8"]
        for replay in REPLAYS:
            shipped = f"{inside}/across-dimensions/_internal/levels/replays/{replay.name}"
            cmd = ["chroot", str(DEBIAN11), *env, f"{inside}/across-dimensions/across-dimensions"]
            done = subprocess.run([*cmd, "replay", replay.stem, shipped, "--json"], capture_output=True, text=True)
            assert done.returncode == 0, f"{replay.name}: {done.stderr}"
            result, final = json.loads(done.stdout), json.loads(replay.read_text())["final"]
            assert (result["hash"], result["ticks"]) == (final["hash"], final["ticks"])
        assert not list((player / "home").rglob("*.nbi")), "kernels were compiled inside Debian 11"
    finally:
        shutil.rmtree(player)


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
