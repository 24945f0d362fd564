"""Physics of the 4D rigid-body world: conservation laws, contacts, rolling, stacking."""

import numpy as np
import pytest

from across_dimensions.core import transform
from across_dimensions.physics import BodyDef, PhysicsWorld, WorldDef

G = 9.81


def _kinetic(world, ids):
    e = 0.0
    for i in ids:
        v, w = world.body_velocity(i)
        e += 0.5 * world.body_mass(i) * v @ v
        e += 0.5 * w @ world.body_inertia(i) @ w
    return e


# ---------------------------------------------------------------- free motion
def test_free_fall_matches_g():
    world = PhysicsWorld(WorldDef(ground=False))
    b = world.add_body(
        BodyDef("hypersphere", radius=0.3, position=(1.0, 50.0, -2.0, 0.5), velocity=(0.5, 0.0, 0.0, 0.25))
    )
    ticks = 90
    for _ in range(ticks):
        world.step(1 / 60)
    t = ticks / 60
    h = world.tick_dt / world.substeps
    n = ticks * world.substeps
    y = world.body_position(b)[1]
    # Semi-implicit Euler exactly: y_n = y0 - g h^2 n (n + 1) / 2 ...
    assert y == pytest.approx(50.0 - G * h * h * n * (n + 1) / 2, abs=1e-9)
    # ... which is the parabola up to its O(h) error g t h / 2.
    assert abs(y - (50.0 - G * t * t / 2)) <= G * t * h / 2 + 1e-9
    v, w = world.body_velocity(b)
    assert v[1] == pytest.approx(-G * t, rel=1e-12)
    # No force along w (or x) by default: those velocities stay.
    assert v[3] == 0.25 and v[0] == 0.5
    assert world.body_position(b)[3] == pytest.approx(0.5 + 0.25 * t, abs=1e-12)


def test_gravity_is_settable_per_level():
    world = PhysicsWorld(WorldDef(gravity=(0.0, 0.0, 0.0, -2.0), ground=False))
    b = world.add_body(BodyDef("hypercube", size=0.5))
    for _ in range(60):
        world.step(1 / 60)
    v, _ = world.body_velocity(b)
    np.testing.assert_allclose(v, [0, 0, 0, -2.0], atol=1e-12)
    world.gravity = (0, -1, 0, 0)
    np.testing.assert_allclose(world.gravity, [0, -1, 0, 0])


def test_inverse_cube_attraction():
    gc = 0.5
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), inverse_cube_G=gc, ground=False, softening=0.0))
    a = world.add_body(BodyDef("hypersphere", radius=0.1, position=(0, 0, 0, 0), mass=3.0))
    b = world.add_body(BodyDef("hypersphere", radius=0.1, position=(0, 0, 0, 2.0), mass=5.0))
    world.step(1 / 60)
    r = 2.0
    va, _ = world.body_velocity(a)
    vb, _ = world.body_velocity(b)
    dt = world.tick_dt
    # |F| = G m1 m2 / r^3 along the line of centres (here w); momentum is conserved.
    assert va[3] / dt == pytest.approx(gc * 5.0 / r**3, rel=1e-3)
    assert vb[3] / dt == pytest.approx(-gc * 3.0 / r**3, rel=1e-3)
    np.testing.assert_allclose(3.0 * va + 5.0 * vb, 0.0, atol=1e-15)
    # Doubling the distance divides the pull by eight (not four as in 3D).
    world2 = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), inverse_cube_G=gc, ground=False, softening=0.0))
    world2.add_body(BodyDef("hypersphere", radius=0.1, position=(0, 0, 0, 0), mass=3.0))
    b2 = world2.add_body(BodyDef("hypersphere", radius=0.1, position=(0, 0, 0, 4.0), mass=5.0))
    world2.step(1 / 60)
    assert world2.body_velocity(b2)[0][3] == pytest.approx(vb[3] / 8, rel=1e-3)


def test_free_tumbling_box_conserves_angular_momentum_and_energy():
    # A box with four different sides has an anisotropic inertia on bivectors, so
    # omega precesses while L = I_world omega must stay fixed in the world frame.
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), ground=False))
    b = world.add_body(
        BodyDef(
            "hypercube",
            size=(0.4, 1.0, 0.7, 1.6),
            position=(0, 5, 0, 0),
            angles={"xy": 0.3, "zw": -0.5, "yw": 0.2},
            angular_velocity=(1.0, -2.0, 0.5, 3.0, -1.5, 2.5),
            mass=2.0,
        )
    )
    _, w0 = world.body_velocity(b)
    l0 = world.body_inertia(b) @ w0
    e0 = _kinetic(world, [b])
    for _ in range(180):
        world.step(1 / 60)
    _, w1 = world.body_velocity(b)
    l1 = world.body_inertia(b) @ w1
    np.testing.assert_allclose(l1, l0, atol=1e-9 * np.linalg.norm(l0))
    assert _kinetic(world, [b]) == pytest.approx(e0, rel=1e-4)
    # It really tumbles: omega has changed direction.
    assert np.linalg.norm(w1 - w0) > 0.1
    assert transform.orthonormality_error(world.body_rotation(b)) < 1e-12


def test_free_hypercube_spin_is_steady():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), ground=False))
    w0 = np.array([0.2, 0.0, -1.0, 1.5, 0.7, -0.3])
    b = world.add_body(BodyDef("hypercube", size=1.0, angular_velocity=w0))
    for _ in range(60):
        world.step(1 / 60)
    # Isotropic inertia: omega is constant and R(t) = expm(t skew(w0)).
    np.testing.assert_allclose(world.body_velocity(b)[1], w0, atol=1e-14)
    np.testing.assert_allclose(world.body_rotation(b), transform.bivector_rotation(w0, 1.0), atol=1e-9)


# ---------------------------------------------------------------- collisions
@pytest.mark.parametrize("m2", [1.0, 3.0])
def test_elastic_head_on_collision_conserves_momentum_and_energy(m2):
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), ground=False))
    a = world.add_body(
        BodyDef(
            "hypersphere",
            radius=0.5,
            position=(-2, 1, 0, 0.3),
            velocity=(3, 0, 0, 0),
            mass=1.0,
            restitution=1.0,
            friction=0.5,
        )
    )
    b = world.add_body(
        BodyDef(
            "hypersphere",
            radius=0.5,
            position=(2, 1, 0, 0.3),
            velocity=(-1, 0, 0, 0),
            mass=m2,
            restitution=1.0,
            friction=0.5,
        )
    )
    p0 = 1.0 * world.body_velocity(a)[0] + m2 * world.body_velocity(b)[0]
    e0 = _kinetic(world, [a, b])
    for _ in range(120):
        world.step(1 / 60)
    va, vb = world.body_velocity(a)[0], world.body_velocity(b)[0]
    np.testing.assert_allclose(1.0 * va + m2 * vb, p0, atol=1e-6)
    assert _kinetic(world, [a, b]) == pytest.approx(e0, abs=1e-6)
    # The 1D elastic result.
    u1, u2 = 3.0, -1.0
    assert va[0] == pytest.approx(((1 - m2) * u1 + 2 * m2 * u2) / (1 + m2), abs=1e-6)
    assert world.body_position(a)[0] < world.body_position(b)[0]


@pytest.mark.parametrize("e", [0.0, 0.5, 0.8])
def test_restitution_sets_the_bounce_speed(e):
    world = PhysicsWorld()
    r = 0.25
    b = world.add_body(BodyDef("hypersphere", radius=r, position=(0, 2 + r, 0, 0.4), restitution=e))
    before = after = None
    for _ in range(60):
        v0 = world.body_velocity(b)[0][1]
        world.step(1 / 60)
        v1 = world.body_velocity(b)[0][1]
        if world.events:
            before, after = v0, v1
            break
    assert before is not None and before < -5.0
    # The approach speed of the impact tick comes back scaled by e.
    assert after == pytest.approx(-e * before, abs=1e-9)


def test_hypersphere_slides_into_rolling_with_four_d_inertia():
    # Friction converts slip into spin until the contact point rests. With the
    # 4-ball's plane inertia m r^2 / 3 the final speed is v0 / (1 + 1/3) = 3/4 v0
    # (5/7 in 3D). The slide is along x + w so the spin is in the xy and yw planes.
    world = PhysicsWorld()
    r = 0.4
    d = np.array([1.0, 0.0, 0.0, 1.0]) / np.sqrt(2)
    v0 = 4.0
    b = world.add_body(BodyDef("hypersphere", radius=r, position=(0, r, 0, 0), velocity=v0 * d, friction=0.6))
    for _ in range(120):
        world.step(1 / 60)
    v, w = world.body_velocity(b)
    assert v @ d == pytest.approx(0.75 * v0, rel=2e-3)
    contact = v + transform.skew(w) @ np.array([0.0, -r, 0.0, 0.0])
    assert np.linalg.norm(contact) < 1e-3 * np.linalg.norm(v)
    assert w[0] == pytest.approx(-v[0] / r, rel=1e-3)  # xy
    assert w[4] == pytest.approx(v[3] / r, rel=1e-3)  # yw
    assert world.body_position(b)[1] == pytest.approx(r, abs=5e-3)


def test_spin_friction_and_rolling_resistance_stop_a_ball():
    # Spinning in place in the xz plane (parallel to the ground) is braked by
    # the contact patch; rolling only by the optional rolling resistance.
    world = PhysicsWorld(WorldDef(rolling_resistance=0.05))
    r = 0.3
    spinner = world.add_body(
        BodyDef("hypersphere", radius=r, position=(0, r, 0, 0), angular_velocity={"xz": 5.0, "zw": -3.0})
    )
    roller = world.add_body(
        BodyDef(
            "hypersphere", radius=r, position=(3, r, 0, 0), velocity=(0, 0, 0, 2.0), angular_velocity={"yw": 2.0 / r}
        )
    )
    ideal = PhysicsWorld()
    free = ideal.add_body(
        BodyDef(
            "hypersphere", radius=r, position=(0, r, 0, 0), velocity=(0, 0, 0, 2.0), angular_velocity={"yw": 2.0 / r}
        )
    )
    for _ in range(600):
        world.step(1 / 60)
        ideal.step(1 / 60)
    assert world.is_sleeping(spinner) and world.is_sleeping(roller)
    assert world.body_position(roller)[3] > 1.0
    # Without rolling resistance the ball rolls on at its speed.
    assert ideal.body_velocity(free)[0][3] == pytest.approx(2.0, rel=1e-3)


def test_hypersphere_rolls_down_a_slope_without_slipping():
    theta = 0.3
    world = PhysicsWorld(WorldDef(ground=False))
    # Slope: the solid below a plane through the origin tilted in the xy plane.
    n = np.array([np.sin(theta), np.cos(theta), 0.0, 0.0])
    world.add_half_space(n, 0.0)
    r = 0.5
    b = world.add_body(BodyDef("hypersphere", radius=r, position=r * n, friction=0.8))
    down = np.array([np.cos(theta), -np.sin(theta), 0.0, 0.0])
    speeds = []
    for _ in range(90):
        world.step(1 / 60)
        speeds.append(world.body_velocity(b)[0] @ down)
    v, w = world.body_velocity(b)
    # Rolling without slipping: the contact point is at rest.
    contact = v + transform.skew(w) @ (-r * n)
    assert np.linalg.norm(contact) < 2e-3 * np.linalg.norm(v)
    # and the acceleration is g sin(theta) / (1 + I / (m r^2)) = 3/4 g sin(theta).
    acc = (speeds[-1] - speeds[29]) / (60 / 60)
    assert acc == pytest.approx(0.75 * G * np.sin(theta), rel=5e-3)
    # It stays on the slope.
    assert world.body_position(b) @ n == pytest.approx(r, abs=5e-3)


def test_off_centre_hit_tumbles_a_hypercube_through_w_planes():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), ground=False))
    cube = world.add_body(
        BodyDef(
            "hypercube",
            size=1.0,
            position=(0, 0, 0, 0),
            angles={"xy": 0.2, "zw": 0.3, "xw": 0.25, "yz": -0.15},
            mass=1.0,
        )
    )
    ball = world.add_body(
        BodyDef("hypersphere", radius=0.2, position=(-2.0, 0.3, -0.25, 0.35), velocity=(4.0, 0.0, 0.0, 0.0), mass=0.5)
    )
    for _ in range(60):
        world.step(1 / 60)
    _, w = world.body_velocity(cube)
    xw, yw, zw = w[3], w[4], w[5]
    assert min(abs(xw), abs(yw), abs(zw)) > 0.02
    # Momentum and angular momentum about the origin are conserved by the hit.
    p = world.body_velocity(cube)[0] + 0.5 * world.body_velocity(ball)[0]
    np.testing.assert_allclose(p, [2.0, 0, 0, 0], atol=1e-9)


def test_push_at_a_point_spins_the_body():
    world = PhysicsWorld(WorldDef(gravity=(0, 0, 0, 0), ground=False))
    b = world.add_body(BodyDef("hypercube", size=1.0, mass=2.0))
    world.push(b, (0, 0, 0, 1.0), point=(0.5, 0, 0, 0))
    v, w = world.body_velocity(b)
    np.testing.assert_allclose(v, [0, 0, 0, 0.5])
    # r ^ p = 0.5 in the xw plane; plane inertia m (1 + 1) / 12 = 1/3.
    np.testing.assert_allclose(w, [0, 0, 0, 1.5, 0, 0], atol=1e-12)


# ---------------------------------------------------------------- resting
def _stack(allow_sleep):
    world = PhysicsWorld(WorldDef(allow_sleep=allow_sleep))
    ids = [
        world.add_body(
            BodyDef("hypercube", size=1.0, position=(0.02 * k, 0.5 + 1.0 * k + 0.01 * k, 0, -0.01 * k), friction=0.6)
        )
        for k in range(3)
    ]
    return world, ids


def test_stack_of_three_hypercubes_settles_and_stays():
    world, ids = _stack(allow_sleep=False)
    for _ in range(300):
        world.step(1 / 60)
    rest = np.array([world.body_position(i) for i in ids])
    speeds = []
    for _ in range(120):
        world.step(1 / 60)
        speeds.append(max(np.linalg.norm(np.concatenate(world.body_velocity(i))) for i in ids))
    after = np.array([world.body_position(i) for i in ids])
    assert max(speeds) < 1e-3
    assert np.abs(after - rest).max() < 1e-3
    # Resting on each other, not sunk in: centres 1 m apart, bottom on the ground.
    np.testing.assert_allclose(after[:, 1], [0.5, 1.5, 2.5], atol=0.01)
    for i in ids:
        assert np.abs(world.body_rotation(i) - np.eye(4)).max() < 1e-3


def test_stack_sleeps_and_wakes_when_touched():
    world, ids = _stack(allow_sleep=True)
    for _ in range(300):
        world.step(1 / 60)
    assert all(world.is_sleeping(i) for i in ids)
    resting = [world.body_pose(i) for i in ids]
    for _ in range(30):
        world.step(1 / 60)
    # Asleep means frozen exactly, at zero velocity.
    for i, pose in zip(ids, resting):
        np.testing.assert_array_equal(world.body_pose(i), pose)
        assert not np.any(np.concatenate(world.body_velocity(i)))
    # A ball dropped on top wakes the whole stack (one island), not just the top.
    ball = world.add_body(BodyDef("hypersphere", radius=0.3, position=(0.0, 4.0, 0.0, 0.0)))
    woke = False
    for _ in range(60):
        world.step(1 / 60)
        woke = woke or not any(world.is_sleeping(i) for i in ids)
    assert woke
    for _ in range(300):
        world.step(1 / 60)
    assert all(world.is_sleeping(i) for i in ids + [ball])
    assert world.body_position(ball)[1] == pytest.approx(3.3, abs=0.01)
    # A push wakes the body it is applied to, and it moves.
    world.push(ids[2], (0.0, 0.0, 0.0, 0.5))
    assert not world.is_sleeping(ids[2])
    world.step(1 / 60)
    assert world.body_velocity(ids[2])[0][3] > 0


def test_removing_support_wakes_sleepers():
    world, ids = _stack(allow_sleep=True)
    for _ in range(300):
        world.step(1 / 60)
    assert world.is_sleeping(ids[1])
    world.remove_body(ids[0])
    assert not world.is_sleeping(ids[1])
    for _ in range(60):
        world.step(1 / 60)
    assert world.body_position(ids[1])[1] == pytest.approx(0.5, abs=0.02)
    with pytest.raises(KeyError):
        world.body_pose(ids[0])
