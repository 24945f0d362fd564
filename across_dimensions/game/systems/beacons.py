"""Reset beacons: a key object that leaves its range is put back at its start, and the HUD
says so (the level's ``[[beacon]]`` tables, :mod:`across_dimensions.world.beacons`).

Each beacon's state is its body's entity data (:class:`Beacon`, hashed with the entity): how long the body has been
out of range, and until when the HUD says it came back. A body out of range for the
beacon's ``after`` seconds is put back at the pose the level gave it, at rest; while the
player stands where it would reappear, it waits, so it never lands on them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...world.beacons import BeaconSpec
from ..events import ObjectReset
from ..player import player_box
from ..system import System, fixed

MESSAGE_TICKS = 180  # three seconds on screen


@dataclass
class Beacon:
    """A body's beacon (its entity's ``data``): the level's entry, the pose it started in
    (``position (4,)``, ``rotation (4, 4)``), ticks spent out of range and the tick until
    which the HUD says it was brought back."""

    spec: BeaconSpec = fixed()
    position: np.ndarray = fixed()
    rotation: np.ndarray = fixed()
    out_ticks: int = 0
    said_until: int = -1


def _beacons(game) -> list:
    """The beaconed bodies with their :class:`Beacon` s, handed out on the first tick (before
    the physics has moved anything, so the pose taken is the level's)."""
    out = []
    if not game.level.beacons:
        return out
    specs = {b.object: b for b in game.level.beacons}
    for e in game.entities.of_kind("body"):
        spec = specs.get(e.name)
        if spec is not None and e.data is None:
            body = e.motion.body
            e.data = Beacon(spec, game.physics.body_position(body), game.physics.body_rotation(body))
        if isinstance(e.data, Beacon):
            out.append(e)
    return out


def _home_taken(game, entity, beacon: Beacon) -> bool:
    """Does the player stand where the body would reappear (its reach round its start, in
    space and in w)?"""
    lo, hi = player_box(game.player.position)
    r = entity.radius
    p = beacon.position
    if abs(float(game.player.position[3]) - p[3]) > r:
        return False
    return bool(np.all(lo < p[:3] + r) and np.all(hi > p[:3] - r))


def step(game, actions) -> None:
    for e in _beacons(game):
        b = e.data
        c = np.asarray(e.center(game))
        if np.all(c >= b.spec.lo) and np.all(c <= b.spec.hi):
            b.out_ticks = 0
            continue
        b.out_ticks += 1
        if b.out_ticks < round(b.spec.after / game.dt) or _home_taken(game, e, b):
            continue
        game.physics.set_pose(e.motion.body, b.position, b.rotation)
        game.physics.set_velocity(e.motion.body, np.zeros(4), np.zeros(6))
        b.out_ticks = 0
        b.said_until = game.tick + MESSAGE_TICKS
        game.emit(ObjectReset(e.name))


def draw(game, frame, alpha) -> None:
    for e in game.entities.of_kind("body") if game.level.beacons else ():
        b = e.data
        if isinstance(b, Beacon) and game.tick < b.said_until and not frame.hud.message:
            frame.hud.message = f"The {e.name} went out of reach: its beacon brought it back to its start"


SYSTEM = System("beacons", step=step, draw=draw)
