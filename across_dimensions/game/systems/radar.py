"""The holographic radar (the paper's Fig. "Across Dimensions"): every 4D entity
within range as a pin whose height is its w offset from the player.

The disc lies in the player's x-z plane and turns with the player's yaw, so a
pin straight ahead of the player is always at the disc's front. A pin on the
disc is an entity the player can see now; above the disc lies ana (+w), below
it kata (-w).
"""

from __future__ import annotations

import numpy as np

from ..frame import Radar, RadarPin


def draw(game, frame, alpha) -> None:
    settings = game.radar_settings
    if settings is None:
        return
    p = game.player
    eye = frame.camera.position
    yaw = frame.camera.yaw
    fwd = np.array([np.sin(yaw), np.cos(yaw)])  # x, z of "ahead"
    right = np.array([np.cos(yaw), -np.sin(yaw)])
    w = float(p.position[3])
    pins = []
    for e in game.entities:
        if e.radar is None:
            continue
        c = e.center(game)
        rel = np.array([c[0] - eye[0], c[2] - eye[2]])
        if rel @ rel > settings.range ** 2:
            continue
        bounds = game.sections.bounds(f"draw:{e.id}")  # the sections system sliced it this frame
        pins.append(RadarPin(e.radar, float(rel @ right) / settings.range, float(rel @ fwd) / settings.range,
                             (float(c[3]) - w) * settings.w_scale, not np.isnan(bounds).any()))
    frame.radar = Radar(settings.range, settings.w_scale, pins)
