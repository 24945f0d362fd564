"""The baked meshes a level uses, and the level hash that covers them.

A level's 4D content depends on more than its file: every asset it lifts
(``[[world]]`` meshes, ``[[object]]`` assets, ``morph`` enemies) is a tetrahedral
mesh baked from a 3D file (:mod:`.bake`). Two machines with different bakes of
one asset play different games from one file, so a replay checks the bakes as it
checks the file: its ``level_hash`` is the file's sha256 folded with the digest
of every bake (:func:`fold_level_hash`), and its ``bakes`` entry lists the digests
so a difference is named ("asset meshes/tree.obj baked differently") instead of
showing up as a divergence some ticks in. A level that lifts nothing keeps its
file's sha256 as its hash.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from .flat_level import FlatLevel
from .resources import assets_dir


def baked_assets(level) -> list[Path]:
    """Every asset file ``level`` lifts into 4D, each once, sorted.

    Parameters
    ----------
    level : Level or FlatLevel
        A Flatland prologue level lifts nothing: its solids are built from its own numbers.

    Returns
    -------
    list of Path
        Resolved paths inside the assets folder.
    """
    if isinstance(level, FlatLevel):
        return []
    found = {m.asset for w in level.worlds for m in w.meshes}
    found |= {o.asset for o in level.objects if o.asset is not None}
    found |= {e.asset for e in level.enemies if e.asset is not None}
    return sorted({Path(p) for p in found})


def asset_name(path: Path) -> str:
    """``path`` as a level names it: relative to the assets folder (``meshes/tree.obj``)."""
    try:
        return Path(path).resolve().relative_to(assets_dir().resolve()).as_posix()
    except ValueError:
        return Path(path).name


def level_bakes(level) -> dict[str, str]:
    """Asset name -> digest of its bake (:func:`~.assets.bake_cache.bake_digest`) for ``level``.

    Each bake comes from where the game takes it (shipped, cached, or baked now),
    so the digests are those of the meshes this game plays.

    Raises
    ------
    AssetError
        An asset cannot be baked.
    """
    if not baked_assets(level):
        return {}
    from .bake import bake_digest, bake_solid  # trimesh and pytetwild only when a level lifts assets

    return {asset_name(p): bake_digest(*bake_solid(p, progress=False)) for p in baked_assets(level)}


def fold_level_hash(source_hash: str, bakes: dict[str, str]) -> str:
    """The level hash replays record: the file's sha256, folded with each bake's digest.

    Parameters
    ----------
    source_hash : str
        sha256 hex of the level file.
    bakes : dict of str to str
        Asset name -> bake digest; empty gives ``source_hash`` itself.
    """
    if not bakes:
        return source_hash
    h = hashlib.sha256(source_hash.encode())
    for name in sorted(bakes):
        h.update(f"\n{name}={bakes[name]}".encode())
    return h.hexdigest()
