"""The player: walking, looking, moving along w (paid for with energy), falling out.

Moving along w costs the level's ``w_cost`` energy per unit of w travelled. The
bar limits how far the player may move in a tick, so the player stops exactly
when it runs dry and never owes energy; what was travelled is then paid.

A move has a grace: while the player stays within :data:`W_GRACE` of where they last
paid, nothing is paid yet, so a short press of a w key does not touch the bar. A move
that goes farther pays for the whole way from there at once (the bar shows that part
drop), then every tick pays for its own travel until the player comes to rest along w;
the next move has its grace again. What a grace leaves unpaid stays counted
(``Walk.w_unpaid``): small moves never add up to free travel (at most W_GRACE of w is
ever unpaid), and the bar still limits how far the player may go from where they last
paid, as if the grace were paid: the grace defers a payment, it never extends a reach.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..events import Respawned, WBlocked
from ..player import Surroundings, step_player
from ..system import System, encode
from . import seek

FALL_LIMIT = -30.0  # below this y the player has fallen out of the level
#: Units of w a move may go from where the player last paid before it costs anything (a
#: tap of a w key at walking speed moves about 0.04).
W_GRACE = 0.1


@dataclass
class Walk:
    """What the walk carries from tick to tick (``game.states.player``); the player's own
    position and velocity are ``game.player``.

    Attributes
    ----------
    w_blocked : bool
        The player pushed along w into something last tick (a new push is a new event).
    w_unpaid : float
        Signed w moved since the last payment and not yet paid (within the grace).
    w_paying : bool
        The move under way has gone past its grace: each tick pays for its travel.
    """

    w_blocked: bool = False
    w_unpaid: float = 0.0
    w_paying: bool = False


def setup(game) -> Walk:
    return Walk()


def state_bytes(game) -> bytes:
    return encode(game.states.player)


def _w_cost(game) -> int:
    """Thousandths per unit of w; 0 when moving along w is free."""
    return game.level.energy.w_cost_milli if game.energy is not None else 0


def _w_budget(game):
    """How far along w the bar can pay for this tick, ``(down, up)`` (unlimited when w is free):
    as far from where the player last paid as the whole bar pays for, the grace's unpaid part
    counted, so the grace defers a payment but never lets the player go farther."""
    cost = _w_cost(game)
    if cost <= 0:
        return np.inf
    walk, reach = game.states.player, game.energy.milli / cost
    if walk.w_paying:
        return reach
    return max(0.0, reach + walk.w_unpaid), max(0.0, reach - walk.w_unpaid)


def _pay_w(game, walk: Walk, moved: float) -> None:
    """Pay for ``moved`` (signed w travelled this tick), keeping the grace (module docstring)."""
    cost = _w_cost(game)
    if cost <= 0:
        return
    # Round up so that no run of tiny steps is free, but never past what the bar holds.
    if walk.w_paying:
        game.energy.spend_up_to(game, int(np.ceil(abs(moved) * cost - 1e-9)), "w_move")
    else:
        walk.w_unpaid += moved
        if abs(walk.w_unpaid) > W_GRACE:
            game.energy.spend_up_to(game, int(np.ceil(abs(walk.w_unpaid) * cost - 1e-9)), "w_move")
            walk.w_unpaid, walk.w_paying = 0.0, True
    if moved == 0.0 and game.player.velocity[3] == 0.0:
        walk.w_paying = False  # at rest along w: the next move starts with its grace


def step(game, actions) -> None:
    p = game.player
    w_before = float(p.position[3])
    cut = step_player(
        p,
        actions,
        game.dt,
        float(game.level.gravity[1]),
        Surroundings(
            game.level.w_range,
            game.colliders_at,
            game.bodies_block_w if game.physics is not None else None,
            game.sections_at,
        ),
        _w_budget(game),
        seek.w_goal(game),  # a seek glides through the same w motion, checks and payment
    )
    seek.moved(game, cut)
    walk = game.states.player
    _pay_w(game, walk, float(p.position[3]) - w_before)
    pushing = actions.w != 0.0 and cut is not None
    if pushing and not walk.w_blocked:
        game.emit(WBlocked(cut, 1 if actions.w > 0 else -1))
    walk.w_blocked = pushing

    if p.position[1] < FALL_LIMIT:
        game.respawn()
        game.emit(Respawned())


SYSTEM = System("player", setup, step, state_bytes=state_bytes)
