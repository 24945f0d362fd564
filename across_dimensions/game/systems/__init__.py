"""The game's systems, in the order they run.

A system is a module with either or both of

``step(game, actions)``
    Advance its part of the simulation by one tick. It may return a replacement
    :class:`~across_dimensions.game.actions.Actions` that the systems after it see
    this tick (manipulation takes the walking keys while an object is held);
    returning None leaves the actions as they are. Systems run in the order of
    :data:`SYSTEMS` every tick; a later system sees what earlier ones did this
    tick (the player has moved before crystals are checked for pickup).
``draw(game, frame, alpha)``
    Add what it shows to ``frame`` (a :class:`~across_dimensions.game.frame.Frame`
    with the camera already set): drawables, HUD items, radar pins. ``alpha`` is
    how far the picture lies between the previous tick and this one.

Adding a system: write one module here with ``step`` and/or ``draw``, and add
it to :data:`SYSTEMS` at the place in the order where it belongs. Systems keep
their state on the game (``game.energy``) or on entities (``entity.data``), never
in module globals, so two games never share anything.
"""

from . import (
    bullets,
    camera,
    crystals,
    enemies,
    energy,
    ghosts,
    health,
    manipulation,
    outcome,
    player,
    push,
    radar,
    rigid_bodies,
    scenery,
    sections,
    seek,
    solid_bodies,
    weapons,
)

#: Tick order: energy first (new tick); the 4D camera (turning the slice, the frustum
#: switch; it holds the w keys while detached); seek reads its presses before the player moves
#: (the glide starts on the tick of the press); manipulation (it turns objects and takes
#: the walking keys while one is held); the player moves, pushes bodies; weapons fire and
#: steer bullets before physics runs, bullets read its contacts after; enemies (the blast, bullet
#: hits, their moves and shots) and the player's health after the bullets; pickups; the outcome.
#: Frame order: manipulation (its ghost previews, HUD line), scenery, entities, radar, HUD,
#: then the ghosts along w, after everything solid.
SYSTEMS = (
    energy,
    camera,
    seek,
    manipulation,
    player,
    push,
    weapons,
    solid_bodies,
    rigid_bodies,
    bullets,
    enemies,
    health,
    crystals,
    outcome,
    scenery,
    sections,
    radar,
    ghosts,
)

__all__ = ["SYSTEMS"]
