"""check-level on what each entry cannot show alone: placement, names, and the cost of enemies and crystals.

Each case is a shipped level with one thing moved or added, refused with the file,
the table and its index; the shipped levels themselves pass (tests/test_levels.py).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.world import limits
from across_dimensions.world.level import LevelError, load_level
from across_dimensions.world.placement import _inside_solid

REPO = Path(__file__).resolve().parents[1]
LEVELS = REPO / "levels"


def variant(tmp_path, level: str, old: str, new: str, name="level.toml") -> Path:
    text = (LEVELS / f"{level}.toml").read_text()
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new, 1))
    return path


def check_level(env, path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", "check-level", str(path)],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )


def refused(env, path, *needles) -> str:
    r = check_level(env, path)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    head, line = r.stderr.splitlines()
    assert head == f"{path}: 1 problem(s)"
    assert line.strip().startswith(f"{path}: ")
    for n in needles:
        assert n in line, line
    return line


def test_a_spawn_inside_the_closed_gate_is_refused(env, tmp_path):
    path = variant(tmp_path, "09_hive", "position = [0.0, 0.0, -20.0, 0.0]", "position = [0.0, 0.0, 16.0, 0.0]")
    refused(env, path, "[spawn]: [0, 0, 16, 0] puts the player inside the solid [[object]] #1 'hive gate'")


def test_a_spawn_inside_a_wall_of_a_world_is_refused_only_at_its_w(env, tmp_path):
    inside = variant(tmp_path, "01_first_steps", "position = [0.0, 0.0, -8.0, 0.0]", "position = [0.0, 0.0, 2.0, 0.0]")
    refused(env, inside, "[spawn]: [0, 0, 2, 0] puts the player inside the wall [[world]] #1 'blue' [[world.box]] #1")
    ana = variant(tmp_path, "01_first_steps", "position = [0.0, 0.0, -8.0, 0.0]", "position = [0.0, 0.0, 2.0, 1.2]")
    assert check_level(env, ana).returncode == 0  # the wall exists only near w = 0


def test_an_enemy_inside_a_wall_is_refused(env, tmp_path):
    path = variant(tmp_path, "09_hive", "position = [0.0, 1.5, -10.0, 1.6]", "position = [4.8, 1.5, -10.0, 1.6]")
    refused(
        env, path, "[[enemy]] #1 'drone': [4.8, 1.5, -10, 1.6] puts the enemy inside the wall [[box]] #3", "open space"
    )


def test_two_objects_with_the_name_a_manipulable_refers_to_are_refused(env, tmp_path):
    path = variant(
        tmp_path,
        "06_bridge",
        "[[manipulable]]",
        '[[object]]\nname = "slab"\nshape = "5-cell"\nposition = [3.0, 1.0, 3.0, 0.0]\nsolid = false\n\n'
        "[[manipulable]]",
    )
    refused(env, path, "[[manipulable]] #1: field 'object': 'slab' names [[object]] #1 and [[object]] #2")


def test_two_objects_with_the_name_an_enemy_opens_are_refused(env, tmp_path):
    path = variant(
        tmp_path,
        "09_hive",
        "# ---- the enemies",
        '[[object]]\nname = "hive gate"\nshape = "5-cell"\nposition = [0.0, 1.0, 30.0, 0.0]\n\n# ---- the enemies',
    )
    refused(env, path, "[[enemy]] #4: field 'opens': 'hive gate' names [[object]] #1 and [[object]] #2")


def test_inside_a_solid_is_exact_not_its_bounding_box():
    level = load_level(LEVELS / "09_hive.toml")
    gate = level.objects[0]
    gate.shape, gate.params, gate.scale = "hypersphere", {"subdivisions": 1}, np.full(4, 2.0)
    gate.rotation_deg = {"xw": 30.0, "yz": 20.0}
    centre = gate.position
    radius = 1.0  # the hypersphere's own, times the scale of 2 ... its vertices are on radius 1 * 2
    for direction in np.eye(4):
        assert _inside_solid(
            gate, centre + 1.8 * radius * direction
        )  # within the radius 2 (its polytope's inradius is ~1.9)
        assert not _inside_solid(gate, centre + 2.1 * radius * direction)
    assert not _inside_solid(gate, centre + 1.9 * np.ones(4))  # a corner of its bounding box


def test_enemies_and_crystals_count_in_the_cost_estimate(env, tmp_path):
    hive = (LEVELS / "09_hive.toml").read_text()
    enemies = "".join(
        f'\n[[enemy]]\nname = "e{i}"\nkind = "morph"\nposition = [{i % 8 - 3.5:.1f}, 1.6, {i // 8 * 2 - 8:.1f}, -1.6]\n'
        for i in range(60)
    )
    path = tmp_path / "crowded.toml"
    path.write_text(hive + enemies)
    level = load_level(path)
    assert level.frame_cost_ms() > limits.FRAME_MS
    assert level.frame_cost_ms() - load_level(LEVELS / "09_hive.toml").frame_cost_ms() == pytest.approx(
        60 * limits.PER_ENEMY_MS
    )
    r = check_level(env, path)
    assert r.returncode == 0, r.stderr  # a warning, not a refusal
    (warning,) = r.stderr.splitlines()
    assert warning.startswith(f"{path}: warning: will likely not keep 60 Hz") and "64 enemies and 2 crystals" in warning
    crystals = "".join(
        f'\n[[crystal]]\nname = "c{i}"\nposition = [{i % 8 - 3.5:.1f}, 1.0, {i // 8 * 0.5 - 18:.2f}, 0.3]\n'
        for i in range(64)
    )
    more = tmp_path / "sparkling.toml"
    more.write_text(hive + crystals)
    assert load_level(more).frame_cost_ms() - load_level(LEVELS / "09_hive.toml").frame_cost_ms() == pytest.approx(
        64 * limits.PER_CRYSTAL_MS
    )


def test_problems_of_placement_reach_the_editor_too(tmp_path):
    path = variant(tmp_path, "09_hive", "position = [0.0, 1.5, -10.0, 1.6]", "position = [4.8, 1.5, -10.0, 1.6]")
    with pytest.raises(LevelError) as info:
        load_level(path)
    assert len(info.value.problems) == 1 and "[[enemy]] #1 'drone'" in info.value.problems[0]
