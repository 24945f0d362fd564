"""Baked meshes: reproducible, shipped, and part of the level hash a replay checks.

- A bake of one asset gives the same bytes in fresh processes, and those of the
  bake shipped in ``assets/baked/`` (fTetWild's entropy draws replaced by a fixed
  sequence, :mod:`across_dimensions.world.assets.fixed_seed`).
- Every asset a shipped level lifts has its bake shipped, under its current key.
- A level's hash folds in its bakes, and a replay recorded with another bake
  says which asset, not "diverges at tick 60".
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from across_dimensions.game.replay import Replay
from across_dimensions.game.replay_format import VERSION
from across_dimensions.game.replay_level import level_divergence, level_identity, same_file
from across_dimensions.world import bake
from across_dimensions.world.assets import bake_cache, fixed_seed
from across_dimensions.world.level import load_level
from across_dimensions.world.level_bakes import baked_assets, fold_level_hash, level_bakes

REPO = Path(__file__).resolve().parents[1]
TREE = REPO / "assets" / "meshes" / "tree.obj"
HIVE = REPO / "levels" / "09_hive.toml"

#: In a fresh process: bake tree.obj with nothing shipped and an empty cache folder, print the entry's path.
_BAKE_FRESH = """
import sys
from pathlib import Path
from across_dimensions.world import bake
bake.shipped_dir = lambda: Path(sys.argv[2]) / "none-shipped"
bake.bake_solid(sys.argv[1], cache_dir=sys.argv[2], progress=False)
print(next(Path(sys.argv[2]).glob("*.npz")))
"""


@pytest.mark.slow
def test_a_bake_gives_the_same_bytes_in_three_fresh_processes_and_those_shipped(env, tmp_path):
    files = []
    for i in range(3):
        out = subprocess.run(
            [sys.executable, "-c", _BAKE_FRESH, str(TREE), str(tmp_path / str(i))],
            capture_output=True,
            text=True,
            env=env,
            timeout=300,
        )
        assert out.returncode == 0, out.stderr
        files.append(Path(out.stdout.strip()))
    first = files[0].read_bytes()
    assert all(f.read_bytes() == first for f in files[1:])
    shipped = bake_cache.shipped_dir() / files[0].name  # the same key names the same file
    assert shipped.read_bytes() == first
    v, t = bake_cache.load_entry(shipped)
    assert len(v) > 100 and len(t) > 100  # a real tree, not a box


def test_the_fixed_sequence_is_installed_in_pytetwild():
    pytetwild = pytest.importorskip("pytetwild")
    if not sys.platform.startswith("linux"):
        pytest.skip("the table entry is patched on Linux only")
    library = pytetwild.PyfTetWildWrapper.__file__
    assert fixed_seed.slot_offsets(Path(library).read_bytes())  # the draw is imported through a table entry
    assert fixed_seed.slot_offsets(Path(library).read_bytes(), b"no_such_symbol") == []
    assert fixed_seed.slot_offsets(b"not an ELF file") == []


def test_every_lifted_asset_of_the_shipped_levels_has_its_bake_shipped(env):
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions.world.ship_bakes", "--check"],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert r.returncode == 0, r.stdout + r.stderr
    assert "all current" in r.stdout


def test_ship_bakes_names_a_missing_and_a_stale_bake(tmp_path, monkeypatch, capsys):
    from across_dimensions.world import ship_bakes

    monkeypatch.setattr(ship_bakes, "shipped_dir", lambda: tmp_path)
    (tmp_path / "tree-000000000000000000000000.npz").write_bytes(b"old")
    assert ship_bakes.main(["--check"]) == 1
    out = capsys.readouterr().out.splitlines()
    assert len(out) == 2 and "missing: the bake of meshes/tree.obj" in out[0] and "stale" in out[1]
    assert (tmp_path / "tree-000000000000000000000000.npz").exists()  # --check changes nothing


def test_a_level_that_lifts_nothing_keeps_its_file_hash():
    level = load_level(REPO / "levels" / "01_first_steps.toml")
    assert baked_assets(level) == [] and level_identity(level) == (level.source_hash, {})


def test_the_hive_folds_its_tree_bake_into_its_hash():
    level = load_level(HIVE)
    bakes = level_bakes(level)
    assert list(bakes) == ["meshes/tree.obj"]
    v, t = bake_cache.load_entry(bake_cache.entry_path(bake_cache.shipped_dir(), TREE, bake.bake_key(TREE)))
    assert bakes["meshes/tree.obj"] == bake_cache.bake_digest(v, t)
    folded = fold_level_hash(level.source_hash, bakes)
    assert folded != level.source_hash
    assert fold_level_hash(level.source_hash, {"meshes/tree.obj": "0" * 64}) != folded
    shipped = Replay.load(REPO / "levels" / "replays" / "09_hive.json")
    assert (shipped.level_hash, shipped.bakes) == (folded, bakes)


def test_a_different_bake_is_named_before_any_tick(tmp_path, monkeypatch):
    level = load_level(HIVE)
    shipped = Replay.load(REPO / "levels" / "replays" / "09_hive.json")
    # This machine has no shipped bake and baked the tree differently (a box of the same size).
    monkeypatch.setattr(bake, "shipped_dir", lambda: tmp_path / "none")
    monkeypatch.setattr(bake_cache, "shipped_dir", lambda: tmp_path / "none")
    monkeypatch.setattr(bake_cache, "default_cache_dir", lambda: tmp_path)
    from across_dimensions.core.lift import box_solid

    v, t = box_solid([0.0, 1.7, 0.0], [1.8, 3.4, 1.8])
    bake_cache.save_entry(bake_cache.entry_path(tmp_path, TREE, bake.bake_key(TREE)), v, np.asarray(t))
    game = SimpleNamespace(level=level)
    assert same_file(shipped, level)  # the file is the same ...
    why = level_divergence(shipped, game)  # ... the bake is not
    assert why.startswith("asset meshes/tree.obj baked differently:"), why
    assert shipped.bakes["meshes/tree.obj"][:12] in why and "baked on this machine" in why


def test_a_replay_of_an_older_format_checks_the_file_alone():
    level = load_level(HIVE)
    old = Replay("09_hive", level.source_hash)  # version 2: no bakes
    assert same_file(old, level) and level_divergence(old, SimpleNamespace(level=level)) is None
    edited = Replay("09_hive", "0" * 64)
    assert "the level file changed" in level_divergence(edited, SimpleNamespace(level=level))


def test_every_shipped_replay_is_of_the_current_format():
    for path in sorted((REPO / "levels" / "replays").glob("*.json")):
        data = json.loads(path.read_text())
        assert data["version"] == VERSION and isinstance(data["bakes"], dict), path
