"""Tests for level files: the shipped levels, the example in levels/README.md,
and broken levels (tests/data/levels/*.toml) with the problems they must report.

``load_level`` must report every problem of a file at once, each naming the
file, the entry, the field and what was expected, and ``check-level`` must
print them one per line with exit status 2 and no traceback. Level files are
data: nothing in them is executed and asset paths stay inside assets/.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder, write_text

from across_dimensions.core.shapes import SHAPES
from across_dimensions.core.transform import PLANES
from across_dimensions.world import resources
from across_dimensions.world.level import Level, LevelError, load_level

REPO = Path(__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parent / "data" / "levels"
README = REPO / "levels" / "README.md"


def base(**kw) -> LevelBuilder:
    """A small valid level (format 1) that tests add entries to."""
    return LevelBuilder("base", format=None, **kw)


# Its text, for the tests about how a specific text is read.
BASE = base().text()

OBJECT = """
[[object]]
name = "thing"
shape = "tesseract"
position = [2.0, 1.0, 3.0, 0.0]
"""


def problems_of(path) -> list[str]:
    """The problems ``load_level`` reports for ``path`` (fails if it loads)."""
    with pytest.raises(LevelError) as info:
        load_level(path)
    err = info.value
    assert Path(err.path) == Path(path)
    assert str(err) == "\n".join(err.problems)
    return err.problems


def check_level(*paths, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", "check-level", *map(str, paths)],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=cwd,
    )


# ------------------------------------------------------------ shipped levels
SHIPPED = resources.level_files()


def test_there_are_shipped_levels():
    assert SHIPPED, f"no level files in {resources.levels_dir()}"
    assert SHIPPED[0].name == "00_arrival.toml"


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_shipped_level_loads(path):
    level = load_level(path)
    assert isinstance(level, Level)
    assert level.name and level.name != path.stem, "shipped levels should have a proper [level] name"
    lo, hi = level.w_range
    assert lo <= level.spawn[3] <= hi
    if level.goal.w_range is not None:
        glo, ghi = level.goal.w_range
        assert glo < ghi and glo <= hi and ghi >= lo, "the goal's w_range must be reachable"


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_shipped_level_builds_and_runs(path):
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game

    game = Game(load_level(path))
    for _ in range(30):
        game.step(Actions())
    assert game.respawns == 0, "the player fell out of the level standing still at the spawn"
    assert game.player.on_ground, "the spawn point should be on a floor"
    assert game.frame().drawables


def test_check_level_accepts_shipped_levels():
    res = check_level(*SHIPPED)
    assert res.returncode == 0, res.stderr
    assert res.stderr == ""
    lines = res.stdout.splitlines()
    assert len(lines) == len(SHIPPED)
    for path, line in zip(SHIPPED, lines):
        assert line.startswith(f"{path}: ok - '")


# ------------------------------------------------------ the README's example
def readme_toml_blocks() -> list[str]:
    return re.findall(r"^```toml\n(.*?)^```", README.read_text(encoding="utf-8"), re.S | re.M)


@pytest.fixture
def example(tmp_path) -> Path:
    """The complete example level from levels/README.md, as a file."""
    blocks = [b for b in readme_toml_blocks() if "[level]" in b and "The Crossing" in b]
    assert len(blocks) == 1, "levels/README.md should have exactly one complete example, The Crossing"
    return write_text(tmp_path, blocks[0], "example.toml")


def test_readme_documents_every_table_field_and_shape():
    text = README.read_text(encoding="utf-8")
    for table in (
        "[level]",
        "[spawn]",
        "[goal]",
        "[physics]",
        "[[box]]",
        "[[mesh]]",
        "[[world]]",
        "[[world.box]]",
        "[[world.mesh]]",
        "[[object]]",
    ):
        assert f"`{table}`" in text, table
    fields = (
        "format name description w_range hints position yaw center size color asset scale "
        "w depth profile shape params rotation spin solid body mass gravity inverse_cube_g rolling_resistance "
        "velocity"
    ).split()
    for f in fields:
        assert f"| `{f}` |" in text, f"field {f} is not in a table of levels/README.md"
    for name in SHAPES:
        assert f"`{name}`" in text, f"shape {name} is not documented"
    for plane in PLANES:
        assert f"`{plane}`" in text
    for cmd in ("across-dimensions check-level levels/my_level.toml", "across-dimensions play levels/my_level.toml"):
        assert cmd in text


def test_readme_example_loads_and_uses_every_table(example):
    level = load_level(example)
    assert level.name == "The Crossing"
    assert level.goal.w_range == (1.2, 2.0)
    assert level.boxes and level.meshes and len(level.worlds) == 2
    assert {w.profile for w in level.worlds} == {"prism", "taper"}
    assert {o.name for o in level.objects} == {"beacon", "ring", "hypercrate"}
    assert any(o.shape and o.params for o in level.objects)
    assert any(o.asset is not None for o in level.objects)
    ring = next(o for o in level.objects if o.name == "ring")
    assert ring.scale.tolist() == [1.0, 1.0, 1.0, 2.0]


def test_readme_snippets_are_valid(tmp_path):
    """The snippets, appended to the minimal base level with a crate (the body the [[beacon]]
    snippet watches), load."""
    snippets = [b for b in readme_toml_blocks() if "[level]" not in b]
    assert snippets
    for i, snippet in enumerate(snippets):
        level = base().object([0.0, 0.55, 2.0, 0.0], name="crate", scale=1.1, body="hypercube")
        load_level(level.write(tmp_path, f"snippet{i}.toml", extra=snippet))


def test_world_mesh_builds(tmp_path):
    """The README's [[world.mesh]] snippet builds: the mesh is baked, placed and shrinks with the profile."""
    from across_dimensions.game.sim import Game

    snippet = next(b for b in readme_toml_blocks() if "[[world.mesh]]" in b)
    game = Game(load_level(base().write(tmp_path, extra=snippet)))
    (world,) = game.scene.worlds
    assert world.scale_at(-0.3) == pytest.approx(1.0)
    lo, hi = world.boxes_at(-0.3)[0]
    assert np.isfinite(lo).all() and np.isfinite(hi).all()
    # tree.obj is 1.8 x 3.4 x 1.77 m standing on y = 0; scaled 0.8 at (-2, 0, 8).
    assert lo[1] == pytest.approx(0.0, abs=0.05) and hi[1] == pytest.approx(3.4 * 0.8, rel=0.05)
    assert (lo[0] + hi[0]) / 2 == pytest.approx(-2.0, abs=0.2) and (lo[2] + hi[2]) / 2 == pytest.approx(8.0, abs=0.2)
    assert world.scale_at(-0.1) < 1.0 and np.isnan(world.boxes_at(0.1)).all()  # round profile, gone past w = 0


def test_readme_example_passes_check_level(example):
    res = check_level(example)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == (f"{example}: ok - 'The Crossing', 6 boxes, 2 worlds, 3 4D objects, w in [-0.5, 2.0]")
    # The README shows this very line.
    assert "ok - 'The Crossing', 6 boxes, 2 worlds, 3 4D objects, w in [-0.5, 2.0]" in README.read_text()


def test_readme_error_sample_is_real(example, tmp_path):
    """The check-level output shown in the README is what the command prints for
    the example with the three mistakes it describes."""
    text = example.read_text(encoding="utf-8")
    edits = [
        ("position = [0.0, 0.0, -8.0, 0.0]", "position = [0.0, 0.0, -8.0, 3.0]"),
        ("[[box]]   # left wall\ncenter", "[[box]]   # left wall\ncentre"),
        ("  size = [0.8, 0.8, 0.8]\n", "  size = [1.0, -2.0, 1.0]\n"),
    ]
    for old, new in edits:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    (tmp_path / "levels").mkdir()
    (tmp_path / "levels" / "my_level.toml").write_text(text, encoding="utf-8")
    res = check_level("levels/my_level.toml", cwd=tmp_path)
    assert res.returncode == 2
    sample = re.search(r"^```\n(levels/my_level.toml: \d+ problem\(s\)\n.*?)^```", README.read_text(), re.S | re.M)
    assert sample, "the README's check-level error sample is missing"
    assert res.stderr == sample.group(1)


def test_readme_example_can_be_played_to_the_exit(example):
    """The walk-through the README describes: red wall, ana, green wall, ana, exit."""
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.player import overlapping, player_box
    from across_dimensions.game.sim import Game

    game = Game(load_level(example))

    def run(ticks, **kw):
        for _ in range(ticks):
            game.step(Actions(**kw))

    run(30)
    assert game.player.on_ground and game.player.position[1] == pytest.approx(0.0, abs=1e-3)
    run(150, forward=1.0)  # up against the red wall at z = 0
    assert -1.0 < game.player.position[2] < -0.3
    assert not overlapping(*player_box(game.player.position), game.colliders_at(0.0)).any()  # touching, not inside
    assert game.outcome is None
    run(40, w=1.0)  # ana until the red wall has gone
    assert 0.5 < game.player.position[3] < 0.8
    run(150, forward=1.0)  # past the green wall at z = 6 (absent for w < 0.8)
    assert game.player.position[2] > 7.0
    assert game.outcome is None, "the goal is only open for w >= 1.2"
    run(60, w=1.0)
    assert game.player.position[3] >= 1.2
    run(150, forward=1.0)
    assert game.outcome == "complete"
    assert game.respawns == 0
    # At the goal's w: static (the open part of the scenery, drawn both sides, apart), floor, the
    # 2 worlds, and the objects that reach this slice.
    w = game.player.position[3]
    reaching = [e for e in game.entities if abs(e.center(game)[3] - w) <= e.radius]
    frame = game.frame()
    solid = [d.key for d in frame.drawables if d.style != "ghost"]  # ghosts: tests/test_ghosts.py
    solid += [k for b in frame.batches if b.style != "ghost" for k in b.members]  # entities, sliced together
    scenery = 2 + (not game.scene.open_mesh.is_empty)
    assert len(solid) == scenery + 2 + len(reaching) and reaching


def test_readme_example_green_wall_blocks_at_its_w(example):
    """At w = 1.6 the green (taper) wall is full size and the player cannot pass."""
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game

    game = Game(load_level(example))
    world = next(w for w in game.scene.worlds if w.name == "green")
    assert world.scale_at(1.6) == pytest.approx(1.0)
    assert world.scale_at(0.8) == pytest.approx(0.0, abs=1e-9) and world.scale_at(2.4) == pytest.approx(0.0, abs=1e-9)
    assert world.scale_at(0.7) == 0.0 and world.scale_at(2.5) == 0.0
    assert 0.0 < world.scale_at(1.2) < 1.0
    game.player.position[:] = [0.0, 0.0, 3.0, 1.6]
    for _ in range(200):
        game.step(Actions(forward=1.0))
    assert game.player.position[2] < 6.0


# ------------------------------------------------------------ broken levels
# fixture file -> the problems it must report, in order; each problem is given
# as fragments that must all appear in its message (besides the file's path).
SHAPE_LIST = ", ".join(SHAPES)
PLANE_LIST = ", ".join(PLANES)
CASES = {
    "syntax_error": [["not valid TOML", "at line 17"]],
    "wrong_type": [["[[box]] #2", "field 'size'", "expected a list of 3 numbers", "'big'"]],
    "negative_size": [["[[box]] #2", "field 'size'", "expected 3 positive numbers", "[1.0, -2.0, 1.0]"]],
    "wrong_vector_length": [
        ["[goal]", "field 'center'", "expected a list of 3 numbers", "[0.0, 1.0]"],
        ["[[object]] #1 'cube'", "field 'position'", "expected a list of 4 numbers ['x', 'y', 'z', 'w']"],
    ],
    "unknown_field": [
        ["[[box]] #2", "unknown field 'centre'", "expected one of: center, color, size"],
        ["[[box]] #2", "missing field 'center'"],
    ],
    "unknown_shape": [["[[object]] #1 'cube'", "field 'shape'", f"expected one of {SHAPE_LIST}", "'hypercube'"]],
    "bad_shape_params": [["[[object]] #1 'cube'", "field 'params'", "'radius'", "shape 'tesseract' accepts: size"]],
    "unknown_rotation_plane": [
        ["[[object]] #1 'cube'", "field 'rotation'", "unknown rotation plane 'xq'", PLANE_LIST],
        ["[[object]] #1 'cube'", "field 'spin'", "unknown rotation plane 'wx'", PLANE_LIST],
    ],
    "color_out_of_range": [["[[box]] #2", "field 'color'", "between 0 and 1", "[255, 128, 0]"]],
    "spawn_outside_w_range": [["[spawn]", "field 'position'", "w = 3 is outside", "w_range [-1.0, 1.0]"]],
    "w_range_reversed": [["[level]", "field 'w_range'", "low <= high", "[1.0, -1.0]"]],
    "asset_escapes": [["[[mesh]] #1", "field 'asset'", "inside the assets folder", "'../../etc/passwd'", "leaves it"]],
    "asset_absolute": [
        ["[[mesh]] #1", "field 'asset'", "inside the assets folder", "absolute path '/etc/passwd'"],
        ["[[object]] #1 'win'", "field 'asset'", "inside the assets folder", "absolute path", "win.ini"],
    ],
    "asset_missing": [["[[mesh]] #1", "field 'asset'", "no asset 'meshes/no_such_mesh.obj'"]],
    "shape_and_asset": [["[[object]] #1 'confused'", "exactly one of 'shape'", "or 'asset'"]],
    "several_problems": [
        ["[level]", "field 'format'", "reads formats 1 and 2", "says 3"],
        ["[spawn]", "field 'yaw'", "expected a number", "'north'"],
        ["[goal]", "field 'size'", "positive"],
        ["[physics]", "field 'gravity'", "expected a list of 4 numbers"],
        ["[[box]] #1", "unknown field 'colour'"],
        ["[[world]] #1 'blue'", "field 'depth'", "> 0"],
        ["[[world]] #1 'blue'", "field 'profile'", "prism, round, taper", "'square'"],
        ["[[object]] #1 'beacon'", "field 'mass'", "> 0"],
    ],
}


def test_every_fixture_has_a_case():
    files = {p.stem for p in DATA.glob("*.toml")}
    assert files == set(CASES) | {"missing_spawn", "code_is_data"}


@pytest.mark.parametrize("name", sorted(CASES))
def test_broken_level_reports_its_problems(name):
    path = DATA / f"{name}.toml"
    problems = problems_of(path)
    expected = CASES[name]
    assert len(problems) == len(expected), "\n".join(problems)
    for msg, fragments in zip(problems, expected):
        assert msg.startswith(f"{path}: "), msg
        for frag in fragments:
            assert frag in msg, f"{frag!r} not in {msg!r}"
        assert "\n" not in msg


def test_missing_spawn_is_reported():
    path = DATA / "missing_spawn.toml"
    problems = problems_of(path)
    assert f"{path}: [spawn]: missing table [spawn]" in problems


def test_several_problems_are_reported_at_once():
    problems = problems_of(DATA / "several_problems.toml")
    assert len(problems) == 8
    assert len(set(problems)) == 8


def test_every_problem_names_the_file(tmp_path):
    """Even when the file is somewhere else, under another name."""
    src = (DATA / "several_problems.toml").read_text(encoding="utf-8")
    path = write_text(tmp_path, src, "elsewhere.toml")
    assert all(p.startswith(f"{path}: ") for p in problems_of(path))


def test_unknown_shape_lists_every_known_shape():
    (msg,) = problems_of(DATA / "unknown_shape.toml")
    for name in SHAPES:
        assert name in msg


def test_syntax_error_names_file_and_line():
    path = DATA / "syntax_error.toml"
    (msg,) = problems_of(path)
    assert str(path) in msg
    assert re.search(r"\bline 17\b", msg)


def test_missing_table_entries(tmp_path):
    problems = problems_of(write_text(tmp_path, "# nothing here\n"))
    assert any("missing table [level]" in p for p in problems)
    assert any("missing table [spawn]" in p for p in problems)
    assert any("missing table [goal]" in p for p in problems)


@pytest.mark.parametrize(
    "extra, fragments",
    [
        (
            "[[world]]\nname = 'w'\nw = 0.0\ndepth = 1.0\n",
            ["[[world]] #1 'w'", "has no [[world.box]] or [[world.mesh]]"],
        ),
        (
            "[[world]]\nname = 'w'\nw = 0.0\ndepth = 1.0\nprofile = 'cube'\n[[world.box]]\ncenter = [0, 0, 0]\n"
            "size = [1, 1, 1]\n",
            ["[[world]] #1 'w'", "field 'profile'", "expected one of prism, round, taper"],
        ),
        (
            "[[world]]\nname = 'w'\nw = 0.0\ndepth = 1.0\n[[world.box]]\ncenter = [0, 0, 0]\nsize = [1, 1]\n",
            ["[[world]] #1 'w' > box #1", "field 'size'", "3 numbers"],
        ),
        (
            "[[world]]\nname = 'w'\ndepth = 1.0\n[[world.box]]\ncenter = [0, 0, 0]\nsize = [1, 1, 1]\n",
            ["[[world]] #1 'w'", "missing field 'w'"],
        ),
        (OBJECT.replace("position", "scale = [1.0, 1.0, 0.0, 1.0]\nposition"), ["field 'scale'", "positive"]),
        (OBJECT.replace("position", "solid = 'yes'\nposition"), ["field 'solid'", "true or false", "'yes'"]),
        (OBJECT.replace("position", "body = 'sphere'\nposition"), ["field 'body'", "none, hypersphere, hypercube"]),
        (OBJECT.replace("position", "rotation = { xy = 'ten' }\nposition"), ["field 'rotation.xy'", "degrees"]),
        (OBJECT.replace("position", "spin = 30\nposition"), ["field 'spin'", "table of plane = degrees"]),
        (OBJECT.replace("position", "params = [1, 2]\nposition"), ["field 'params'", "table of shape parameters"]),
        ("[physics]\ninverse_cube_g = -1\n", ["[physics]", "field 'inverse_cube_g'", ">= 0"]),
        ("[[box]]\ncenter = [nan, 0, 0]\nsize = [1, 1, 1]\n", ["[[box]] #2", "field 'center'", "numbers", "nan"]),
        ("[[box]]\ncenter = [0, 0, 0]\nsize = [1, inf, 1]\n", ["[[box]] #2", "field 'size'", "numbers", "inf"]),
        ("[[box]]\ncenter = [true, 0, 0]\nsize = [1, 1, 1]\n", ["[[box]] #2", "field 'center'", "numbers"]),
        ("[[mesh]]\nasset = 7\n", ["[[mesh]] #1", "field 'asset'", "expected a string"]),
        ("[[mesh]]\nasset = 'meshes/crate.obj'\nyaw = 'left'\n", ["[[mesh]] #1", "field 'yaw'", "a number"]),
        ("[[mesh]]\nasset = 'meshes/../../README.md'\n", ["[[mesh]] #1", "leaves it"]),
        ("[[mesh]]\nasset = 'meshes'\n", ["[[mesh]] #1", "no asset 'meshes'"]),
        ("[bonus]\nx = 1\n", ["top level", "unknown field 'bonus'"]),
        ("box = 3\n", ["top level", "'box' must be an array of tables ([[box]])"]),
    ],
    ids=[
        "world_empty",
        "world_profile",
        "world_box_size",
        "world_no_w",
        "object_scale",
        "object_solid",
        "object_body",
        "rotation_degrees",
        "spin_table",
        "params_table",
        "inverse_cube_g",
        "nan",
        "inf",
        "bool",
        "asset_type",
        "mesh_yaw",
        "asset_dotdot_inside",
        "asset_directory",
        "unknown_table",
        "box_not_array",
    ],
)
def test_more_single_problems(tmp_path, extra, fragments):
    if extra.startswith("box = "):  # a top-level key must come before the first table
        path = write_text(tmp_path, extra + base(floor=None).text())
    else:
        path = base().write(tmp_path, extra=extra)
    problems = problems_of(path)
    assert len(problems) == 1, problems
    for frag in fragments:
        assert frag in problems[0], f"{frag!r} not in {problems[0]!r}"


def test_hints_and_format_types(tmp_path):
    problems = problems_of(base().level(format="1", hints="just one").write(tmp_path))
    assert len(problems) == 2
    assert "field 'format': expected a number" in problems[0]
    assert "field 'hints': expected a list of strings" in problems[1]


# --------------------------------------------------------- unreadable files
def test_non_utf8_file_gives_one_clear_message(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(BASE.replace('"base"', '"caf\u00e9"').encode("latin-1"))
    assert problems_of(path) == [f"{path}: not a text file (expected UTF-8 TOML)"]


def test_binary_file_gives_one_clear_message(tmp_path):
    path = tmp_path / "image.toml"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe")
    assert problems_of(path) == [f"{path}: not a text file (expected UTF-8 TOML)"]


def test_missing_file_gives_one_clear_message(tmp_path):
    path = tmp_path / "no_such_level.toml"
    (msg,) = problems_of(path)  # the shared bounded reader's wording (core.fileio)
    assert msg == f"{path}: no such file (expected a level)"


def test_directory_gives_one_clear_message(tmp_path):
    (msg,) = problems_of(tmp_path)
    assert msg.startswith(f"{tmp_path}: is a folder")


# ---------------------------------------------------------- levels are data
def test_python_in_strings_is_just_text(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    level = load_level(DATA / "code_is_data.toml")
    assert level.name == "__import__('os').system('touch MARKER')"
    assert level.description.startswith("eval(")
    assert level.hints[0].text == "__import__('os').system('touch MARKER')"
    assert level.worlds[0].name == "os.system('touch MARKER')"
    assert list(tmp_path.iterdir()) == []  # nothing ran: no MARKER file


def test_python_in_numbers_is_not_evaluated(tmp_path):
    (msg,) = problems_of(base().table("goal", size="[1.0, 2.0, 0.5 + 0.5]").write(tmp_path))
    assert "[goal]: field 'size': expected a list of 3 numbers" in msg


def test_python_in_params_is_not_evaluated(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    extra = OBJECT.replace(
        "position", "params = { \"__class__\" = \"__import__('os').system('touch MARKER')\" }\nposition"
    )
    (msg,) = problems_of(base().write(tmp_path, extra=extra))
    assert "field 'params'" in msg and "'__class__'" in msg
    assert sorted(p.name for p in tmp_path.iterdir()) == ["level.toml"]


def test_asset_paths_stay_inside_assets(tmp_path):
    root = resources.assets_dir().resolve()
    ok = resources.resolve_asset("meshes/crate.obj")
    assert ok.is_relative_to(root) and ok.is_file()
    for bad in (
        "../../etc/passwd",
        "/etc/passwd",
        "meshes/../../pyproject.toml",
        "C:/Windows/win.ini",
        "C:\\Windows\\win.ini",
        "\\\\server\\share\\x.obj",
        "",
    ):
        with pytest.raises(ValueError, match="inside the assets folder"):
            resources.resolve_asset(bad)


def test_asset_symlink_out_of_assets_is_refused(tmp_path):
    """A link inside assets/ that points outside is caught after resolving it."""
    root = resources.assets_dir()
    link = root / f"_test_link_{tmp_path.name}.obj"
    target = tmp_path / "outside.obj"
    target.write_text("v 0 0 0\n")
    try:
        link.symlink_to(target)
    except OSError as e:
        pytest.skip(f"cannot make a symlink here: {e}")
    try:
        with pytest.raises(ValueError, match="leaves it"):
            resources.resolve_asset(link.name)
    finally:
        link.unlink()


# -------------------------------------------------------------- check-level
def test_check_level_ok_line():
    good = REPO / "levels" / "01_first_steps.toml"
    res = check_level(good)
    assert res.returncode == 0
    assert res.stderr == ""
    assert res.stdout.startswith(f"{good}: ok - 'First Steps', ")
    assert res.stdout.count("\n") == 1


@pytest.mark.parametrize("name", ["several_problems", "syntax_error", "asset_absolute", "unknown_shape"])
def test_check_level_prints_one_line_per_problem(name):
    path = DATA / f"{name}.toml"
    want = problems_of(path)
    res = check_level(path)
    assert res.returncode == 2
    assert "Traceback" not in res.stderr
    assert res.stdout == ""
    lines = res.stderr.splitlines()
    assert lines[0] == f"{path}: {len(want)} problem(s)"
    assert lines[1:] == [f"  {p}" for p in want]


def test_check_level_several_files(tmp_path):
    good = REPO / "levels" / "01_first_steps.toml"
    bad1, bad2 = DATA / "wrong_type.toml", DATA / "several_problems.toml"
    res = check_level(bad1, good, bad2)
    assert res.returncode == 2
    assert "Traceback" not in res.stderr
    assert res.stdout.startswith(f"{good}: ok")
    lines = res.stderr.splitlines()
    assert lines[0] == f"{bad1}: 1 problem(s)"
    assert lines[2] == f"{bad2}: 8 problem(s)"
    assert len(lines) == 1 + 1 + 1 + 8


def test_check_level_unreadable_files(tmp_path):
    latin1 = tmp_path / "latin1.toml"
    latin1.write_bytes("[level]\nname = 'caf\u00e9'\n".encode("latin-1"))
    missing = tmp_path / "missing.toml"
    res = check_level(latin1, missing)
    assert res.returncode == 2
    assert "Traceback" not in res.stderr
    assert res.stderr.splitlines() == [
        f"{latin1}: 1 problem(s)",
        f"  {latin1}: not a text file (expected UTF-8 TOML)",
        f"{missing}: 1 problem(s)",
        f"  {missing}: no such file (expected a level)",
    ]


def test_check_level_relative_path_is_echoed(tmp_path):
    base().box([0, 0, 0], [0, 1, 1]).write(tmp_path, "mine.toml")
    res = check_level("mine.toml", cwd=tmp_path)
    assert res.returncode == 2
    assert res.stderr.splitlines()[:2] == [
        "mine.toml: 1 problem(s)",
        "  mine.toml: [[box]] #2: field 'size': expected 3 positive numbers, got [0, 1, 1]",
    ]


# ============================================================== known bugs
# Each test below fails today. The reasons describe the bug; the suggested
# fixes are in the report that introduced these tests.

HUGE = "9" * 400  # a TOML integer far beyond float range (tomllib accepts any size)
HUGER = "9" * 5000  # beyond Python's int-string limit: tomllib raises a bare ValueError


@pytest.mark.parametrize(
    "extra",
    [
        f"[[box]]\ncenter = [{HUGE}, 0, 0]\nsize = [1, 1, 1]\n",
        OBJECT.replace("position", f"mass = {HUGE}\nposition"),
        OBJECT.replace("position", f"scale = {HUGE}\nposition"),
        OBJECT.replace("position", f"rotation = {{ xy = {HUGE} }}\nposition"),
        OBJECT.replace("position", f"mass = {HUGER}\nposition"),
    ],
    ids=["vector", "number", "scale", "angles", "5000_digits"],
)
def test_huge_integer_is_a_problem_not_a_crash(tmp_path, extra):
    problems = problems_of(base().write(tmp_path, extra=extra))
    assert len(problems) == 1


@pytest.mark.parametrize("digits", [HUGE, HUGER], ids=["400_digits", "5000_digits"])
def test_check_level_huge_integer(tmp_path, digits):
    path = base().write(tmp_path, extra=OBJECT.replace("position", f"mass = {digits}\nposition"))
    good = REPO / "levels" / "01_first_steps.toml"
    res = check_level(path, good)
    assert res.returncode == 2 and "internal error" not in res.stderr
    assert res.stderr.splitlines()[0] == f"{path}: 1 problem(s)"
    assert res.stdout.startswith(f"{good}: ok")


@pytest.mark.parametrize(
    "shape, params",
    [
        ("tesseract", "{ size = -1.0 }"),
        ("5-cell", '{ radius = "big" }'),
        ("duoprism", "{ p = 2 }"),
        ("hypersphere", "{ subdivisions = 1.5 }"),
        ("hypersphere", "{ subdivisions = 9 }"),  # 600 * 8**9 tets: would exhaust memory
        ("tesseract", '{ color = "red" }'),
    ],
)
def test_bad_shape_param_values(tmp_path, shape, params):
    extra = OBJECT.replace('"tesseract"', f'"{shape}"').replace("position", f"params = {params}\nposition")
    (msg,) = problems_of(base().write(tmp_path, extra=extra))
    assert "[[object]] #1 'thing': field 'params'" in msg


def test_unknown_shape_with_params_reports_one_problem(tmp_path):
    extra = OBJECT.replace('"tesseract"', '"hypercube"').replace("position", "params = { size = 2.0 }\nposition")
    problems = problems_of(base().write(tmp_path, extra=extra))
    assert len(problems) == 1, problems
    assert "5-cell" not in problems[0].split("expected one of")[0]


@pytest.mark.parametrize(
    "extra",
    [
        '[[mesh]]\nasset = ""\n',
        '[[object]]\nname = "blank"\nasset = ""\nposition = [0.0, 1.0, 3.0, 0.0]\n',
    ],
    ids=["mesh", "object"],
)
def test_empty_asset_path(tmp_path, extra):
    (msg,) = problems_of(base().write(tmp_path, extra=extra))
    assert "field 'asset'" in msg


@pytest.mark.parametrize("asset", ["README.md", "meshes/make_assets.py"])
def test_asset_must_be_a_mesh_format(tmp_path, asset):
    (msg,) = problems_of(base().mesh(asset).write(tmp_path))
    assert "field 'asset'" in msg and ".obj" in msg


def test_nul_in_asset_path(tmp_path):
    (msg,) = problems_of(base().mesh("meshes/crate\u0000.obj").write(tmp_path))
    assert "inside the assets folder" in msg


@pytest.mark.parametrize(
    "level",
    [
        base(w_range=(1.0,)),  # + "got [0.0, 0.0]"
        base(w_range=(0.5, 1.0), spawn=(0.0, 0.0, 0.0)),  # + "w = 0 is outside"
        base().without("spawn"),  # + "missing field 'position'"
        base().world(0.0, 1.0, name="m", meshes=[{"asset": "../x.obj"}]),
    ],
    ids=["w_range_short", "spawn_short", "missing_spawn", "world_only_bad_mesh"],
)
def test_one_mistake_one_problem(tmp_path, level):
    problems = problems_of(level.write(tmp_path))
    assert len(problems) == 1, problems


@pytest.mark.parametrize("goal_w", [(1.0, -1.0), (5.0, 6.0)], ids=["reversed", "outside_level"])
def test_goal_w_range_checked(tmp_path, goal_w):
    (msg,) = problems_of(base(goal_w=goal_w).write(tmp_path))
    assert "[goal]: field 'w_range'" in msg


@pytest.mark.parametrize("hint", ["Press { to open", "Use {} here", "a } b", "{w_ana.upper}"])
def test_hint_braces_are_checked(tmp_path, hint):
    (msg,) = problems_of(base().level(hints=[hint]).write(tmp_path))
    assert "field 'hints'" in msg


def test_utf8_bom_is_accepted(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + BASE.encode("utf-8"))
    assert load_level(path).name == "base"
