"""Every 4D thing (extended worlds, entities with a mesh) as the 4D camera shows it:
its cross-section by the player's slice, or its frustum projection while the camera
is detached. The work is the projection stage's (:mod:`..projection`).

Entities whose bounding radius does not reach the slice are skipped without
slicing (most 4D things in a level are at other w most of the time); the rest
are sliced together, one batch per style (see ``game/entity_sections.py``).
"""

from __future__ import annotations

import numpy as np

from ..occlusion import hidden_rows, sky_boxes
from ..projection import items, project, world_items
from ..system import System


def draw(game, frame, alpha) -> None:
    rig = game.camera
    eye = frame.camera.eye4
    if rig.detached:  # frustum projection (and the return's fade): the projection stage, per thing
        frame.drawables.extend(project(game, rig, items(game, alpha), eye))
        return
    # The slice: the extended worlds one drawable each; the entities that reach the slice cut
    # together, one kernel call and one draw call per style (game/entity_sections.py), their
    # models made in one pass (game/entity_models.py).
    frame.drawables.extend(project(game, rig, world_items(game), eye))
    s = frame.camera.w
    table = game.entity_models
    table.update(game)
    reach = np.abs(rig.to_slice(table.centers)[:, 3] - s) <= table.radii
    models = table.models(game, alpha)
    # What a box hides is not cut at all (see game/occlusion.py).
    hidden = reach & hidden_rows(game, frame, models, alpha)
    shown = np.flatnonzero(reach & ~hidden)
    entities = [table.entities[i] for i in shown]
    frame.sky_boxes = sky_boxes(game, frame, models, alpha) if frame.sky == "dome" else None
    game.entity_sections.draw(frame, entities, models[shown], rig.slice_pose(s), game.sections)
    rows = np.flatnonzero(hidden)
    game.entity_sections.note_reaching([table.entities[i] for i in rows], models[rows], s)


def draw_per_object(game, frame, alpha) -> None:
    """The entities as one drawable each, through the projection stage (the path :func:`draw`
    replaces with batches; tests compare the two)."""
    things = [it for it in items(game, alpha) if it.entity >= 0]
    frame.drawables.extend(project(game, game.camera, things, frame.camera.eye4))


SYSTEM = System("sections", draw=draw)
