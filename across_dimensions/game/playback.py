"""Playing a replay back: the checks on its state hashes, taking them afresh, and the summary.

``replay`` on the command line (``app/commands.py``) is these functions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .energy import MILLI
from .events import event_kinds
from .replay import Recorder, Replay
from .replay_level import level_divergence
from .sim import TICK_RATE, Game


@dataclass
class PlayResult:
    """How a replay ended."""

    ticks: int
    outcome: str | None
    final_hash: str
    divergence: str | None  # None when every recorded hash matched


def play(replay: Replay, game: Game, on_tick=None, check: bool = True) -> PlayResult:
    """Drive ``game`` with the replay's actions.

    Parameters
    ----------
    replay : Replay
    game : Game
        Fresh, built from the replay's level and seed.
    on_tick : callable, optional
        ``on_tick(game)`` after every tick (screenshots, progress).
    check : bool
        Compare state hashes; the first mismatch is reported in ``divergence``
        and the run continues so the outcome is still known.
    """
    divergence = level_divergence(replay, game) if check else None
    for a in replay.actions:
        game.step(a)
        if on_tick is not None:
            on_tick(game)
        if check and divergence is None:
            expected = replay.hashes.get(game.tick)
            if expected is not None and expected != game.state_hash():
                divergence = (
                    f"replay diverges at tick {game.tick} ({game.tick / TICK_RATE:.2f} s): "
                    f"expected state {expected}, got {game.state_hash()}"
                )
    final = game.state_hash()
    if check and divergence is None and replay.final_hash and replay.final_hash != final:
        divergence = f"replay diverges at the end (tick {game.tick}): expected state {replay.final_hash}, got {final}"
    return PlayResult(game.tick, game.outcome, final, divergence)


def rehash(replay: Replay, game: Game) -> tuple[PlayResult, Replay]:
    """Play the replay's actions unchecked and record its state hashes afresh.

    For a deliberate change of the simulation that keeps behaviour but not
    the last bits: the actions stay, the hashes are taken again by the same
    :class:`Recorder` a recording uses (a hash every ``hash_every`` ticks and
    a final one), so the new replay has exactly the layout a recording would.

    Parameters
    ----------
    replay : Replay
        A finished replay (not a recovered journal).
    game : Game
        Fresh, built from the replay's level and seed.

    Returns
    -------
    result : PlayResult
        How the run ended now (``divergence`` is None: nothing is compared).
    fresh : Replay
        ``replay`` with the new hashes, final hash, ticks and outcome, and the
        level hash and bakes of ``game``'s level (written only when its file is
        the one recorded, see :func:`.replay_level.same_file`); its level name,
        seed, hash_every and actions are the replay's own.
    """
    recorder = Recorder(game, replay.level)
    fresh = recorder.replay
    fresh.seed = replay.seed
    fresh.hash_every = replay.hash_every
    for a in replay.actions:
        game.step(a)
        recorder.record(a)
    recorder.finish()
    return PlayResult(game.tick, game.outcome, fresh.final_hash, None), fresh


def changed_hashes(old: Replay, new: Replay) -> tuple[int, int]:
    """``(changed, total)``: how many of ``new``'s state hashes, the final one
    included, differ from (or are missing in) ``old``."""
    changed = sum(old.hashes.get(tick) != h for tick, h in new.hashes.items())
    changed += old.final_hash != new.final_hash
    return changed, len(new.hashes) + 1


# ----------------------------------------------------------------- summary
def summary(game: Game, result: PlayResult) -> dict:
    """What ``replay --json`` prints: one JSON object for tools.

    Keys: ``level`` (the level's name), ``outcome`` (null when not finished),
    ``ticks``, ``hash`` (the final state hash), ``events`` (a count for every
    event kind the game defines, 0 for those that did not happen; see
    ``game.events``), ``causes`` (counts of events by cause, ``"loot_released:camera"``, for the
    kinds that have one: see :class:`~.events.Event`), ``energy`` (``{"min", "max", "end"}`` in energy units over
    the run, or null when the level has no energy bar), ``position`` (the
    player's final ``[x, y, z, w]``), ``respawns`` and ``divergence`` (null, or
    the message).
    """
    position = [float(v) if math.isfinite(v) else None for v in game.player.position]
    bar = game.energy
    energy = (
        None if bar is None else {"min": bar.low_milli / MILLI, "max": bar.high_milli / MILLI, "end": bar.milli / MILLI}
    )
    events = {kind: game.event_counts.get(kind, 0) for kind in event_kinds()}
    return {
        "level": game.level.name,
        "outcome": result.outcome,
        "ticks": result.ticks,
        "hash": result.final_hash,
        "events": events,
        "causes": dict(sorted(game.cause_counts.items())),
        "energy": energy,
        "position": position,
        "respawns": game.respawns,
        "divergence": result.divergence,
    }
