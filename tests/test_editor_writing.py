"""The editor writes new entries and fields as the level's author would (compared with files
written by hand in tests/data/editor_style/): after the last entry of their kind, before the
comment that heads the next section, with the file's blank lines, indentation and inline tables."""

from __future__ import annotations

from pathlib import Path

import pytest

from across_dimensions.world.level_edit import LevelEditor
from across_dimensions.world.level_style import inline_spaced, render_value

DATA = Path(__file__).parent / "data" / "editor_style"


@pytest.fixture
def ed():
    return LevelEditor(DATA / "source.toml")


def expected(name: str) -> str:
    return (DATA / name).read_text(encoding="utf-8")


def test_a_new_object_goes_after_the_last_object_before_the_next_section(ed):
    ed.add("object", {"position": [1.0, 1.0, 1.0, 0.5], "rotation": {"xw": 55.9}})
    assert ed.text() == expected("add_object.toml")
    assert ed.selection == ("object", 1)


def test_a_new_world_box_goes_into_its_world_indented_like_its_parts(ed):
    ed.add("box", {"center": [2.0, 0.5, 1.0]}, parent=("world", 0))
    assert ed.text() == expected("add_world_box.toml")
    assert ed.selection == ("world", 0, "box", 1)


def test_new_fields_go_after_the_entrys_last_field(ed):
    ed.set(("box", 0), "color", [0.3, 0.3, 0.3])
    ed.set(("object", 0), "spin", {"xw": 25.0})
    ed.set(("world", 0, "box", 0), "color", [1.0, 0.0, 0.0])
    assert ed.text() == expected("new_fields.toml")


def test_a_kind_the_file_lacks_goes_at_the_end(ed):
    ed.add("mesh", {"position": [1.0, 0.0, 2.0]})
    assert ed.text() == expected("add_new_kind.toml")


def test_undo_of_an_add_restores_the_exact_file(ed):
    ed.add("object", {"position": [1.0, 1.0, 1.0, 0.5]})
    ed.undo()
    assert ed.text() == expected("source.toml")


def test_inline_tables_follow_the_files_spacing():
    assert inline_spaced("rotation = { xy = 20.0 }\n") and not inline_spaced("rotation = {xy = 20.0}\n")
    assert render_value({"xw": 1.5, "yz": -2.0}) == "{ xw = 1.5, yz = -2.0 }"
    assert render_value({"xw": 1.5}, spaced=False) == "{xw = 1.5}"


def test_a_tight_file_keeps_its_tight_inline_tables(tmp_path):
    f = tmp_path / "tight.toml"
    f.write_text(expected("source.toml").replace("{ xy = 20.0 }", "{xy = 20.0}"), encoding="utf-8")
    ed = LevelEditor(f)
    ed.set(("crystal", 0), "spin", {"xw": 10.0})
    assert "position = [2.0, 1.0, 0.0, 0.0]\nspin = {xw = 10.0}\n" in ed.text()
