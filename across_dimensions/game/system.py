"""The systems' lifecycle: what a system is, where its state lives, how the state is hashed.

A system (one module of :mod:`.systems`) declares one :class:`System`: its name and up
to four hooks, each optional.

``setup(game) -> state or None``
    Called once, by ``Game.__init__``, in the order of :data:`.systems.SYSTEMS`, after
    the level's scene, physics world, entities and player exist. Returns the system's
    state, a dataclass of its own, or None when the system keeps nothing in this level.
    The game keeps it under the system's name: ``game.states.<name>``.
``step(game, actions) -> Actions or None``
    One tick of the system (see :mod:`.systems` for the order and the actions it may take).
``draw(game, frame, alpha) -> None``
    What the system shows in a :class:`~.frame.Frame`, ``alpha`` of the way from the last
    tick to this one. Reads the simulation, never changes its state.
``state_bytes(game) -> bytes``
    Everything of the system's state that a tick carries to the next, for
    ``Game.state_hash``; every system whose ``setup`` can return a state has one.

A state dataclass's fields are all state unless declared otherwise: :func:`fixed` for what
``setup`` takes from the level and never changes (weapon specs, meshes), :func:`derived`
for caches of other state (version counters, shapes worked out once). :func:`encode`
hashes every other field, so a field added later is covered without more code, and
``tests/test_state_hash.py`` changes each field of each state and checks the hash moves.
Systems never keep state anywhere else: not in module globals (two games share nothing)
and not as attributes hung on the game.
"""

from __future__ import annotations

import dataclasses
import functools
import struct
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import PurePath
from typing import Any

import numpy as np

#: Field metadata: set once from the level by ``setup``, never changed after (not hashed).
FIXED = {"state": "fixed"}
#: Field metadata: a cache or counter derived from other state (not hashed).
DERIVED = {"state": "derived"}


def fixed(**kw) -> Any:
    """A dataclass field that ``setup`` fills from the level and nothing changes after."""
    return dataclasses.field(metadata=FIXED, **kw)


def derived(**kw) -> Any:
    """A dataclass field that caches what other state already says (not part of the hash)."""
    return dataclasses.field(metadata=DERIVED, **kw)


def state_fields(obj) -> tuple[dataclasses.Field, ...]:
    """The fields of dataclass ``obj`` that are state (neither :func:`fixed` nor :func:`derived`)."""
    return _state_fields(type(obj))


@functools.cache
def _state_fields(cls: type) -> tuple[dataclasses.Field, ...]:
    return tuple(f for f in dataclasses.fields(cls) if "state" not in f.metadata)


@dataclass(frozen=True)
class System:
    """One system of the game: a name and its hooks (see the module docstring).

    Parameters
    ----------
    name : str
        Where its state lives (``game.states.<name>``); the module's name.
    setup, step, draw, state_bytes : callable or None
        The hooks it has.
    hashed_when_absent : bool
        False: a level where the system keeps no state (None) leaves the state hash as it was
        without the system, so shipped replays of levels that do not use a system added later
        keep their hashes.
    """

    name: str
    setup: Callable[[Any], Any] | None = None
    step: Callable[[Any, Any], Any] | None = None
    draw: Callable[[Any, Any, float], None] | None = None
    state_bytes: Callable[[Any], bytes] | None = None
    hashed_when_absent: bool = True


class States:
    """Each system's state under the system's name (``game.states.weapons``); None for a
    system that keeps none in this level. Only the systems' names exist: a misspelt name
    fails at once instead of hanging a new attribute on the game."""

    def __init__(self, names):
        for name in names:
            object.__setattr__(self, name, None)

    def __setattr__(self, name: str, value) -> None:
        if name not in self.__dict__:
            raise AttributeError(f"no system is named {name!r}")
        object.__setattr__(self, name, value)

    def __iter__(self) -> Iterator[tuple[str, Any]]:
        """``(name, state)`` for every system, in :data:`.systems.SYSTEMS` order."""
        return iter(list(self.__dict__.items()))


def encode(value) -> bytes:
    """Bytes that tell ``value`` apart from any other value of the state's types.

    Handles None, bools, whole numbers, floats, text, bytes, numpy arrays and scalars,
    tuples, lists, dicts (in their order, which the simulation keeps deterministic) and
    dataclasses (their state fields, see :func:`state_fields`). Anything else is a
    TypeError: a state holding it must mark the field :func:`fixed` or :func:`derived`.
    """
    out: list[bytes] = []
    _encode(value, out)
    return b"".join(out)


def _encode(v, out: list) -> None:
    if v is None:
        out.append(b"N")
    elif isinstance(v, bool | np.bool_):
        out.append(b"T" if v else b"F")
    elif isinstance(v, int | np.integer):
        b = str(int(v)).encode()
        out.append(b"i%d:" % len(b) + b)
    elif isinstance(v, float | np.floating):
        out.append(b"f" + struct.pack("<d", float(v)))
    elif isinstance(v, str | PurePath):
        b = str(v).encode()
        out.append(b"s%d:" % len(b) + b)
    elif isinstance(v, bytes):
        out.append(b"b%d:" % len(v) + v)
    elif isinstance(v, np.ndarray):
        out.append(f"a{v.dtype.str}{v.shape}:".encode() + np.ascontiguousarray(v).tobytes())
    elif isinstance(v, tuple | list):
        out.append(b"l%d:" % len(v))
        for x in v:
            _encode(x, out)
    elif isinstance(v, dict):
        out.append(b"d%d:" % len(v))
        for k, x in v.items():
            _encode(k, out)
            _encode(x, out)
    elif dataclasses.is_dataclass(v) and not isinstance(v, type):
        fields = state_fields(v)
        out.append(f"c{type(v).__name__}{len(fields)}:".encode())
        for f in fields:
            _encode(getattr(v, f.name), out)
    else:
        raise TypeError(f"cannot hash a {type(v).__name__} as state: mark its field fixed() or derived()")


__all__ = ["DERIVED", "FIXED", "States", "System", "derived", "encode", "fixed", "state_fields"]
