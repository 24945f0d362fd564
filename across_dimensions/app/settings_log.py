"""Settings problems reported: one line on screen and on the terminal, every detail in a log file."""

from __future__ import annotations

import os
from pathlib import Path

import platformdirs

from ..core.fileio import FileProblem, atomic_writer
from .settings import APP_NAME, settings_path

#: Environment variable that replaces the log folder (tests, portable installs).
LOG_DIR_ENV = "ACROSS_DIMENSIONS_LOG_DIR"


def log_path() -> Path:
    """The settings log: ``settings.log`` in platformdirs' per-user log folder (or ``$ACROSS_DIMENSIONS_LOG_DIR``)."""
    override = os.environ.get(LOG_DIR_ENV, "").strip()
    folder = Path(override).expanduser() if override else Path(platformdirs.user_log_dir(APP_NAME))
    return folder / "settings.log"


def report_warnings(warnings: list[str], path: str | os.PathLike | None = None) -> str:
    """Write every settings warning to the log file and return the one line a player sees.

    Parameters
    ----------
    warnings : list of str
        From :func:`load_settings`.
    path : path-like, optional
        The settings file they are about (named in the line); defaults to :func:`settings_path`.

    Returns
    -------
    str
        ``""`` when there is nothing to report; otherwise one line naming the settings file, how
        many problems it has and where the details are (or that the log could not be written).
        The log file is replaced on each start: it describes the settings this run uses.
    """
    if not warnings:
        return ""
    source = Path(path) if path is not None else settings_path()
    log = log_path()
    n = len(warnings)
    what = "a problem" if n == 1 else f"{n} problems"
    line = f"Settings: {what} in {source}; defaults used for those entries"
    try:
        log.parent.mkdir(parents=True, exist_ok=True)  # the game's own log folder
        with atomic_writer(log, "w") as f:
            f.write("".join(w + "\n" for w in warnings))
    except (OSError, FileProblem) as e:
        return f"{line} (log not written: {e}); first: {warnings[0]}"
    return f"{line}; details in {log}"


def warning_screen_line(warnings: list[str], path: str | os.PathLike | None = None) -> str:
    """The short form of :func:`report_warnings`' line for the screen: file and log by name only."""
    if not warnings:
        return ""
    source = Path(path) if path is not None else settings_path()
    n = len(warnings)
    what = "a problem" if n == 1 else f"{n} problems"
    return f"{what.capitalize()} in {source.name}: see {log_path().name}"
