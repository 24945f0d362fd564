"""Hints that wait for an outcome (``until`` in the level file) follow the level's state, not keys.

The shipped replays finish each level by its intended route; a hint book is driven alongside with
the same actions and the game after each tick, as the window drives it. A hint with ``until`` must
be done on the very tick its state first holds (not before, however often its keys were pressed),
and every hint is closed by the level's end.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import per_level

from across_dimensions.game.actions import Actions
from across_dimensions.game.events import event_kinds
from across_dimensions.game.hints import HintBook, holds
from across_dimensions.game.playback import play
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import DT, Game
from across_dimensions.world import hints as world_hints
from across_dimensions.world.level import LevelError, load_level
from across_dimensions.world.resources import level_files

ROOT = Path(__file__).resolve().parents[1]
REPLAYS = ROOT / "levels" / "replays"


def _shipped_with_until() -> list[Path]:
    return [
        p for p in level_files() if any(h.until for h in load_level(p).hints) and (REPLAYS / f"{p.stem}.json").exists()
    ]


def test_hint_events_are_game_events():
    assert set(world_hints.EVENTS) <= set(event_kinds())


@pytest.mark.parametrize("path", per_level(_shipped_with_until()))
def test_a_hint_waiting_for_an_outcome_is_done_on_the_tick_it_happens(path):
    level = load_level(path)
    game = Game(level, seed=0)
    replay = Replay.load(REPLAYS / f"{path.stem}.json")
    game = Game(level, seed=replay.seed)
    book = HintBook(level.hints)
    first_holds: dict[int, int] = {}  # hint index -> first tick its until held
    done_at: dict[int, int] = {}
    actions = iter(replay.actions)

    def on_tick(g):
        a = next(actions)
        book.tick(a, DT, g)
        for i, spec in enumerate(level.hints):
            if spec.until and i not in first_holds and holds(spec.until, g):
                first_holds[i] = g.tick
            if book.hints[i].done and i not in done_at:
                done_at[i] = g.tick

    result = play(replay, game, on_tick=on_tick)
    assert result.outcome == "complete" and result.divergence is None  # hints never touch the simulation
    assert all(h.done for h in book.hints), "the level's end closes every hint"
    for i, spec in enumerate(level.hints):
        if not spec.until or spec.until.get("event") == "level_complete":
            continue
        assert i in first_holds, f"hint #{i + 1}'s state {spec.until} never held on the intended route"
        # Done when its state holds, or earlier only when a later hint's state held first.
        later = [first_holds[j] for j in first_holds if j > i]
        assert done_at[i] == first_holds[i] or done_at[i] == min(later, default=-1), (i, done_at, first_holds)


def test_pressing_the_keys_of_an_outcome_hint_is_not_enough():
    """Blast and Field's third hint asks for the switch hit: firing at nothing leaves it up."""
    level = load_level(ROOT / "levels" / "05_blast_and_field.toml")
    game = Game(level, seed=0)
    book = HintBook(level.hints)
    for h in book.hints[:2]:
        h.done = True
    fire = Actions(fire=True)
    for _ in range(120):
        game.step(fire)
        book.tick(fire, DT, game)
        book.note("fire")
    assert book.current_index() == 2 and "switch" in book.current().text


def test_a_later_hints_state_closes_the_ones_before_it():
    level = load_level(ROOT / "levels" / "00_arrival.toml")
    game = Game(level, seed=0)
    book = HintBook(level.hints)
    game.place_player([0.0, 0.0, 3.0, 0.0])  # past the barrier without walking or jumping
    book.tick(Actions(), DT, game)
    assert book.current_index() == 2 and "pad" in book.current().text


def test_until_is_checked_by_the_loader(tmp_path):
    src = (ROOT / "levels" / "05_blast_and_field.toml").read_text()
    bad = src.replace('until = { gone = "door B" }', 'until = { gone = "door Q", when = 3 }', 1)
    bad = bad.replace('until = { event = "blast" }', 'until = { event = "blasted" }', 1)
    p = tmp_path / "bad.toml"
    p.write_text(bad)
    with pytest.raises(LevelError) as e:
        load_level(p)
    msg = str(e.value)
    assert "hints #3 > until: unknown field 'when'" in msg
    assert "field 'event': expected one of" in msg and "'blasted'" in msg
    # The unknown name is reported only once the rest reads well (names are checked last).
    p.write_text(src.replace('until = { gone = "door B" }', 'until = { gone = "door Q" }', 1))
    with pytest.raises(LevelError, match=r"hints #3: field 'gone': nothing named 'door Q'"):
        load_level(p)
