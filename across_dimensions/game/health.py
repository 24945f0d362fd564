"""The player's health: damage, death and checkpoints.

A level with enemies (or a ``[health]`` table) gives the player health
(``game.states.health``, a :class:`Health` the health system makes with the
game); a level without either has none and nothing here runs.

Enemy shots take health through :func:`damage`. At zero the player dies
(and the enemies' system makes its enemies back off): :func:`die` brings them
back at the last checkpoint they touched (or the spawn point) with full health,
a few seconds of safety and a message that says so. Nothing else is undone:
collected crystals, energy, defeated enemies and opened doors stay as they are,
so a death costs the walk back, never progress.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .events import CheckpointReached, PlayerDied, PlayerHit
from .player import Player
from .system import fixed

FLASH_TICKS = 24  # the red flash and the bar's flash after a hit (0.4 s)
CUE_TICKS = 90  # the damage direction cue stays 1.5 s, fading
MESSAGE_TICKS = 240  # the death message stays 4 s
CHECKPOINT_MESSAGE_TICKS = 120
#: How far along w from a checkpoint's w the player may be and still touch it
#: (units of w): about a body's width, so it is touched where it is seen.
CHECKPOINT_W = 0.3


@dataclass
class Health:
    """The player's health (``game.states.health``).

    Attributes
    ----------
    maximum, value : float
    safe_ticks : int
        Ticks of safety after coming back from a death.
    safe_until : int
        Tick before which no damage is taken.
    hit_tick : int
        Tick of the last hit (flashes and cue fade from it).
    hit_dir : (2,) float64
        Unit ``(x, z)`` from the player towards the last hit's source.
    deaths : int
    checkpoint : int
        Index of the checkpoint the player comes back to; -1 for the spawn point.
    message, message_until
        A HUD line and the tick it goes.
    """

    maximum: float = fixed()
    value: float
    safe_ticks: int = fixed()
    safe_until: int = 0
    hit_tick: int = -(10**9)
    hit_dir: np.ndarray | None = None
    deaths: int = 0
    checkpoint: int = -1
    message: str = ""
    message_until: int = 0


def damage(game, amount: float, source_xz, source: int) -> bool:
    """Take ``amount`` from the player, hit from ``source_xz (2,)`` by entity ``source``
    (nothing during the safety after a death, or in a level without health).

    Returns True when the hit killed the player (they are back at their checkpoint).
    """
    h = game.states.health
    if h is None or amount <= 0 or game.tick < h.safe_until:
        return False
    d = np.asarray(source_xz, np.float64) - game.player.position[[0, 2]]
    # sqrt, never hypot: the C library's hypot rounds differently from one glibc to the next
    # (Debian 11's 2.31 and Debian 12's 2.36 differ in the last bit), and the hit's direction
    # is hashed state.
    n = math.sqrt(d[0] * d[0] + d[1] * d[1])
    h.hit_dir = d / n if n > 1e-9 else np.array([0.0, 1.0])
    h.value = max(0.0, h.value - float(amount))
    h.hit_tick = game.tick
    game.emit(PlayerHit(float(amount), (float(h.hit_dir[0]), float(h.hit_dir[1])), source))
    if h.value <= 0.0:
        die(game)
        return True
    return False


def die(game) -> None:
    """Back to the last checkpoint with full health; everything won so far is kept."""
    h = game.states.health
    where = _place_at_checkpoint(game, h.checkpoint)
    h.deaths += 1
    h.value = h.maximum
    h.safe_until = game.tick + h.safe_ticks
    place = f"checkpoint '{where}'" if where else "the start"
    h.message = f"You died. Back at {place}: your crystals and defeated enemies are kept."
    h.message_until = game.tick + MESSAGE_TICKS
    game.emit(PlayerDied(where))


def _place_at_checkpoint(game, index: int) -> str:
    """Put a fresh player at checkpoint ``index`` (-1: the spawn point); returns its name."""
    if index >= 0:
        cp = game.level.checkpoints[index]
        position, yaw, where = cp.position.astype(np.float64).copy(), float(np.radians(cp.yaw_deg)), cp.name
    else:
        position, where = game.level.spawn.astype(np.float64).copy(), ""
        yaw = float(np.radians(game.level.spawn_yaw_deg))
    game.player = Player(position, yaw=yaw)
    game.reset_interpolation()  # no camera sweep from where the player was
    return where


def restart_at(game, index: int) -> None:
    """Start play at checkpoint ``index`` (continuing a saved game): the player stands there,
    and it is the one they come back to.

    Raises
    ------
    IndexError
        When the level has no checkpoint ``index`` (it changed since the save).
    ValueError
        When the level gives the player no health (so no checkpoints either).
    """
    h = game.states.health
    if h is None:
        raise ValueError("this level has no checkpoints")
    if not 0 <= index < len(game.level.checkpoints):
        raise IndexError(f"checkpoint {index}: the level has {len(game.level.checkpoints)}")
    h.checkpoint = index
    _place_at_checkpoint(game, index)


def touched_checkpoint(game) -> int | None:
    """Index of a checkpoint (later than the current one) the player's feet are in, or None."""
    h = game.states.health
    p = game.player.position
    for i, cp in enumerate(game.level.checkpoints):
        if i <= h.checkpoint:
            continue
        half = cp.size / 2.0
        centre = cp.position[:3] + np.array([0.0, half[1], 0.0])
        if np.all(np.abs(p[:3] - centre) <= half) and abs(p[3] - cp.position[3]) <= CHECKPOINT_W:
            return i
    return None


def reach_checkpoints(game) -> None:
    """Make the latest checkpoint the player touches the one they come back to."""
    i = touched_checkpoint(game)
    if i is None:
        return
    h = game.states.health
    h.checkpoint = i
    name = game.level.checkpoints[i].name
    if game.tick >= h.message_until or not h.message.startswith("You died"):
        h.message, h.message_until = f"Checkpoint '{name}'", game.tick + CHECKPOINT_MESSAGE_TICKS
    game.emit(CheckpointReached(name))
