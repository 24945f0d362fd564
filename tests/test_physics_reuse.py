"""Kept box manifolds: reused only while a pair barely moves, never inherited, part of the state."""

import numpy as np

from across_dimensions.core import transform
from across_dimensions.physics import BodyDef, PhysicsWorld, WorldDef, collide, reuse
from across_dimensions.physics.bench import build_pile


def _rot(angles):
    return transform.angles_to_rotation(dict(zip(transform.PLANES, angles)))


def _box_box(xa, ra, ha, xb, rb, hb, margin):
    cp, cd = np.zeros((collide.SCRATCH_POINTS, 4)), np.zeros(collide.SCRATCH_POINTS)
    wk = np.zeros((collide.SCRATCH_ROWS, 4))
    op, on, od = np.zeros((8, 4)), np.zeros((8, 4)), np.zeros(8)
    n = max(collide.box_box(xa, ra, ha, xb, rb, hb, margin, cp, cd, wk, op, on, od, 0), 0)
    return op[:n].copy(), on[:n].copy(), od[:n].copy()


def _kept_points(xa, ra, xb, rb, pts, nrm, dep, margin):
    local = np.zeros((8, 12))
    reuse.keep_points((pts, nrm, dep), 0, len(dep), (xa, ra), (xb, rb), local, 0)
    op, on, od = np.zeros((8, 4)), np.zeros((8, 4)), np.zeros(8)
    n = reuse.emit_kept(local, 0, len(dep), (xa, ra), (xb, rb), margin, (op, on, od), 0)
    return local, (op[:n], on[:n], od[:n])


def test_kept_points_come_back_unchanged_and_ride_along_rigidly():
    # A tilted hypercube resting on a bigger one: a manifold of several corners.
    xa, ra, ha = np.zeros(4), np.eye(4), np.full(4, 0.5)
    xb, rb, hb = np.array([0.05, 0.93, -0.02, 0.04]), _rot([0.02, 0, 0.01, 0, 0.03, 0]), np.full(4, 0.45)
    pts, nrm, dep = _box_box(xa, ra, ha, xb, rb, hb, 0.02)
    assert len(dep) >= 4
    local, (p2, n2, d2) = _kept_points(xa, ra, xb, rb, pts, nrm, dep, 0.02)
    np.testing.assert_allclose(p2, pts, atol=1e-14)
    np.testing.assert_allclose(n2, nrm, atol=1e-14)
    np.testing.assert_allclose(d2, dep, atol=1e-14)
    # Both bodies moved and turned together: the same contact, carried along.
    turn, shift = _rot([0.3, -0.2, 0.5, 0.1, 0.0, 0.4]), np.array([1.0, -2.0, 0.5, 3.0])
    op, on, od = np.zeros((8, 4)), np.zeros((8, 4)), np.zeros(8)
    frame_a, frame_b = (shift + turn @ xa, turn @ ra), (shift + turn @ xb, turn @ rb)
    n = reuse.emit_kept(local, 0, len(dep), frame_a, frame_b, 0.02, (op, on, od), 0)
    assert n == len(dep)
    np.testing.assert_allclose(od[:n], dep, atol=1e-12)
    np.testing.assert_allclose(op[:n], shift + pts @ turn.T, atol=1e-12)
    np.testing.assert_allclose(on[:n], nrm @ turn.T, atol=1e-12)


def test_kept_depths_follow_a_small_relative_motion():
    xa, ra, ha = np.zeros(4), np.eye(4), np.full(4, 0.5)
    xb, rb, hb = np.array([0.05, 0.93, -0.02, 0.04]), np.eye(4), np.full(4, 0.45)
    pts, nrm, dep = _box_box(xa, ra, ha, xb, rb, hb, 0.02)
    local, _ = _kept_points(xa, ra, xb, rb, pts, nrm, dep, 0.02)
    # b sinks 0.4 mm and slides: each kept point's depth grows by the sink (the
    # full test agrees: a face contact's depth does not depend on the slide).
    xb2 = xb + np.array([0.0003, -0.0004, 0.0002, 0.0])
    op, on, od = np.zeros((8, 4)), np.zeros((8, 4)), np.zeros(8)
    n = reuse.emit_kept(local, 0, len(dep), (xa, ra), (xb2, rb), 0.02, (op, on, od), 0)
    _, _, fresh = _box_box(xa, ra, ha, xb2, rb, hb, 0.02)
    np.testing.assert_allclose(od[:n], dep + 0.0004, atol=1e-12)
    np.testing.assert_allclose(np.sort(od[:n]), np.sort(fresh), atol=1e-12)


def _stack(reuse_angle):
    world = PhysicsWorld(WorldDef(allow_sleep=False, reuse_angle=reuse_angle))
    for k in range(5):
        world.add_body(
            BodyDef("hypercube", size=0.5, position=(0.02 * k, 0.25 + 0.5 * k, 0.0, -0.01 * k), angles={"xw": 0.01 * k})
        )
    return world


def test_a_resting_stack_reuses_its_manifolds_and_rests_as_without():
    kept, fresh = _stack(np.radians(2.0)), _stack(0.0)
    for _ in range(240):
        kept.step(1.0 / 60.0)
        fresh.step(1.0 / 60.0)
    assert int(kept._kept[0].pairs[0]) == 5  # four box pairs and the ground pair of the bottom box
    assert int(fresh._kept[0].pairs[0]) == 0
    np.testing.assert_allclose(kept.bodies.position[:5], fresh.bodies.position[:5], atol=2e-3)
    assert np.abs(kept.bodies.velocity[:5]).max() < 1e-2


def test_a_pair_that_moves_past_the_tolerance_is_tested_again():
    world = _stack(np.radians(2.0))
    for _ in range(120):
        world.step(1.0 / 60.0)
    kept = world._kept[0]
    before = kept.pose[: int(kept.pairs[0])].copy()
    # Turn the top box by 5 degrees: its pair with the box below is found again.
    top = 4
    world.set_pose(top, rotation=_rot([0, 0, 0, np.radians(5.0), 0, 0]) @ world.body_rotation(top))
    world.step(1.0 / 60.0)
    kept = world._kept[0]
    after = kept.pose[: int(kept.pairs[0])]
    changed = np.any(after != before, axis=1)
    keys = kept.key[: int(kept.pairs[0])]
    assert changed[keys == ((3 << 32) | 4)].all()
    assert not changed[keys == ((0 << 32) | 1)].any()


def test_a_new_body_in_a_freed_slot_does_not_inherit_a_manifold():
    world = _stack(np.radians(2.0))
    for _ in range(60):
        world.step(1.0 / 60.0)
    world.remove_body(4)
    keys = world._kept[0].key[: int(world._kept[0].pairs[0])]
    assert not np.any(((keys >> 32) == 4) | ((keys & 0xFFFFFFFF) == 4))
    # Static colliders changing drops the pairs with them.
    world.add_half_space((1.0, 0.0, 0.0, 0.0), -5.0)
    keys = world._kept[0].key[: int(world._kept[0].pairs[0])]
    assert np.all((keys & 0xFFFFFFFF) < (1 << 30))


def test_kept_manifolds_are_part_of_the_state():
    a, b = build_pile(60, seed=1), build_pile(60, seed=1)
    for _ in range(90):
        a.step(1.0 / 60.0)
        b.step(1.0 / 60.0)
    assert a.state_hash() == b.state_hash()
    b._kept[0].local[0, 0] += 1e-9
    assert a.state_hash() != b.state_hash()
