"""The game's systems, in the order they run.

Each module here declares one :class:`~..system.System` named ``SYSTEM``: its name and
its hooks ``setup``, ``step``, ``draw`` and ``state_bytes`` (see :mod:`..system` for
what each does and when it runs). ``Game`` sets every system up once, in this order,
when it is made; runs every ``step`` in this order each tick, and every ``draw`` each
frame; and hashes every ``state_bytes``. A ``step`` may return a replacement
:class:`~across_dimensions.game.actions.Actions` that the systems after it see this
tick (manipulation takes the walking keys while an object is held); returning None
leaves the actions as they are. A later system sees what earlier ones did this tick
(the player has moved before crystals are checked for pickup).

A system's state is a dataclass its ``setup`` returns, kept by the game as
``game.states.<name>``; per-entity state is the entity's ``data``. Never module
globals (two games share nothing), never attributes hung on the game. How to add a
mechanic: ``CONVENTIONS.md``, *Systems*.
"""

from . import (
    beacons,
    bullets,
    camera,
    crystals,
    enemies,
    energy,
    frustum_walk,
    ghosts,
    health,
    manipulation,
    outcome,
    player,
    push,
    radar,
    rigid_bodies,
    scenery,
    secrets,
    sections,
    seek,
    solid_bodies,
    weapons,
)

#: Tick order: energy first (new tick); the 4D camera (turning the slice, the frustum
#: switch; it holds the w keys while detached); seek reads its presses before the player moves
#: (the glide starts on the tick of the press); manipulation (it turns objects and takes
#: the walking keys while one is held); the player moves (walking into frustum images, and put
#: somewhere safe when the view ends inside geometry), pushes bodies; weapons fire and
#: steer bullets, and the beacons bring back bodies out of range, before physics runs; bullets
#: read its contacts after; enemies (the blast, bullet
#: hits, their moves and shots) and the player's health after the bullets; pickups; the outcome;
#: the secrets (a secret exit finishes the level only when the goal did not this tick).
#: Frame order: manipulation (its ghost previews, HUD line), scenery, entities, radar, HUD,
#: then the ghosts along w, after everything solid. Setup runs in the same order, so the
#: entities systems spawn get their ids in it: targets, then enemies, then the level's crystals.
SYSTEMS = (
    energy.SYSTEM,
    camera.SYSTEM,
    seek.SYSTEM,
    manipulation.SYSTEM,
    player.SYSTEM,
    frustum_walk.SYSTEM,
    push.SYSTEM,
    weapons.SYSTEM,
    solid_bodies.SYSTEM,
    beacons.SYSTEM,
    rigid_bodies.SYSTEM,
    bullets.SYSTEM,
    enemies.SYSTEM,
    health.SYSTEM,
    crystals.SYSTEM,
    outcome.SYSTEM,
    secrets.SYSTEM,
    scenery.SYSTEM,
    sections.SYSTEM,
    ghosts.SYSTEM,
    radar.SYSTEM,
)

__all__ = ["SYSTEMS"]
