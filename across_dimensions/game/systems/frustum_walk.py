"""Walking into frustum images (objects a level marks ``walkable_in_frustum``), each tick after
the player moved.

While the frustum view holds, the walker meets such an object as its image (:mod:`..frustum_walk`,
through ``game.sections_at``). This system reports the player stepping onto or into an image
(:class:`~..events.EnteredFrustumObject`, once per entry), and when the view ends (the glide back
starts: the key, or an empty bar) and the objects are their cross-sections again, puts a player
who now stands inside geometry at the nearest free spot (:func:`..frustum_walk.safe_spot`; the
place the view was switched on from, or the last checkpoint, when nothing near is free) with a
:class:`~..events.MovedToSafety`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..events import EnteredFrustumObject, MovedToSafety
from ..frustum_walk import images_hold, overlaps, safe_spot, walkable
from ..player import player_box
from ..system import System, encode

#: Metres the player's box may stand off an image's bounds and still touch it: the walker keeps
#: a skin (``player.SKIN``, 0.1 mm) off what it stands on or leans on, so standing on an image or
#: walking into its wall counts as entering it.
TOUCH = 0.01


@dataclass
class FrustumWalk:
    """``game.states.frustum_walk``: where the view was switched on from (feet, ``(4,)`` as a
    list) and the walkable entities whose image the player touches."""

    anchor: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0, 0.0])
    touching: list[int] = field(default_factory=list)


def setup(game) -> FrustumWalk | None:
    """A state when the level marks any object ``walkable_in_frustum``; None otherwise."""
    if not any(o.walkable_in_frustum for o in game.scene.objects):
        return None
    return FrustumWalk(anchor=[float(x) for x in game.player.position])


def state_bytes(game) -> bytes:
    return encode(game.states.frustum_walk)


def _touching(game) -> list[int]:
    lo, hi = player_box(game.player.position)
    out = []
    for e in game.entities:
        if not walkable(e):
            continue
        tris = game.image_triangles(e)
        if len(tris) and np.all(lo <= tris.max(axis=(0, 1)) + TOUCH) and np.all(hi >= tris.min(axis=(0, 1)) - TOUCH):
            out.append(e.id)
    return out


def _to_safety(game, walk: FrustumWalk) -> None:
    if not overlaps(game, game.player.position):
        return
    spot = safe_spot(game, walk.anchor)
    if spot is None:
        game.respawn()
    else:
        game.player.position = spot
        game.player.velocity = np.zeros(4)
    game.emit(MovedToSafety(tuple(float(x) for x in game.player.position)))


def step(game, actions) -> None:
    walk = game.states.frustum_walk
    if walk is None:
        return
    switched = [ev.mode for ev in game.events if ev.kind == "camera_switched"]
    if "frustum" in switched:
        walk.anchor = [float(x) for x in game.player.position]
    if images_hold(game):
        now = _touching(game)
        for eid in now:
            if eid not in walk.touching:
                game.emit(EnteredFrustumObject(eid, game.entities.get(eid).name))
        walk.touching = now
        return
    walk.touching = []
    if "returning" in switched:
        _to_safety(game, walk)


SYSTEM = System("frustum_walk", setup, step, state_bytes=state_bytes)
