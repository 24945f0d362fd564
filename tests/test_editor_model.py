"""The level editor's model, headless: edits, undo/redo, validation by the loader, saving."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from conftest import per_level

pytest.importorskip("tomlkit")

from across_dimensions.game.actions import Actions  # noqa: E402
from across_dimensions.game.sim import Game  # noqa: E402
from across_dimensions.world.level import LevelError, load_level  # noqa: E402
from across_dimensions.world.level_edit import LevelEditor  # noqa: E402
from across_dimensions.world.resources import level_files  # noqa: E402

LEVELS = level_files()
CACHE = next(p for p in LEVELS if p.name == "02_crystal_cache.toml")


@pytest.fixture
def cache(tmp_path) -> Path:
    p = tmp_path / CACHE.name
    shutil.copy(CACHE, p)
    return p


def _meaning(level):
    """A level's content as comparable plain data (without its path and hash)."""
    d = {k: v for k, v in vars(level).items() if k not in ("path", "source_hash")}
    return repr(
        {k: (v.tolist() if isinstance(v, np.ndarray) else repr(v).replace(str(level.path), "")) for k, v in d.items()}
    )


def _interleaved(text: str) -> bool:
    """Does an array of tables (``[[box]]``) come back after another table in between?
    tomlkit keeps each array's tables together, so such a file is saved reordered."""
    headers = re.findall(r"^\s*\[\[?([A-Za-z_.]+)\]\]?", text, re.M)
    seen, last = set(), None
    for h in headers:
        top = h.split(".")[0]
        if top != last and top in seen:
            return True
        seen.add(top)
        last = top
    return False


@pytest.mark.parametrize("path", LEVELS, ids=lambda p: p.stem)
def test_round_trip_of_every_shipped_level(path, tmp_path):
    """Load, save with no change, load: byte-identical, or equal in meaning where the file
    interleaves arrays of tables (each array's order is kept; only their grouping moves)."""
    ed = LevelEditor(path)
    original = path.read_text(encoding="utf-8")
    assert ed.text() == original or _interleaved(original)
    assert not ed.dirty and ed.problems == []
    out = ed.save(tmp_path / path.name)
    assert out.read_bytes() == path.read_bytes() or _interleaved(original)
    assert _meaning(load_level(out)) == _meaning(load_level(path))


@pytest.mark.parametrize("path", per_level(LEVELS))
def test_every_edit_then_undo_restores_the_exact_level(path):
    ed = LevelEditor(path)
    original = ed.text()
    for ref in ed.entries():
        model_keys = [k for k in ("position", "center", "w", "depth", "rotation", "scale") if k in ed.table(ref)]
        for key in model_keys:
            before = ed.text()
            old = ed.get(ref, key)
            new = {"xw": 33.0} if isinstance(old, dict) else [1.5] * len(old) if isinstance(old, list) else 0.75
            ed.set(ref, key, new)
            assert ed.text() != before
            assert ed.undo() is not None
            assert ed.text() == before
            ed.redo()
            assert ed.get(ref, key) == new
            ed.undo()
    for ref in [r for r in ed.entries() if len(r) == 2][::-1]:
        ed.delete(ref)
        ed.undo()
    ed.add("object")
    ed.add("crystal")
    ed.undo()
    ed.undo()
    assert ed.text() == original


def test_drag_merges_into_one_undo_step(cache):
    ed = LevelEditor(cache)
    for w in np.linspace(0.0, 0.5, 20):
        ed.set(("crystal", 1), "position", [-3.0, 1.0, -3.0, float(w)], merge=True)
    assert len(ed.undo_stack) == 1
    ed.set(("crystal", 1), "energy", 4.0, merge=True)  # another field: a new step
    assert len(ed.undo_stack) == 2
    ed.undo()
    ed.undo()
    assert not ed.dirty


def test_saving_keeps_comments_and_order(cache):
    ed = LevelEditor(cache)
    ed.set(("energy",), "w_cost", 2.5)
    ed.set(("object", 0), "rotation", {"xy": 20.0, "xw": 30.0})
    ed.save()
    text = cache.read_text()
    assert "w_cost = 2.5        # energy per unit of w: reaching w = 0.8 costs 3.2" in text
    assert "[[box]]   # floor" in text and "# ---- crystals" in text
    assert "rotation = { xy = 20.0, xw = 30.0" in text
    # the order of entries: only the two edited lines differ from the original
    old, new = CACHE.read_text().splitlines(), text.splitlines()
    assert len(old) == len(new)
    assert sum(a != b for a, b in zip(old, new)) == 2
    assert not ed.dirty


def test_invalid_value_is_refused_with_the_loaders_message(cache):
    ed = LevelEditor(cache)
    ed.set(("crystal", 0), "energy", -1.0)
    hand = cache.with_name("hand.toml")
    hand.write_text(CACHE.read_text().replace("energy = 2.0", "energy = -1.0"))
    with pytest.raises(LevelError) as by_loader:
        load_level(hand)
    expected = [p.replace(str(hand), str(cache)) for p in by_loader.value.problems]
    assert ed.problems == expected
    assert ed.problems_for(("crystal", 0), "energy") == expected
    assert ed.problems_for(("crystal", 1)) == [] and ed.problems_for(("crystal", 0), "position") == []
    before = cache.read_bytes()
    with pytest.raises(LevelError):
        ed.save()
    assert cache.read_bytes() == before  # nothing invalid is written
    assert list(cache.parent.glob("*.tmp")) == []
    ed.undo()
    assert ed.problems == []


def test_problems_of_a_world_box_name_the_box(cache):
    ed = LevelEditor(cache)
    ed.set(("world", 0, "box", 0), "size", [9.0, -4.0, 0.6])
    assert len(ed.problems_for(("world", 0, "box", 0), "size")) == 1
    assert ed.problems_for(("world", 0)) == []


def test_saved_level_plays_like_one_written_by_hand(cache, tmp_path):
    ed = LevelEditor(cache)
    ed.set(("object", 0), "position", [0.0, 2.6, 11.0, 0.7])
    ed.set(("crystal", 1), "position", [-3.0, 1.0, -6.0, 0.0])
    ed.set(("spawn",), "position", [0.0, 0.0, -8.0, 0.0])
    ed.save()
    hand = tmp_path / "hand.toml"
    text = CACHE.read_text()
    text = text.replace("position = [0.0, 2.6, 12.0, 0.9]", "position = [0.0, 2.6, 11.0, 0.7]")
    text = text.replace("position = [-3.0, 1.0, -3.0, 0.5]", "position = [-3.0, 1.0, -6.0, 0.0]")
    text = re.sub(r"position = \[0\.0, 0\.0, -9\.0, 0\.0\]", "position = [0.0, 0.0, -8.0, 0.0]", text)
    hand.write_text(text)
    a, b = Game(load_level(cache)), Game(load_level(hand))
    walk = Actions(forward=1.0, w=0.0)
    for _ in range(150):  # walking forward picks up the moved crystal at z = -6
        a.step(walk)
        b.step(walk)
    assert a.state_hash() == b.state_hash()
    assert a.event_counts == b.event_counts and sum(a.event_counts.values()) > 0


def test_add_and_delete_entries(cache):
    ed = LevelEditor(cache)
    n = len(ed.entries())
    ref = ed.add("object", {"position": [1.0, 1.0, 0.0, 0.2]})
    assert ref == ("object", 1) and ed.selection == ref
    assert ed.problems == []
    level, _ = ed.check()
    assert [o.name for o in level.objects] == ["beacon", "new object"]
    world_box = ed.add("box", parent=("world", 0))
    assert world_box == ("world", 0, "box", 1)
    assert len(ed.check()[0].worlds[0].boxes) == 2
    ed.add("world")
    assert len(ed.check()[0].worlds) == 2 and ed.problems == []
    ed.delete(("crystal", 0))
    assert [c.name for c in ed.check()[0].crystals] == ["ana cache", "kata cache"]
    assert len(ed.entries()) == n + 2 + 1 + 1 - 1
    ed.duplicate(("world", 0))
    assert len(ed.check()[0].worlds) == 3 and ed.check()[0].worlds[2].name == "blue copy"
    with pytest.raises(ValueError):
        ed.delete(("spawn",))


def test_removing_a_field_restores_its_default(cache):
    ed = LevelEditor(cache)
    ed.set(("object", 0), "spin", None)
    assert "spin" not in ed.table(("object", 0))
    assert ed.check()[0].objects[0].spin_deg == {}
    assert ed.value(("object", 0), "body") == "none"  # unwritten: the model's default


@pytest.mark.parametrize("kind", ["box", "mesh", "world", "object", "crystal"])
def test_every_kind_is_added_valid_and_removed_by_undo(cache, kind):
    ed = LevelEditor(cache)
    before = ed.text()
    ref = ed.add(kind)
    assert ed.problems == [], ed.problems
    assert ed.exists(ref) and ref in ed.entries()
    ed.undo()
    assert ed.text() == before and ed.selection is None


def test_a_level_without_a_kind_gets_its_first_entry(tmp_path):
    first = next(p for p in LEVELS if p.name.startswith("01_"))
    p = tmp_path / first.name
    shutil.copy(first, p)
    ed = LevelEditor(p)
    assert "crystal" not in ed.doc
    ed.set(("level",), "format", 2)
    ref = ed.add("crystal", {"position": [0.0, 1.0, 0.0, 0.0]})
    assert ref == ("crystal", 0) and ed.problems == []
    ed.save()
    assert [c.name for c in load_level(p).crystals] == ["new crystal"]
