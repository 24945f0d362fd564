"""The game: a pure simulation stepped at a fixed 60 Hz, and what each frame shows.

- :mod:`.sim` -- :class:`~.sim.Game`: ``step(actions)`` runs the systems in
  order; ``frame(alpha)`` asks them what to draw.
- :mod:`.system` -- the systems' lifecycle: a :class:`~.system.System` is a
  name and ``setup``, ``step``, ``draw`` and ``state_bytes`` hooks; each system's
  state is a dataclass kept as ``game.states.<name>`` and hashed field by field.
- :mod:`.systems` -- one module per system (energy, camera, seek, manipulation,
  player, weapons, enemies, crystals, ...), in the order they run. Add a
  mechanic: ``CONVENTIONS.md``, *Systems*.
- :mod:`.entities` -- everything that lives in 4D is an entity with a stable
  id; add a kind by spawning it with a new ``kind`` and writing its system.
- :mod:`.events` -- typed per-tick events (``crystal_collected``,
  ``energy_empty``, ``w_blocked``, ...) read by the HUD, tests and the replay
  summary.
- :mod:`.energy` -- the energy bar, the one account every 4D action pays from.
- :mod:`.actions`, :mod:`.replay` -- per-tick player intent, and replays of it
  (:mod:`.replay_format` reads the files, :mod:`.playback` plays them).
- :mod:`.frame` -- plain data for the renderer: camera, drawables, HUD, radar.
- :mod:`.poses`, :mod:`.entity_models` -- many poses in one pass (the same bits as one by
  one): every enemy's each tick, every drawn entity's each frame.

Nothing here imports a window or GL library or reads the wall clock; see
``CONVENTIONS.md`` at the repository's top level.
"""
