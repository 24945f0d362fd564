"""Keep Python's garbage collector from stalling frames.

A running game holds a few hundred thousand long-lived objects (numba's and LLVM's
type objects, the level, the meshes). Python's oldest-generation collection walks
all of them: measured here at up to 90 ms, a visible hitch, every time enough new
objects have survived the young generations. Once a level is loaded, its objects
and everything before it live until the next load, so they are moved out of the
collector's sight (``gc.freeze``); the objects a frame makes and drops are still
collected, and cheaply.
"""

from __future__ import annotations

import gc


def settle() -> None:
    """Collect what the previous level left, then freeze every surviving object.

    Call it right after loading a level (the load itself is a pause the player
    expects). The objects frozen by the previous call are unfrozen first, so a
    level's garbage is collected at the next load instead of kept for ever.
    """
    gc.unfreeze()
    gc.collect()
    gc.freeze()


__all__ = ["settle"]
