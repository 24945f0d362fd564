"""The Flatland prologue: the w step learnt one dimension down.

The player is a flat being in the side view ``(x, y)`` of a 2D world with gravity, the slice
``z = z0`` of a 3D world it cannot see; the player's w keys move that slice along z. Walls that
exist only near some z shrink and vanish, a 3D ball rolling through the plane is a circle that
grows and shrinks, a staircase is a different shape at each z. Its physics is pymunk
(:mod:`.space`, the only module that imports it), fed the sections the core computes
(:mod:`across_dimensions.core.flat_section`); the level format is ``world.flat_level``.

* :mod:`.world3`: the 3D world and its sections at a z.
* :mod:`.space`: the pymunk space, the being's walk.
* :mod:`.sim`: :class:`FlatGame`, one fixed tick at a time.
* :mod:`.hints`: hints done by the level's state.
* :mod:`.view`: what a frame shows, as plain data.
"""

from .sim import DT, TICK_RATE, FlatEvent, FlatGame

__all__ = ["DT", "TICK_RATE", "FlatEvent", "FlatGame"]
