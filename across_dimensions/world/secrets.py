"""``[[secret]]``: a hidden place the level counts, found by stepping into its 4D volume.

A secret is a named box in ``[x, y, z, w]``: a hidden crystal's nook, a room that exists at
another w, or a secret exit. The player finds it the first time the centre of their box
(0.875 m above the feet) and their w are inside it::

    [[secret]]
    name = "the drowned garden"
    min = [-6.0, 0.0, 10.0, 1.2]
    max = [-2.0, 3.0, 14.0, 1.8]
    exit = false      # true: finding it also finishes the level (a secret exit)

The game counts each once (the ``secret_found`` event,
:mod:`across_dimensions.game.systems.secrets`), the HUD says which of how many it was, and
the level select shows how many of a level's secrets the player has ever found.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fields import Field
from .limits import COORD, MAX_NAME_CHARS, Range

SECRET_TABLE = {
    "name": Field("text", range=Range(1, MAX_NAME_CHARS)),
    "min": Field("vector", 4, range=COORD),
    "max": Field("vector", 4, range=COORD),
    "exit": Field("bool", default=False),
}


@dataclass(frozen=True)
class SecretSpec:
    """A ``[[secret]]``: its name, its volume ``lo, hi (4,) float64`` (``[x, y, z, w]`` of the
    player's box centre and w) and whether finding it finishes the level."""

    name: str
    lo: np.ndarray
    hi: np.ndarray
    exit: bool = False

    def holds(self, center: np.ndarray, w: float) -> bool:
        """Is a player whose box centre is ``center (3,)`` at ``w`` inside the volume?"""
        p = np.append(np.asarray(center, float)[:3], float(w))
        return bool(np.all(p >= self.lo) and np.all(p <= self.hi))


def read_secrets(r, data, w_range) -> tuple[SecretSpec, ...]:
    """The ``[[secret]]`` tables (``r`` is the level loader's reader; ``w_range`` the level's, or
    None when it is broken). Each has a distinct name and a volume the player can be in: min < max
    on every axis, its w overlapping the level's w range."""
    tables = r.entries(data, "secret", "top level", lambda k: f"[[secret]] #{k}") if "secret" in data else []
    out, seen = [], set()
    for i, t in enumerate(tables, 1):
        where = f"[[secret]] #{i}"
        r.unknown(t, SECRET_TABLE, where)
        n = len(r.problems)
        v = r.read(t, SECRET_TABLE, where)
        if len(r.problems) > n:
            continue
        name = v["name"]
        where = f"[[secret]] #{i} '{name}'"
        if name in seen:
            r.problem(where, f"field 'name': another secret is named '{name}' (expected each name once)")
        seen.add(name)
        lo, hi = np.asarray(v["min"], float), np.asarray(v["max"], float)
        if np.any(lo >= hi):
            r.problem(
                where, f"fields 'min', 'max': expected min < max on every axis, got {lo.tolist()} and {hi.tolist()}"
            )
        elif w_range is not None and (hi[3] < w_range[0] or lo[3] > w_range[1]):
            r.problem(
                where,
                f"fields 'min', 'max': its w from {lo[3]:g} to {hi[3]:g} is outside the level's w_range "
                f"{[float(x) for x in w_range]}, so it can never be found",
            )
        out.append(SecretSpec(name, lo, hi, bool(v["exit"])))
    return tuple(out)
