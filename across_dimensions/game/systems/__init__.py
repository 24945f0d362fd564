"""The game's systems, in the order they run.

A system is a module with either or both of

``step(game, actions)``
    Advance its part of the simulation by one tick. Systems run in the order of
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

from . import crystals, energy, ghosts, outcome, player, push, radar, rigid_bodies, scenery, sections, seek

#: Tick order: energy first (new tick), the player moves, pushes bodies, physics
#: runs, pickups, then the outcome. Frame order: scenery, entities, radar, HUD.
#: Seek reads its presses before the player moves (the glide starts on the tick of the
#: press); ghosts draw last, after everything solid.
SYSTEMS = (energy, seek, player, push, rigid_bodies, crystals, outcome, scenery, sections, radar, ghosts)

__all__ = ["SYSTEMS"]
