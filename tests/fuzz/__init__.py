"""Fuzzing what a player or modder can hand the game: levels, replays, settings, meshes, options.

- :mod:`.mutate` and :mod:`.npzgen` make hostile variants of the shipped files;
  :mod:`.emit` writes them as TOML or JSON, NaN and 5000-digit integers included.
- :mod:`.cases` turns ``(seed, index)`` into one case: the files to write and
  the commands a user would run on them.
- :mod:`.worker` runs cases in a separate, memory-capped process;
  :mod:`.harness` drives it and judges the output.

The pytest entry point is ``tests/test_fuzz.py``; ``python -m tests.fuzz`` (from
the repository root) rebuilds and reruns single cases by index.
"""
