"""The flat world's physics: a pymunk space holding the sections of the 3D world, the being and its crates.

This is the one module that imports pymunk (``tests/test_layering.py``): the 4D game keeps its own
deterministic physics, and pymunk never reaches ``core`` or ``physics``. It is used through its
public API, stepped with the game's fixed tick and no threads, so the same actions give the same
states in any process.

* Each solid's section is static :class:`pymunk.Poly` pieces, replaced only when the section
  changes (the being moved along z past an edge of the solid, or the solid is gone): a body
  resting on a piece that goes simply falls.
* Each ball's circle is a :class:`pymunk.Circle` on a kinematic body at the ball's ``(x, y)``,
  replaced when its radius changes; the ball's motion is along z, which the plane cannot feel.
* The being is a dynamic box that does not turn, walking by friction (:func:`drive`): its feet's
  ``surface_velocity`` is the walk it wants and their friction how hard it may push for it, so it
  walks on moving circles, pushes crates against their friction and is carried by what it stands
  on. A crate is a dynamic box present while the plane cuts it; away from the plane it rests
  where it was left.
"""

from __future__ import annotations

import math
import struct

import numpy as np
import pymunk

from ...world.flat_level import FlatLevel
from ..player import HALF_WIDTH, HEIGHT, JUMP_SPEED, WALK_SPEED

BEING_MASS = 70.0  # kg, pushing a 20 kg crate easily and a 200 kg one barely
#: Walking acceleration on the ground (m/s^2): the feet's friction is this over gravity.
GROUND_ACCEL = 30.0
#: Steering in the air (m/s^2): a side view needs a platformer's air control, so a jump from
#: standing still towards a ledge 3 m away gets there (at the 4D walker's 8 it fell short).
AIR_ACCEL = 20.0
#: Overlap pymunk leaves between resting shapes (m): small against the being, big enough that a
#: resting contact stays a contact from tick to tick.
COLLISION_SLOP = 0.004
ITERATIONS = 20  # solver passes per tick: a crate stack stays put at 20, sinks at pymunk's 10
SOLID_FRICTION = 0.9
CRATE_FRICTION = 1.0  # times the floor's 0.9: a crate let go at a walk slides about a metre
FEET_HEIGHT = 0.2
#: How far the feet's rounded corners reach (m): the being slides over seams between pieces.
FEET_ROUND = 0.04
#: A contact whose normal points this much downward (from the being) holds the being up.
GROUND_NORMAL_Y = -0.5


class FlatSpace:
    """The pymunk space of a prologue level.

    Parameters
    ----------
    level : FlatLevel
    dt : float
        The fixed tick.
    """

    def __init__(self, level: FlatLevel, dt: float):
        self.dt = dt
        s = self.space = pymunk.Space()
        s.gravity = (0.0, level.gravity)
        s.iterations = ITERATIONS
        s.collision_slop = COLLISION_SLOP
        self._static: list[tuple[bytes, list[pymunk.Poly]]] = [(b"", []) for _ in level.solids]
        self._balls: list[tuple[pymunk.Body, pymunk.Circle | None, float]] = []
        for ball in level.balls:
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            body.position = (float(ball.center[0]), float(ball.center[1]))
            s.add(body)
            self._balls.append((body, None, 0.0))
        self.crates: list[tuple[pymunk.Body, pymunk.Poly]] = []
        for c in level.crates:
            hx, hy = float(c.size[0]) / 2, float(c.size[1]) / 2
            body = pymunk.Body(c.mass, pymunk.moment_for_box(c.mass, (2 * hx, 2 * hy)))
            body.position = (float(c.center[0]), float(c.center[1]))
            shape = pymunk.Poly(body, [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)])
            shape.friction = CRATE_FRICTION
            self.crates.append((body, shape))
        self.being = pymunk.Body(BEING_MASS, math.inf)  # it never tips over
        self.being.position = (float(level.spawn[0]), float(level.spawn[1]))
        w, f = HALF_WIDTH, FEET_HEIGHT
        self.torso = pymunk.Poly(self.being, [(-w, f / 2), (w, f / 2), (w, HEIGHT), (-w, HEIGHT)])
        self.torso.friction = 0.0  # only the feet grip: a being pressed to a wall does not cling to it
        inner = w - 0.03 - FEET_ROUND  # narrower than the torso, so walls meet the torso first
        self.feet = pymunk.Poly(
            self.being,
            [(-inner, FEET_ROUND), (inner, FEET_ROUND), (inner, f - FEET_ROUND), (-inner, f - FEET_ROUND)],
            radius=FEET_ROUND,
        )
        s.add(self.being, self.torso, self.feet)

    # ------------------------------------------------------------ the sections
    def set_solid(self, i: int, pieces: list[np.ndarray]) -> None:
        """Make solid ``i``'s shapes these convex pieces (nothing happens when they are the same)."""
        key = b"".join(np.ascontiguousarray(p).tobytes() for p in pieces) + bytes([len(pieces)])
        old_key, old = self._static[i]
        if key == old_key:
            return
        if old:
            self.space.remove(*old)
        new = []
        for p in pieces:
            shape = pymunk.Poly(self.space.static_body, [(float(x), float(y)) for x, y in p])
            shape.friction = SOLID_FRICTION
            new.append(shape)
        if new:
            self.space.add(*new)
        self._static[i] = (key, new)

    def set_ball(self, i: int, radius: float) -> None:
        """Give ball ``i``'s circle this radius (none at 0)."""
        body, shape, old = self._balls[i]
        if radius == old:
            return
        if shape is not None:
            self.space.remove(shape)
        shape = None
        if radius > 0.0:
            shape = pymunk.Circle(body, radius)
            shape.friction = SOLID_FRICTION
            self.space.add(shape)
        self._balls[i] = (body, shape, radius)

    def set_crate(self, i: int, present: bool) -> None:
        """Put crate ``i`` in the plane or take it out (it keeps its place and stops moving)."""
        body, shape = self.crates[i]
        if present == (body.space is not None):
            return
        if present:
            self.space.add(body, shape)
        else:
            self.space.remove(body, shape)
            body.velocity, body.angular_velocity = (0.0, 0.0), 0.0

    # ------------------------------------------------------------ stepping
    def step(self) -> None:
        """One fixed tick."""
        self.space.step(self.dt)

    def ground(self) -> tuple[bool, tuple[float, float]]:
        """Whether something holds the being up, and the velocity of what it stands on."""
        found: list[tuple[float, float]] = []

        def look(arbiter: pymunk.Arbiter) -> None:
            if arbiter.normal.y <= GROUND_NORMAL_Y:
                other = arbiter.shapes[1].body
                found.append((other.velocity.x, other.velocity.y))

        self.being.each_arbiter(look)
        return (True, found[0]) if found else (False, (0.0, 0.0))

    def state_bytes(self) -> bytes:
        """The being, the crates and the contacts they carry to the next tick (warm-start impulses)."""
        out = [_body_bytes(self.being)]
        for body, _ in self.crates:
            out.append(_body_bytes(body) + (b"+" if body.space is not None else b"-"))
        for body in [self.being] + [b for b, _ in self.crates]:
            contacts: list[float] = []
            body.each_arbiter(lambda a, c=contacts: c.extend((*a.normal, *a.total_impulse)))
            out.append(struct.pack(f"<{len(contacts)}d", *contacts))
        out.append(struct.pack(f"<{len(self._balls)}d", *(r for _, _, r in self._balls)))
        return b"".join(out)


def _body_bytes(b: pymunk.Body) -> bytes:
    return struct.pack("<6d", *b.position, *b.velocity, b.angle, b.angular_velocity)


def drive(space: FlatSpace, walk: float, jump: bool, grounded: bool, ground_velocity) -> None:
    """Set the being's walk (and its jump, when ``jump``) for the next tick.

    On the ground the feet's surface velocity asks for ``walk * WALK_SPEED`` relative to what they
    stand on, and their friction (``GROUND_ACCEL`` over gravity) bounds the force that gets it, so
    a crate in the way is pushed only as hard as feet can push. In the air the being steers at
    ``AIR_ACCEL``. A jump sets the upward speed to :data:`JUMP_SPEED` plus that of the ground
    (whether a jump may happen now is the simulation's call: see ``FlatGame``'s coyote time).
    """
    b, feet = space.being, space.feet
    want = walk * WALK_SPEED
    g = abs(space.space.gravity.y)
    # No grip in the air: feet pressed to a wall while steering at it must not hold the being up.
    feet.friction = (GROUND_ACCEL / g if g > 0 else 1.0) if grounded else 0.0
    feet.surface_velocity = (-want, 0.0)
    if not grounded:
        vx, vy = b.velocity
        step = AIR_ACCEL * space.dt
        b.velocity = (vx + min(max(want - vx, -step), step), vy)
    if jump:
        b.velocity = (b.velocity.x, JUMP_SPEED + ground_velocity[1])
