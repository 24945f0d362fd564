"""``[[beacon]]``: a reset beacon that brings a key object back when it leaves its range.

A level names a rigid body the player needs (a crate to climb on, a ball to roll) and the
4D box it belongs in::

    [[beacon]]
    object = "crate"
    min = [-1.0, -1.0, -3.0, -0.5]
    max = [1.0, 3.0, 8.5, 0.5]

When the body's centre has stayed outside that box for ``after`` seconds, the game puts it
back where the level placed it, at rest, and says so on screen
(:mod:`across_dimensions.game.systems.beacons`), so no push, shot or fall can lose it for
good. The box must hold the body's start, and the body's start must be a place it can be
put back to.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fields import Field
from .limits import COORD, MAX_NAME_CHARS, Range

AFTER = Range(0.0, 60.0, "s")
BEACON_TABLE = {
    "object": Field("text", range=Range(1, MAX_NAME_CHARS)),
    "min": Field("vector", 4, range=COORD),
    "max": Field("vector", 4, range=COORD),
    "after": Field("number", default=1.0, range=AFTER, sign="nonnegative"),
}


@dataclass
class BeaconSpec:
    """A ``[[beacon]]``: the body's name, its range ``lo, hi (4,) float64`` and the seconds
    it may spend outside before it is brought back."""

    object: str
    lo: np.ndarray
    hi: np.ndarray
    after: float = 1.0


def read_beacons(r, data, objects) -> list[BeaconSpec]:
    """The ``[[beacon]]`` tables (``r`` is the level loader's reader; ``objects`` the level's
    :class:`~.level.ObjectSpec` s). Each names a rigid body, once, whose start lies in its box."""
    tables = r.array_of_tables(data, "beacon", "top level")[: len(objects) + 1] if "beacon" in data else []
    by_name = {o.name: o for o in objects}
    out, seen = [], set()
    for i, t in enumerate(tables, 1):
        where = f"[[beacon]] #{i}"
        r.unknown(t, BEACON_TABLE, where)
        n = len(r.problems)
        v = r.read(t, BEACON_TABLE, where)
        if len(r.problems) > n:
            continue
        name = v["object"]
        where = f"[[beacon]] #{i} '{name}'"
        o = by_name.get(name)
        if o is None:
            r.problem(where, f"field 'object': no [[object]] is named '{name}'")
            continue
        if o.body == "none":
            r.problem(where, f"field 'object': '{name}' is not a rigid body (give it a body) and never moves")
        if name in seen:
            r.problem(where, f"field 'object': '{name}' already has a beacon (one per object)")
        seen.add(name)
        lo, hi = np.asarray(v["min"], float), np.asarray(v["max"], float)
        if np.any(lo >= hi):
            got = f"got {lo.tolist()} and {hi.tolist()}"
            r.problem(where, f"fields 'min', 'max': expected min < max on every axis, {got}")
        elif np.any(o.position < lo) or np.any(o.position > hi):
            r.problem(where, f"'{name}' starts at {o.position.tolist()}, outside [min, max]: it would be reset at once")
        out.append(BeaconSpec(name, lo, hi, float(v["after"])))
    return out
