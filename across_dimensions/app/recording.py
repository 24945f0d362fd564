"""The replay being recorded from play: ``--record FILE``, or the record key (F9).

The replay file is written from the start and grows every simulated second (see
:class:`~across_dimensions.game.replay.Recorder`), so a crash loses at most the last second.
Without ``--record`` it goes to the game's own replay folder, named by level and time. Failures
(a full disk, a read-only folder) stop the recording and say so; play goes on.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from pathlib import Path

from ..core.fileio import FileProblem
from ..game.replay import Recorder
from .saves import replay_folder


class Recording:
    """At most one replay being recorded.

    Parameters
    ----------
    path : str or None
        ``--record FILE``: where the first recording goes (the next ones go to the replay folder).
    say : callable
        ``say(text, seconds)`` shows a notice.
    warn : callable
        ``warn(text)`` shows a notice and prints it as a warning.
    """

    def __init__(self, path: str | None, say: Callable[[str, float], None], warn: Callable[[str], None]):
        self.path_given = path
        self.recorder: Recorder | None = None
        self.say, self.warn = say, warn

    @property
    def active(self) -> bool:
        return self.recorder is not None

    def start(self, game, level_path: Path) -> None:
        """Record ``game``, which must be at its level's start (a replay always starts at the spawn)."""
        try:
            if self.path_given:
                path = Path(self.path_given)
            else:
                folder = replay_folder()
                folder.mkdir(parents=True, exist_ok=True)  # the game's own folder: ours to create
                path = _unused(folder / f"{level_path.stem}_{time.strftime('%Y%m%d-%H%M%S')}.json")
            self.recorder = Recorder(game, level_path.stem, path)
        except (FileProblem, OSError) as e:
            self.recorder = None
            self.warn(f"Cannot record: {e}")
            return
        self.say("Recording (level restarted)", 4.0)

    def record(self, actions) -> None:
        """One tick's actions, when recording."""
        if self.recorder is None:
            return
        try:
            self.recorder.record(actions)
        except FileProblem as e:  # e.g. the disk is full: keep playing, say so
            with contextlib.suppress(FileProblem):
                self.recorder.close()
            self.recorder = None
            self.warn(f"Recording stopped: {e}")

    def stop(self) -> None:
        """Finish the recording in progress, if any, and save it over its journal."""
        if self.recorder is None:
            return
        recorder, self.recorder = self.recorder, None
        self.path_given = None  # the next recording goes to the replay folder
        try:
            recorder.finish()
        except FileProblem as e:  # the journal written so far stays, and still loads
            self.warn(f"Replay not saved: {e}")
            return
        self.say(f"Replay saved: {recorder.path}", 4.0)
        print(f"replay saved: {recorder.path}", flush=True)


def _unused(path: Path) -> Path:
    """``path``, or ``name-2.json``, ``name-3.json``... if it exists (two recordings in one second)."""
    n = 1
    candidate = path
    while candidate.exists():
        n += 1
        candidate = path.with_name(f"{path.stem}-{n}{path.suffix}")
    return candidate
