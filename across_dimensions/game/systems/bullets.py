"""Bullets after the physics tick: what they touched, the targets they hit, and their end.

A bullet's first contact ends its prescribed flight (from then on physics moves
it: it pushes what it hit, falls and rolls). A bullet whose centre comes within
a target's size plus its own radius hits the target and is spent (and, while the 4D
camera is detached, a bullet whose frustum image overlaps the target's image): the
target's door (the object named by ``opens``) is removed. A bullet is removed after its lifetime or
once it sleeps; the blast's finished pulls are settled here too.

A bullet whose first touch of a box-shaped body finds that body hidden (its w extent clear of
the player's slice) and leaves it turning in a w plane (t, u or v) knocks the slab: a
:class:`~..events.SlabKnocked`.
"""

from __future__ import annotations

import numpy as np

from .. import weapons as wp
from ..events import BulletHit, SlabKnocked, TargetHit
from ..system import System
from . import camera

#: The slowest turn in a w plane (rad/s, the norm of the t, u, v parts) that counts as a knock:
#: a turn of about a degree a second, far above the solver's rounding on a body at rest
#: (which stays below 1e-9) and below any hit a player would notice.
KNOCK_SPIN = 0.02


def _w_half(phys, body: int, half: np.ndarray) -> float:
    """How far a box body reaches along the world's w from its centre."""
    return float(np.abs(phys.body_rotation(body)[3]) @ half)


def _knock(game, bullet: int, slab: int, body: int) -> None:
    """Report a knocked slab: ``slab`` (an entity with rigid ``body``) touched by ``bullet``."""
    phys = game.physics
    half = phys.body_half_extents(body)
    if half is None or phys.body_kind(body) != "dynamic":
        return
    # Hidden: none of the slab reaches the player's slice (the bullet met it off the slice).
    pw = float(game.player.position[3])
    if abs(pw - float(phys.body_position(body)[3])) <= _w_half(phys, body, half):
        return
    spin = phys.body_velocity(body)[1][3:]
    if float(np.linalg.norm(spin)) > KNOCK_SPIN:
        game.emit(SlabKnocked(slab, bullet, tuple(float(x) for x in spin)))


def _contacts(game, ars) -> None:
    bullets = set(ars.bullets)
    for c in game.physics.events:
        if not c.began:
            continue
        ends = [(c.a, c.b), (c.b, c.a)] if not isinstance(c.b, str) else [(c.a, c.b)]
        for mine, other in ends:
            eid = game.entity_of_body.get(mine)
            if eid not in bullets:
                continue
            e = game.entities.get(eid)
            if isinstance(other, str):
                what, oid = "world", None
            else:
                oid = game.entity_of_body.get(other)
                oe = game.entities.get(oid) if oid is not None else None
                what = "bullet" if oe is not None and oe.kind == "bullet" else "body"
            if not e.data.contacted or what == "body":
                game.emit(BulletHit(eid, what, oid))
                if what == "body":
                    ars.hit_tick = game.tick
                    _knock(game, eid, oid, other)
            e.data.contacted = True


def _targets(game, ars) -> None:
    targets = [t for t in game.entities.of_kind("target") if not t.data.hit]
    if not targets:
        return
    tc = np.array([t.center(game) for t in targets])
    tr = np.array([t.radius for t in targets])
    for eid in list(ars.bullets):
        b = game.entities.get(eid)
        d = np.linalg.norm(tc - b.center(game), axis=1)
        # While the 4D camera is detached, what the player sees is what is hit: a bullet
        # whose frustum image overlaps a target's image hits it too (around corners).
        touching = (d <= tr + b.radius) | camera.seen_touching(game, b.center(game), b.radius, tc, tr)
        for k in np.flatnonzero(touching)[:1]:  # the nearest in firing order is enough
            t = targets[k]
            if t.data.hit:
                continue
            t.data.hit = True
            # A hit target changes its look (after the field's wireframe, if it is showing).
            own = ars.wired[t.id][0] if t.id in ars.wired else t.style
            looks = "glow" if own != "glow" else "solid"
            if t.id in ars.wired:
                ars.wired[t.id] = (looks, ars.wired[t.id][1])
            else:
                t.style = looks
            opened = ""
            door = game.entities.named(t.data.spec.opens) if t.data.spec.opens else None
            if door is not None and door.kind in ("object", "body"):
                game.remove(door.id)
                opened = t.data.spec.opens
            ars.hit_tick = game.tick
            game.emit(BulletHit(eid, "target", t.id))
            game.emit(TargetHit(t.id, eid, opened))
            # The switch takes the bullet: one shot never throws two switches.
            ars.bullets.remove(eid)
            game.remove(eid)


def step(game, actions) -> None:
    ars = game.states.weapons
    if ars is None:
        return
    wp.settle_pulled_bodies(game)
    if not ars.bullets:
        return
    _contacts(game, ars)
    _targets(game, ars)
    for eid in list(ars.bullets):
        e = game.entities.get(eid)
        old = (game.tick + 1 - e.data.born) * game.dt >= e.data.spec.lifetime
        if old or game.physics.is_sleeping(e.motion.body):
            ars.bullets.remove(eid)
            game.remove(eid)


SYSTEM = System("bullets", step=step)
