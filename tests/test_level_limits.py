"""Levels are bounded and finite (issue 7, points 4 and 5).

A level may ask for only so much (world/limits.py: counts, tetrahedra, file
size), every number has a range, and whatever check-level accepts plays with
finite numbers. Each refusal is one line naming the file, the entry, the field
and the limit or range.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder, write_text

from across_dimensions.core import shapes
from across_dimensions.world import limits, resources
from across_dimensions.world.level import LevelError, load_level

REPO = Path(__file__).resolve().parents[1]
README = REPO / "levels" / "README.md"


def base(**kw) -> LevelBuilder:
    """A small valid level (format 1) that tests add entries to."""
    return LevelBuilder("base", format=None, **kw)


# Its text, for the tests about how a specific text is read.
BASE = base().text()


def problems_of(path) -> list[str]:
    with pytest.raises(LevelError) as info:
        load_level(path)
    return info.value.problems


def check_level(*paths) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", "check-level", *map(str, paths)],
        capture_output=True,
        text=True,
        timeout=120,
    )


def obj(shape="tesseract", position="[2.0, 1.0, 3.0, 0.0]", **fields) -> str:
    lines = ["[[object]]", f'shape = "{shape}"', f"position = {position}"]
    lines += [f"{k} = {v}" for k, v in fields.items()]
    return "\n" + "\n".join(lines) + "\n"


# ------------------------------------------------------------ tetrahedra
@pytest.mark.parametrize(
    "shape, params",
    [
        ("5-cell", {}),
        ("tesseract", {}),
        ("16-cell", {}),
        ("24-cell", {}),
        ("120-cell", {}),
        ("600-cell", {}),
        ("hypersphere", {"subdivisions": 0}),
        ("hypersphere", {}),
        ("hypersphere", {"subdivisions": 2}),
        ("spherinder", {"subdivisions": 0}),
        ("spherinder", {}),
        ("spherinder", {"subdivisions": 3}),
        ("duoprism", {}),
        ("duoprism", {"p": 3, "q": 3}),
        ("duoprism", {"p": 5, "q": 17}),
        ("duocylinder", {"segments": 3}),
        ("duocylinder", {}),
        ("cubinder", {"segments": 3}),
        ("cubinder", {}),
        ("cubinder", {"segments": 64}),
    ],
)
def test_tet_estimate_is_exact_for_shapes(shape, params):
    assert limits.shape_tets(shape, params) == len(shapes.make_shape(shape, **params).tets)


@pytest.mark.parametrize(
    "shape, fine, coarse",
    [
        ("duoprism", {"p": 128, "q": 128}, {"p": 3, "q": 128}),
        ("cubinder", {"segments": 128}, {"segments": 3}),
        ("spherinder", {"subdivisions": 3}, {"subdivisions": 0}),
    ],
)
def test_accepted_shape_proportions_build(tmp_path, shape, fine, coarse):
    """The most different lengths a level accepts still build, at both ends of the size range."""
    a, b = limits.SHAPE_LENGTH_PAIRS[shape]
    k = limits.MAX_SHAPE_ASPECT
    lo, hi = shapes.SHAPE_PARAM_RULES[a][1]  # the lengths a shape (and so a level) accepts
    for params in (fine, coarse):
        for big, small in ((lo * k, lo), (hi, hi / k)):
            for x, y in ((big, small), (small, big)):
                p = {**params, a: x, b: y}
                assert limits.shape_aspect_problem(shape, p) is None
                assert len(shapes.make_shape(shape, **p).tets) == limits.shape_tets(shape, p)
    assert limits.shape_aspect_problem(shape, {a: 1.0, b: 1.0 / k / 1.01})


def test_every_shape_has_an_estimate():
    for name in shapes.SHAPES:
        assert limits.shape_tets(name, {}) > 0


def test_world_box_estimate_matches_the_built_world(tmp_path):
    from across_dimensions.world.scene import build_scene

    boxes = [{"center": [float(i), 1.0, 2.0], "size": [0.5, 2.0, 0.5]} for i in range(3)]
    level = base().world(0.0, 1.0, name="w", boxes=boxes).load(tmp_path)
    (world,) = build_scene(level).worlds
    assert len(world.mesh.tets) == 3 * limits.WORLD_BOX_TETS == level.tets


# ------------------------------------------------------------ counts
@pytest.mark.parametrize(
    "kind, entry, text",
    [
        ("box", "[[box]] #1001", "".join("[[box]]\ncenter = [0, 0, 0]\nsize = [1, 1, 1]\n" for _ in range(1004))),
        (
            "box",
            "[[world]] #1 'w' > box #1000",  # the level's own box is #1 of the 1000
            "[[world]]\nname = 'w'\nw = 0.0\ndepth = 1.0\n"
            + "".join("[[world.box]]\ncenter = [0, 0, 0]\nsize = [1, 1, 1]\n" for _ in range(1000)),
        ),
        ("mesh", "[[mesh]] #65", "".join("[[mesh]]\nasset = 'meshes/crate.obj'\n" for _ in range(70))),
        (
            "world",
            "[[world]] #33",
            "".join(
                "[[world]]\nw = 0.0\ndepth = 1.0\n[[world.box]]\ncenter = [0, 0, 0]\nsize = [1, 1, 1]\n"
                for _ in range(33)
            ),
        ),
        ("object", "[[object]] #257", "".join(obj() for _ in range(300))),
        ("body", "[[object]] #201", "".join(obj(body='"hypercube"') for _ in range(201))),
    ],
    ids=["box", "world_box", "mesh", "world", "object", "body"],
)
def test_count_limits(tmp_path, kind, entry, text):
    limit, what = limits.MAX_COUNTS[kind]
    problems = problems_of(base().write(tmp_path, extra=text))
    assert len(problems) == 1, problems[:3]
    (msg,) = problems
    assert msg.startswith(f"{tmp_path / 'level.toml'}: {entry}")
    assert f"at most {limit} {what}" in msg


def test_limit_is_reported_once(tmp_path):
    """Past the limit in [[box]], the worlds' boxes are not read either, and not reported again."""
    boxes = "".join("[[box]]\ncenter = [0, 0, 0]\nsize = [1, 1, 1]\n" for _ in range(1000))
    world = "[[world]]\nw = 0.0\ndepth = 1.0\n[[world.box]]\ncenter = [0, 0, 0]\nsize = [1, 1, 1]\n"
    problems = problems_of(base().write(tmp_path, extra=boxes + world + world))
    assert len(problems) == 1 and "[[box]] #1001" in problems[0], problems


def test_entries_past_the_limit_are_not_read(tmp_path):
    """A broken box after the limit is not reported: reading stops there."""
    boxes = "".join("[[box]]\ncenter = [0, 0, 0]\nsize = [1, 1, 1]\n" for _ in range(1100))
    bad = "[[box]]\ncenter = 'far away'\nsize = [1, 1, 1]\n"
    problems = problems_of(base().write(tmp_path, extra=boxes + bad))
    assert len(problems) == 1 and "[[box]] #1001" in problems[0]


def test_hint_limits(tmp_path):
    (msg,) = problems_of(base().level(hints=["hi"] * 21).write(tmp_path))
    assert "[level]: field 'hints'" in msg and "at most 20 hints" in msg
    (msg,) = problems_of(base().level(hints=["x" * 1001]).write(tmp_path))
    assert "hint #1" in msg and "at most 1000 characters" in msg
    (msg,) = problems_of(base().level(name="n" * 101).write(tmp_path))
    assert "[level]: field 'name'" in msg and "at most 100 characters" in msg


def test_tets_per_level_limit(tmp_path):
    # Six 128 x 128 duoprisms of 98,304 tetrahedra: the fifth crosses 400,000.
    level = base()
    for _ in range(6):
        level.object([2.0, 1.0, 3.0, 0.0], "duoprism", params={"p": 128, "q": 128}, solid=False)
    (msg,) = problems_of(level.write(tmp_path))
    assert "[[object]] #5 'object5'" in msg and "483,840 tetrahedra" in msg and "at most 400,000" in msg


def test_tets_per_object_limit(tmp_path, monkeypatch):
    monkeypatch.setattr(limits, "MAX_OBJECT_TETS", 100_000)
    (msg,) = problems_of(base().object([2.0, 1.0, 3.0, 0.0], "hypersphere", params={"subdivisions": 3}).write(tmp_path))
    assert "[[object]] #1 'object1': field 'params'" in msg and "307,200 tetrahedra" in msg
    assert "at most 100,000" in msg


def test_file_size_limit(tmp_path):
    """A million boxes: refused by size before parsing, quickly, in one line."""
    box = "[[box]]\ncenter = [0.0, -0.5, 0.0]\nsize = [10.0, 1.0, 12.0]\n"
    path = tmp_path / "huge.toml"
    with open(path, "w", encoding="utf-8") as f:
        f.write(BASE)
        for _ in range(1000):
            f.write(box * 1000)
    good = REPO / "levels" / "01_first_steps.toml"
    res = check_level(path, good)
    assert res.returncode == 2
    size = f"{path.stat().st_size / 2**20:.3g} MiB"
    assert res.stderr.splitlines() == [
        f"{path}: 1 problem(s)",
        f"  {path}: {size} is larger than the 524288 bytes a level may be",
    ]
    assert res.stdout.startswith(f"{good}: ok")


def test_nested_too_deeply_is_one_line(tmp_path):
    (msg,) = problems_of(write_text(tmp_path, "x = " + "[" * 5000 + "]" * 5000 + "\n"))
    assert "not valid TOML" in msg


# ------------------------------------------------------------ frame-time warning
def test_check_level_warns_about_a_heavy_level(tmp_path):
    heavy = base()
    for i in range(100):
        heavy.object([i % 20 - 10.0, 1.5, i // 20 * 1.0, 0.0], "120-cell", scale=0.4, solid=False)
    path = heavy.write(tmp_path)
    level = load_level(path)
    assert level.tets == 100 * 3240
    assert level.frame_cost_ms() > limits.FRAME_MS
    res = check_level(path)
    assert res.returncode == 0, res.stderr
    assert res.stdout.startswith(f"{path}: ok - ")
    (warning,) = res.stderr.splitlines()
    assert warning.startswith(f"{path}: warning: will likely not keep 60 Hz")
    assert "324,000 tetrahedra" in warning and "100 4D objects" in warning


def test_shipped_levels_are_cheap():
    for path in resources.level_files():
        assert load_level(path).frame_cost_ms() < 0.5 * limits.FRAME_MS, path


# ------------------------------------------------------------ ranges (issue 7.5)
WORLD = (
    "\n[[world]]\nname = 'wd'\nw = {w}\ndepth = {depth}\n[[world.box]]\ncenter = [0.0, 2.0, 2.0]\nsize = [1, 1, 1]\n"
)
EXTREMES = {
    # The values issue 7.5 reports, then one per other numeric field.
    "object_scale": (obj(scale="1e300"), "[[object]] #1 'object1'", "field 'scale'", "0.001 to 10000"),
    "box_center": (
        "[[box]]\ncenter = [1e308, 0, 0]\nsize = [1, 1, 1]\n",
        "[[box]] #2",
        "field 'center'",
        "-10000 to 10000 m",
    ),
    "world_depth": (WORLD.format(w=0.0, depth="5e-324"), "[[world]] #1 'wd'", "field 'depth'", "0.001 to 10000 m"),
    "world_w": (WORLD.format(w="1e308", depth=1.0), "[[world]] #1 'wd'", "field 'w'", "-10000 to 10000 m"),
    "gravity": (
        "[physics]\ngravity = [0.0, -1e300, 0.0, 0.0]\n",
        "[physics]",
        "field 'gravity'",
        "length of at most 100",
    ),
    "gravity_down_1e5": (
        "[physics]\ngravity = [0.0, -1e5, 0.0, 0.0]\n",
        "[physics]",
        "field 'gravity'",
        "length of at most 100",
    ),
    "gravity_sideways": (
        "[physics]\ngravity = [80.0, 0.0, 0.0, 80.0]\n",
        "[physics]",
        "field 'gravity'",
        "length 113.1",
    ),
    "inverse_cube_g": ("[physics]\ninverse_cube_g = 1e300\n", "[physics]", "field 'inverse_cube_g'", "0 to 10"),
    "rolling_resistance": (
        "[physics]\nrolling_resistance = 2.0\n",
        "[physics]",
        "field 'rolling_resistance'",
        "0 to 1",
    ),
    "velocity": (
        obj(body='"hypersphere"', velocity="[1e300, 0.0, 0.0, 0.0]"),
        "[[object]] #1 'object1'",
        "field 'velocity'",
        "-50 to 50 m/s",
    ),
    "spin": (obj(spin="{ xw = 1e300 }"), "[[object]] #1 'object1'", "field 'spin.xw'", "-720 to 720 degrees/s"),
    "body_scale": (
        obj(body='"hypercube"', scale="1e-300"),
        "[[object]] #1 'object1'",
        "field 'scale'",
        "0.001 to 10000",
    ),
    "body_too_small": (
        obj(body='"hypercube"', scale="0.005"),
        "[[object]] #1 'object1'",
        "field 'scale'",
        "a body must measure from 0.01 to 100 m along each axis",
    ),
    "body_too_big": (
        obj("hypersphere", body='"hypersphere"', scale="60"),
        "[[object]] #1 'object1'",
        "field 'scale'",
        "measures [120, 120, 120, 120] m",
    ),
    "body_too_thin": (
        obj(body='"hypercube"', scale="[1.0, 5.0, 1.0, 1.0]"),
        "[[object]] #1 'object1'",
        "field 'scale'",
        "the longest at most 4 times the shortest",
    ),
    "body_shape_too_thin": (
        obj("duoprism", body='"hypercube"', params="{ r1 = 1.0, r2 = 0.2 }"),
        "[[object]] #1 'object1'",
        "field 'scale'",
        "the longest at most 4 times the shortest",
    ),
    "body_scale_vector": (
        obj(body='"hypercube"', scale="[1.0, 1.0, 1e-300, 1.0]"),
        "[[object]] #1 'object1'",
        "field 'scale'",
        "0.001 to 10000",
    ),
    "mass": (obj(body='"hypercube"', mass="1e300"), "[[object]] #1 'object1'", "field 'mass'", "0.001 to 10000 kg"),
    "rotation": (
        obj(rotation="{ xy = 1e300 }"),
        "[[object]] #1 'object1'",
        "field 'rotation.xy'",
        "-3600 to 3600 degrees",
    ),
    "object_position": (
        obj(position="[0.0, 0.0, 0.0, -1e20]"),
        "[[object]] #1 'object1'",
        "field 'position'",
        "-10000 to 10000 m",
    ),
    "object_depth": (
        "[[object]]\nasset = 'meshes/crate.obj'\nposition = [0, 0, 0, 0]\ndepth = 1e9\n",
        "[[object]] #1 'object1'",
        "field 'depth'",
        "0.001 to 10000 m",
    ),
    "shape_radius": (
        obj("600-cell", params="{ radius = 1e300 }"),
        "[[object]] #1 'object1'",
        "field 'params'",
        "'radius' must be a number from 0.001 to 1000 m",
    ),
    "shape_aspect": (
        obj("duoprism", params="{ p = 3, q = 128, r1 = 10.0, r2 = 0.001 }"),
        "[[object]] #1 'object1'",
        "field 'params'",
        "'r1' and 'r2' may differ by a factor of at most 10, got 10 and 0.001",
    ),
    "mesh_scale": (
        "[[mesh]]\nasset = 'meshes/crate.obj'\nscale = 1e300\n",
        "[[mesh]] #1",
        "field 'scale'",
        "0.001 to 10000",
    ),
    "mesh_position": (
        "[[mesh]]\nasset = 'meshes/crate.obj'\nposition = [0, 1e5, 0]\n",
        "[[mesh]] #1",
        "field 'position'",
        "-10000 to 10000 m",
    ),
    "mesh_yaw": (
        "[[mesh]]\nasset = 'meshes/crate.obj'\nyaw = 1e300\n",
        "[[mesh]] #1",
        "field 'yaw'",
        "-3600 to 3600 degrees",
    ),
    "box_size": (
        "[[box]]\ncenter = [0, 0, 0]\nsize = [1, 1e300, 1]\n",
        "[[box]] #2",
        "field 'size'",
        "0.001 to 10000 m",
    ),
    "box_size_tiny": (
        "[[box]]\ncenter = [0, 0, 0]\nsize = [1, 5e-324, 1]\n",
        "[[box]] #2",
        "field 'size'",
        "0.001 to 10000 m",
    ),
}
EDITS = {  # extremes in the base tables, as (old, new) edits of BASE
    "w_range": (
        ("w_range = [-1.0, 1.0]", "w_range = [-1.0, 1e308]"),
        "[level]",
        "field 'w_range'",
        "-10000 to 10000 m",
    ),
    "spawn_position": (
        ("position = [0.0, 0.0, 0.0, 0.0]", "position = [1e308, 0.0, 0.0, 0.0]"),
        "[spawn]",
        "field 'position'",
        "-10000 to 10000 m",
    ),
    "spawn_yaw": (
        ("position = [0.0, 0.0, 0.0, 0.0]", "position = [0.0, 0.0, 0.0, 0.0]\nyaw = -1e300"),
        "[spawn]",
        "field 'yaw'",
        "-3600 to 3600 degrees",
    ),
    "goal_center": (
        ("center = [0.0, 1.0, 5.0]", "center = [0.0, 1.0, 5e300]"),
        "[goal]",
        "field 'center'",
        "-10000 to 10000 m",
    ),
    "goal_size": (("size = [1.0, 2.0, 1.0]", "size = [1.0, 2.0, 1e300]"), "[goal]", "field 'size'", "0.001 to 10000 m"),
}


def _extreme_text(name) -> tuple[str, str, str, str]:
    if name in EXTREMES:
        extra, entry, fld, rng = EXTREMES[name]
        return BASE + "\n" + extra, entry, fld, rng
    (old, new), entry, fld, rng = EDITS[name]
    assert old in BASE
    return BASE.replace(old, new, 1), entry, fld, rng


@pytest.mark.parametrize("name", sorted(EXTREMES) + sorted(EDITS))
def test_extreme_value_is_one_line_refusal(tmp_path, name):
    text, entry, fld, rng = _extreme_text(name)
    path = write_text(tmp_path, text)
    problems = problems_of(path)
    assert len(problems) == 1, problems
    (msg,) = problems
    assert msg.startswith(f"{path}: {entry}: {fld}"), msg
    assert rng in msg, msg
    assert "\n" not in msg


def test_extreme_values_through_check_level(tmp_path):
    paths = []
    for name in ("object_scale", "box_center", "world_depth", "world_w", "gravity", "body_scale"):
        text, *_ = _extreme_text(name)
        paths.append(write_text(tmp_path, text, f"{name}.toml"))
    res = check_level(*paths)
    assert res.returncode == 2
    assert "Traceback" not in res.stderr and "internal error" not in res.stderr
    lines = res.stderr.splitlines()
    assert len(lines) == 2 * len(paths)
    for path, (head, line) in zip(paths, zip(lines[::2], lines[1::2])):
        assert head == f"{path}: 1 problem(s)"
        assert line.startswith(f"  {path}: ")


# ------------------------------------------------------------ whatever is accepted plays finite
# The largest values the ranges accept, together: strong gravity (up and down),
# heavy and light bodies thrown at top speed and spin, far-away and huge things,
# the strongest inverse-cube pull.
def largest(gx: float, gy: float, gw: float) -> LevelBuilder:
    spin = {"xw": 720.0, "yw": -720.0, "zw": 720.0}
    return (
        LevelBuilder(
            "largest",
            format=None,
            w_range=(-10000.0, 10000.0),
            spawn=(0.0, 3000.0, 0.0, 0.0),
            yaw=3600.0,
            goal=(10000.0, 1.0, 10000.0),
            goal_size=(0.001, 0.001, 0.001),
            goal_w=(9999.0, 10000.0),
            floor=(10000.0, 0.001, 10000.0),  # thin, far below the spawn: a 3 km fall must not go through it
        )
        .table("physics", gravity=[gx, gy, 0.0, gw], inverse_cube_g=10.0, rolling_resistance=1.0)
        .box([-10000.0, 10000.0, -10000.0], [10000.0, 10000.0, 10000.0])
        .world(
            -10000.0,
            10000.0,
            name="far",
            profile="taper",
            boxes=[{"center": [10000.0, 0.0, 0.0], "size": [0.001, 10000.0, 0.001]}],
        )
        .object(
            [10000.0, 10000.0, 10000.0, 10000.0],
            "hypersphere",
            name="heavy",
            params={"subdivisions": 0, "radius": 10.0},
            rotation={"xw": 3600.0, "yz": -3600.0},
            scale=5.0,
            body="hypersphere",
            mass=10000.0,
            velocity=[50.0, -50.0, 50.0, -50.0],
            spin=spin,
        )
        .object(
            [0.0, 5.0, 0.0, 0.0],
            "tesseract",
            name="light",
            params={"size": 0.001},
            scale=[10.0, 40.0, 10.0, 10.0],
            body="hypercube",
            mass=0.001,
            velocity=[-50.0, 50.0, -50.0, 50.0],
            spin={"xy": -720.0, "zw": 720.0},
        )
        .object(
            [1.0, 1.0, 1.0, 0.0],
            "24-cell",
            name="small",
            params={"radius": 0.001},
            scale=5.0,
            body="hypersphere",
            mass=10000.0,
            velocity=[50.0, 50.0, 50.0, 50.0],
        )
        .object(
            [-10000.0, -10000.0, -10000.0, -10000.0],
            "duoprism",
            name="spinner",
            params={"p": 3, "q": 128, "r1": 1000.0, "r2": 100.0},
            scale=[10000.0, 0.001, 10000.0, 0.001],
            spin={"xy": 720.0, "xw": -720.0},
            solid=True,
        )
    )


def _play_random(game, ticks: int, seed: int) -> None:
    from across_dimensions.game.actions import Actions

    rng = np.random.default_rng(seed)
    for t in range(ticks):
        game.step(
            Actions(
                forward=float(rng.uniform(-1, 1)),
                right=float(rng.uniform(-1, 1)),
                w=float(rng.choice([-1.0, 0.0, 1.0])),
                jump=bool(rng.random() < 0.1),
                yaw=float(rng.normal(0, 0.05)),
                pitch=float(rng.normal(0, 0.05)),
            )
        )
        p = game.player
        assert np.isfinite(p.position).all() and np.isfinite(p.velocity).all(), (t, p.position, p.velocity)
        if game.physics is not None:
            for b in (e.motion.body for e in game.entities.of_kind("body")):
                assert np.isfinite(game.physics.body_position(b)).all(), (t, b)
                assert np.isfinite(game.physics.body_velocity(b)[0]).all(), (t, b)


@pytest.mark.parametrize("path", resources.level_files(), ids=[p.stem for p in resources.level_files()])
def test_shipped_level_plays_finite(path):
    from across_dimensions.game.sim import Game

    _play_random(Game(load_level(path)), 600, seed=7)


@pytest.mark.slow  # the first of them builds and plays the largest level: 30-50 s on a slow machine
@pytest.mark.parametrize(
    "gravity", [(0.0, -100.0, 0.0), (0.0, 100.0, 0.0), (70.0, -70.0, 10.0)], ids=["down", "up", "sideways"]
)
def test_largest_accepted_values_play_finite(tmp_path, gravity):
    from across_dimensions.game.sim import Game

    gx, gy, gw = gravity
    path = largest(gx, gy, gw).write(tmp_path)
    level = load_level(path)  # every value here is accepted...
    game = Game(level)
    _play_random(game, 600, seed=3)  # ... and plays finite
    if gy < 0:  # fell 3 km at up to 100 m/s^2 and landed on the 1 mm floor, not through it
        assert 0.0 <= game.player.position[1] < 0.2  # maybe in a (low, at this gravity) jump
        assert game.respawns == 0


# ------------------------------------------------------------ documentation
def test_readme_states_the_limits_and_ranges():
    text = README.read_text(encoding="utf-8")
    section = text.split("## Limits and ranges", 1)[1].split("\n## ", 1)[0]
    for limit, what in limits.MAX_COUNTS.values():
        assert re.search(rf"\b{limit:,}\b".replace(",", ",?"), section), (limit, what)
    for n in (limits.MAX_OBJECT_TETS, limits.MAX_TOTAL_TETS):
        assert f"{n:,}" in section
    assert f"{limits.MAX_LEVEL_BYTES // 1024} KiB" in section
    for rng in (
        limits.COORD,
        limits.SIZE,
        limits.ANGLE,
        limits.SPIN,
        limits.SPEED,
        limits.MASS,
        limits.INVERSE_CUBE_G,
        limits.ROLLING_RESISTANCE,
    ):
        assert f"{rng.lo:g} to {rng.hi:g}" in section, rng
    assert f"{limits.GRAVITY_MAX:g} m/s²" in section
    assert "`rolling_resistance`" in text


def test_a_body_thrown_off_the_level_is_caught(tmp_path):
    """Off the edge of an open floor a body used to fall for ever; the box of
    walls around the level catches it, and it comes to rest there."""
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game
    from across_dimensions.world.scene import BOUNDS_MARGIN, level_bounds

    level = base().table("physics", rolling_resistance=0.05)
    level.object([0.0, 1.0, 2.0, 0.0], "hypersphere", body="hypersphere", scale=0.5, velocity=[40.0, 10.0, 0.0, 0.0])
    game = Game(level.load(tmp_path))
    lo, hi = level_bounds(game.scene)
    (b,) = (e.motion.body for e in game.entities.of_kind("body"))
    farthest = 0.0
    for _ in range(40 * 60):
        game.step(Actions())
        p = game.physics.body_position(b)
        farthest = max(farthest, p[0])
        assert np.all(p[:3] > lo - BOUNDS_MARGIN - 0.05) and np.all(p[:3] < hi + BOUNDS_MARGIN + 0.05), p
    assert farthest > hi[0] + BOUNDS_MARGIN - 1.0, "it should have flown off to the wall"
    assert p[1] == pytest.approx(lo[1] - BOUNDS_MARGIN + 0.5, abs=0.05), "resting on the catching floor"
    assert game.physics.is_sleeping(b)


def _g(x: float, digits: int = 6) -> float:
    """``x`` as the level file once wrote it, to ``digits`` significant digits."""
    return float(f"{x:.{digits}g}")


def _random_level(rng) -> LevelBuilder:
    """A level of random bodies anywhere inside the accepted ranges, on thin floors."""
    g = rng.normal(size=4)
    g *= rng.uniform(0, limits.GRAVITY_MAX * 0.999) / np.linalg.norm(g)
    level = base(floor=(10.0, 0.001, 12.0)).table(
        "physics",
        gravity=[_g(x) for x in g],
        inverse_cube_g=float(rng.choice([0.0, limits.INVERSE_CUBE_G.hi])),
        rolling_resistance=round(rng.uniform(0, 1), 3),
    )
    level.box([3.0, 1.0, 0.0], [0.001, 2.0, 6.0])
    for k in range(4):
        shape, body, unit = [
            ("hypersphere", "hypersphere", 2.0),
            ("tesseract", "hypercube", 1.0),
            ("24-cell", "hypersphere", 2.0),
        ][int(rng.integers(3))]
        extent = np.exp(rng.uniform(np.log(0.011), np.log(25.0)))  # the body's smallest extent, m
        scale = extent / unit * np.exp(rng.uniform(0, np.log(limits.BODY_ASPECT * 0.99), 4))
        if body == "hypersphere":
            scale[:] = scale[0]
        spin = {p: round(rng.uniform(-720, 720), 1) for p in ("xy", "xw", "yz", "zw")}
        level.object(
            [round(rng.uniform(-2, 2), 3), 2 + 3 * k, round(rng.uniform(-2, 2), 3), round(rng.uniform(-0.5, 0.5), 3)],
            shape,
            scale=[_g(s) for s in scale],
            body=body,
            mass=_g(np.exp(rng.uniform(np.log(1e-3), np.log(1e4)))),
            velocity=[round(v, 3) for v in rng.uniform(-50, 50, 4)],
            spin=spin,
        )
    return level


@pytest.mark.slow
def test_random_levels_inside_the_ranges_play_finite(tmp_path):
    """Property: random levels at the edges of the ranges (thin floors, strong
    gravity any way, fast, spinning, heavy and light bodies) all load and play
    finite for 10 s with random input."""
    from across_dimensions.game.sim import Game

    rng = np.random.default_rng(2026)
    for i in range(40):
        path = _random_level(rng).write(tmp_path, f"random{i}.toml")
        _play_random(Game(load_level(path)), 600, seed=i)
