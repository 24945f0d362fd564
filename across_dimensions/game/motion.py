"""Reduce motion: what glides snaps, and what turns while held turns in jumps.

The player's "reduce motion" setting reaches the simulation as a flag on every tick's actions
(:attr:`~.actions.Actions.reduced_motion`), so a replay records it. With it on:

- a 90-degree slice step, the snap to the nearest step and a seek land on the tick they are
  pressed (no glide);
- the detached camera's return skips its glide back and only fades the frustum view out
  (:data:`~.camera.GLIDE_SHARE` of the return is skipped);
- what turns smoothly while a key is held (the slice's turns, the frustum camera's orbit, a
  manipulated object) turns in jumps instead: :data:`JUMP_DEG` degrees (or the object's step) on
  the tick the key goes down, then one more every :data:`JUMP_SECONDS` while it stays down.
  That is the same average speed as the glide at 60 degrees per second, without the frames
  in between.

With it off nothing here changes anything: the simulation is exactly what it was.
"""

from __future__ import annotations

#: Degrees of one jump of a held turn (slice turns, orbit; an object without a step).
JUMP_DEG = 15.0
#: Seconds between two jumps while the key stays down.
JUMP_SECONDS = 0.25


def jump_now(game, control: str, held: bool) -> bool:
    """Whether the held ``control`` (a name, e.g. ``"turn_xw"``) jumps on this tick.

    True on the tick it goes down and every :data:`JUMP_SECONDS` after while it is held. Which
    controls are down and since when is kept on the game (``game.held_since``), outside the
    state hash: it follows from the actions played so far, which a replay has.
    """
    since = game.__dict__.setdefault("held_since", {})
    if not held:
        since.pop(control, None)
        return False
    start = since.setdefault(control, game.tick)
    return (game.tick - start) % max(1, round(JUMP_SECONDS / game.dt)) == 0


__all__ = ["JUMP_DEG", "JUMP_SECONDS", "jump_now"]
