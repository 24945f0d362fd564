"""Rigid bodies against the true 4D shape of non-convex solid objects (their boundary tets).

The arch is three boxes lifted to 4D (as in test_section_collision): legs 0.4 m wide at
x = -1 and 1, 2.2 m high, and a lintel 2.4 m long and 0.4 m thick on them, its flat top at
y = 2.601; 0.6 m deep in z, 1 m in w. The doorway is 1.6 m wide. The round arch is
``assets/meshes/arch.obj`` lifted 1 m deep (one non-convex mesh, a curved top at
y = 3.5). Tolerances: the solver leaves a resting body about
0.1-0.5 mm inside what it rests on (its soft contacts push out only what sinks in), and
the margin of a speculative contact is 2 cm, so heights are compared within 5 mm and
"never inside" allows 2 cm (a landing's one-tick overlap) but no more.
"""

from __future__ import annotations

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.core import lift
from across_dimensions.core.mesh import concatenate
from across_dimensions.core.transform import pose
from across_dimensions.game.actions import Actions
from across_dimensions.game.entities import Placed, reach
from across_dimensions.game.player_bodies import tet_colliders
from across_dimensions.game.sim import Game
from across_dimensions.physics import BodyDef, PhysicsWorld, WorldDef
from across_dimensions.physics.tet_mesh import tet_geometry

TOP = 2.601  # the arch's top
HEIGHT_TOL = 5e-3
SLOP = 0.02


def _game(tmp_path, crate=None) -> Game:
    """The level (with the round arch at z = 8, and a crate at ``crate`` if given) and the box arch
    at the origin, placed by a system."""
    level = LevelBuilder(
        w_range=(-0.5, 0.5), spawn=(-6.0, 0.0, -6.0, 0.0), goal=(30.0, 1.0, 0.0), floor=(20.0, 1.0, 20.0)
    ).object([0.0, 0.0, 8.0, 0.0], None, name="round arch", asset="meshes/arch.obj", depth=1.0)
    if crate is not None:
        level.object(crate, name="crate", scale=0.5, body="hypercube")
    game = Game(level.load(tmp_path, "arch.toml"))
    parts = []
    pillar, lintel = [0.4, 2.2, 0.6], [2.4, 0.4, 0.6]
    for c, size in (([-1.0, 1.1, 0.0], pillar), ([1.0, 1.1, 0.0], pillar), ([0.0, 2.401, 0.0], lintel)):
        parts.append(lift.extrude(*lift.box_solid(c, size), [-0.5, 0.5]))
    mesh = concatenate(parts)
    game.entities.spawn("object", "arch", mesh, Placed(np.eye(5)), solid=True, radius=reach(mesh))
    return game


@pytest.fixture(scope="module")
def arches(tmp_path_factory):
    """The boundary tets ``(T, 4, 4)`` of the round arch and the box arch, as the game hands them over."""
    return tet_colliders(_game(tmp_path_factory.mktemp("arch")))


@pytest.fixture(scope="module")
def arch(arches):
    return arches[1]


def inside_mesh(points, tets) -> np.ndarray:
    """Which ``points (n, 4)`` lie inside the closed boundary ``tets (T, 4, 4)``: the parity of
    the tets a ray from each point crosses (a fixed, generic direction, so no ray grazes an edge)."""
    d = np.array([0.3127, 0.2231, 0.5413, 0.7487])
    d /= np.linalg.norm(d)
    e = np.transpose(tets[:, 1:] - tets[:, :1], (0, 2, 1))  # (T, 4, 3): edges as columns
    a = np.concatenate([e, -np.broadcast_to(d, (len(tets), 4))[:, :, None]], axis=2)  # (T, 4, 4)
    keep = np.abs(np.linalg.det(a)) > 1e-12
    a, t0 = a[keep], tets[keep, 0]
    out = []
    for p in np.atleast_2d(points):
        sol = np.linalg.solve(a, (p - t0)[:, :, None])[:, :, 0]  # barycentrics 1..3, then ray t
        lam, t = sol[:, :3], sol[:, 3]
        hit = (t > 0) & (lam >= 0).all(axis=1) & (lam.sum(axis=1) <= 1)
        out.append(bool(hit.sum() % 2))
    return np.array(out)


def _corners(world, body, shrink: float) -> np.ndarray:
    """The 16 corners of a box body, each moved ``shrink`` metres in along every axis."""
    h = world.bodies.half_extents[body] - shrink
    signs = np.array([[1 if (j >> a) & 1 else -1 for a in range(4)] for j in range(16)], dtype=np.float64)
    return world.body_position(body) + (signs * h) @ world.body_rotation(body).T


@pytest.mark.parametrize("which", [0, 1])
def test_the_arches_are_closed_and_their_tets_point_out(arches, which):
    tets = arches[which]
    _, planes, _, _ = tet_geometry(tets)
    assert len(planes) == len(tets) > 50  # no tet dropped as degenerate
    centroids = tets.mean(axis=1)
    eps = 2e-4  # under the 1 mm between the box arch's legs and its lintel
    assert not inside_mesh(centroids + eps * planes[:, :4], tets).any()  # just outside every face
    assert inside_mesh(centroids - eps * planes[:, :4], tets).all()  # just inside every face
    # In the doorway is outside, in a leg and in the top inside.
    z = 8.0 if which == 0 else 0.0
    pts = np.array([[0.0, 1.0, z, 0.0], [-1.1, 1.0, z, 0.1], [0.0, 2.45, z, -0.4], [0.0, 1.0, z, 0.7]])
    if which == 0:
        pts[1, 0], pts[2, 1] = -1.25, 3.2
    assert list(inside_mesh(pts, tets)) == [False, True, True, False]


def test_a_ball_and_boxes_dropped_on_the_arch_rest_on_its_top(arch):
    world = PhysicsWorld()  # with the ground y = 0
    world.set_static_tets([arch])
    ball = world.add_body(BodyDef("hypersphere", radius=0.3, position=(-0.3, 4.0, 0.02, 0.05)))
    # A small box over the lintel's end, 0.1 m of it beyond the end.
    box = world.add_body(BodyDef("hypercube", size=0.4, position=(-1.1, 4.5, 0.0, 0.0)))
    # A box wider than the top (0.6 m deep in z, it is 1 m): held by the top's edges, no corner over it.
    wide = world.add_body(BodyDef("hypercube", size=1.0, position=(0.65, 5.0, 0.0, 0.1)))
    lowest = {ball: np.inf, box: np.inf, wide: np.inf}
    rest = {ball: TOP + 0.3, box: TOP + 0.2, wide: TOP + 0.5}
    for _ in range(240):
        world.step(1 / 60)
        for b in lowest:
            lowest[b] = min(lowest[b], world.body_position(b)[1] - rest[b])
    for b, y in rest.items():
        assert world.body_position(b)[1] == pytest.approx(y, abs=HEIGHT_TOL)
        assert lowest[b] > -SLOP  # never sank into the top, even landing
        assert world.is_sleeping(b)
    # Landing off-centre spins it a little (as on a box collider); it stays on the top.
    assert world.body_position(box)[0] == pytest.approx(-1.1, abs=0.03)
    assert abs(world.body_position(wide)[2]) < 0.1  # landing on two edges nudges it a few cm, no more


def test_a_ball_on_the_round_arch_rolls_off_its_curved_top_and_lands_beside_it(arches):
    round_arch = arches[0]
    world = PhysicsWorld()
    world.set_static_tets([round_arch])
    ball = world.add_body(BodyDef("hypersphere", radius=0.25, position=(0.05, 4.5, 8.0, 0.0)))
    for _ in range(300):
        world.step(1 / 60)
        assert not inside_mesh(world.body_position(ball), round_arch)[0]
    x, y, _, _ = world.body_position(ball)
    assert abs(x) > 1.5 + 0.25 - SLOP and y == pytest.approx(0.25, abs=HEIGHT_TOL)  # on the ground, outside


def test_bodies_thrown_through_the_doorway_pass_and_those_thrown_at_a_leg_bounce_back(arch):
    world = PhysicsWorld()
    world.set_static_tets([arch])
    v = (0.0, 0.0, 8.0, 0.0)
    through = world.add_body(BodyDef("hypersphere", radius=0.4, position=(0.0, 1.2, -4.0, 0.0), velocity=v))
    leg = world.add_body(
        BodyDef("hypersphere", radius=0.4, position=(-1.0, 1.2, -4.0, 0.0), velocity=v, restitution=0.5)
    )
    box = world.add_body(BodyDef("hypercube", size=0.6, position=(0.2, 1.5, -4.0, 0.1), velocity=v))
    box_leg = world.add_body(BodyDef("hypercube", size=0.6, position=(1.0, 1.5, -4.0, 0.0), velocity=v))
    nearest = np.inf
    bounced = False
    for _ in range(90):
        world.step(1 / 60)
        nearest = min(nearest, -0.3 - world.body_position(leg)[2])
        bounced |= world.body_velocity(leg)[0][2] < -1.0
        assert not inside_mesh(world.body_position(leg), arch)[0]
        assert not inside_mesh(_corners(world, box_leg, SLOP), arch).any()
    assert world.body_position(through)[2] > 3.0  # through the 1.6 m wide doorway
    assert world.body_position(box)[2] > 3.0
    assert nearest > 0.4 - SLOP  # the ball thrown at the leg never went into it...
    assert bounced and world.body_position(leg)[2] < -0.3 - 0.4  # ...and bounced back
    assert world.body_position(box_leg)[2] < -0.3 - 0.3 + SLOP  # the box stopped at the leg


def test_rays_hit_the_arch_where_it_is_and_pass_its_doorway(arch):
    world = PhysicsWorld(WorldDef(ground=False))
    world.set_static_tets([arch])
    assert world.raycast((0.0, 1.0, -3.0, 0.0), (0, 0, 1, 0), 10.0) is None  # through the doorway
    who, t, _, normal = world.raycast((-1.1, 1.0, -3.0, 0.2), (0, 0, 1, 0), 10.0)
    assert who == "world" and t == pytest.approx(2.7, abs=1e-6)  # the leg's face at z = -0.3 (float32 mesh)
    assert np.allclose(normal, [0, 0, -1, 0], atol=1e-9)
    _, t, _, normal = world.raycast((0.3, 9.0, 0.1, -0.2), (0, -1, 0, 0), 10.0)
    assert t == pytest.approx(9.0 - TOP, abs=1e-6) and np.allclose(normal, [0, 1, 0, 0], atol=1e-9)
    d = np.array([0.0, -1.0, 0.0, 1.0])  # from kata of the arch, down and ana: meets its w = -0.5 face
    _, t, p, normal = world.raycast((0.3, 3.0, 0.1, -1.0), d, 20.0)
    assert t == pytest.approx(np.sqrt(2) * 0.5, abs=1e-6) and np.allclose(normal, [0, 0, 0, -1], atol=1e-9)
    # A ray from inside passes out of it (as from inside a body).
    assert world.raycast((0.0, 2.4, 0.0, 0.0), (0, 1, 0, 0), 10.0) is None


def test_a_box_on_a_turning_arch_goes_down_with_it_or_falls_and_is_never_inside_it(tmp_path):
    game = _game(tmp_path, crate=[0.5, 2.86, 0.0, 0.0])
    arch = game.entities.named("arch")
    body = game.entities.named("crate").motion.body
    world = game.physics
    heights = []
    for tick in range(300):
        # The arch turns about its foot in xy, 12 degrees a second: its top tilts and comes down.
        arch.motion.move(pose((0.0, 0.0, 0.0, 0.0), {"xy": np.radians(12.0 * tick / 60.0)}))
        game.step(Actions())
        tets = tet_colliders(game)[1]
        assert not inside_mesh(_corners(world, body, SLOP), tets).any(), f"inside the arch at tick {tick}"
        heights.append(world.body_position(body)[1])
    assert heights[20] == pytest.approx(TOP + 0.25, abs=0.05)  # on the top while it has hardly turned
    assert heights[-1] < 2.0  # went down with the top (it turned 60 degrees) or slid off it


def test_a_ball_bounces_off_the_arch_as_high_as_off_the_same_box(arch):
    """Restitution 0.5: the rebound reaches e^2 = 1/4 of the drop, as on the lintel given as a solid box."""
    rebounds = []
    for as_tets in (True, False):
        world = PhysicsWorld(WorldDef(world_restitution=0.5))
        if as_tets:
            world.set_static_tets([arch])
        else:
            world.set_static_solids([((0.0, 2.401, 0.0, 0.0), (1.2, 0.2, 0.3, 0.5), np.eye(4))])
        ball = world.add_body(BodyDef("hypersphere", radius=0.3, position=(0.0, 4.0, 0.0, 0.0), restitution=0.5))
        ys = []
        for _ in range(120):
            world.step(1 / 60)
            ys.append(world.body_position(ball)[1])
        first = int(np.argmin(ys[:60]))  # the first touch
        rebounds.append(max(ys[first:]) - (TOP + 0.3))
    drop = 4.0 - (TOP + 0.3)
    assert rebounds[0] == pytest.approx(rebounds[1], rel=0.02)
    assert rebounds[0] == pytest.approx(0.25 * drop, rel=0.2)  # a 60 Hz tick blurs the touch


def test_meshes_handed_over_again_change_nothing_and_a_removed_one_drops_what_rested_on_it(arch):
    world = PhysicsWorld()
    world.set_static_tets([arch])
    box = world.add_body(BodyDef("hypercube", size=0.4, position=(0.0, TOP + 0.25, 0.0, 0.0)))
    for _ in range(120):
        world.step(1 / 60)
    assert world.is_sleeping(box)
    static = world.static
    world.set_static_tets([arch])  # the same mesh again: nothing changes, the box sleeps on
    assert world.static is static and world.is_sleeping(box)
    with pytest.raises(ValueError, match="1 tet meshes but 2 motions"):
        world.set_static_tets([arch], [np.zeros((4, 5))] * 2)
    world.set_static_tets([])  # the arch is gone (a door opened): the box wakes and falls
    assert not world.is_sleeping(box)
    for _ in range(60):
        world.step(1 / 60)
    assert world.body_position(box)[1] < TOP - 1.0


def test_the_bench_line_times_both_floors_in_the_same_run():
    from across_dimensions.physics.bench import bench_tet_mesh

    r = bench_tet_mesh(n_bodies=4, tiles=2, ticks=2)
    assert r["tets"] == 4 * 48  # a lifted box is 48 tets
    assert r["tet_cpu_ms"] >= 0.0 and r["box_cpu_ms"] >= 0.0
    assert r["tet_contacts"] > 0 and r["box_contacts"] > 0  # the bodies rest on both floors


def _test_level(name: str, w_range=(-1.0, 1.0)) -> LevelBuilder:
    """A level: a 30 m floor, the spawn and a goal far away."""
    return LevelBuilder(
        name,
        w_range=w_range,
        spawn=(0.0, 0.0, -8.0, 0.0),
        goal=(0.0, 1.0, 9.0),
        goal_size=(1.0, 1.0, 1.0),
        floor=(30.0, 1.0, 30.0),
    )


def arch_level() -> LevelBuilder:
    """An arch asset at every w (x from -1.5 to 1.5, y from 0 to 3.5, z from -0.25 to 0.25, a doorway
    in the middle), two balls rolling at it and a box falling on its top."""
    ball = dict(scale=0.25, body="hypersphere", velocity=[0.0, 0.0, 6.0, 0.0])
    return (
        _test_level("Arch test")
        .mesh("meshes/arch.obj", position=(0.0, 0.0, 0.0))
        .object([0.0, 0.6, -3.0, 0.0], "hypersphere", name="through", **ball)
        .object([1.25, 0.6, -3.0, 0.0], "hypersphere", name="blocked", **ball)
        .object([0.0, 5.0, 0.0, 0.0], name="top", scale=0.4, body="hypercube")
    )


def test_bodies_meet_a_mesh_part_by_its_true_surface_not_its_box(tmp_path):
    """A ``[[mesh]]`` arch (the same at every w): a ball rolls through its doorway, which its
    bounding box would close; one aimed at a leg bounces back; a box lands on its top."""
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game

    game = Game(arch_level().load(tmp_path, "arch.toml"))
    for _ in range(150):
        game.step(Actions())
    at = {n: game.entities.named(n).center(game) for n in ("through", "blocked", "top")}
    assert at["through"][2] > 3.0  # through the doorway
    assert at["blocked"][2] < -0.25 - 0.25 + 1e-6  # stopped in front of the leg, never in it
    assert at["top"][1] == pytest.approx(3.5 + 0.2, abs=0.01)  # resting on the top, half its size up


def test_prism_tets_point_out_of_the_solid():
    from across_dimensions.core.mesh import cross4
    from across_dimensions.world.scene import prism_tets

    # A unit cube's surface, wound inward on purpose: the prism turns it outward.
    v = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.float64)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = np.array([v[[a, c, b]] for a, b, c, d in quads] + [v[[a, d, c]] for a, b, c, d in quads])
    tets = prism_tets(tris, -2.0, 2.0)
    assert tets.shape == (3 * 12, 4, 4)
    n = cross4(tets[:, 1] - tets[:, 0], tets[:, 2] - tets[:, 0], tets[:, 3] - tets[:, 0])
    centre = tets.mean(axis=1)
    assert np.all(np.abs(n[:, 3]) < 1e-12)  # the side of a prism along w
    assert np.all(np.einsum("ij,ij->i", n[:, :3], centre[:, :3] - 0.5) > 0.0)  # outward


def world_level() -> LevelBuilder:
    """A table 1 m high that exists from w = -0.6 to 0.6, a crate over it and one at w = 1.2."""
    table = {"center": [0.0, 0.5, 0.0], "size": [2.0, 1.0, 2.0]}
    return (
        _test_level("World test", (-2.0, 2.0))
        .world(0.0, 1.2, name="table", profile="prism", boxes=[table])
        .object([0.0, 3.0, 0.0, 0.0], name="on", scale=0.4, body="hypercube")
        .object([0.0, 3.0, 0.0, 1.2], name="beside", scale=0.4, body="hypercube")
    )


def test_bodies_meet_an_extended_world_where_it_exists_along_w(tmp_path):
    """An extended world is met as its own 4D mesh: a crate at its w lands on the table's top;
    one at a w where the table is absent falls to the floor through where it would be."""
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game

    game = Game(world_level().load(tmp_path, "world.toml"))
    for _ in range(150):
        game.step(Actions())
    on, beside = (game.entities.named(n).center(game) for n in ("on", "beside"))
    assert on[1] == pytest.approx(1.0 + 0.2, abs=0.01)
    assert beside[1] == pytest.approx(0.2, abs=0.01)


def manipulable_level(ball=(0.0, 3.5, 0.0, 0.0)) -> LevelBuilder:
    """A 24-cell and a slab the player may turn, and a ball dropped at ``ball``."""
    return (
        _test_level("Manipulable test")
        .object([0.0, 1.0, 0.0, 0.0], "24-cell", name="pink", solid=True)
        .object([4.0, 0.5, 0.0, 0.0], name="slab", solid=True)
        .object(ball, "hypersphere", name="ball", scale=0.25, body="hypersphere")
        .add("manipulable", object="pink", max={"xw": 90.0})
        .add("manipulable", object="slab", max={"xw": 90.0})
    )


def test_a_manipulable_that_is_not_a_box_is_met_by_its_true_shape(tmp_path):
    """A box-shaped manipulable is its own kinematic hypercube (exact); any other shape (here a
    24-cell) is its boundary tets, not its bounding box: a ball dropped over a slanted facet,
    inside the bounding box's top, slides off it instead of resting on the box, and is never
    inside the 24-cell."""
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game

    game = Game(manipulable_level(ball=(0.6, 3.5, 0.6, 0.0)).load(tmp_path, "manip.toml"))
    pink, slab = game.entities.named("pink"), game.entities.named("slab")
    assert pink.data.body is None and slab.data.body is not None
    assert any(len(t) for t in tet_colliders(game))
    # This 24-cell: |x_i| <= 1/sqrt(2) and |x| + |y| + |z| + |w| <= sqrt(2), centred at y = 1.
    h = 1.0 / np.sqrt(2.0)
    nearest = np.inf
    for _ in range(180):
        game.step(Actions())
        local = np.abs(game.entities.named("ball").center(game) - np.array([0.0, 1.0, 0.0, 0.0]))
        nearest = min(nearest, max(float(local.max()) - h, float(local.sum()) / 2.0 - h))
    ball = game.entities.named("ball").center(game)
    assert nearest > 0.25 - 0.05  # the ball (radius 0.25) never sank into it (facet distance: a lower bound)
    box_top = 1.0 + h + 0.25
    assert not (abs(ball[1] - box_top) < 0.05 and abs(ball[0] - 0.6) < 0.05)  # not held up by the box
