"""The player's health each tick (checkpoints) and on the HUD (bar, red flash, where the hit came from).

Damage and death are in :mod:`..health`; enemy shots call it. Nothing runs in a
level without health.
"""

from __future__ import annotations

import numpy as np

from .. import health as hp
from ..frame import HealthGauge
from ..system import System, encode


def setup(game) -> hp.Health | None:
    """Full health, or None when the level gives the player none (no enemies, no ``[health]``)."""
    spec = game.level.health
    return None if spec is None else hp.Health(spec.maximum, spec.maximum, round(spec.invulnerable / game.dt))


def state_bytes(game) -> bytes:
    return encode(game.states.health)


def step(game, actions) -> None:
    if game.states.health is not None:
        hp.reach_checkpoints(game)


def draw(game, frame, alpha) -> None:
    h = game.states.health
    if h is None:
        return
    since = game.tick - h.hit_tick
    flash = max(0.0, 1.0 - since / hp.FLASH_TICKS)
    frame.hud.health = HealthGauge(h.value, h.maximum, flash, game.tick < h.safe_until)
    frame.hud.damage_flash = flash
    if h.hit_dir is not None and since < hp.CUE_TICKS:
        # The cue turns with the view: 0 straight ahead, positive to the right (yaw turns towards +x).
        world = float(np.arctan2(h.hit_dir[0], h.hit_dir[1]))
        frame.hud.damage_dir = float((world - frame.camera.yaw + np.pi) % (2 * np.pi) - np.pi)
    if game.tick < h.message_until and (not frame.hud.message or h.message.startswith("You died")):
        frame.hud.message = h.message


SYSTEM = System("health", setup, step, draw, state_bytes)
