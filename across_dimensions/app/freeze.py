"""Build the standalone game: a folder a player unpacks and runs, no Python needed.

``python -m across_dimensions.app.freeze [--dist DIR] [--work DIR] [--no-archive]``

Runs PyInstaller (the ``standalone`` extra: ``pip install -e '.[standalone]'``)
on ``packaging/across-dimensions.spec`` from a source checkout, then adds what
a player expects next to the executable and packs the folder::

    DIST/across-dimensions/
        across-dimensions              the game: the same command, options and exit statuses
        across-dimensions.desktop      desktop entry (Linux)
        across-dimensions.png          its icon, rendered by packaging/make_icon.py
        install-desktop-entry.sh       adds the entry to the user's application menu
        README.txt                     how to start it
        _internal/                     Python, the libraries, levels/ and assets/
    DIST/across-dimensions-VERSION-PLATFORM.tar.gz   (.zip on Windows)

The folder is built for the platform this runs on. Exit status 0 on success,
2 when PyInstaller is missing or this is not a source checkout, 1 when the
build or the built executable's self-check fails.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import os
import platform
import shutil
import subprocess
import sys
from pathlib import Path

PROG = "python -m across_dimensions.app.freeze"
NAME = "across-dimensions"
ROOT = Path(__file__).resolve().parents[2]
PACKAGING = ROOT / "packaging"
SPEC = PACKAGING / f"{NAME}.spec"
#: Copied next to the executable.
EXTRAS = (f"{NAME}.desktop", f"{NAME}.png", "install-desktop-entry.sh")

_README = """Across Dimensions {version}

Start the game: double-click across-dimensions, or run ./across-dimensions in a terminal.
Add it to your application menu: ./install-desktop-entry.sh (./install-desktop-entry.sh --remove to undo).
The first start compiles the 4D kernels into {cache} (about a minute);
later starts take a second or two. ./across-dimensions --help lists the other commands
(demo, replay, check-level, ...). Settings and recordings live in your user folders, never here.
"""


class FreezeError(Exception):
    """A problem the user can fix (exit status 2)."""


def archive_name(version: str) -> str:
    """``across-dimensions-0.1.0-linux-x86_64`` (no suffix)."""
    system = {"win32": "windows", "darwin": "macos"}.get(sys.platform, sys.platform)
    return f"{NAME}-{version}-{system}-{platform.machine().lower()}"


def folder_size(path: Path) -> int:
    """Bytes in all files under ``path`` (links not followed)."""
    return sum(f.stat().st_size for f in path.rglob("*") if f.is_file() and not f.is_symlink())


def _version() -> str:
    try:
        return importlib.metadata.version(NAME)
    except importlib.metadata.PackageNotFoundError:
        return "0+unknown"


def _check_ready() -> None:
    try:
        import PyInstaller  # noqa: F401  (run as a child process below; imported here only to check)
    except ImportError:
        hint = "install the standalone extra: pip install -e '.[standalone]'"
        raise FreezeError(f"PyInstaller is not installed; {hint}") from None
    if not SPEC.is_file():
        raise FreezeError(f"no {SPEC}: the standalone build runs from a source checkout of the game")


def build(dist: Path, work: Path, archive: bool = True, log=print) -> tuple[Path, Path | None]:
    """Freeze the game into ``dist/across-dimensions`` and pack it.

    Returns
    -------
    folder : Path
        The standalone folder.
    archive : Path or None
        The archive of it, unless ``archive`` is False.

    Raises
    ------
    FreezeError
        PyInstaller missing, or not a source checkout.
    RuntimeError
        PyInstaller failed, or the built executable does not answer ``--help``.
    """
    _check_ready()
    dist, work = dist.resolve(), work.resolve()
    folder = dist / NAME
    cmd = [sys.executable, "-m", "PyInstaller", str(SPEC), "--noconfirm", "--clean", "--log-level", "WARN"]
    cmd += ["--distpath", str(dist), "--workpath", str(work)]
    log(f"freezing with PyInstaller into {folder} (a minute or two)")
    if subprocess.run(cmd, cwd=ROOT).returncode != 0:
        raise RuntimeError("PyInstaller failed (its messages are above)")
    for name in EXTRAS:
        shutil.copy2(PACKAGING / name, folder / name)
    version = _version()
    cache = os.path.join("~", ".cache", NAME)
    (folder / "README.txt").write_text(_README.format(version=version, cache=cache), encoding="utf-8")
    exe = folder / (NAME + (".exe" if os.name == "nt" else ""))
    # The self-check needs no display and compiles nothing: --help imports the
    # command line, which fails the same way a missing module would in play.
    done = subprocess.run([str(exe), "--help"], capture_output=True, text=True, timeout=300)
    if done.returncode != 0 or "usage:" not in done.stdout:
        raise RuntimeError(f"the built {exe} does not start: {done.stderr.strip()[-2000:]}")
    log(f"built {folder} ({folder_size(folder) / 1e6:.0f} MB)")
    if not archive:
        return folder, None
    base = dist / archive_name(version)
    fmt = "zip" if os.name == "nt" else "gztar"
    log(f"packing {base.name} ...")
    packed = Path(shutil.make_archive(str(base), fmt, root_dir=dist, base_dir=NAME))
    log(f"wrote {packed} ({packed.stat().st_size / 1e6:.0f} MB)")
    return folder, packed


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.splitlines()[0])
    ap.add_argument("--dist", default=str(ROOT / "dist"), metavar="DIR", help="where the folder and archive go (dist/)")
    ap.add_argument("--work", default=str(ROOT / "build"), metavar="DIR", help="PyInstaller's work folder (build/)")
    ap.add_argument("--no-archive", action="store_true", help="build the folder only")
    args = ap.parse_args(argv)
    try:
        build(Path(args.dist), Path(args.work), archive=not args.no_archive)
    except FreezeError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    except (RuntimeError, OSError, subprocess.TimeoutExpired) as e:
        print(f"{PROG}: build failed: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
