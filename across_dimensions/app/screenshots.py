"""Screenshots (F12, ``--screenshot-after``): where they go and what they are called.

They go to the player's pictures folder (``platformdirs.user_pictures_dir()``,
``~/Pictures`` on Linux), in its ``Across Dimensions`` folder, named by the local
date and time: ``across-dimensions_2026-12-02_08-41-07.png``, then ``_2``, ``_3``
for more in the same second. ``$ACROSS_DIMENSIONS_SCREENSHOT_DIR`` replaces the
folder (tests, portable installs). A name is claimed by creating the file
exclusively before the image is written over it, so a shot never replaces
another, this game's or a second one's, whatever was deleted in between.

Failing to write a screenshot (a read-only or full disk) is a notice on screen,
never the end of the game: :func:`save_screenshot` returns the line to show.
"""

from __future__ import annotations

import contextlib
import os
from datetime import datetime
from pathlib import Path

from ..core.errors import InputError

DIR_ENV = "ACROSS_DIMENSIONS_SCREENSHOT_DIR"
SUBFOLDER = "Across Dimensions"
PREFIX = "across-dimensions_"
#: Most shots named in one second before giving up (a held key repeats about 30 times a second).
MAX_PER_SECOND = 999


def screenshot_folder() -> Path:
    """Where screenshots go (see the module docstring)."""
    override = os.environ.get(DIR_ENV, "").strip()
    if override:
        return Path(override).expanduser()
    import platformdirs

    return Path(platformdirs.user_pictures_dir()) / SUBFOLDER


def claim_name(folder: Path, now: datetime) -> Path:
    """Create and return a new empty file in ``folder`` named for ``now``; never an existing name.

    Raises
    ------
    OSError
        The folder cannot be written, or every name of that second is taken.
    """
    stamp = now.strftime("%Y-%m-%d_%H-%M-%S")
    for n in range(1, MAX_PER_SECOND + 1):
        path = folder / f"{PREFIX}{stamp}{'' if n == 1 else f'_{n}'}.png"
        try:
            os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644))
        except FileExistsError:
            continue
        return path
    raise OSError(f"{MAX_PER_SECOND} screenshots already named for {stamp}")


def save_screenshot(write, folder: Path | None = None, now: datetime | None = None) -> tuple[Path | None, str]:
    """Claim a name and let ``write(path)`` write the PNG over it; never raises for a disk problem.

    Parameters
    ----------
    write : callable
        ``write(path)`` writes the image to ``path`` (whole or not at all).
    folder : Path, optional
        Default :func:`screenshot_folder`; created when missing (the game's own folder).
    now : datetime, optional
        The time the name is made of (default: now, local time).

    Returns
    -------
    path : Path or None
        The file written, or None when it could not be.
    message : str
        One line for the screen and the terminal: where it went, or why not.
    """
    folder = Path(folder) if folder is not None else screenshot_folder()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        path = claim_name(folder, now or datetime.now())
    except OSError as e:
        return None, f"Screenshot not saved: {folder}: {e.strerror or e}"
    try:
        write(path)
    except (OSError, InputError) as e:
        with contextlib.suppress(OSError):
            if path.stat().st_size == 0:  # only our own empty claim
                path.unlink()
        why = e.strerror if isinstance(e, OSError) and e.strerror else str(e).replace(f"{path}: ", "")
        return None, f"Screenshot not saved: {path}: {why}"
    return path, f"Screenshot saved: {path}"
