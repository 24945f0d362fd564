"""The editor's model on several entries: new levels from the template, save as, multi-selection,
group move / rotate / scale with snapping, delete, copy and paste as TOML text."""

from __future__ import annotations

import numpy as np
import pytest

from across_dimensions.core.transform import angles_to_rotation, rotation4
from across_dimensions.world import level_group as group
from across_dimensions.world.level import load_level
from across_dimensions.world.level_edit import LevelEditor
from across_dimensions.world.level_template import TEMPLATE_NAME, template_names, template_text


@pytest.fixture
def ed(tmp_path):
    return LevelEditor.new(tmp_path / "new.toml", template_text(TEMPLATE_NAME, "Test room"))


def test_the_template_is_a_valid_level_not_yet_saved(ed, tmp_path):
    level, problems = ed.check()
    assert problems == [] and level.name == "Test room" and level.w_range == (-1.0, 2.0)
    assert ed.dirty and not (tmp_path / "new.toml").exists()
    ed.save()
    assert not ed.dirty and load_level(tmp_path / "new.toml").name == "Test room"


def test_new_from_a_shipped_level_copies_its_text():
    names = template_names()
    assert names[0] == TEMPLATE_NAME and "01_first_steps" in names
    assert 'name = "First Steps"' in template_text("01_first_steps")
    with pytest.raises(KeyError):
        template_text("no such level")


def test_save_as_goes_on_editing_the_new_file_and_refuses_a_broken_level(ed, tmp_path):
    ed.save_as(tmp_path / "other.toml")
    assert ed.path == tmp_path / "other.toml" and not ed.dirty
    ed.set(("goal",), "size", [-1.0, 2.0, 2.0])
    with pytest.raises(Exception, match="size"):
        ed.save_as(tmp_path / "third.toml")
    assert ed.path == tmp_path / "other.toml" and not (tmp_path / "third.toml").exists()


def test_shift_click_adds_and_removes(ed):
    ed.select(("box", 0))
    ed.select(("box", 1), toggle=True)
    ed.select(("goal",), toggle=True)
    assert ed.selected == [("box", 0), ("box", 1), ("goal",)] and ed.selection == ("goal",)
    ed.select(("box", 1), toggle=True)
    assert ed.selected == [("box", 0), ("goal",)]
    ed.select(("spawn",))
    assert ed.selected == [("spawn",)]


def test_group_move_snaps_the_first_and_keeps_offsets_in_one_step(ed):
    a = ed.add("crystal", {"position": [0.1, 1.0, 2.0, 0.0]})
    b = ed.add("crystal", {"position": [1.1, 1.0, 3.0, 0.5]})
    steps = len(ed.undo_stack)
    group.move(ed, [a, b], [0.3, 0.0, 0.0, 0.33], grid=0.25, w_step=0.1)
    assert ed.get(a, "position") == [0.5, 1.0, 2.0, 0.3]  # 0.4 -> 0.5 on the 0.25 grid, w 0.33 -> 0.3
    assert ed.get(b, "position") == [1.5, 1.0, 3.0, 0.8]
    assert len(ed.undo_stack) == steps + 1
    ed.undo()
    assert ed.get(a, "position") == [0.1, 1.0, 2.0, 0.0]


def test_moving_a_world_moves_its_parts_and_its_w(ed):
    ed.add("world", {"name": "blue", "w": 1.0, "box": [{"center": [0.0, 2.0, 0.0], "size": [10.0, 4.0, 0.5]}]})
    group.move(ed, [("world", 0), ("world", 0, "box", 0)], [1.0, 0.0, 0.0, 0.5])
    assert ed.get(("world", 0, "box", 0), "center") == [1.0, 2.0, 0.0]  # once, not twice
    assert ed.get(("world", 0), "w") == 1.5


def test_rotations_compose_exactly_and_snap(ed):
    o = ed.add("object", {"position": [0.0, 1.0, 0.0, 0.0], "rotation": {"xy": 20.0}})
    group.rotate(ed, [o], "xw", 30.0)
    got = group.rotation_of(ed, o)
    want = rotation4("xw", np.radians(30.0)) @ angles_to_rotation({"xy": np.radians(20.0)})
    np.testing.assert_allclose(got, want, atol=1e-5)  # angles kept to 4 places of a degree
    o2 = ed.add("object", {"position": [0.0, 1.0, 0.0, 0.0]})
    group.rotate(ed, [o2], "zw", 37.0, step=15.0)
    assert ed.get(o2, "rotation") == {"zw": 30.0}


def test_group_rotation_turns_places_about_the_pivot(ed):
    a = ed.add("crystal", {"position": [1.0, 1.0, 0.0, 0.0]})
    b = ed.add("crystal", {"position": [-1.0, 1.0, 0.0, 0.0]})
    group.rotate(ed, [a, b], "xw", 90.0)
    np.testing.assert_allclose(ed.get(a, "position"), [0.0, 1.0, 0.0, 1.0], atol=1e-9)
    np.testing.assert_allclose(ed.get(b, "position"), [0.0, 1.0, 0.0, -1.0], atol=1e-9)


def test_a_quarter_turn_swaps_a_boxs_sizes(ed):
    group.rotate(ed, [("box", 1)], "xz", 90.0)
    assert ed.get(("box", 1), "size") == [20.0, 4.0, 0.5]


def test_scale_includes_the_hyper_depth(ed):
    o = ed.add("object", {"position": [0.0, 1.0, 0.0, 0.0]})
    group.scale(ed, [o], [1.0, 1.0, 1.0, 2.5])
    assert ed.get(o, "scale") == [1.0, 1.0, 1.0, 2.5]
    group.scale(ed, [("box", 0)], [0.5, 1.0, 1.0, 1.0])
    assert ed.get(("box", 0), "size") == [5.0, 1.0, 20.0]


def test_copy_and_paste_between_levels_as_toml(ed, tmp_path):
    w = ed.add("world", {"name": "blue", "w": 1.0, "box": [{"center": [0.0, 2.0, 0.0], "size": [10.0, 4.0, 0.5]}]})
    c = ed.add("crystal", {"position": [0.0, 1.0, 4.0, 1.0]})
    text = group.copy_text(ed, [w, c])
    assert "[[world]]" in text and "  [[world.box]]" in text and "[[crystal]]" in text
    other = LevelEditor.new(tmp_path / "other.toml", template_text(TEMPLATE_NAME))
    new = group.paste(other, text, offset=(1.0, 0.0, 0.0, 0.0))
    assert new == [("world", 0), ("crystal", 0)] and other.selected == new
    assert other.get(("world", 0, "box", 0), "center") == [1.0, 2.0, 0.0]
    assert other.get(("crystal", 0), "position") == [1.0, 1.0, 4.0, 1.0]
    assert other.problems == []
    with pytest.raises(ValueError, match="clipboard"):
        group.paste(other, "[[crystal]\nnot toml")
    assert group.paste(other, "just = 'text'") == []


def test_delete_several_in_one_step(ed):
    n = len(ed.doc["box"])
    group.delete(ed, [("box", 1), ("box", 3)])
    assert len(ed.doc["box"]) == n - 2 and ed.selection is None
    ed.undo()
    assert len(ed.doc["box"]) == n


def test_duplicate_keeps_a_worlds_part_in_its_world(ed):
    ed.add("world", {"name": "blue", "w": 1.0, "box": [{"center": [0.0, 2.0, 0.0], "size": [1.0, 1.0, 1.0]}]})
    new = group.duplicate(ed, [("world", 0, "box", 0)])
    assert new == [("world", 0, "box", 1)]
    assert ed.get(new[0], "center") == [0.5, 2.0, 0.5]


def test_quick_warnings_flag_what_cannot_be_reached_as_you_edit(ed):
    from across_dimensions.world.level_lint import lint

    assert lint(ed, ed.check()[0]) == {}
    c = ed.add("object", {"position": [0.0, 1.0, 2.0, 3.5]})  # w range is [-1, 2]
    ed.add("world", {"name": "far", "w": 5.0, "depth": 1.0})
    ed.add("checkpoint", {"name": "in the wall", "position": [-5.25, 0.0, 0.0, 0.0], "size": [2.0, 2.0, 2.0]})
    ed.add("checkpoint", {"name": "on the spawn", "position": [0.0, 0.0, -8.0, 0.0], "size": [2.0, 2.0, 2.0]})
    ed.set(("goal",), "center", [0.0, 4.0, 8.0])  # 3 m over the floor
    found = lint(ed, ed.check()[0])
    assert "outside the level's w range" in found[c][0]
    assert "never seen" in found[("world", 0)][0]
    assert "overlaps solid geometry" in found[("checkpoint", 0)][0]  # the loader refuses a spawn there
    assert found[("checkpoint", 1)] == ["at the same place as spawn"]
    assert "no floor within a jump" in found[("goal",)][0]


def test_the_checks_panel_runs_check_level_and_the_probe_and_names_the_entries(ed):
    pytest.importorskip("imgui_bundle")
    import time

    from across_dimensions.app.editor.checks import Checks

    class Mode:  # what the panel reads of the editor's view
        model = ed

    ed.set(("goal",), "size", [-1.0, 2.0, 2.0])  # a problem check-level names, in [goal]
    checks = Checks(Mode())
    checks.run()
    for _ in range(1200):
        checks.poll()
        if not checks.running:
            break
        time.sleep(0.1)
    assert not checks.running and checks.folder is None  # both finished, their folder removed
    texts = [t for t, _ in checks.findings]
    assert any("size" in t and ("goal",) == ref for t, ref in checks.findings), texts
    assert any(t.startswith("probe: ") for t in texts), texts  # the probe refuses a broken level too
