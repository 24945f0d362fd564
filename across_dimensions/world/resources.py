"""Where the game's data lives: ``levels/`` and ``assets/``.

In a source checkout (or an editable install) they sit at the repository's top
level; a wheel carries them inside the package as ``_data/levels`` and
``_data/assets``. A standalone build (PyInstaller, see
:mod:`across_dimensions.app.freeze`) unpacks them next to its libraries, in the
folder ``sys._MEIPASS`` names. Everything else asks this module, never ``__file__``.
"""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

from ..core.fileio import FileProblem, read_text
from .limits import MAX_LEVEL_BYTES

_PACKAGE = Path(__file__).resolve().parent.parent
#: ``[level] format`` of the Flatland prologue's levels (``world/flat_level.py``); 4D levels have a number.
FLAT_FORMAT = "flatland"


def _bundle_dir() -> Path | None:
    """The standalone build's data folder, or None when not frozen."""
    if not getattr(sys, "frozen", False):
        return None
    meipass = getattr(sys, "_MEIPASS", None)
    return Path(meipass) if meipass else Path(sys.executable).resolve().parent


def _data_dir(name: str) -> Path:
    bundle = _bundle_dir()
    frozen = (bundle / name,) if bundle is not None else ()
    for candidate in (*frozen, _PACKAGE / "_data" / name, _PACKAGE.parent / name):
        if candidate.is_dir():
            return candidate
    return _PACKAGE.parent / name


def levels_dir() -> Path:
    """The folder holding the shipped level files."""
    return _data_dir("levels")


def assets_dir() -> Path:
    """The folder holding the shipped 3D assets and baked meshes."""
    return _data_dir("assets")


def is_prologue_file(path) -> bool:
    """Whether the level file at ``path`` says ``format = "flatland"`` (a Flatland prologue level).

    False for a file that cannot be read or parsed: the loader that reads it next says why.
    """
    try:
        data = tomllib.loads(read_text(Path(path), limit=MAX_LEVEL_BYTES, what="level"))
    except (FileProblem, tomllib.TOMLDecodeError, UnicodeDecodeError, ValueError, RecursionError):
        return False
    meta = data.get("level")
    return isinstance(meta, dict) and meta.get("format") == FLAT_FORMAT


def _shipped() -> list[Path]:
    return sorted(p for p in levels_dir().glob("*.toml") if p.name != "campaign.toml")


def level_files() -> list[Path]:
    """Shipped 4D levels sorted by file name (the campaign file beside them is not a level, and the
    prologue's levels are :func:`prologue_files`)."""
    return [p for p in _shipped() if not is_prologue_file(p)]


def prologue_files() -> list[Path]:
    """Shipped Flatland prologue levels (``format = "flatland"``), sorted by file name."""
    return [p for p in _shipped() if is_prologue_file(p)]


def resolve_asset(relative: str) -> Path:
    """Resolve an asset path from a level file, confined to the assets folder.

    Raises
    ------
    ValueError
        If the path is absolute or escapes the assets folder (``..``), or the
        file does not exist.
    """
    root = assets_dir().resolve()
    p = Path(relative)
    if "\x00" in relative:
        raise ValueError(f"expected a path inside the assets folder, got {relative!r} which contains a NUL character")
    if not relative or p.is_absolute() or relative.startswith(("/", "\\")) or ":" in relative:
        raise ValueError(f"expected a path inside the assets folder, got the absolute path {relative!r}")
    full = (root / p).resolve()
    if not full.is_relative_to(root):
        raise ValueError(f"expected a path inside the assets folder, got {relative!r} which leaves it")
    if not full.is_file():
        raise ValueError(f"no asset {relative!r} in {root}")
    return full


def resolve_level(name_or_path: str) -> Path:
    """A level given as a path, or as a shipped level's name (``01_first_steps``)."""
    p = Path(name_or_path)
    if p.suffix == ".toml" and p.exists():
        return p
    for f in _shipped():
        if f.stem == name_or_path or f.name == name_or_path:
            return f
    if p.exists():
        return p
    known = ", ".join(f.stem for f in _shipped())
    raise FileNotFoundError(f"no level {name_or_path!r}; shipped levels: {known}")
