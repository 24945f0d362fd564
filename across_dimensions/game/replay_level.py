"""Is a replay for this level? Its file and its bakes, checked before a tick is played.

A replay records the level's hash: the level file's sha256 folded with the digest
of every mesh the level bakes (:mod:`across_dimensions.world.level_bakes`), and,
from version 3 on, those digests by asset. A different file makes every state
hash meaningless; a different bake of one asset is named as such.
"""

from __future__ import annotations

from pathlib import Path

from ..world.level_bakes import fold_level_hash, level_bakes


def level_identity(level) -> tuple[str, dict[str, str]]:
    """``(level_hash, bakes)`` a recording of ``level`` writes in its header."""
    bakes = level_bakes(level)
    return fold_level_hash(level.source_hash, bakes), bakes


def same_file(replay, level) -> bool:
    """Was ``replay`` recorded on this very level file (whatever its bakes)?"""
    if replay.bakes is None:  # versions 1 and 2 hashed the file alone
        return replay.level_hash == level.source_hash
    return fold_level_hash(level.source_hash, replay.bakes) == replay.level_hash


def other_level(replay, level) -> str | None:
    """The name of the level ``replay`` was recorded on when it is plainly not ``level``, else None.

    Said before anything is played: another level's file under another name.
    """
    recorded = Path(replay.level).stem
    if recorded == Path(level.path).stem or same_file(replay, level):
        return None
    return recorded


def level_divergence(replay, game) -> str | None:
    """Why ``replay`` cannot be checked against ``game``'s level, or None.

    The level file comes first (a changed file changes everything), then each
    baked asset in name order.
    """
    level = game.level
    if not same_file(replay, level):
        ours, _ = level_identity(level)
        return (
            "the level file changed since this replay was recorded "
            f"(level hash {ours[:12]}, replay expects {replay.level_hash[:12]})"
        )
    if replay.bakes is None:
        return None
    ours = level_bakes(level)
    for name in sorted(set(ours) | set(replay.bakes)):
        mine, theirs = ours.get(name), replay.bakes.get(name)
        if mine != theirs:
            return (
                f"asset {name} baked differently: this replay was recorded with bake {str(theirs)[:12]}, "
                f"this game plays bake {str(mine)[:12]} ({_origin(name)}); its state hashes cannot match"
            )
    return None


def _origin(name: str) -> str:
    """Where this game's bake of the asset ``name`` comes from, for the message."""
    from ..world.assets.bake_cache import entry_path, shipped_dir
    from ..world.bake import bake_key
    from ..world.resources import resolve_asset

    try:
        path = resolve_asset(name)
    except ValueError:
        return "the asset is missing"
    if entry_path(shipped_dir(), path, bake_key(path)).exists():
        return "the bake shipped with the game"
    return "baked on this machine: no bake of this asset file is shipped with the game"
