"""Secrets: hidden places a level counts (``[[secret]]``, :mod:`across_dimensions.world.secrets`).

Each secret is an entity of kind ``"secret"`` (no mesh, off the radar) whose data is a
:class:`Secret`, hashed with it: the tick it was found. The first tick the player's box
centre and w are inside its volume, it is found: the game emits ``secret_found`` once, the
HUD says which of how many it was for a few seconds, and a secret exit finishes the level.
Levels without secrets spawn nothing, so their state (and their replays' hashes) are as before.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...core.transform import translation
from ...world.secrets import SecretSpec
from ..entities import Placed
from ..events import LevelComplete, SecretFound
from ..system import System, fixed

MESSAGE_TICKS = 240  # four seconds on screen


@dataclass
class Secret:
    """A secret's state (its entity's ``data``): the level's entry and the tick it was found (-1: not yet)."""

    spec: SecretSpec = fixed()
    found_tick: int = -1


def _spawn(game) -> list:
    """One entity per secret, placed at the centre of its volume. Spawned on the first tick,
    after every system's setup, so the entities of the others keep their ids (and the secrets
    need no state of their own: found or not, the entities stay)."""
    for spec in game.level.secrets:
        pose = translation((spec.lo + spec.hi) / 2)
        game.entities.spawn("secret", spec.name, None, Placed(pose), data=Secret(spec))
    return game.entities.of_kind("secret")


def found(game) -> list[str]:
    """The names of the secrets found so far, in the level's order."""
    return [e.name for e in game.entities.of_kind("secret") if e.data.found_tick >= 0]


def step(game, actions) -> None:
    if not game.level.secrets or game.outcome is not None:  # nothing is found after the level's end
        return
    center, w = game.player.center(), float(game.player.position[3])
    secrets = game.entities.of_kind("secret") or _spawn(game)
    for e in secrets:
        s = e.data
        if s.found_tick >= 0 or not s.spec.holds(center, w):
            continue
        s.found_tick = game.tick
        count = sum(x.data.found_tick >= 0 for x in secrets)
        game.emit(SecretFound(e.name, count, len(secrets)))
        if s.spec.exit and game.outcome is None:
            game.outcome = "complete"
            game.completed_tick = game.tick + 1  # the tick being finished, as the goal does
            game.emit(LevelComplete())


def draw(game, frame, alpha) -> None:
    if not game.level.secrets or game.outcome == "complete":
        return
    secrets = game.entities.of_kind("secret")
    if not secrets:
        return
    last = max(secrets, key=lambda e: e.data.found_tick)
    if last.data.found_tick >= 0 and game.tick - last.data.found_tick < MESSAGE_TICKS:
        count = sum(x.data.found_tick >= 0 for x in secrets)
        frame.hud.message = f"Secret found: {last.name} ({count} of {len(secrets)})"


SYSTEM = System("secrets", step=step, draw=draw)
