"""The 3D world the flat being lives in, as it is and not as the being sees it.

It keeps what changes in 3D (how far each rolling ball has rolled along z, which solids are gone,
which items were taken) and answers what the plane ``z = z0`` cuts of it: each solid's section as
convex pieces (:func:`~across_dimensions.core.flat_section.section_loops`, then
:func:`~across_dimensions.core.flat_solids.convex_pieces`), each ball's circle. No pymunk here:
:mod:`.space` turns these answers into the flat world's physics shapes.
"""

from __future__ import annotations

import numpy as np

from ...core.flat_section import section_loops, sphere_circle_radius
from ...core.flat_solids import convex_pieces
from ...world.flat_level import FlatLevel

#: How many planes' sections are kept: the being's plane and the one it steps to, with room.
_KEEP_PLANES = 4


class World3:
    """The level's 3D content over time.

    Parameters
    ----------
    level : FlatLevel

    Attributes
    ----------
    ball_z : (b,) float64
        Each ball's centre along z.
    ball_dir : (b,) float64
        +1 or -1: which way along z each rolling ball goes.
    gone : set of str
        Names of solids removed (doors opened).
    taken : set of str
        Names of items taken.
    """

    def __init__(self, level: FlatLevel):
        self.level = level
        self.ball_z = np.array([b.center[2] for b in level.balls], np.float64)
        self.ball_dir = np.ones(len(level.balls), np.float64)
        self.gone: set[str] = set()
        self.taken: set[str] = set()
        self._extents = [s.solid.z_extent() for s in level.solids]
        self._pieces: dict[float, list[tuple[list, list]]] = {}

    def advance(self, dt: float) -> None:
        """Roll the balls ``dt`` seconds on: each runs along z at its speed and turns back at the
        ends of its ``roll`` (its path folded at the end it passed, so no time is lost there)."""
        for i, b in enumerate(self.level.balls):
            if b.roll is None or b.speed == 0.0:
                continue
            lo, hi = b.roll
            z = self.ball_z[i] + self.ball_dir[i] * b.speed * dt
            if z > hi:
                z, self.ball_dir[i] = 2.0 * hi - z, -1.0
            elif z < lo:
                z, self.ball_dir[i] = 2.0 * lo - z, 1.0
            self.ball_z[i] = min(max(z, lo), hi)

    def pieces(self, z0: float) -> list[list[np.ndarray]]:
        """Each solid's section at ``z0`` as convex counter-clockwise pieces ``(k, 2) float64``, in
        level order; a solid that is gone or that the plane misses has none."""
        return [[] if s.name in self.gone else p for s, (_, p) in zip(self.level.solids, self._cuts(z0))]

    def outlines(self, z0: float) -> list[list[np.ndarray]]:
        """Each solid's section at ``z0`` as its closed outlines ``(k, 2) float64`` (what is drawn
        round it: the pieces' inner edges are the physics' business only)."""
        return [[] if s.name in self.gone else o for s, (o, _) in zip(self.level.solids, self._cuts(z0))]

    def _cuts(self, z0: float) -> list[tuple[list, list]]:
        """``(outlines, pieces)`` of every solid at ``z0``, kept for a few planes: nothing about a
        solid changes but whether it is gone."""
        found = self._pieces.get(z0)
        if found is None:
            if len(self._pieces) >= _KEEP_PLANES:
                self._pieces.pop(next(iter(self._pieces)))
            found = self._pieces[z0] = [self._cut(i, z0) for i in range(len(self.level.solids))]
        return found

    def _cut(self, i: int, z0: float) -> tuple[list, list]:
        lo, hi = self._extents[i]
        if not lo <= z0 < hi:
            return [], []
        loops = section_loops(self.level.solids[i].solid, z0)
        return loops, [piece for loop in loops for piece in convex_pieces(loop)]

    def ball_radius(self, i: int, z0: float) -> float:
        """Radius of ball ``i``'s circle in the plane ``z0`` (0 when it misses the plane)."""
        return sphere_circle_radius(float(self.ball_z[i]), self.level.balls[i].radius, z0)

    def item_radius(self, i: int, z0: float) -> float:
        """Radius of item ``i``'s circle in the plane ``z0`` (0 when it misses it or was taken)."""
        item = self.level.items[i]
        return 0.0 if item.name in self.taken else sphere_circle_radius(float(item.position[2]), item.radius, z0)

    def crate_present(self, i: int, z0: float) -> bool:
        """Whether the plane ``z0`` cuts crate ``i`` (a box over its own z extent)."""
        c = self.level.crates[i]
        return c.center[2] - c.size[2] / 2 <= z0 < c.center[2] + c.size[2] / 2

    def state_bytes(self) -> bytes:
        """What of the 3D world evolves, for the state hash."""
        return b"".join(
            [
                self.ball_z.tobytes(),
                self.ball_dir.tobytes(),
                repr(sorted(self.gone)).encode(),
                repr(sorted(self.taken)).encode(),
            ]
        )
