"""The holographic radar (the paper's Fig. "Across Dimensions"): every 4D entity
within range as a pin whose height is its w offset from the player.

The disc lies in the player's x-z plane and turns with the player's yaw, so a
pin straight ahead of the player is always at the disc's front. A pin on the
disc is an entity the player can see now; above the disc lies ana (+w), below
it kata (-w). The level sets the range and the height scale; the player's
settings (``game.radar_view``) multiply them or hide the radar.
"""

from __future__ import annotations

import numpy as np

from ..frame import Radar, RadarPin
from ..system import System
from .seek import sought_id

#: Radar kinds the player may be looking for: the radar never hides them (see ``Radar.interest``).
INTEREST = ("crystal", "target", "body", "enemy")


def draw(game, frame, alpha) -> None:
    level, view = game.radar_settings, game.radar_view
    if level is None or not view.shown:
        return
    reach = level.range * view.range_scale  # metres to the rim
    w_scale = level.w_scale * view.height_scale
    table = game.entity_table()
    tracked = [i for i, e in enumerate(table.entities) if e.radar is not None]
    if not tracked:
        frame.radar = Radar(reach, w_scale, [])
        return
    c = game.camera.to_slice(table.centers[tracked])  # slice space: x, z on the disc, w as height
    yaw = frame.camera.yaw
    rel = c[:, [0, 2]] - frame.camera.position[[0, 2]]
    # Into the player's frame: x to the right, z ahead, in disc radii.
    x = (rel[:, 0] * np.cos(yaw) - rel[:, 1] * np.sin(yaw)) / reach
    z = (rel[:, 0] * np.sin(yaw) + rel[:, 1] * np.cos(yaw)) / reach
    w = frame.camera.w
    height = (c[:, 3] - w) * w_scale
    inside = x * x + z * z <= 1.0
    pins, interest = [], []
    sought = sought_id(game)
    for k in np.flatnonzero(inside):
        e = table.entities[tracked[k]]
        if game.camera.detached:
            # Nothing is sliced while the frustum camera is out: say whether it reaches the
            # player's slice (its bounding sphere does), as the slice would show on return.
            visible = bool(abs(c[k, 3] - w) <= e.radius)
        else:
            visible = game.entity_sections.has_section(e.id)  # the sections system sliced it this frame
        pins.append(RadarPin(e.radar, float(x[k]), float(z[k]), float(height[k]), visible, e.id == sought))
        if visible and e.radar in INTEREST:
            interest.append((*c[k, :3], e.radius))
    frame.radar = Radar(reach, w_scale, pins, np.array(interest, np.float64).reshape(-1, 4))


SYSTEM = System("radar", draw=draw)
