"""The paper's physics figure: a bullet knocks a hidden slab, which turns in t, u, v, and the
bullet falls and rolls away (``slab_knocked``)."""

from __future__ import annotations

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import Actions
from across_dimensions.game.events import SlabKnocked
from across_dimensions.game.sim import Game
from across_dimensions.game.systems.bullets import KNOCK_SPIN

PLANES = ((0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3))
FIRE = Actions(presses=(("fire", 1),))


def _level(tmp_path, slab_w: float, gravity=(0.0, -9.81, 0.0, 0.0), amplitude=0.6):
    gun = dict(
        cost=0.0,
        cooldown=0.0,
        speed=10.0,
        amplitude=amplitude,
        period=2.0,
        size=0.15,
        mass=0.5,
        lifetime=6.0,
        max_live=4,
    )
    slab = f"""
[[object]]
name = "slab"
shape = "tesseract"
position = [0.3, 1.6, 3.0, {slab_w}]
scale = [1.2, 1.2, 0.4, 0.4]
body = "hypercube"
mass = 2.0
"""
    level = (
        LevelBuilder("knock", spawn=(0.0, 0.0, -3.0, 0.0), goal=(0.0, 1.0, 30.0), floor=(20.0, 1.0, 80.0))
        .table("physics", gravity=list(gravity))
        .weapon("gun", **gun)
    )
    return Game(level.load(tmp_path, extra=slab))


def _momentum(phys, bodies) -> np.ndarray:
    """Total angular momentum about the origin, a bivector ``(6,)`` (``xy xz yz xw yw zw``):
    each body's ``x ^ m v`` plus its spin ``I omega``. ``bodies`` are ``(id, velocity (4,))``."""
    total = np.zeros(6)
    for body, v in bodies:
        x, m = phys.body_position(body), phys.body_mass(body)
        total += [m * (x[a] * v[b] - x[b] * v[a]) for a, b in PLANES]
        total += phys.body_inertia(body) @ phys.body_velocity(body)[1]
    return total


def _fire_until_contact(game):
    game.step(Actions())
    game.step(FIRE)
    (eid,) = game.states.weapons.bullets
    bullet = game.entities.get(eid)
    slab = game.entities.named("slab")
    phys = game.physics
    seen = []
    for _ in range(120):
        b = bullet.data
        k = game.tick - b.born + 1
        v_cmd = (b.planned(k, game.dt) - phys.body_position(bullet.motion.body)) / game.dt  # what steering sets
        before = _momentum(
            phys, [(bullet.motion.body, v_cmd), (slab.motion.body, phys.body_velocity(slab.motion.body)[0])]
        )
        game.step(Actions())
        seen += game.events
        if b.contacted:
            return bullet, slab, before, seen
    raise AssertionError("the bullet never touched the slab")


def test_the_knock_turns_the_slab_by_the_impulse_and_keeps_angular_momentum(tmp_path):
    # Zero gravity: nothing but the contact acts in the tick of the knock, so the angular
    # momentum of bullet and slab about the origin is the same before and after it, and the
    # slab's turn in the w planes is what the impulse at an off-centre w gives it.
    game = _level(tmp_path, slab_w=0.5, gravity=(0.0, 0.0, 0.0, 0.0))
    bullet, slab, before, seen = _fire_until_contact(game)
    phys = game.physics
    after = _momentum(
        phys,
        [(b, phys.body_velocity(b)[0]) for b in (bullet.motion.body, slab.motion.body)],
    )
    # Tolerance: the solver pushes each body at its own side of the contact, which lie as far
    # apart as the bullet got into the slab within one substep (its speed times the substep):
    # the moment of the bullet's momentum over that lever.
    p = 0.5 * 10.0  # the bullet's mass times its speed
    lever = 10.0 * game.dt / phys.substeps
    assert np.allclose(after, before, atol=p * lever)
    knocks = [ev for ev in seen if isinstance(ev, SlabKnocked)]
    assert [(ev.entity, ev.bullet) for ev in knocks] == [(slab.id, bullet.id)]
    omega = phys.body_velocity(slab.motion.body)[1]
    assert np.allclose(knocks[0].spin, omega[3:])
    assert np.linalg.norm(omega[3:]) > KNOCK_SPIN
    # The slab's own angular momentum is the impulse's moment about its centre: r ^ (m dv).
    c = [ev for ev in phys.events if {ev.a, ev.b} == {bullet.motion.body, slab.motion.body}][0]
    r = c.point - phys.body_position(slab.motion.body)
    j = phys.body_mass(slab.motion.body) * phys.body_velocity(slab.motion.body)[0]
    moment = np.array([r[a] * j[b] - r[b] * j[a] for a, b in PLANES])
    spin_l = phys.body_inertia(slab.motion.body) @ omega
    # Tolerance: the same lever, and the slab moved by v dt after the push (a few millimetres).
    slide = np.linalg.norm(phys.body_velocity(slab.motion.body)[0]) * game.dt
    assert np.allclose(spin_l, moment, atol=np.linalg.norm(j) * (lever + slide))


def test_the_bullet_falls_and_rolls_away_after_the_knock(tmp_path):
    game = _level(tmp_path, slab_w=0.5)
    for _ in range(30):
        game.step(Actions())  # the slab falls to the floor and rests there, its top at 1.2 m
    game.step(Actions(pitch=-0.15))  # aim at its upper half
    bullet, slab, _, seen = _fire_until_contact(game)
    assert [ev.entity for ev in seen if isinstance(ev, SlabKnocked)] == [slab.id]
    phys = game.physics
    y_hit = phys.body_position(bullet.motion.body)[1]
    for _ in range(120):
        game.step(Actions())
    at = phys.body_position(bullet.motion.body)
    assert y_hit > 0.5 and at[1] == pytest.approx(0.15, abs=0.02)  # fell to the floor (its radius)


def test_a_slab_in_the_slice_is_not_knocked(tmp_path):
    # The player stands in the slab's slice; a bullet that hardly swings meets it off-centre.
    game = _level(tmp_path, slab_w=0.1, gravity=(0.0, 0.0, 0.0, 0.0), amplitude=0.05)
    _, slab, _, seen = _fire_until_contact(game)
    assert not [ev for ev in seen if isinstance(ev, SlabKnocked)]
    spin = game.physics.body_velocity(slab.motion.body)[1][3:]
    assert np.linalg.norm(spin) > KNOCK_SPIN  # it turns in a w plane, but in plain sight
