"""Bake 3D mesh assets into 4D solids, with an on-disk cache.

Pipeline (paper section 4.2, "lifting and tetrahedralization")::

    OBJ / GLB / STL --read--> triangles --repair--> closed surface
        --tetrahedralize (pytetwild)--> 3D tets --extrude--> TetMesh4

Each step is its own module in :mod:`across_dimensions.world.assets`; this one
runs them in order and is what the rest of the game calls. The hyper-depth,
``w`` position and profile only feed :func:`~across_dimensions.core.lift.extrude`,
which takes milliseconds, so the cache keeps the 3D tets and a designer tuning
them never waits for a re-bake.

Errors for people: anything wrong with an asset file raises :class:`AssetError`
with one line naming the file and what is wrong, never a traceback from deep
inside a loader. Every bound (file size, triangles, tets) is in
:mod:`~across_dimensions.world.assets.limits`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.fileio import check_folder
from ..core.lift import HyperDepth, extend_solid
from ..core.mesh import MeshError, TetMesh4
from .assets import mesh_files
from .assets.bake_cache import (
    BAKE_VERSION,
    bake_digest,
    cache_key,
    default_cache_dir,
    entry_path,
    load_entry,
    save_entry,
    shipped_dir,
)
from .assets.errors import AssetError
from .assets.limits import MAX_ASSET_BYTES, MAX_TETS, MAX_TRIANGLES
from .assets.mesh_files import SUPPORTED, check_format, read_triangles
from .assets.progress import BakeProgress
from .assets.repair import repair_surface
from .assets.tetwild import DEFAULT_EDGE_LENGTH_FAC, REPRODUCIBLE, tetrahedralize

__all__ = [
    "AssetError",
    "BAKE_VERSION",
    "DEFAULT_EDGE_LENGTH_FAC",
    "MAX_ASSET_BYTES",
    "MAX_TETS",
    "MAX_TRIANGLES",
    "SUPPORTED",
    "bake_digest",
    "bake_key",
    "bake_solid",
    "cache_key",
    "default_cache_dir",
    "lift_asset",
    "lift_to_file",
    "load_surface",
    "read_triangles",
    "repair_surface",
    "tetrahedralize",
]


def load_surface(path, cache_dir=None) -> tuple[np.ndarray, np.ndarray]:
    """Read a closed triangle surface, repairing small defects; cached as the bakes are.

    The repaired surface is kept in the bake cache under the asset's key, so loading a level
    again reads it back without trimesh (which alone is 60 MB of a game's memory).

    Parameters
    ----------
    path : str or Path
        ``.obj``, ``.glb``, ``.gltf`` or ``.stl``. A scene (glTF) is flattened:
        every mesh with its node transform applied.
    cache_dir : str or Path, optional
        Default :func:`default_cache_dir`.

    Returns
    -------
    vertices : (n, 3) float64
    faces : (f, 3) int64
        Closed, consistently wound, counter-clockwise seen from outside.

    Raises
    ------
    AssetError
        Unreadable, unknown format, too large, referencing files outside its
        folder, no triangles, or still open after repair.
    """
    file = _surface_entry(path, cache_dir)
    cached = _load_surface_entry(file) if file is not None and file.exists() else None
    if cached is not None:
        return cached
    v, f = read_triangles(path)
    v, f = repair_surface(v, f, path)
    if file is not None:
        try:
            save_entry(file, v, f, names=("vertices", "faces"))
        except OSError:
            pass  # a read-only cache: the next load repairs again
    return v, f


def _surface_entry(path, cache_dir) -> Path | None:
    """Where the repaired surface of ``path`` is cached (None for a file that cannot be keyed:
    reading it then reports why)."""
    try:
        check_format(path)
        return entry_path(cache_dir, path, cache_key(path, surface=1))
    except AssetError:
        return None


def _load_surface_entry(file) -> tuple[np.ndarray, np.ndarray] | None:
    """A cached surface, or None when it is unusable or over today's triangle limit (then it is
    read and repaired again, which says why)."""
    found = load_entry(file, names=("vertices", "faces"))
    return found if found is not None and len(found[1]) <= mesh_files.MAX_TRIANGLES else None


def bake_key(path, edge_length_fac: float = DEFAULT_EDGE_LENGTH_FAC) -> str:
    """The key of ``path``'s bake: its bytes, the bake's settings and :data:`BAKE_VERSION` (see
    :func:`~.assets.bake_cache.cache_key`)."""
    return cache_key(path, edge_length_fac=float(edge_length_fac), **REPRODUCIBLE)


def bake_solid(
    path, edge_length_fac: float = DEFAULT_EDGE_LENGTH_FAC, cache_dir=None, progress: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """The tetrahedralized 3D solid of a mesh file: shipped, cached, or baked now.

    A bake shipped with the game (``assets/baked/``) under the asset's key comes
    first, then the user's cache; only an asset with neither is baked (and cached).

    Parameters
    ----------
    path : str or Path
    edge_length_fac : float
        Tetrahedralization resolution (see :func:`tetrahedralize`).
    cache_dir : str or Path, optional
        Default :func:`default_cache_dir`.
    progress : bool
        A status line while a bake runs, when stderr is a terminal (a cache
        hit prints nothing).

    Returns
    -------
    vertices : (n, 3) float64
    tets : (m, 4) int64
        Positively oriented; at most :data:`MAX_TETS`.

    Raises
    ------
    AssetError
    """
    path = Path(path)
    check_format(path)
    key = bake_key(path, edge_length_fac)
    for found in (entry_path(shipped_dir(), path, key), entry_path(cache_dir, path, key)):
        cached = load_entry(found) if found.exists() else None
        if cached is not None:
            return cached
    file = entry_path(cache_dir, path, key)
    bar = BakeProgress(path.name, progress)
    try:
        if file.exists():
            bar.stage("cache entry unreadable, rebaking")
        bar.stage("load")
        v, f = read_triangles(path)
        bar.stage("repair")
        v, f = repair_surface(v, f, path)
        bar.stage(f"tetrahedralize {len(f)} triangles")
        try:
            tv, tt = tetrahedralize(v, f, edge_length_fac, on_wait=bar.tick)
        except AssetError as e:
            raise AssetError(f"{path}: {e}") from None
        if len(tt) > MAX_TETS:
            raise AssetError(
                f"{path}: tetrahedralization made {len(tt)} tets, more than the {MAX_TETS} "
                f"a baked asset may have; use a coarser edge length than {edge_length_fac}"
            )
        bar.stage("save")
        save_entry(file, tv, tt)
    except BaseException:
        bar.close()
        raise
    bar.done(f"{len(tt)} tets")
    return tv, tt


def lift_asset(
    path,
    extent: HyperDepth | float,
    *,
    cache_dir=None,
    progress: bool = True,
    edge_length_fac: float = DEFAULT_EDGE_LENGTH_FAC,
    color=None,
    center=None,
) -> TetMesh4:
    """A mesh file extended along ``w`` into a closed 4D solid.

    Parameters
    ----------
    path : str or Path
        ``.obj``, ``.glb``, ``.gltf`` or ``.stl``; must be (repairably) watertight.
    extent : HyperDepth or float
        How far along ``w`` and with which profile (see
        :func:`~across_dimensions.core.lift.profile_scales`); a number is the full depth of
        a prism centred on ``w = 0``.
    cache_dir : str or Path, optional
        Where baked 3D tets are kept; default :func:`default_cache_dir`.
    progress : bool
        A status line while a bake runs, when stderr is a terminal (a cache
        hit prints nothing).
    edge_length_fac : float
        Tetrahedralization resolution (see :func:`tetrahedralize`).
    color : (3,) or (4,) array_like float, optional
        One linear RGB(A) colour for the whole solid.
    center : (3,) array_like float, optional
        Centre the profile scales about (default the bounding-box centre).

    Returns
    -------
    TetMesh4
        Validated; named after the file's stem.

    Raises
    ------
    AssetError
    """
    path = Path(path)
    if not isinstance(extent, HyperDepth):
        extent = HyperDepth(0.0, float(extent), "prism")
    v, t = bake_solid(path, edge_length_fac, cache_dir, progress)
    try:
        mesh = extend_solid(v, t, extent, colors=color, center=center, name=path.stem)
        return mesh.validate()
    except (MeshError, ValueError) as e:
        raise AssetError(f"{path}: cannot lift to 4D: {e}") from None


def lift_to_file(mesh_path, extent: HyperDepth | float, out_path, **kw) -> Path:
    """Bake ``mesh_path`` with :func:`lift_asset` and write it as ``.npz`` (:meth:`TetMesh4.save`).

    The output's folder must exist: a typo must not create folders.

    Returns
    -------
    Path
        ``out_path``.

    Raises
    ------
    AssetError
        The mesh cannot be lifted.
    FileProblem
        The output's folder is missing.
    """
    out = check_folder(out_path)
    mesh = lift_asset(mesh_path, extent, **kw)
    mesh.save(out)
    return out
