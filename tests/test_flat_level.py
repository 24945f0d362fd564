"""The prologue's level format (world/flat_level.py): read by the level loader's own reader, every
problem reported at once, each naming the file, the table, the entry's index and the field."""

from __future__ import annotations

import subprocess
import sys

import pytest

from across_dimensions.world.flat_level import load_flat_level
from across_dimensions.world.level import LevelError, load_level
from across_dimensions.world.resources import is_prologue_file, level_files, levels_dir, prologue_files

PROLOGUE = levels_dir() / "prologue.toml"

BROKEN = """
[level]
format = "flatland"
z_range = [-1.0, 1.0]
colour = "blue"

[spawn]
position = [0.0, 0.0, 2.0]

[[box]]
name = "floor"
center = [0.0, -1.0, 0.0]
size = [10.0, 2.0, 4.0]

[[box]]
name = "wall"
center = [3.0, 1.0, 0.0]
size = [0.5, -2.0, 1.0]

[[prism]]
along = "y"
extent = [1.0, 0.0]
profile = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]

[[stairs]]
position = [0.0, 0.0, 0.0]
steps = 2.5
run = 0.5
rise = 0.3
width = 2.0

[[ball]]
name = "floor"
center = [2.0, 1.0, 3.0]
radius = 1.0
roll = [-1.0, 1.0]

[[item]]
position = [1.0, 1.0, 0.5]
opens = "door"

[[hint]]
text = "Hold {w_ana}."
until = { z_least = 0.5, event = "won" }

[[hint]]
text = "A {} brace."

[[spike]]
center = [0.0, 0.0, 0.0]
"""


def test_the_shipped_prologue_loads():
    level = load_flat_level(PROLOGUE)
    assert level.name == "Flatland" and level.z_range == (-3.0, 3.0)
    assert {s.kind for s in level.solids} == {"box", "prism", "stairs"}
    assert [b.name for b in level.balls] == ["ball"] and [i.opens for i in level.items] == ["gate"]
    assert all(h.until for h in level.hints)  # every hint waits for a state, none for a key


def test_the_prologue_is_told_apart_by_its_format_key():
    assert is_prologue_file(PROLOGUE) and prologue_files() == [PROLOGUE]
    assert PROLOGUE not in level_files() and level_files()  # the 4D levels stay what they were
    with pytest.raises(LevelError) as info:
        load_level(PROLOGUE)  # one clear line, not a list of 4D fields it lacks
    (line,) = info.value.problems
    assert str(PROLOGUE) in line and 'format = "flatland"' in line


def test_every_problem_is_reported_at_once_naming_file_table_and_entry(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text(BROKEN, encoding="utf-8")
    with pytest.raises(LevelError) as info:
        load_flat_level(path)
    problems = info.value.problems
    assert all(p.startswith(f"{path}: ") for p in problems)
    expected = [
        "top level: unknown field 'spike'",
        "[level]: unknown field 'colour'",
        "[goal]: missing table [goal]",
        "[spawn]: field 'position': z = 2 is outside the level's z_range [-1.0, 1.0]",
        "[[box]] #2 'wall': field 'size': expected 3 positive numbers",
        "[[prism]] #1: field 'along': expected one of x, z, got 'y'",
        "[[prism]] #1: field 'profile': expected a simple polygon",
        "[[prism]] #1: field 'extent': expected [low, high] with low < high",
        "[[stairs]] #1: field 'steps': expected a whole number, got 2.5",
        "[[ball]] #1 'floor': field 'center': z = 3 is outside its roll [-1.0, 1.0]",
        "[[item]] #1: field 'opens': no box, prism or stairs named 'door'",
        "[[hint]] #1 > until: unknown field 'z_least'",
        "[[hint]] #1 > until: field 'event': expected one of item_taken",
        "[[hint]] #2: field 'text': '{}' is not an {action} placeholder",
        "top level: the name 'floor' is given to more than one entry",
    ]
    for fragment in expected:
        assert sum(fragment in p for p in problems) == 1, (fragment, problems)
    assert len(problems) == len(expected)


def test_check_level_prints_each_problem_and_exits_2(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text(BROKEN, encoding="utf-8")
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "check-level", str(PROLOGUE), str(path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 2, r.stderr
    assert r.stdout.startswith(f"{PROLOGUE}: ok - 'Flatland', a Flatland prologue level")
    assert f"{path}: 15 problem(s)" in r.stderr and "[[stairs]] #1" in r.stderr
    assert "Traceback" not in r.stderr


GOAL = "[goal]\ncenter = [1, 1]\nsize = [1, 1]\n"


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("[level]\nformat = 'flatland'\n", "missing table [spawn]"),
        ("[level]\nformat = 'flatland'\n[spawn]\nposition = [0, 0]\n" + GOAL, "3 numbers"),
        ("[level]\nformat = 2\n[spawn]\nposition = [0, 0, 0]\n" + GOAL, "expected a string"),
    ],
)
def test_small_mistakes_get_one_clear_line(tmp_path, text, fragment):
    path = tmp_path / "small.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(LevelError) as info:
        load_flat_level(path)
    assert any(fragment in p and p.startswith(str(path)) for p in info.value.problems), info.value.problems
