"""The on-disk cache of baked 3D solids, and the bakes shipped with the game.

The slow step of a bake is tetrahedralization (seconds), so its result, the
3D tets, is what an entry stores, keyed by the bytes of the asset (the mesh
file and every file it references), the tetrahedralization parameters and
:data:`BAKE_VERSION`. The game ships the entries of every asset its levels
lift, under the same names, in ``assets/baked/`` (:func:`shipped_dir`): a player
never waits for those bakes, and every machine plays the same tets. The user's
cache holds the rest (a modder's own assets). Entries are written whole or not at all
(:func:`~across_dimensions.core.fileio.atomic_writer`), so an interrupted bake
leaves no partial entry and no temporary file; an entry that is unreadable
anyway (truncated by a full disk, edited, from another version) is rebuilt.
"""

from __future__ import annotations

import hashlib
import io
import json
import zipfile
from pathlib import Path

import numpy as np

from ...core.fileio import atomic_writer, read_bytes
from .confine import Budget, referenced_files
from .limits import MAX_ASSET_BYTES, MAX_TETS, MAX_TRIANGLES

#: Bump when anything changes what a bake produces for the same input.
#: 2: holes are filled by trimesh (its own diagonal for a quad hole); surfaces
#: that need no repair bake exactly as in version 1.
#: 3: reproducible: one thread and a fixed sequence for fTetWild's draws.
BAKE_VERSION = 3
#: An entry holds at most MAX_TETS tets and 4 * MAX_TETS vertices (int32 and float64).
MAX_ENTRY_BYTES = MAX_TETS * (4 * 4 + 4 * 3 * 8) + (1 << 16)


#: Names a folder that replaces the per-user cache folder (a fresh one for a benchmark's first start).
CACHE_DIR_ENV = "ACROSS_DIMENSIONS_CACHE_DIR"


def default_cache_dir() -> Path:
    """``$ACROSS_DIMENSIONS_CACHE_DIR/bake`` when set, else
    ``platformdirs.user_cache_dir("across-dimensions") / "bake"``."""
    import os

    import platformdirs

    return Path(os.environ.get(CACHE_DIR_ENV) or platformdirs.user_cache_dir("across-dimensions")) / "bake"


def shipped_dir() -> Path:
    """The bakes shipped with the game: ``assets/baked/`` (see :mod:`across_dimensions.world.ship_bakes`)."""
    from ..resources import assets_dir

    return assets_dir() / "baked"


def bake_digest(vertices: np.ndarray, tets: np.ndarray) -> str:
    """sha256 hex of a bake's content: what a level's hash folds in for it.

    Parameters
    ----------
    vertices : (n, 3) float64
    tets : (m, 4) int64
        As :func:`load_entry` returns them (the same arrays give the same digest
        whatever dtype they were stored in).
    """
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(vertices, "<f8").tobytes())
    h.update(np.ascontiguousarray(tets, "<i8").tobytes())
    return h.hexdigest()


def cache_key(path, **params) -> str:
    """sha256 hex of :data:`BAKE_VERSION`, the parameters and the asset's bytes.

    A glTF also hashes the buffers and images it references, so editing its
    ``.bin`` invalidates the bake too. Only files inside the asset's folder
    are read (see :mod:`.confine`), within :data:`~.limits.MAX_ASSET_BYTES`.

    Raises
    ------
    AssetError
        The file or a file it references is missing, not a regular file, too
        large, or outside the asset's folder.
    """
    path = Path(path)
    budget = Budget(MAX_ASSET_BYTES)
    h = hashlib.sha256()
    h.update(json.dumps({"bake_version": BAKE_VERSION, **params}, sort_keys=True).encode())
    data = budget.read(path, "mesh asset")
    h.update(data)
    for ref in referenced_files(path, data, path.resolve().parent):
        h.update(budget.read(ref, "mesh asset"))
    return h.hexdigest()


def entry_path(cache_dir, path, key: str) -> Path:
    """Where the entry for ``path`` with ``key`` lives: ``<cache_dir>/<stem>-<key[:24]>.npz``."""
    folder = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    return folder / f"{Path(path).stem}-{key[:24]}.npz"


def load_entry(file, names=("vertices", "tets")) -> tuple[np.ndarray, np.ndarray] | None:
    """The cached 3D tets, or None when missing or unusable (then it is rebuilt).

    ``names=("vertices", "faces")`` reads a cached repaired surface instead (faces ``(m, 3)``,
    ``0 < m <= MAX_TRIANGLES``).

    Returns
    -------
    vertices : (n, 3) float64
    tets : (m, 4) int64
        ``0 < m <= MAX_TETS``, indices in range.
    """
    width, most = (4, MAX_TETS) if names[1] == "tets" else (3, MAX_TRIANGLES)
    try:
        raw = read_bytes(file, limit=MAX_ENTRY_BYTES, what="bake cache entry")
        with zipfile.ZipFile(io.BytesIO(raw)) as z:
            # Declared sizes bound what np.load inflates: a damaged or planted
            # entry cannot expand into gigabytes.
            if sum(i.file_size for i in z.infolist()) > MAX_ENTRY_BYTES:
                return None
        with np.load(io.BytesIO(raw), allow_pickle=False) as d:
            v, t = d[names[0]], d[names[1]]
            version = int(d["bake_version"])
    except Exception:  # noqa: BLE001 -- missing, truncated, corrupt, old format: all mean "rebake"
        return None
    if (
        version != BAKE_VERSION
        or v.ndim != 2
        or v.shape[1] != 3
        or t.ndim != 2
        or t.shape[1] != width
        or not 0 < len(t) <= most
        or t.min() < 0
        or t.max() >= len(v)
        or not np.isfinite(v).all()
    ):
        return None
    return v.astype(np.float64), t.astype(np.int64)


def save_entry(file, vertices: np.ndarray, tets: np.ndarray, names=("vertices", "tets")) -> None:
    """Write an entry atomically (unique temporary file, fsync, rename); creates the cache folder.

    The file is an ``.npz`` whose bytes depend on the arrays alone (members in a
    fixed order, a fixed time stamp), so one bake always gives one file.
    """
    file = Path(file)
    file.parent.mkdir(parents=True, exist_ok=True)  # the cache's own folder, not one a user typed
    arrays = {names[0]: vertices, names[1]: tets.astype(np.int32), "bake_version": np.asarray(BAKE_VERSION)}
    with atomic_writer(file, "wb") as f, zipfile.ZipFile(f, "w", zipfile.ZIP_DEFLATED) as z:
        for name, a in arrays.items():
            member = io.BytesIO()
            np.lib.format.write_array(member, np.asarray(a), allow_pickle=False)
            z.writestr(
                zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0)), member.getvalue(), zipfile.ZIP_DEFLATED
            )
