"""Game events: what happened in a tick, as typed records.

Systems report what happens with ``game.emit(SomeEvent(...))``. ``game.events``
holds the events of the last tick in the order they happened, and
``game.event_counts`` counts every kind since the start (the replay summary
prints it). The HUD, sound, tests and tools read these instead of poking at
system internals, and because systems run in a fixed order on a fixed tick,
the list is the same on every run of a replay.

Adding an event kind: a frozen dataclass deriving from :class:`Event` with a
``kind`` class attribute in snake_case. Kinds are part of the replay summary's
contract (``across-dimensions replay --json``): never rename one.
"""

from .base import Event, event_kinds
from .combat import (
    Blast,
    BulletHit,
    EnemyDefeated,
    EnemyHit,
    FieldCast,
    LootReleased,
    PlayerDied,
    PlayerHit,
    ShotFired,
    SlabKnocked,
    TargetHit,
    WeaponAcquired,
    WeaponRefused,
    WeaponSelected,
)
from .objects import (
    Manipulated,
    ManipulationEnded,
    ManipulationStarted,
    ObjectReset,
    SeekArrived,
    SeekBlocked,
    SeekStarted,
)
from .player import (
    CameraSwitched,
    CheckpointReached,
    Contact,
    CrystalCollected,
    EnergyEmpty,
    EnergySpent,
    EnteredFrustumObject,
    LevelComplete,
    MovedToSafety,
    Respawned,
    SecretFound,
    SliceAligned,
    SliceTurnRefused,
    SliceTurnUnpaid,
    WBlocked,
)

__all__ = [
    "Event",
    "event_kinds",
    "CrystalCollected",
    "EnergySpent",
    "EnergyEmpty",
    "WBlocked",
    "Contact",
    "Respawned",
    "LevelComplete",
    "CheckpointReached",
    "SecretFound",
    "CameraSwitched",
    "EnteredFrustumObject",
    "MovedToSafety",
    "SliceTurnRefused",
    "SliceTurnUnpaid",
    "SliceAligned",
    "ShotFired",
    "BulletHit",
    "Blast",
    "FieldCast",
    "TargetHit",
    "WeaponRefused",
    "WeaponAcquired",
    "WeaponSelected",
    "EnemyHit",
    "EnemyDefeated",
    "PlayerHit",
    "PlayerDied",
    "LootReleased",
    "SlabKnocked",
    "ManipulationStarted",
    "Manipulated",
    "ManipulationEnded",
    "SeekStarted",
    "SeekArrived",
    "SeekBlocked",
    "ObjectReset",
]
