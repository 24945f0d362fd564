"""The state hash covers all state: every system that keeps state hashes it, and changing any
field of any system's state, of any entity (its motion and data) or of the player changes
``Game.state_hash``.

Fields are found by walking the dataclasses (``game.system.state_fields``), so a field added
later is checked without touching this file. A field that is ``None`` or an empty container at
the moment of the check is given a value made from its type annotation, which is why state
fields are annotated precisely (``list[int]``, ``tuple[float, float, int, int] | None``).
Fields marked ``fixed`` must really never change: that is checked over whole shipped replays.
"""

from __future__ import annotations

import dataclasses
import types
import typing
from collections.abc import Iterator

import numpy as np
import pytest
from conftest import per_level

from across_dimensions.game import sim
from across_dimensions.game.actions import Actions
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import Game
from across_dimensions.game.system import state_fields
from across_dimensions.game.systems import SYSTEMS
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir

REPLAYS = levels_dir() / "replays"
#: Shipped replays that between them set every system going: rigid bodies (03), the gun and
#: targets (04), the blast's pulls and the field (05), manipulation (06), the turned slice (07),
#: the frustum camera and seek (08), enemies, their shots, health and checkpoints (09).
COVERING = ("03_tumbling_hall", "05_blast_and_field", "06_bridge", "07_orthogonal_worlds", "08_around_the_corner")


# ------------------------------------------------------------ values from types
def _args(hint) -> tuple:
    return typing.get_args(hint)


def _is_union(hint) -> bool:
    return typing.get_origin(hint) in (typing.Union, types.UnionType)


def example(hint):
    """A value of type ``hint`` (a field's annotation), for a field that is empty now."""
    if _is_union(hint):
        return example(next(a for a in _args(hint) if a is not type(None)))
    origin = typing.get_origin(hint) or hint
    simple = {bool: True, int: 7, float: 0.25, str: "x", bytes: b"x", np.ndarray: np.full(4, 0.25)}
    if origin in simple:
        return simple[origin]
    if origin is tuple and _args(hint):
        return tuple(example(a) for a in _args(hint))
    if origin is list and _args(hint):
        return [example(_args(hint)[0])]
    if origin is dict and _args(hint):
        k, v = _args(hint)
        return {example(k): example(v)}
    if dataclasses.is_dataclass(origin):
        hints = typing.get_type_hints(origin)
        need = [
            f
            for f in dataclasses.fields(origin)
            if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
        ]
        return origin(**{f.name: example(hints[f.name]) for f in need})
    raise AssertionError(f"cannot make a {hint!r}: annotate the state field precisely")


def variants(value, hint) -> list:
    """Values other than ``value`` that a field of type ``hint`` could hold."""
    if value is None:
        return [] if hint is typing.Any else [example(hint)]  # an entity without data
    if isinstance(value, bool | np.bool_):
        return [not value]
    if isinstance(value, int | np.integer):
        return [value + 1]
    if isinstance(value, float | np.floating):
        return [value + 0.5 if np.isfinite(value) else 0.5]
    if isinstance(value, str):
        return [value + "x"]
    if isinstance(value, bytes):
        return [value + b"x"]
    if isinstance(value, np.ndarray):
        if value.size == 0:
            return [np.zeros(1, value.dtype)]
        changed = value.copy()
        changed.flat[0] = not changed.flat[0] if changed.dtype == bool else changed.flat[0] + 1
        return [changed]
    args = _args(next((a for a in _args(hint) if a is not type(None)), hint) if _is_union(hint) else hint)
    if isinstance(value, tuple):
        first = args[0] if args else type(value[0])
        return [(v, *value[1:]) for v in variants(value[0], first)] if value else [example(hint)]
    if isinstance(value, list):
        if not value:
            return [example(hint)]
        first = args[0] if args else type(value[0])
        return [value[:-1]] + [[v, *value[1:]] for v in variants(value[0], first)]
    if isinstance(value, dict):
        if not value:
            return [example(hint)]
        key = next(iter(value))
        kind = args[1] if args else type(value[key])
        return [{k: v for k, v in value.items() if k != key}] + [{**value, key: v} for v in variants(value[key], kind)]
    if dataclasses.is_dataclass(value):
        return []  # walked field by field instead
    raise AssertionError(f"cannot vary a {type(value).__name__}: mark the field fixed() or derived()")


# ------------------------------------------------------------- the walk
def _hints(obj) -> dict:
    return typing.get_type_hints(type(obj))


def _nested(value, path: str = ""):
    """``(path, dataclass)`` for the dataclasses inside a field's value: the value itself, the
    first item of a list or dict, every item of a tuple."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        yield path, value
    elif isinstance(value, tuple):
        for i, x in enumerate(value):
            yield from _nested(x, f"{path}[{i}]")
    elif isinstance(value, list) and value:
        yield from _nested(value[0], f"{path}[0]")
    elif isinstance(value, dict) and value:
        key = next(iter(value))
        yield from _nested(value[key], f"{path}[{key!r}]")


def uncovered(game, obj, where: str) -> list[str]:
    """Every state field under dataclass ``obj`` (and the dataclasses it holds) whose change
    leaves ``game.state_hash()`` as it was."""
    missed = []
    before = game.state_hash()
    hints = _hints(obj)
    for f in state_fields(obj):
        value = getattr(obj, f.name)
        for v in variants(value, hints[f.name]):
            setattr(obj, f.name, v)
            try:
                if game.state_hash() == before:
                    missed.append(f"{where}.{f.name} = {v!r:.60}")
            finally:
                setattr(obj, f.name, value)
        for path, inner in _nested(value):
            missed += uncovered(game, inner, f"{where}.{f.name}{path}")
    assert game.state_hash() == before, f"{where}: the walk did not put everything back"
    return missed


def every_uncovered(game) -> list[str]:
    """:func:`uncovered` for each system's state, each entity and the player."""
    missed = []
    for name, state in game.states:
        if state is not None:
            missed += uncovered(game, state, f"states.{name}")
    for e in game.entities:
        missed += uncovered(game, e, f"entity {e.id} ({e.kind})")
    return missed + uncovered(game, game.player, "player")


def _game(name: str) -> Game:
    return Game(load_level(levels_dir() / f"{name}.toml"))


def _checkpoints(name: str, at: tuple) -> Iterator[Game]:
    """The game of a shipped replay, stopped at each fraction of its length in ``at`` (one game
    played on; the walk is run at each stop)."""
    replay = Replay.load(REPLAYS / f"{name}.json")
    game = _game(name)
    stops = {max(1, int(f * replay.final_ticks)) for f in at}
    for a in replay.actions:
        game.step(a)
        if game.tick in stops:
            yield game


# ------------------------------------------------------------------ tests
def test_every_system_that_sets_up_state_hashes_it():
    for system in SYSTEMS:
        if system.setup is not None:
            assert system.state_bytes is not None, f"system {system.name!r} keeps state but gives no state_bytes"
    for name in (p.stem for p in sorted(levels_dir().glob("*.toml")) if p.stem[:2].isdigit()):
        game = _game(name)
        for system_name, state in game.states:
            system = next(s for s in SYSTEMS if s.name == system_name)
            assert state is None or system.state_bytes is not None, (name, system_name)


@pytest.mark.parametrize("name", per_level(["09_hive", *COVERING]))
def test_changing_any_state_changes_the_hash(name):
    for game in _checkpoints(name, (0.3, 0.7)):
        missed = every_uncovered(game)
        assert not missed, f"{name} at tick {game.tick}: state the hash does not cover:\n" + "\n".join(missed)


def test_a_state_left_out_of_the_hash_is_found(monkeypatch):
    game = _game("08_around_the_corner")
    game.step(Actions(presses=(("seek", 1),)))
    assert not every_uncovered(game)
    forgetful = tuple(dataclasses.replace(s, state_bytes=lambda g: b"") if s.name == "seek" else s for s in SYSTEMS)
    monkeypatch.setattr(sim, "SYSTEMS", forgetful)
    missed = every_uncovered(game)
    assert missed and all(m.startswith("states.seek.") for m in missed), missed
    assert {m.split(" ")[0] for m in missed} == {f"states.seek.{f.name}" for f in state_fields(game.states.seek)}


def _fixed_fields(obj, where: str, out: dict) -> dict:
    """Every fixed field under dataclass ``obj``: path -> (value, a shallow copy of it)."""
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if f.metadata.get("state") == "fixed":
            copy = value.copy() if isinstance(value, np.ndarray | list | dict) else None
            out[f"{where}.{f.name}"] = (obj, f.name, value, copy)
        elif dataclasses.is_dataclass(value) and not isinstance(value, type):
            _fixed_fields(value, f"{where}.{f.name}", out)
    return out


def _unchanged(before: tuple) -> bool:
    obj, name, value, copy = before
    now = getattr(obj, name)
    if now is not value:
        return False
    if isinstance(copy, np.ndarray):
        return np.array_equal(now, copy)
    if isinstance(copy, list):
        return len(now) == len(copy) and all(a is b for a, b in zip(now, copy))
    if isinstance(copy, dict):
        return now.keys() == copy.keys() and all(now[k] is copy[k] for k in copy)
    return True


@pytest.mark.parametrize("name", per_level(["09_hive", *COVERING]))
def test_fixed_fields_never_change(name):
    """What the hash leaves out as fixed is set once and stays: over a whole shipped replay, for
    every state and entity there at the start and every entity spawned on the way."""
    replay = Replay.load(REPLAYS / f"{name}.json")
    game = _game(name)
    seen: dict = {}
    for a in replay.actions:
        for sname, state in game.states:
            if state is not None and f"states.{sname}" not in seen:
                seen[f"states.{sname}"] = _fixed_fields(state, f"states.{sname}", {})
        for e in game.entities:
            seen.setdefault(f"entity {e.id}", _fixed_fields(e, f"entity {e.id}", {}))
        game.step(a)
    alive = {f"entity {e.id}" for e in game.entities}
    changed = [
        path
        for owner, fields in seen.items()
        if not owner.startswith("entity") or owner in alive
        for path, before in fields.items()
        if not _unchanged(before)
    ]
    assert not changed, "fields marked fixed that changed:\n" + "\n".join(changed)
    assert game.outcome == "complete"


def test_systems_hang_nothing_on_the_game():
    game = _game("09_hive")
    names = set(vars(game))
    for _ in range(30):
        game.step(Actions(forward=1.0, presses=(("fire", 1),)))
        game.frame(0.5)
    assert set(vars(game)) - names == set(), "attributes hung on the game at run time"
