"""The design probe on the Flatland prologue: its strategies can win where the level lets them,
and the shipped prologue lets none of its shortcuts through."""

from __future__ import annotations

from pathlib import Path

import pytest

from across_dimensions.game.flatland import FlatGame
from across_dimensions.probe.flat import flat_library, flat_route
from across_dimensions.world.flat_level import load_flat_level

REPO = Path(__file__).resolve().parents[1]
PROLOGUE = REPO / "levels" / "prologue.toml"
REPLAY = REPO / "levels" / "replays" / "prologue.json"


def play(level, route, name: str, limit: int = 40_000) -> FlatGame:
    strategy = next(s for s in flat_library() if s.name == name)
    game = FlatGame(level)
    bot = strategy.bot(game, route)
    for actions in bot:
        game.step(actions)
        if game.outcome == "complete" or game.tick >= limit:
            break
    return game


def narrowed(tmp_path) -> Path:
    """The prologue with the pit as it once was: 5.4 m wide, the far ground from x = 41.4."""
    text = PROLOGUE.read_text(encoding="utf-8")
    for now, then in (
        ("center = [50.5, -2.0, 0.0]\nsize = [15.0, 4.0, 8.0]", "center = [49.7, -2.0, 0.0]\nsize = [16.6, 4.0, 8.0]"),
        ("center = [39.5, -3.5, 0.0]\nsize = [7.0, 1.0, 8.0]", "center = [38.7, -3.5, 0.0]\nsize = [5.4, 1.0, 8.0]"),
        ("center = [39.5, -1.5, 0.0]", "center = [38.7, -1.5, 0.0]"),
    ):
        assert now in text
        text = text.replace(now, then)
    path = tmp_path / "prologue.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.slow
def test_no_bodies_crosses_a_pit_a_late_jump_can_clear(tmp_path):
    # The shortcut is real: where the pit is narrow enough, it wins without the ball.
    level = load_flat_level(narrowed(tmp_path))
    route = flat_route(level, replay_path=REPLAY)
    game = play(level, route, "no_bodies")
    assert game.outcome == "complete"
    assert route.on_ball.any()  # the replay rides the ball; the bot never does


@pytest.mark.slow
def test_the_shipped_prologue_needs_its_ball_its_key_and_its_z():
    level = load_flat_level(PROLOGUE)
    route = flat_route(level)
    assert route is not None and route.won and set(level.needs) == {"w_move", "radar", "rigid_bodies"}
    for name in ("straight", "no_radar", "no_bodies"):
        assert play(level, route, name, limit=2 * route.ticks).outcome is None, name


@pytest.mark.slow
def test_after_a_fall_into_the_pit_the_bot_gets_back_on_the_route():
    level = load_flat_level(PROLOGUE)
    route = flat_route(level)
    game = play(level, route, "fall_in_pit", limit=3 * route.ticks)
    assert game.outcome == "complete"
