"""The levels' ghosts, kept with the progress data: each level's best run from its start to its goal.

In ``ghosts/`` of the game's data folder (:func:`~.saves.data_folder`), two files a level:

- ``<level>.json``: the run's track, what a time trial races (format:
  :mod:`across_dimensions.game.ghost_run`);
- ``<level>.replay.json``: the same run as a replay (``across-dimensions replay LEVEL FILE``
  plays it back).

Both are written atomically (:func:`~across_dimensions.core.fileio.atomic_write`), the replay
first: a crash leaves the old ghost or the new one, never half of one. A ghost file that cannot
be read is moved aside (``<level>.corrupt-N.json``) with one warning, and the level has no ghost
until the next finished run; a ghost never stops the game.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..core.fileio import FileProblem, MiB, atomic_write, read_text
from ..game.ghost_run import GhostTrack
from .saves import data_folder, set_aside

FOLDER = "ghosts"
#: Largest ghost file read: a two-hour run (the longest replay) is about 9 MB.
MAX_BYTES = 16 * MiB


def ghost_folder() -> Path:
    """Where the ghosts live: ``ghosts/`` in the game's data folder."""
    return data_folder() / FOLDER


def ghost_path(level: str, folder: Path | None = None) -> Path:
    """The ghost file of the level ``level`` (its stem)."""
    return Path(folder if folder is not None else ghost_folder()) / f"{level}.json"


def replay_path(level: str, folder: Path | None = None) -> Path:
    """The replay of the level's ghost run."""
    return Path(folder if folder is not None else ghost_folder()) / f"{level}.replay.json"


def load_ghost(level: str, folder: Path | None = None) -> tuple[GhostTrack | None, list[str]]:
    """The level's ghost, never raising.

    Returns
    -------
    ghost : GhostTrack or None
        None when there is none, or it could not be read.
    warnings : list of str
        Empty, or one line: the file was not a ghost (and why), where it was kept aside.
    """
    path = ghost_path(level, folder)
    if not os.path.lexists(path):
        return None, []
    try:
        ghost = GhostTrack.from_json(read_text(path, limit=MAX_BYTES, what="ghost"))
    except (FileProblem, ValueError, RecursionError) as e:  # json.JSONDecodeError is a ValueError
        why = str(e).replace(f"{path}: ", "").splitlines()[0]
        return None, [f"{path}: not a ghost this game can read ({why}); {set_aside(path)}; no ghost for this level"]
    if ghost.level != level:
        return None, [f"{path}: the ghost of {ghost.level!r}, not of {level!r}; {set_aside(path)}"]
    return ghost, []


def save_ghost(ghost: GhostTrack, replay, folder: Path | None = None) -> Path:
    """Keep ``ghost`` (and ``replay``, the same run) as its level's ghost, replacing the old one.

    The game's own ghost folder is created when missing.

    Raises
    ------
    FileProblem
        When either file cannot be written (the old ghost stays as it was).
    """
    own = folder is None
    folder = Path(folder) if folder is not None else ghost_folder()
    if own:
        try:
            folder.mkdir(parents=True, exist_ok=True)  # the game's own folder: ours to create
        except OSError as e:
            raise FileProblem(f"{folder}: cannot create the ghosts' folder ({e.strerror or e})") from None
    replay.save(replay_path(ghost.level, folder))
    return atomic_write(ghost_path(ghost.level, folder), ghost.to_json() + "\n")
