"""Crystals: 4D energy the player collects by touching its cross-section.

A crystal can only be touched where it can be seen: the player must be at a w
where the crystal's cross-section exists, and the player's box must reach that
section. A crystal is taken once, adds its energy to the bar (up to the
maximum) and disappears. A crystal with a ``respawn`` time grows back as a new
entity that many seconds later, so a level can make running dry recoverable
(:class:`Regrowth`, ``game.states.crystals``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...core.shapes import make_shape
from ...world.gameplay import CrystalSpec
from ...world.scene import Object4
from ..entities import Scripted, reach
from ..events import CrystalCollected
from ..player import player_box
from ..system import System, derived, encode

REACH = 0.15  # metres beyond the player's box that still count as touching (a hand's reach)


@dataclass
class Crystal:
    """A crystal's state (``Entity.data``): the level entry it came from."""

    spec: CrystalSpec

    @property
    def milli(self) -> int:
        """Energy it holds, thousandths."""
        return self.spec.milli


@dataclass
class Regrowth:
    """Crystals growing back (``game.states.crystals``).

    Attributes
    ----------
    regrowing : list of (int, CrystalSpec)
        The tick each grows back at and what grows, soonest first.
    """

    regrowing: list[tuple[int, CrystalSpec]] = field(default_factory=list)
    meshes: dict = derived(default_factory=dict)  # by shape and colour: crystals alike share one


def setup(game) -> Regrowth:
    """The level's crystals, spawned."""
    state = Regrowth()
    for c in game.level.crystals:
        _spawn(game, c, state.meshes)
    return state


def state_bytes(game) -> bytes:
    """What grows back when; the crystals themselves are entities (hashed with them)."""
    return encode(game.states.crystals)


def spawn(game, spec: CrystalSpec):
    """Put a crystal in the game: a small polychoron turning in the w planes, glowing."""
    return _spawn(game, spec, game.states.crystals.meshes)


def _spawn(game, spec: CrystalSpec, meshes: dict):
    key = (spec.shape, repr(spec.color))
    mesh = meshes.get(key)
    if mesh is None:
        mesh = meshes[key] = make_shape(spec.shape).with_color(spec.color)
    obj = Object4.prop(spec.name, mesh, spec.position, spec.size, spin_deg=spec.spin_deg)
    return game.entities.spawn(
        "crystal",
        spec.name,
        mesh,
        Scripted(obj),
        radar="crystal",
        style="glow",
        data=Crystal(spec),
        radius=reach(mesh, spec.size),
    )


def touching(game, entity) -> bool:
    """Does the player's box (plus :data:`REACH`) touch the entity's section in the player's slice?"""
    p = game.player
    # In slice space (the entity's own centre on the plain slice; see game.camera).
    centre, w = game.camera.to_slice(entity.center(game)), float(p.position[3])
    # Cheap rejections before slicing: out of reach in w or in space.
    lo, hi = player_box(p.position)
    far = entity.radius + REACH
    if abs(centre[3] - w) > entity.radius or np.any(centre[:3] < lo - far) or np.any(centre[:3] > hi + far):
        return False
    key = f"tick:{entity.id}"
    game.sections.section(key, entity.mesh, entity.model(game), game.slice_of(w))
    b = game.sections.bounds(key)
    if np.isnan(b).any():
        return False  # not in the slice: invisible, so untouchable
    return bool(np.all(lo - REACH < b[1]) and np.all(hi + REACH > b[0]))


def step(game, actions) -> None:
    regrowing = game.states.crystals.regrowing
    while regrowing and regrowing[0][0] <= game.tick:
        spawn(game, regrowing.pop(0)[1])
    table = game.entity_table()
    p = game.player.position
    # One vectorised test for every entity, then the full test for the crystals within reach.
    near = np.abs(game.camera.to_slice(table.centers) - p).max(axis=1) <= table.radii + 2.0 + REACH
    for e in [e for e, n in zip(table.entities, near) if n and e.kind == "crystal"]:
        if touching(game, e):
            gained = game.energy.gain(e.data.milli) if game.energy is not None else 0
            game.emit(CrystalCollected(e.id, e.data.milli, gained))
            game.remove(e.id)
            if e.data.spec.respawn > 0:
                due = game.tick + max(1, round(e.data.spec.respawn / game.dt))
                regrowing.append((due, e.data.spec))
                regrowing.sort(key=lambda item: item[0])  # stable: equal ticks keep pickup order


SYSTEM = System("crystals", setup, step, state_bytes=state_bytes)
