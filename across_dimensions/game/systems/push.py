"""The player and rigid bodies in the slice: bodies block the player, and the player pushes them."""

from __future__ import annotations

import numpy as np

from ..player import HALF_WIDTH, HEIGHT, move_axis
from ..player_bodies import player_collide
from ..section_collision import Soup
from ..system import System

PUSH = 0.5  # share of the player's velocity into a body given to it per tick of contact


def step(game, actions) -> None:
    if game.physics is None:
        return
    p = game.player
    corr, touched = player_collide(game.physics, p.position, HALF_WIDTH, HEIGHT)
    n = np.linalg.norm(corr)
    if n == 0.0:
        return
    # Apply the push-out as a move, so the static world still stops it: a
    # body never shoves the player through a floor or a wall.
    boxes = game.colliders_at(float(p.position[3]))
    found = [t for t in game.sections_at(float(p.position[3])) if len(t)]  # nor through a solid's section
    tris = Soup(np.concatenate(found)) if found else None
    for axis in (0, 2, 1):
        p.position, _ = move_axis(p.position, axis, float(corr[axis]), boxes, tris)
    normal = corr / n
    into = float(p.velocity[:3] @ normal)
    if into < 0.0:  # stop moving into the body, pass the motion on to it
        p.velocity[:3] -= into * normal
        for b in touched:
            mass = game.physics.body_mass(b)
            game.physics.push(b, np.append(into * normal * mass * PUSH, 0.0))  # away from the player
    if normal[1] > 0.7:  # standing on a body
        p.on_ground = True
        p.velocity[1] = max(p.velocity[1], 0.0)


SYSTEM = System("push", step=step)
