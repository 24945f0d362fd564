"""A scripted route through the Flatland prologue (levels/prologue.toml), closed-loop: it reads the
game's state as a player reads the screen (the being's x, its plane's z, the ball's pin) and holds
the keys a player would. It wrote levels/replays/prologue.json::

    python tests/flatland_route.py levels/replays/prologue.json
"""

from __future__ import annotations

import sys

from across_dimensions.game.actions import Actions


def route(g):
    """Yield the next :class:`Actions` for the prologue game ``g``, for ever (after the goal: none)."""

    def x():
        return g.position[0]

    # 1. to the stairs block, jump it, on to the wall
    while x() < 2.2:
        yield Actions(right=1.0)
    while x() < 5.6:
        yield Actions(right=1.0, jump=True)
    while x() < 7.0:
        yield Actions(right=1.0)
    # 2. along z until the wall is low
    while g.z < 0.95:
        yield Actions(w=1.0)
    while x() < 9.5:
        yield Actions(right=1.0, jump=True)
    # 3. to the key's x, then along z to the key's plane
    while x() < 19.8:
        yield Actions(right=1.0)
    for _ in range(5):
        yield Actions()
    while "key" not in g.world.taken:
        yield Actions(w=-1.0)
    while x() < 35.2:
        yield Actions(right=1.0)

    # 4. follow the ball's pin along z; jump onto its circle when it is full, then across
    def follow():
        return max(-1.0, min(1.0, 4.0 * (g.world.ball_z[0] - g.z)))

    while abs(g.world.ball_z[0] - g.z) > 0.05 or g.world.ball_radius(0, g.z) < 1.45:
        yield Actions(w=follow())
    while x() < 38.6:
        yield Actions(right=0.7, jump=g.grounded and x() < 36.5, w=follow())
    for _ in range(20):
        yield Actions(w=follow())
    while x() < 43.0:
        yield Actions(right=1.0, jump=True, w=follow())
    while True:
        yield Actions(right=1.0)


def record(path) -> None:
    """Play the route on the shipped prologue and save the replay to ``path``."""
    from across_dimensions.game.flatland import FlatGame
    from across_dimensions.game.replay import Recorder
    from across_dimensions.world.flat_level import load_flat_level
    from across_dimensions.world.resources import levels_dir

    game = FlatGame(load_flat_level(levels_dir() / "prologue.toml"))
    recorder = Recorder(game, "prologue")
    steps = route(game)
    while game.outcome is None and game.tick < 60 * 120:
        a = next(steps)
        game.step(a)
        recorder.record(a)
    recorder.finish().save(path)
    print(f"{path}: {game.outcome} after {game.tick} ticks, final state {game.state_hash()}")


if __name__ == "__main__":
    record(sys.argv[1])
