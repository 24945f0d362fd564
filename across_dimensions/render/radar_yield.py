"""The radar gives way: it fades while something the player may be looking for lies behind it.

The radar's corner is large (it must read at a glance), and a crystal, a switch or a rolling
body can drift into that corner of the view. :attr:`~across_dimensions.game.frame.Radar.interest`
lists what the player may be after in the slice (centre and radius in the frame's 3D space);
:func:`interest_on_screen` projects them with the frame's camera, and :func:`radar_yields` says
whether any of them touches the radar's rectangle. Then the radar is drawn at
:data:`YIELD_ALPHA` and its labels are left out, so the thing behind it stays in plain sight.
The HUD's gauges do the same (:func:`give_way`): the energy bar and weapon panel, the health bar
and the slice gauges each fade as a block while a thing of interest lies behind them. Pure numpy,
tested without OpenGL.
"""

from __future__ import annotations

import numpy as np

from ..game.frame import Frame
from .hud_layout import HudMetrics

#: The radar's opacity while it gives way: still there for the player who looks for it, but it
#: changes a target's pixels by less than a fifth.
YIELD_ALPHA = 0.18


def interest_on_screen(frame: Frame, width: int, height: int) -> np.ndarray:
    """The radar's things of interest as screen circles ``(n, 3) float64``: centre ``x, y`` in
    pixels (origin top-left) and radius in pixels; those behind the camera are left out."""
    radar = frame.radar
    if radar is None or len(radar.interest) == 0:
        return np.zeros((0, 3))
    cam = frame.camera
    proj = cam.projection_matrix(width / max(height, 1))
    vp = proj @ cam.view_matrix()
    pts = np.asarray(radar.interest, np.float64)
    clip = np.c_[pts[:, :3], np.ones(len(pts))] @ vp.T
    front = clip[:, 3] > cam.near
    clip, radius = clip[front], pts[front, 3]
    ndc = clip[:, :2] / clip[:, 3:4]
    x = (ndc[:, 0] + 1.0) * 0.5 * width
    y = (1.0 - ndc[:, 1]) * 0.5 * height
    r = radius * proj[1, 1] * 0.5 * height / clip[:, 3]
    return np.stack([x, y, r], axis=1)


def _touch(circles: np.ndarray, x0, y0, x1, y1) -> np.ndarray:
    """Which ``circles`` (``(n, 3)``: centre and radius) reach the rectangle ``x0..x1, y0..y1``."""
    dx = np.maximum(np.maximum(x0 - circles[:, 0], circles[:, 0] - x1), 0.0)
    dy = np.maximum(np.maximum(y0 - circles[:, 1], circles[:, 1] - y1), 0.0)
    return np.hypot(dx, dy) <= circles[:, 2]


def give_way(quads: np.ndarray, interest: np.ndarray | None) -> np.ndarray:
    """``quads`` (``(n, 12)`` HUD quads of one gauge, see :func:`~.hud.hud_quads`), drawn at
    :data:`YIELD_ALPHA` when one of ``interest`` (screen circles, :func:`interest_on_screen`)
    reaches their bounding rectangle; else ``quads`` unchanged."""
    if interest is None or len(interest) == 0 or len(quads) == 0:
        return quads
    x0, y0 = quads[:, 0].min(), quads[:, 1].min()
    x1, y1 = (quads[:, 0] + quads[:, 2]).max(), (quads[:, 1] + quads[:, 3]).max()
    if not _touch(interest, x0, y0, x1, y1).any():
        return quads
    faded = quads.copy()
    faded[:, 11] *= YIELD_ALPHA
    return faded


def radar_yields(frame: Frame, width: int, height: int) -> bool:
    """Whether something of interest lies (even partly) behind the radar's rectangle."""
    circles = interest_on_screen(frame, width, height)
    if len(circles) == 0:
        return False
    rx, ry, rw, rh = HudMetrics(int(width), int(height)).radar_rect()
    return bool(_touch(circles, rx, ry, rx + rw, ry + rh).any())
