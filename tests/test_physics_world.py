"""The game-facing API: determinism, player collider, ray casts, events, world geometry."""

import numpy as np
import pytest

from across_dimensions.core import transform
from across_dimensions.game.player_bodies import player_collide
from across_dimensions.physics import BodyDef, ContactEvent, PhysicsWorld, WorldDef
from across_dimensions.physics.bench import bench_physics, build_pile


def _scene(seed=3, n=24):
    rng = np.random.default_rng(seed)
    world = PhysicsWorld()
    world.set_static_boxes([((0.0, 0.25, 2.0), (1.0, 0.25, 0.5))])
    for k in range(n):
        p = np.array([rng.uniform(-1.5, 1.5), 0.6 + 0.7 * k, rng.uniform(-1.5, 1.5), rng.uniform(-0.5, 0.5)])
        if k % 2:
            world.add_body(
                BodyDef(
                    "hypercube",
                    size=rng.uniform(0.4, 0.8),
                    position=p,
                    angles={"xw": rng.uniform(-1, 1), "yz": rng.uniform(-1, 1)},
                    angular_velocity=rng.normal(size=6),
                )
            )
        else:
            world.add_body(
                BodyDef(
                    "hypersphere",
                    radius=rng.uniform(0.2, 0.4),
                    position=p,
                    velocity=rng.normal(size=4),
                    restitution=0.4,
                )
            )
    return world


# ---------------------------------------------------------------- determinism
def test_replay_is_bit_identical():
    hashes = []
    states = []
    for _ in range(2):
        world = _scene()
        for t in range(150):
            world.step(1 / 60)
            if t == 70:
                world.push(3, (0.5, 1.0, 0.0, -0.5), point=world.body_position(3) + 0.1)
        hashes.append(world.state_hash())
        states.append(world.state_bytes())
    assert states[0] == states[1]
    assert hashes[0] == hashes[1]
    # and the scene did something: a different push gives a different state.
    world = _scene()
    for t in range(150):
        world.step(1 / 60)
        if t == 70:
            world.push(3, (0.5, 1.0, 0.0, -0.5000001), point=world.body_position(3) + 0.1)
    assert world.state_hash() != hashes[0]


_REPLAY = """
import sys
sys.path.insert(0, {tests!r})
from test_physics_world import _scene
world = _scene()
for t in range(90):
    world.step(1 / 60)
print(world.state_hash())
"""


def test_replay_in_a_fresh_process_is_bit_identical():
    # Nothing may depend on the process: hash seeds, addresses, the clock.
    import os
    import subprocess
    import sys

    world = _scene()
    for _ in range(90):
        world.step(1 / 60)
    code = _REPLAY.format(tests=os.path.dirname(__file__))
    env = dict(os.environ, PYTHONHASHSEED="123")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True, timeout=300)
    assert out.stdout.strip().splitlines()[-1] == world.state_hash()


def test_sleeping_bodies_cost_no_contacts():
    world = PhysicsWorld()
    for k in range(6):
        world.add_body(BodyDef("hypercube", size=0.5, position=(0.6 * k, 0.25, 0, 0.3 * k)))
        world.add_body(BodyDef("hypercube", size=0.5, position=(0.6 * k, 0.76, 0, 0.3 * k)))
    for _ in range(120):
        world.step(1 / 60)
    assert not world.bodies.awake[:12].any()
    world.step(1 / 60)
    assert world.last_contact_count == 0


def test_step_runs_fixed_ticks_whatever_the_frame_time():
    a, b = _scene(n=6), _scene(n=6)
    for _ in range(60):
        a.step(1 / 60)
    ran = 0
    for dt in [1 / 120] * 40 + [1 / 30] * 20:
        ran += b.step(dt)
    assert ran == 60
    assert a.state_bytes() != b"" and np.array_equal(a.bodies.position, b.bodies.position)
    assert a.step(0.0) == 0


# ---------------------------------------------------------------- bodies & API
def test_body_pose_is_a_model_matrix():
    world = PhysicsWorld(WorldDef(ground=False, gravity=(0, 0, 0, 0)))
    b = world.add_body(BodyDef("hypercube", size=(1, 2, 3, 4), position=(1, 2, 3, 4), angles={"xw": 0.4}))
    pose = world.body_pose(b)
    assert pose.shape == (5, 5)
    np.testing.assert_allclose(pose, transform.pose((1, 2, 3, 4), {"xw": 0.4}), atol=1e-15)
    corner = np.array([0.5, 1.0, 1.5, 2.0])
    np.testing.assert_allclose(transform.apply(pose, corner), transform.rotation4("xw", 0.4) @ corner + [1, 2, 3, 4])
    with pytest.raises(ValueError):
        world.add_body(BodyDef("cylinder"))
    with pytest.raises(ValueError):
        world.add_body(BodyDef("hypersphere", radius=-1))
    with pytest.raises(ValueError):
        world.add_body(BodyDef("hypercube", kind="floating"))


def test_pose_interpolates_between_ticks():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), ground=False))
    b = world.add_body(BodyDef("hypercube", size=1.0, velocity=(0, 0, 0, 6.0), angular_velocity={"xw": 3.0}))
    world.step(1 / 60)
    world.step(1 / 120)
    assert world.tick_fraction == pytest.approx(0.5)
    half = world.body_pose(b, world.tick_fraction)
    assert half[3, 4] == pytest.approx(0.05)
    np.testing.assert_allclose(half[:4, :4], transform.rotation4("xw", 0.025), atol=1e-4)
    assert transform.orthonormality_error(half[:4, :4]) < 1e-12
    np.testing.assert_array_equal(world.body_pose(b, 1.0), world.body_pose(b))


def test_static_and_kinematic_bodies():
    world = PhysicsWorld()
    floor = world.add_body(BodyDef("hypercube", size=(4, 0.2, 4, 4), position=(0, 1.0, 0, 0), kind="static"))
    ball = world.add_body(BodyDef("hypersphere", radius=0.25, position=(0, 2.0, 0, 0.5)))
    for _ in range(90):
        world.step(1 / 60)
    # The static 4D slab holds the ball up (it never moves itself).
    assert world.body_position(ball)[1] == pytest.approx(1.35, abs=0.01)
    np.testing.assert_array_equal(world.body_position(floor), [0, 1.0, 0, 0])
    # A kinematic paddle moves at its set speed and shoves the ball along w.
    paddle = world.add_body(
        BodyDef("hypercube", size=(0.5, 0.5, 0.5, 0.2), position=(0, 1.35, 0, -0.5), kind="kinematic")
    )
    world.set_velocity(paddle, (0, 0, 0, 1.0))
    for _ in range(60):
        world.step(1 / 60)
    assert world.body_position(paddle)[3] == pytest.approx(0.5, abs=1e-9)
    assert world.body_velocity(paddle)[0][3] == 1.0
    assert world.body_position(ball)[3] > 0.8
    world.push(paddle, (0, 0, 0, 100.0))  # ignored: kinematic
    assert world.body_velocity(paddle)[0][3] == 1.0


def test_world_boxes_extend_along_w():
    world = PhysicsWorld()
    world.set_static_boxes([((0.0, 0.5, 0.0), (1.0, 0.5, 1.0))])
    balls = [world.add_body(BodyDef("hypersphere", radius=0.2, position=(0, 2.0, 0, w))) for w in (-5.0, 0.0, 7.5)]
    cube = world.add_body(BodyDef("hypercube", size=0.4, position=(0.3, 2.0, -0.2, 3.0)))
    for _ in range(90):
        world.step(1 / 60)
    for b in balls:
        assert world.body_position(b)[1] == pytest.approx(1.2, abs=0.01)
    assert world.body_position(cube)[1] == pytest.approx(1.2, abs=0.01)
    # Off the box, things fall to the ground.
    side = world.add_body(BodyDef("hypersphere", radius=0.2, position=(2.0, 2.0, 0, 0)))
    for _ in range(90):
        world.step(1 / 60)
    assert world.body_position(side)[1] == pytest.approx(0.2, abs=0.01)


def test_box_wall_stops_a_sliding_hypercube():
    world = PhysicsWorld()
    world.set_static_boxes([((3.0, 1.0, 0.0), (0.5, 1.0, 2.0))])
    b = world.add_body(BodyDef("hypercube", size=0.5, position=(0, 0.25, 0, 1.0), velocity=(6, 0, 0, 0), friction=0.1))
    for _ in range(120):
        world.step(1 / 60)
    assert world.body_position(b)[0] <= 2.5 - 0.25 + 0.01


# ---------------------------------------------------------------- events
def test_contact_events_report_touches():
    world = PhysicsWorld()
    ball = world.add_body(
        BodyDef("hypersphere", radius=0.5, position=(0, 1.0, 0, 0.2), velocity=(0, -3, 0, 0), restitution=0.0)
    )
    seen = []
    for _ in range(30):
        v0 = world.body_velocity(ball)[0]
        world.step(1 / 60)
        seen.extend(world.events)
        if world.events:
            break
    assert seen, "the ball should have hit the ground"
    dv = world.body_velocity(ball)[0] - v0 - np.array(world.gravity) * world.tick_dt
    ev = seen[0]
    assert isinstance(ev, ContactEvent)
    assert ev.a == ball and ev.b == "world" and ev.began
    np.testing.assert_allclose(ev.normal, [0, -1, 0, 0], atol=1e-12)
    # Half-way across the (speculative) gap at the start of the tick.
    assert ev.point[1] == pytest.approx(0.0, abs=0.05)
    assert ev.point[3] == pytest.approx(0.2, abs=1e-9)
    # The impulse is what changed the ball's momentum beyond gravity.
    assert ev.impulse == pytest.approx(world.body_mass(ball) * dv[1], rel=1e-9)
    assert dv[1] > 1.0
    world.step(1 / 60)
    assert world.events and not world.events[0].began


def test_body_body_events_name_both_bodies():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), ground=False))
    a = world.add_body(BodyDef("hypercube", size=1.0, position=(0, 0, 0, 0)))
    b = world.add_body(BodyDef("hypersphere", radius=0.3, position=(0, 0, 0, 1.2), velocity=(0, 0, 0, -2)))
    began = []
    for _ in range(30):
        world.step(1 / 60)
        began += [e for e in world.events if e.began]
    assert len(began) == 1
    e = began[0]
    assert {e.a, e.b} == {a, b}
    assert abs(e.normal[3]) == pytest.approx(1.0)
    assert e.impulse > 0


# ---------------------------------------------------------------- player
def test_player_is_blocked_only_by_bodies_in_its_slice():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0)))
    near = world.add_body(BodyDef("hypercube", size=1.0, position=(1.0, 0.5, 0.0, 0.0)))
    far = world.add_body(BodyDef("hypercube", size=1.0, position=(-1.0, 0.5, 0.0, 0.8)))
    # Player of radius 0.3 at x = 0.3: overlaps `near` (its face at x = 0.5) by 0.1.
    corr, touched = player_collide(world, (0.3, 0.0, 0.0, 0.0), radius=0.3, height=1.8)
    assert touched == [near]
    np.testing.assert_allclose(corr, [-0.1, 0.0, 0.0], atol=1e-12)
    # The far cube overlaps in x, y, z but sits at w = 0.8: invisible, not blocking.
    corr, touched = player_collide(world, (-0.6, 0.0, 0.0, 0.0), radius=0.3, height=1.8)
    assert touched == [] and not np.any(corr)
    # Step into its slice and it blocks.
    corr, touched = player_collide(world, (-0.6, 0.0, 0.0, 0.8), radius=0.3, height=1.8)
    assert touched == [far]
    np.testing.assert_allclose(corr, [0.4, 0.0, 0.0], atol=1e-12)
    # Ignored once its 4D extent leaves the player's thin w slab.
    corr, touched = player_collide(world, (-0.6, 0.0, 0.0, 1.36), radius=0.3, height=1.8)
    assert touched == []


def test_player_sees_the_cross_section_of_a_hypersphere():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0)))
    s = world.add_body(BodyDef("hypersphere", radius=1.0, position=(0.0, 1.0, 0.0, 0.0)))
    # At w = 0.6 (slab edge 0.55) the section has radius sqrt(1 - 0.55^2).
    r3 = np.sqrt(1 - 0.55**2)
    corr, touched = player_collide(world, (r3 + 0.2, 0.0, 0.0, 0.6), radius=0.25, height=2.0)
    assert touched == [s]
    assert corr[0] == pytest.approx(0.05, abs=1e-9)
    corr, touched = player_collide(world, (r3 + 0.3, 0.0, 0.0, 0.6), radius=0.25, height=2.0)
    assert touched == []


def test_player_push_moves_touched_dynamic_bodies():
    world = PhysicsWorld()
    box = world.add_body(BodyDef("hypercube", size=0.6, position=(0.5, 0.3, 0.0, 0.0), friction=0.3))
    for _ in range(10):
        world.step(1 / 60)
    corr, touched = player_collide(world, (0.0, 0.0, 0.0, 0.0), radius=0.3, height=1.8)
    assert touched == [box] and corr[0] < 0
    for i in touched:
        world.push(i, world.body_mass(i) * np.array([1.5, 0.0, 0.0, 0.0]))
    for _ in range(30):
        world.step(1 / 60)
    assert world.body_position(box)[0] > 0.7
    # Walking into it with a velocity pushes it along (and not backwards).
    before = world.body_velocity(box)[0]
    player_collide(
        world, world.body_position(box) - (0.5, 0.3, 0.0, 0.0), radius=0.3, height=1.8, velocity=(2.0, 0.0, 0.0)
    )
    assert world.body_velocity(box)[0][0] == pytest.approx(max(2.0, before[0]))
    player_collide(
        world, world.body_position(box) + (0.5, -0.3, 0.0, 0.0), radius=0.3, height=1.8, velocity=(2.0, 0.0, 0.0)
    )
    assert world.body_velocity(box)[0][0] == pytest.approx(max(2.0, before[0]))
    # A rotated hypercube still blocks, and the correction separates.
    cube = world.add_body(
        BodyDef("hypercube", size=1.0, position=(0, 0.5, 3.0, 0.0), angles={"xz": 0.5, "zw": 0.4}, kind="static")
    )
    feet = np.array([0.0, 0.0, 2.3, 0.0])
    corr, touched = player_collide(world, feet, radius=0.3, height=1.8)
    assert cube in touched and corr[2] < 0
    corr2, touched2 = player_collide(world, feet + np.append(corr, 0.0), radius=0.3, height=1.8)
    assert cube not in touched2 or np.linalg.norm(corr2) < 1e-9


# ---------------------------------------------------------------- ray casts
def test_raycast_hits_the_nearest_body():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0)))
    s = world.add_body(BodyDef("hypersphere", radius=0.5, position=(5, 1, 0, 0)))
    c = world.add_body(BodyDef("hypercube", size=1.4, position=(8, 1, 0, 0)))
    hit = world.raycast((0, 1, 0, 0), (1, 0, 0, 0), 100)
    assert hit[0] == s
    assert hit[1] == pytest.approx(4.5)
    np.testing.assert_allclose(hit[2], [4.5, 1, 0, 0])
    np.testing.assert_allclose(hit[3], [-1, 0, 0, 0])
    # Off in w the ray passes the ball (it is in another slice) and hits the cube.
    hit = world.raycast((0, 1, 0, 0.6), (1, 0, 0, 0), 100)
    assert hit[0] == c and hit[1] == pytest.approx(7.3)
    np.testing.assert_allclose(hit[3], [-1, 0, 0, 0], atol=1e-12)
    # Max distance, misses and the ground.
    assert world.raycast((0, 1, 0, 0), (1, 0, 0, 0), 4.0) is None
    assert world.raycast((0, 1, 0, 0), (0, 1, 0, 0), 100) is None
    hit = world.raycast((0, 1, 0, 0), (0, -1, 0, 1), 100)
    assert hit[0] == "world" and hit[1] == pytest.approx(np.sqrt(2))
    np.testing.assert_allclose(hit[3], [0, 1, 0, 0])
    assert world.raycast((0, 1, 0, 0), (0, -1, 0, 0), 100, include_world=False) is None


def test_raycast_into_a_rotated_hypercube_and_world_box():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0)))
    rot = transform.angles_to_rotation({"xw": 0.3})
    c = world.add_body(BodyDef("hypercube", size=1.0, position=(0, 5, 0, 0), rotation=rot))
    hit = world.raycast((0, 5, -3, 0), (0, 0, 1, 0), 10)
    assert hit[0] == c and hit[1] == pytest.approx(2.5)
    np.testing.assert_allclose(hit[3], [0, 0, -1, 0], atol=1e-12)
    # Along x the entry face is rotated in xw.
    hit = world.raycast((-3, 5, 0, 0), (1, 0, 0, 0), 10)
    assert hit[1] == pytest.approx(3 - 0.5 / np.cos(0.3))
    np.testing.assert_allclose(hit[3], -rot[:, 0], atol=1e-12)
    world.set_static_boxes([((0, 1, 10), (1, 1, 1))])
    hit = world.raycast((0, 1, 0, 42.0), (0, 0, 1, 0), 100)
    assert hit[0] == "world" and hit[1] == pytest.approx(9.0)


# ---------------------------------------------------------------- benchmark
def test_bench_reports_timings():
    r = bench_physics(n_bodies=12, ticks=3, settle_ticks=2)
    for key in ("mean_ms", "median_ms", "empty_step_ms", "numpy_ms"):
        assert r[key] > 0
    assert r["n_bodies"] == 12


@pytest.mark.slow
def test_bench_pile_stays_inside_the_arena():
    world = build_pile(200)
    for _ in range(240):
        world.step(1 / 60)
    p = world.bodies.position[:200]
    assert p[:, 1].min() > 0.1 and p[:, 1].max() < 3.0
    assert np.abs(p[:, [0, 2, 3]]).max() < 1.5
    speed = np.linalg.norm(world.bodies.velocity[:200], axis=1)
    assert speed.max() < 1.0


def test_events_cover_exactly_the_ticks_of_the_last_step():
    world = PhysicsWorld()
    world.add_body(BodyDef("hypercube", size=0.5, position=(0, 0.25, 0, 0)))
    world.step(1 / 60)
    assert len(world.events) == 1
    world.step(0.001)  # no tick ran: nothing new happened
    assert world.events == []
    world.step(3 / 60)  # three ticks caught up: one touch each
    assert len(world.events) == 3
    assert [e.began for e in world.events] == [False, False, False]


@pytest.mark.slow
def test_random_scenes_stay_sane():
    # Mixed sizes, masses (1:100), shapes, spins and bounciness dropped from
    # up to 25 m onto world boxes: nothing blows up, sinks or passes through.
    for seed in range(3):
        rng = np.random.default_rng(seed)
        world = PhysicsWorld()
        world.set_static_boxes([((0, 0.5, 0), (1.0, 0.5, 1.0)), ((2.5, 1, 0), (0.3, 1, 2))])
        world.add_half_space((0, 0, 0, -1), -2.0)
        world.add_half_space((0, 0, 0, 1), -2.0)
        for k in range(60):
            p = np.array([rng.uniform(-2, 2), 1.5 + 0.4 * k, rng.uniform(-2, 2), rng.uniform(-1.8, 1.8)])
            if rng.random() < 0.5:
                world.add_body(
                    BodyDef(
                        "hypersphere",
                        radius=rng.uniform(0.1, 0.5),
                        position=p,
                        velocity=rng.normal(size=4) * 3,
                        restitution=rng.uniform(0, 0.9),
                    )
                )
            else:
                size = rng.uniform(0.2, 1.0, 4) if rng.random() < 0.3 else rng.uniform(0.2, 1.0)
                world.add_body(
                    BodyDef(
                        "hypercube",
                        size=size,
                        position=p,
                        mass=rng.uniform(0.2, 20),
                        angles={pl: rng.uniform(-3, 3) for pl in ("xy", "xw", "zw")},
                        angular_velocity=rng.normal(size=6) * 3,
                    )
                )
        for _ in range(600):
            world.step(1 / 60)
        pos = world.bodies.position[:60]
        assert np.isfinite(pos).all() and np.isfinite(world.bodies.velocity[:60]).all()
        b = world.bodies
        lowest = np.array([b.half_extents[i].min() if b.shape[i] == 0 else 0.0 for i in range(60)])
        assert (pos[:, 1] >= lowest - 0.02).all()
        assert (np.abs(pos[:, 3]) <= 2.0).all()
        for i in range(60):
            r = world.bodies.rotation[i]
            assert transform.orthonormality_error(r) < 1e-12
        # No energy from nowhere: nothing outruns a fall from the top (25 m).
        assert np.linalg.norm(world.bodies.velocity[:60], axis=1).max() < np.sqrt(2 * 9.81 * 26) + 3


def test_add_body_takes_a_body_def_with_defaults():
    world = PhysicsWorld()
    with pytest.raises(TypeError, match="BodyDef"):
        world.add_body("hypersphere")
    d = BodyDef()
    ball = world.add_body(d)
    assert world.body_kind(ball) == "dynamic" and not world.is_sleeping(ball)
    np.testing.assert_array_equal(world.body_position(ball), 0.0)
    # Diameter 1 by default: the hypervolume of a unit-density 4-ball of radius 1/2.
    assert world.body_mass(ball) == pytest.approx(np.pi**2 / 2 * 0.5**4)
    # One definition makes many bodies; a failed add takes no slot.
    crate = BodyDef("hypercube", size=(1, 2, 1, 1), kind="static", position=(3, 1, 0, 0))
    ids = [world.add_body(crate) for _ in range(2)]
    assert ids == [1, 2] and world.body_kind(ids[0]) == "static"
    with pytest.raises(ValueError, match="position"):
        world.add_body(BodyDef(position=(1, 2, 3)))
    assert world.body_ids == [0, 1, 2]


def test_the_static_world_is_kept_c_ordered_whatever_layout_it_is_given():
    """The tick is compiled (and shipped) for C-ordered arrays: a solid's planes or tets given
    transposed, as a hull or a lifted asset may give them, must not make numba compile it again."""
    from numba import typeof

    world = PhysicsWorld()
    axes = np.vstack([np.eye(4), -np.eye(4)])
    planes = np.asfortranarray(np.hstack([axes, np.ones((8, 1))]))  # the tesseract [-1, 1]^4
    assert not planes.flags.c_contiguous
    world.set_static_convex([(planes, -np.ones(4), np.ones(4))])
    tet = np.array([[5, 0, 0, 0], [6, 0, 0, 0], [5, 1, 0, 0], [5, 0, 1, 0]], float)
    world.set_static_tets([np.asfortranarray(tet[None])], motions=[np.asfortranarray(np.zeros((4, 5)))])
    world.add_body(BodyDef("hypercube", size=0.5, position=(0.0, 1.6, 0.0, 0.0)))
    for _ in range(60):
        world.step(1 / 60)
    assert all(typeof(a).layout == "C" for a in world.static), [str(typeof(a)) for a in world.static]
    assert world.body_position(0)[1] == pytest.approx(1.25, abs=0.02)  # resting on the tesseract's top
