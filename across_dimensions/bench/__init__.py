"""The benchmarks behind ``across-dimensions bench``: each figure next to a baseline timed in the
same run, and a PASS or FAIL line for each of the project's speed targets.

They stand above ``game`` and ``render`` and below ``app`` (``tests/test_layering.py``): they
play levels through the game's public interface (levels, actions, ``Game.step``,
``Game.frame``, ``Game.place_player``) and draw frames with the renderer, never reaching
into a system's state. The command line (``app``) only parses options and calls them.

- :mod:`.report` -- the whole ``bench`` command's CPU report.
- :mod:`.systems` -- entities, crystals and enemies per tick and per frame.
- :mod:`.collision`, :mod:`.camera` -- the walker against turning solids; the 4D camera's modes.
- :mod:`.hud`, :mod:`.ghosts`, :mod:`.look` -- the HUD and radar, ghosts along w, the scene look.
- :mod:`.scene`, :mod:`.levels` -- ``bench scene`` and ``bench levels``.

The kernel benchmarks stay beside their kernels (``core/bench.py``, ``physics/bench.py``):
they time one package against a copy of the same bytes or an empty step and use nothing above
it, so the core and the physics keep their own measure as libraries.
"""
