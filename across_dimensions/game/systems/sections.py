"""Every 4D thing (extended worlds, entities with a mesh) as the 4D camera shows it:
its cross-section by the player's slice, or its frustum projection while the camera
is detached. The work is the projection stage's (:mod:`..projection`).

Entities whose bounding radius does not reach the slice are skipped without
slicing (most 4D things in a level are at other w most of the time).
"""

from __future__ import annotations

from ..projection import items, project


def draw(game, frame, alpha) -> None:
    frame.drawables.extend(project(game, game.camera, items(game, alpha)))
