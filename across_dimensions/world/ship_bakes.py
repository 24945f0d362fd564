"""The bakes shipped with the game: one for every asset a shipped level lifts.

For maintainers, after an asset or the bake changed::

    python -m across_dimensions.world.ship_bakes           # bake what is missing into assets/baked/, drop stale ones
    python -m across_dimensions.world.ship_bakes --check   # exit 1 if one is missing or stale (changes nothing)

A bake is reproducible (:mod:`.assets.fixed_seed`), so anyone running this gets
the shipped files byte for byte; ``tests/test_ship_bakes.py`` checks that the
shipped set is complete and that a fresh bake gives the same bytes.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .assets.bake_cache import entry_path, shipped_dir
from .level import load_level
from .level_bakes import asset_name, baked_assets
from .resources import level_files


def needed() -> dict[Path, Path]:
    """Shipped entry file -> the asset it is the bake of, for every asset the shipped levels lift."""
    from .bake import bake_key

    out = {}
    for f in level_files():
        for asset in baked_assets(load_level(f)):
            out[entry_path(shipped_dir(), asset, bake_key(asset))] = asset
    return out


def stale(wanted: dict[Path, Path]) -> list[Path]:
    """Files in the shipped folder that no shipped level needs any more."""
    folder = shipped_dir()
    return sorted(p for p in folder.glob("*.npz") if p not in wanted) if folder.is_dir() else []


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m across_dimensions.world.ship_bakes", description=__doc__.split("\n")[0])
    p.add_argument("--check", action="store_true", help="change nothing; exit 1 if a bake is missing or stale")
    args = p.parse_args(argv)
    wanted = needed()
    missing = {f: a for f, a in wanted.items() if not f.exists()}
    old = stale(wanted)
    if args.check:
        for f, a in missing.items():
            print(f"{f}: missing: the bake of {asset_name(a)} (run python -m across_dimensions.world.ship_bakes)")
        for f in old:
            print(f"{f}: stale: no shipped level lifts an asset with this key any more")
        if not missing and not old:
            print(f"{shipped_dir()}: {len(wanted)} shipped bakes, all current")
        return 1 if missing or old else 0
    from .bake import bake_solid

    for f, a in missing.items():
        # The shipped folder as the cache: the bake lands there under its key.
        v, t = bake_solid(a, cache_dir=f.parent, progress=False)
        print(f"{f}: baked {asset_name(a)}: {len(v)} vertices, {len(t)} tets")
    for f in old:
        f.unlink()
        print(f"{f}: removed (stale)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
