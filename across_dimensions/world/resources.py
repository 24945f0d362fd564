"""Where the game's data lives: ``levels/`` and ``assets/``.

In a source checkout (or an editable install) they sit at the repository's top
level; a wheel carries them inside the package as ``_data/levels`` and
``_data/assets``. A standalone build (PyInstaller, see
:mod:`across_dimensions.app.freeze`) unpacks them next to its libraries, in the
folder ``sys._MEIPASS`` names. Everything else asks this module, never ``__file__``.
"""

from __future__ import annotations

import sys
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent.parent


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


def level_files() -> list[Path]:
    """Shipped levels sorted by file name (the campaign file beside them is not a level)."""
    return sorted(p for p in levels_dir().glob("*.toml") if p.name != "campaign.toml")


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
    for f in level_files():
        if f.stem == name_or_path or f.name == name_or_path:
            return f
    if p.exists():
        return p
    known = ", ".join(f.stem for f in level_files())
    raise FileNotFoundError(f"no level {name_or_path!r}; shipped levels: {known}")
