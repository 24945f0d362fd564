"""Winning: the level is complete once the player stands in the goal; and losing: once the
level can no longer be won (:mod:`..stranded`), the HUD says why and names the key that
restarts from the last checkpoint."""

from __future__ import annotations

import numpy as np

from ..events import LevelComplete
from ..stranded import notice
from ..system import System


def in_goal(game) -> bool:
    """Is the player's box centre inside the goal (and the player at a goal w)?"""
    g = game.level.goal
    c = game.player.center()
    if np.any(np.abs(c - g.center) > g.size / 2):
        return False
    return g.w_range is None or g.w_range[0] <= game.player.position[3] <= g.w_range[1]


def step(game, actions) -> None:
    if game.outcome is None and in_goal(game):
        game.outcome = "complete"
        game.completed_tick = game.tick + 1  # the tick being finished
        game.emit(LevelComplete())


def draw(game, frame, alpha) -> None:
    if game.outcome == "complete":
        frame.hud.message = "Level complete"
        return
    lost = notice(game)
    if lost is not None:
        frame.hud.message = lost


SYSTEM = System("outcome", step=step, draw=draw)
