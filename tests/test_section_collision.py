"""The walker against the true cross-sections of solid 4D objects.

Tolerances: the walker keeps ``SKIN`` (1e-4 m) from surfaces, and section
vertices are float32 (about 1e-6 m at these sizes), so heights are compared to
analytic truth within 2e-4 m plus SKIN.
"""

from __future__ import annotations

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.core import lift, shapes
from across_dimensions.core.mesh import concatenate
from across_dimensions.core.transform import pose
from across_dimensions.game import section_collision as sc
from across_dimensions.game.actions import Actions
from across_dimensions.game.entities import Placed, reach
from across_dimensions.game.player import HALF_WIDTH, SKIN
from across_dimensions.game.sim import Game
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

TOL = 2e-4 + SKIN


def test_sweep_stops_where_a_falling_box_meets_a_flat_triangle():
    tri = np.array([[[-5.0, 1.0, -5.0], [5.0, 1.0, -5.0], [0.0, 1.0, 5.0]]])
    lo, hi = np.array([-0.3, 2.0, -0.3]), np.array([0.3, 3.75, 0.3])
    s = sc.first_hit(lo, hi, 1, -4.0, tri)
    assert s == pytest.approx(0.25, abs=1e-12)  # 1 m of a 4 m fall
    assert sc.first_hit(lo, hi, 1, -0.5, tri) is None  # stops short of the triangle
    assert sc.first_hit(lo, hi, 0, 3.0, tri) is None  # sideways above it: never touches


def test_sweep_against_a_slanted_triangle_and_its_edge():
    # A triangle in the plane y = x (45 degrees), the box above it (y > x).
    tri = np.array([[[-5.0, -5.0, -5.0], [5.0, 5.0, -5.0], [0.0, 0.0, 5.0]]])
    lo, hi = np.array([-3.0, 0.0, -0.3]), np.array([-2.0, 1.0, 0.3])
    # Moving +x, the lower right edge (x = -2, y = 0) meets y = x first, after 2 m of 6.
    s = sc.first_hit(lo, hi, 0, 6.0, tri)
    assert s == pytest.approx(1.0 / 3.0, abs=1e-12)
    assert sc.overlapping(lo + [3.0, 0, 0], hi + [3.0, 0, 0], tri).all()
    assert not sc.overlapping(lo, hi, tri).any()


def test_inside_a_closed_section():
    cube = np.array([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]])
    from across_dimensions.core.section import cross_section

    tris = sc.triangles_of(cross_section(shapes.tesseract(), model=pose((0, 0, 0, 0), {}, np.full(4, 2.0))))
    assert sc.inside([0.1, 0.2, 0.3], tris)
    assert not sc.inside([0.1, 1.5, 0.3], tris)
    assert not sc.inside([3.0, 0.0, 0.0], tris)
    assert sc.box_blocked(cube[0] * 0.1, cube[1] * 0.1, tris)  # wholly inside: blocked though no triangle is hit


def _room(spawn, goal=(30.0, 1.0, 0.0), yaw=None) -> LevelBuilder:
    """A 20 m floor at w from -0.5 to 0.5."""
    return LevelBuilder(w_range=(-0.5, 0.5), spawn=spawn, yaw=yaw, goal=goal, floor=(20.0, 1.0, 20.0))


def _slab_level(tmp_path, angle_deg: float, plane: str = "xy"):
    slab = dict(name="slab", rotation={plane: angle_deg}, scale=[6.0, 0.2, 3.0, 1.0], solid=True)
    level = _room((-2.0, 0.0, 0.0, 0.0), yaw=90.0).object([2.0, 0.0, 0.0, 0.0], **slab)
    return Game(level.load(tmp_path, "slab.toml"))


def test_player_stands_on_a_slab_turned_20_degrees_at_its_section_height(tmp_path):
    game = _slab_level(tmp_path, 20.0)
    t = np.radians(20.0)
    # Drop the player onto the slope and let them settle.
    game.player.position = np.array([2.5, 3.0, 0.0, 0.0])
    for _ in range(120):
        game.step(Actions())
    p = game.player.position
    assert game.player.on_ground
    # Top face of the turned slab: y = tan(t) (x - 2) + 0.1 / cos(t); the player's box
    # rests on it with its uphill bottom edge, at x + HALF_WIDTH.
    top = np.tan(t) * (p[0] + HALF_WIDTH - 2.0) + 0.1 / np.cos(t)
    assert p[1] == pytest.approx(top, abs=TOL)
    assert p[1] > top  # never inside


def test_a_turned_slab_is_a_ramp_the_player_walks_up(tmp_path):
    game = _slab_level(tmp_path, 15.0)
    t = np.radians(15.0)
    heights = []
    for _ in range(80):  # walk along +x, from the floor onto the ramp and up it (it ends at x = 4.9)
        game.step(Actions(forward=1.0))
        heights.append(game.player.position[1])
    p = game.player.position
    assert 3.5 < p[0] < 4.6, "the walker stopped at the foot of the ramp or ran off its end"
    top = np.tan(t) * (p[0] + HALF_WIDTH - 2.0) + 0.1 / np.cos(t)
    # Each tick climbs the slope by stepping up and settling down onto it; gravity may
    # leave the walker a fall of one tick (under 1 cm) above the surface.
    assert top - 0.01 < p[1] < top + 0.01 + TOL
    assert np.all(np.diff(heights) > -0.01)  # climbs steadily, never drops back


def test_the_same_slab_turned_in_xw_is_flat_and_stood_on(tmp_path):
    # Turned through w, its section at w = 0 is a longer flat box: its top stays at y = 0.1.
    game = _slab_level(tmp_path, 20.0, plane="xw")
    game.player.position = np.array([2.0, 1.0, 0.0, 0.0])
    for _ in range(90):
        game.step(Actions())
    assert game.player.position[1] == pytest.approx(0.1 + SKIN, abs=TOL)


def _arch_game(tmp_path):
    game = _slab_level(tmp_path, 0.0)
    game.remove(game.entities.named("slab").id)
    parts = []
    pillar, lintel = [0.4, 2.2, 0.6], [2.4, 0.4, 0.6]
    for c, s in (([-1.0, 1.1, 4.0], pillar), ([1.0, 1.1, 4.0], pillar), ([0.0, 2.401, 4.0], lintel)):
        v, t = lift.box_solid(c, s)
        parts.append(lift.extrude(v, t, [-0.5, 0.5]))
    mesh = concatenate(parts)
    game.entities.spawn("object", "arch", mesh, Placed(np.eye(5)), solid=True, radius=reach(mesh))
    game.player.position = np.array([0.0, 0.0, 1.0, 0.0])
    game.player.yaw = 0.0  # looking along +z, at the arch
    return game


def test_an_arch_lets_the_player_through_its_doorway(tmp_path):
    game = _arch_game(tmp_path)
    for _ in range(90):
        game.step(Actions(forward=1.0))
    assert game.player.position[2] > 5.0  # walked through the 1.6 m wide, 2.2 m high doorway


def test_an_arch_blocks_the_player_at_its_pillars(tmp_path):
    game = _arch_game(tmp_path)
    game.player.position[0] = -1.0  # in line with the left pillar
    for _ in range(90):
        game.step(Actions(forward=1.0))
    assert game.player.position[2] == pytest.approx(4.0 - 0.3 - HALF_WIDTH - SKIN, abs=TOL)
    assert game.player.position[1] == pytest.approx(0.0, abs=1e-9)  # not climbed: 2.2 m is no step


def test_a_step_along_w_into_a_section_is_refused(tmp_path):
    game = _slab_level(tmp_path, 0.0)
    game.remove(game.entities.named("slab").id)
    mesh = shapes.tesseract()
    model = pose((0.0, 1.0, 0.0, 0.45), {}, np.array([3.0, 3.0, 3.0, 0.4]))  # exists for 0.25 < w < 0.65
    game.entities.spawn("object", "block", mesh, Placed(model), solid=True, radius=reach(mesh, [3, 3, 3, 0.4]))
    game.player.position = np.array([0.0, 0.0, 0.0, 0.0])  # the block would appear around the player
    for _ in range(60):
        game.step(Actions(w=1.0))
    assert game.player.position[3] < 0.25
    assert game.event_counts["w_blocked"] >= 1


def test_shipped_levels_have_no_solid_4d_object():
    # Section collision replaced bounding boxes only for solid, non-body 4D objects;
    # the shipped levels before the Bridge have none, so their replays are unchanged.
    for path in sorted(levels_dir().glob("0[123]_*.toml")):
        level = load_level(path)
        assert not [o.name for o in level.objects if o.solid and o.body == "none"], path.name


def test_collision_benchmark_runs_and_reports_both_ways():
    from across_dimensions.bench.collision import bench_collision

    r = bench_collision(ticks=20)
    for key in ("section_median_ms", "section_p95_ms", "box_median_ms", "box_p95_ms", "triangles"):
        assert np.isfinite(r[key]) and r[key] >= 0, key
    assert r["triangles"] > 100  # the 120-cell's section is near the player


def _world_arch_game(tmp_path, profile: str = "prism"):
    """An arch asset (3 m wide, legs 0.5 m thick, opening 2 m x 2.75 m, 0.5 m deep) as a
    ``[[world.mesh]]`` part across the player's way at z = 4."""
    arch = {"asset": "meshes/arch.obj", "position": [0.0, 0.0, 4.0]}
    level = _room((0.0, 0.0, 1.0, 0.0), goal=(0.0, 1.0, 30.0)).world(0.0, 2.0, profile=profile, meshes=[arch])
    return Game(level.load(tmp_path, "arch.toml"))


def test_a_world_mesh_arch_lets_the_player_through_its_doorway(tmp_path):
    game = _world_arch_game(tmp_path)
    assert len(game.meshes) == 1
    assert np.isnan(game.colliders_at(0.0)[-1]).all()  # its bounding box no longer collides
    for _ in range(90):
        game.step(Actions(forward=1.0))
    assert game.player.position[2] > 5.0  # through the 2 m wide doorway, where its bounding box stood


def test_a_world_mesh_arch_blocks_the_player_at_its_legs(tmp_path):
    game = _world_arch_game(tmp_path)
    game.player.position[0] = -1.25  # in line with the left leg (x from -1.5 to -1.0)
    for _ in range(90):
        game.step(Actions(forward=1.0))
    # The leg's face is at z = 4 - 0.25; the walker keeps its half width and SKIN from it.
    assert game.player.position[2] == pytest.approx(4.0 - 0.25 - HALF_WIDTH - SKIN, abs=TOL)


def test_a_world_mesh_section_shrinks_with_the_profile(tmp_path):
    game = _world_arch_game(tmp_path, "taper")
    feet = np.array([0.0, 0.0, 4.0])
    (full,) = game.meshes.triangles_at(0.0, feet, 3.0)
    (half,) = game.meshes.triangles_at(0.5, feet, 3.0)  # taper: half size halfway to the end
    c = 0.5 * (full.reshape(-1, 3).min(axis=0) + full.reshape(-1, 3).max(axis=0))
    assert np.allclose(half, c + 0.5 * (full - c))
    assert game.meshes.triangles_at(1.0, feet, 3.0) == []  # gone at the world's end


def _bullets_at_door_a(remove_door: bool) -> float:
    """Fire the Armory's gun once from in front of door A (a tesseract slab across the
    hall at z = -4, 0.4 m thick); the farthest z the bullet reaches in 2 s."""
    game = Game(load_level(levels_dir() / "04_armory.toml", arsenal=["gun"]))  # the gun, as if taken
    if remove_door:
        game.remove(game.entities.named("door A").id)
    game.player.position = np.array([0.0, 0.0, -7.0, 0.0])
    game.step(Actions(presses=Actions.count_presses({"fire": 1})))
    (bullet,) = game.entities.of_kind("bullet")
    far = -np.inf
    for _ in range(120):
        game.step(Actions())
        if bullet.id in game.entities:
            far = max(far, float(bullet.center(game)[2]))
    return far


def test_a_bullet_stops_at_a_closed_door_and_passes_once_it_is_open():
    # The door's face is at z = -4.2; the bullet (0.15 m) stops there, whatever its w swing.
    assert _bullets_at_door_a(False) < -4.2
    assert _bullets_at_door_a(True) > -2.0


def test_a_body_rests_on_a_solid_tesseract_slab_where_its_section_is(tmp_path):
    level = (
        _room((-5.0, 0.0, 0.0, 0.0))
        .object([0.0, 1.0, 0.0, 0.0], name="table", scale=[2.0, 0.2, 2.0, 1.0])
        .object([0.0, 2.0, 0.0, 0.0], "hypersphere", name="ball", scale=0.3, body="hypersphere")
    )
    game = Game(level.load(tmp_path, "table.toml"))
    ball = game.entities.named("ball")
    for _ in range(180):
        game.step(Actions())
    # The table's top is at y = 1.1; the ball's radius is its mesh's reach times 0.3.
    r = float(np.linalg.norm(ball.mesh.vertices, axis=1).max()) * 0.3
    assert ball.center(game)[1] == pytest.approx(1.1 + r, abs=0.02)
    game.remove(game.entities.named("table").id)
    for _ in range(120):
        game.step(Actions())
    assert ball.center(game)[1] == pytest.approx(r, abs=0.02)  # the table gone, it falls to the floor


def test_a_3d_mesh_arch_lets_the_player_through_its_doorway_and_stops_them_at_its_legs(tmp_path):
    level = _room((0.0, 0.0, 1.0, 0.0), goal=(0.0, 1.0, 30.0)).mesh("meshes/arch.obj", position=(0.0, 0.0, 4.0))
    p = level.write(tmp_path, "mesh_arch.toml")
    for x, through in ((0.0, True), (-1.25, False)):
        game = Game(load_level(p))
        assert np.isnan(game.colliders_at(0.0)[1]).all()  # the mesh's bounding box does not collide
        game.player.position[0] = x
        for _ in range(90):
            game.step(Actions(forward=1.0))
        if through:
            assert game.player.position[2] > 5.0
        else:
            assert game.player.position[2] == pytest.approx(4.0 - 0.25 - HALF_WIDTH - SKIN, abs=TOL)


def test_what_solid_objects_are_for_the_bodies():
    from across_dimensions.game.player_bodies import _shape_of

    assert _shape_of(shapes.tesseract())[0] == "box"
    v, t = lift.box_solid([0.0, 1.0, 0.0], [1.0, 2.0, 3.0])
    assert _shape_of(lift.extrude(v, t, [-0.5, 0.5]))[0] == "box"  # a box lifted to 4D
    kind, planes, _ = _shape_of(shapes.make_shape("24-cell"))
    assert kind == "convex" and len(planes) == 24  # one half-space per octahedral cell
    kind, planes, _ = _shape_of(shapes.make_shape("5-cell"))
    assert kind == "convex" and len(planes) == 5
    pillar, lintel = [0.4, 2.2, 0.6], [2.4, 0.4, 0.6]
    parts = [lift.extrude(*lift.box_solid(c, s), [-0.5, 0.5]) for c, s in (([-1.0, 1.1, 0.0], pillar),
             ([1.0, 1.1, 0.0], pillar), ([0.0, 2.4, 0.0], lintel))]  # fmt: skip
    assert _shape_of(concatenate(parts))[0] == "none"  # an arch: neither a box nor convex


def test_a_ball_lands_on_a_solid_24_cell_and_never_ends_inside_it(tmp_path):
    from across_dimensions.game.player_bodies import solid_colliders

    level = (
        _room((-5.0, 0.0, 0.0, 0.0))
        .object([0.0, 1.5, 0.0, 0.0], "24-cell", name="rock", scale=1.2)
        .object([0.05, 4.0, 0.03, 0.02], "hypersphere", name="ball", scale=0.3, body="hypersphere")
    )
    game = Game(level.load(tmp_path, "rock.toml"))
    ball = game.entities.named("ball")
    r = float(np.linalg.norm(ball.mesh.vertices, axis=1).max()) * 0.3
    _, ((planes, lo, hi),) = solid_colliders(game)
    top = planes[np.argmax(planes[:, 1])]
    assert np.allclose(top[:4], [0.0, 1.0, 0.0, 0.0], atol=1e-6)  # the 24-cell has a flat top facet
    deepest = np.inf
    for _ in range(150):
        game.step(Actions())
        c = ball.center(game)
        deepest = min(deepest, float(np.max(planes[:, :4] @ c - planes[:, 4])) - r)
    assert ball.center(game)[1] == pytest.approx(top[4] + r, abs=0.02)  # resting on the top facet
    assert deepest > -0.03  # never more than the solver's slop inside
