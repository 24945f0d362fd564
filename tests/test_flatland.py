"""The Flatland prologue's simulation (game/flatland): sections become pymunk shapes, the being
walks, jumps, pushes and falls, the plane moves along z, and the same actions give the same states."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pymunk
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import Actions
from across_dimensions.game.flatland import FlatGame
from across_dimensions.game.flatland.hints import StateHints
from across_dimensions.game.flatland.sim import COYOTE_TICKS
from across_dimensions.game.flatland.space import CRATE_FRICTION, SOLID_FRICTION
from across_dimensions.game.flatland.view import flat_frame
from across_dimensions.game.player import JUMP_SPEED, WALK_SPEED
from across_dimensions.world.flat_level import load_flat_level
from across_dimensions.world.resources import levels_dir

REPO = Path(__file__).resolve().parents[1]
PROLOGUE = levels_dir() / "prologue.toml"


def room(tmp_path, level: LevelBuilder | None = None, name: str = "room") -> FlatGame:
    """A game of ``level``: by default the smallest room, a floor 40 m long at every z of [-3, 3],
    the being at x = 0."""
    level = LevelBuilder.flatland() if level is None else level
    return FlatGame(load_flat_level(level.write(tmp_path, f"{name}.toml")))


def run(game: FlatGame, actions: Actions, ticks: int) -> None:
    for _ in range(ticks):
        game.step(actions)


def shapes(game: FlatGame, kind) -> list:
    return [s for s in game.space.space.shapes if isinstance(s, kind) and s.body is game.space.space.static_body]


def circles(game: FlatGame) -> list[pymunk.Circle]:
    return [s for s in game.space.space.shapes if isinstance(s, pymunk.Circle)]


# ------------------------------------------------------- sections as pymunk shapes
def test_a_balls_circle_radius_follows_z(tmp_path):
    # A ball of radius 1.5 centred at z = 1: in the plane z0 its circle has radius
    # sqrt(1.5^2 - (z0 - 1)^2), and there is no circle where |z0 - 1| >= 1.5.
    game = room(tmp_path, LevelBuilder.flatland().add("ball", center=[6.0, 1.5, 1.0], radius=1.5))
    seen = []
    for _ in range(200):  # hold w_ana: the plane moves from 0 to 3
        game.step(Actions(w=1.0))
        (c,) = circles(game) or (None,)
        expected = math.sqrt(max(0.0, 2.25 - (game.z - 1.0) ** 2))
        got = 0.0 if c is None else c.radius
        assert got == pytest.approx(expected, abs=1e-12), game.z
        if c is not None:
            assert tuple(c.body.position) == (6.0, 1.5)
        seen.append(got)
    assert game.z == 3.0 and seen[-1] == 0.0  # past z = 2.5 the ball is out of the plane
    assert max(seen) == pytest.approx(1.5, abs=1e-3)  # through its middle near z = 1


def test_a_wall_that_tapers_along_z_shrinks_and_vanishes(tmp_path):
    profile = [[-1.0, 0.0], [1.0, 0.0], [0.0, 4.0]]  # [z, y]: 4 m high at z = 0, gone at |z| = 1
    wall = LevelBuilder.flatland().add("prism", name="wall", along="x", extent=[3.0, 3.5], profile=profile)
    game = room(tmp_path, wall)
    heights = []
    while game.z < 1.2:
        game.step(Actions(w=1.0))
        polys = [p for p in shapes(game, pymunk.Poly) if max(v.x for v in p.get_vertices()) <= 3.5 + 1e-9]
        polys = [p for p in polys if min(v.x for v in p.get_vertices()) >= 3.0 - 1e-9]
        top = max((v.y for p in polys for v in p.get_vertices()), default=0.0)
        assert top == pytest.approx(max(0.0, 4.0 * (1 - game.z)), abs=1e-9)
        heights.append(top)
    assert heights[0] > 3.9 and heights[-1] == 0.0  # gone beyond z = 1
    assert heights == sorted(heights, reverse=True)


def test_a_box_outside_its_z_extent_leaves_the_space(tmp_path):
    game = room(tmp_path, LevelBuilder.flatland().box([4.0, 0.5, 0.5], [1.0, 1.0, 1.0], name="block"))
    n0 = len(shapes(game, pymunk.Poly))
    for w, inside in ((1.0, lambda z: z < 1.0), (-1.0, lambda z: z >= 0.0), (1.0, lambda z: z < 0.5)):
        while inside(game.z):  # hold the key until the plane leaves [0, 1) (or reaches its middle)
            assert len(shapes(game, pymunk.Poly)) == n0 if 0.0 <= game.z < 1.0 else n0 - 1
            game.step(Actions(w=w))
        assert len(shapes(game, pymunk.Poly)) == (n0 if 0.0 <= game.z < 1.0 else n0 - 1)
    assert 0.5 <= game.z < 1.0


def test_standing_on_something_that_vanishes_falls(tmp_path):
    # A platform 2 m up, only for z in [-0.5, 0.5]; the being starts on it.
    ledge = LevelBuilder.flatland(spawn=(0.0, 2.0, 0.0)).box([0.0, 1.5, 0.0], [3.0, 1.0, 1.0], name="ledge")
    game = room(tmp_path, ledge, "ledge")
    run(game, Actions(), 30)
    assert game.grounded and game.position[1] == pytest.approx(2.0, abs=0.01)
    run(game, Actions(w=1.0), 45)  # past z = 0.5: the ledge is gone
    assert game.z > 0.5
    run(game, Actions(), 60)
    assert game.grounded and game.position[1] == pytest.approx(0.0, abs=0.01)


# ------------------------------------------------------- the being
def test_the_being_walks_and_jumps(tmp_path):
    game = room(tmp_path)
    run(game, Actions(), 10)
    run(game, Actions(right=1.0), 60)
    assert game.space.being.velocity.x == pytest.approx(WALK_SPEED, rel=1e-3)
    y0, top = game.position[1], 0.0
    game.step(Actions(jump=True))
    for _ in range(70):  # up and down again: 64 ticks in the air
        game.step(Actions())
        top = max(top, game.position[1] - y0)
    # pymunk moves positions before it applies gravity to velocities, so a jump at v rises
    # v^2 / 2g + v dt / 2 (1.42 m); the apex falls between ticks within g dt^2 of it.
    assert top == pytest.approx(JUMP_SPEED**2 / (2 * 9.81) + JUMP_SPEED * game.dt / 2, abs=9.81 * game.dt**2)
    assert game.grounded


def test_the_being_pushes_a_crate_against_its_friction(tmp_path):
    game = room(tmp_path, LevelBuilder.flatland().add("crate", center=[2.0, 0.5, 0.0], size=[1.0, 1.0, 8.0], mass=25.0))
    body, _ = game.space.crates[0]
    run(game, Actions(right=1.0), 120)
    assert body.position.x > 5.0  # pushed along, not climbed
    assert game.position[0] == pytest.approx(body.position.x - 0.5 - 0.3, abs=0.05)
    # Let go: it slides v^2 / (2 mu g) on, mu the product of the crate's and the floor's friction.
    x, v = body.position.x, body.velocity.x
    run(game, Actions(), 120)
    mu = CRATE_FRICTION * SOLID_FRICTION
    assert body.velocity.x == 0.0 or abs(body.velocity.x) < 1e-9
    assert body.position.x - x == pytest.approx(v * v / (2 * mu * 9.81), rel=0.05)


def test_moving_along_z_is_refused_where_a_wall_would_appear_around_the_being(tmp_path):
    game = room(tmp_path, LevelBuilder.flatland().box([0.0, 2.0, 1.5], [1.0, 4.0, 1.0], name="pillar"))
    run(game, Actions(w=1.0), 120)
    assert game.z < 1.0 and game.event_counts["z_blocked"] == 1
    run(game, Actions(right=1.0), 30)  # step out from under it: now the plane moves on
    run(game, Actions(w=1.0), 120)
    assert game.z == 3.0


# ------------------------------------------------------- determinism
SCRIPT = [
    (Actions(right=1.0), 40),
    (Actions(right=1.0, jump=True), 30),
    (Actions(w=1.0), 50),
    (Actions(w=-1.0, right=-0.5), 80),
]


def _hashes(path) -> list[str]:
    game = FlatGame(load_flat_level(path))
    out = []
    for a, n in SCRIPT * 3:
        for _ in range(n):
            game.step(a)
            if game.tick % 20 == 0:
                out.append(game.state_hash())
    return out


def test_same_actions_give_the_same_hashes_twice_and_in_a_fresh_process(tmp_path):
    first, second = _hashes(PROLOGUE), _hashes(PROLOGUE)
    assert first == second and len(set(first)) > len(first) // 2
    code = (
        "import json, sys\n"
        "sys.path.insert(0, sys.argv[1])\n"
        "from test_flatland import _hashes, PROLOGUE\n"
        "print(json.dumps(_hashes(PROLOGUE)))\n"
    )
    env = dict(os.environ, NUMBA_CACHE_DIR=os.environ.get("NUMBA_CACHE_DIR", str(tmp_path / "numba")))
    r = subprocess.run(
        [sys.executable, "-c", code, str(REPO / "tests")], capture_output=True, text=True, timeout=300, env=env
    )
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout.strip().splitlines()[-1]) == first


# ------------------------------------------------------- hints and the frame
def test_hints_are_done_by_the_level_state_not_by_keys(tmp_path):
    level = (
        LevelBuilder.flatland()
        .add("hint", text="Hold {w_ana}.", until={"z_min": 0.5})
        .add("hint", text="Walk right.", until={"x_min": 3.0})
        .add("hint", text="Read me.")
    )
    game = room(tmp_path, level)
    hints = StateHints(game.level.hints)
    for _ in range(20):  # the key held for a third of a second: not far enough along z
        game.step(Actions(w=1.0))
        hints.tick(game, game.dt)
    assert hints.current_index() == 0 and game.z < 0.5
    while game.z < 0.5:
        game.step(Actions(w=1.0))
        hints.tick(game, game.dt)
    assert hints.current_index() == 1
    run(game, Actions(right=1.0), 60)  # past x = 3 before the hint is looked at again
    hints.tick(game, game.dt)
    assert hints.current_index() == 2  # the walk hint was done the moment its state held
    hints.toggle()
    assert hints.current() is None and hints.remaining() == 0


def test_the_frame_shows_the_sections_and_the_z_bar(tmp_path):
    game = room(
        tmp_path,
        LevelBuilder.flatland().add("ball", center=[6.0, 1.5, 2.0], radius=1.0).add("item", position=[3.0, 1.0, -1.0]),
    )
    frame = flat_frame(game)
    assert [p.key for p in frame.pieces] == ["floor"] and frame.circles == []
    assert {(p.kind, p.z, p.in_plane) for p in frame.pins} == {("ball", 2.0, False), ("item", -1.0, False)}
    run(game, Actions(w=1.0), 100)
    frame = flat_frame(game)
    (ball,) = [c for c in frame.circles if c.kind == "ball"]
    assert ball.radius == pytest.approx(math.sqrt(1 - (game.z - 2.0) ** 2))
    assert frame.reveal == 0.0 and frame.solids3 == []


def test_the_pit_needs_the_ball(tmp_path):
    # The prologue without its ball: a running jump from the pit's edge falls in (the pit is wider
    # than a jump carries), so crossing it is the ball's lesson, not a long jump.
    text = PROLOGUE.read_text(encoding="utf-8")
    text = text[: text.index("[[ball]]")].replace(
        "position = [0.0, 0.0, 0.0]   # x, y (feet), z", "position = [31.0, 0.0, 0.0]"
    )
    path = tmp_path / "no_ball.toml"
    path.write_text(text, encoding="utf-8")
    game = FlatGame(load_flat_level(path))
    while game.grounded or game.air_ticks < COYOTE_TICKS - 1:  # full speed off the edge, the latest jump there is
        game.step(Actions(right=1.0))
    run(game, Actions(right=1.0, jump=True), 3)
    assert game.jumped
    run(game, Actions(right=1.0), 120)
    assert game.position[1] < -2.5 and game.position[0] < 43.0  # in the pit, short of the far side


@pytest.mark.parametrize("late, jumps", [(3, True), (COYOTE_TICKS + 3, False)])
def test_a_jump_just_after_leaving_the_ground_still_goes(tmp_path, late, jumps):
    # Coyote time: a being that walked off a ledge (or whose circle shrank away under it) may jump
    # for a few ticks more, so a tap late by a frame still jumps; later it is falling.
    ledge = LevelBuilder.flatland(spawn=(0.0, 2.0, 0.0)).box([-1.0, 1.5, 0.0], [2.4, 1.0, 8.0], name="ledge")
    game = room(tmp_path, ledge, "ledge")
    run(game, Actions(), 20)
    while game.grounded:
        game.step(Actions(right=1.0))
    run(game, Actions(right=1.0), late - 1)
    game.step(Actions(right=1.0, jump=True))
    assert (game.space.being.velocity.y > 0.8 * JUMP_SPEED) == jumps
