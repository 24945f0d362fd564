"""Replays: recorded per-tick actions that drive the same simulation again.

A :class:`Replay` is a file (format and limits: :mod:`.replay_format`): the level,
the seed, the actions of every tick and the state hashes taken on the way. The runs
stay runs in memory (:class:`~.actions.ActionRuns`): a replay costs memory in
proportion to its number of runs, never to its length in ticks. :class:`Recorder`
makes one while a game is played; :mod:`.playback` plays one back.

Recording survives a crash. While a recording is in progress, its file holds a
*journal* (JSON Lines, append-only) that grows once per simulated second::

    {"format": "across-dimensions-replay-journal", "version": 4, "level": ..., "level_hash": ...,
     "bakes": {...}, "arsenal": [...], "seed": 0, "tick_rate": 60, "hash_every": 60}
    [count, [forward, right, yaw, pitch, w, buttons]]       # runs, in order
    {"tick": 60, "hash": "..."}                             # state hashes, in order

When the recording stops (the level is complete, F9, the window closes, or a
SIGTERM), the journal is replaced atomically by the replay file above. If the
game dies first, the journal stays: :meth:`Replay.load` reads it as a replay
(marked ``recovered``, with no final hash), ignoring a last line cut short.
Each second's lines are handed to the operating system at once, so a crash of
the game loses at most the last simulated second; they are forced to the disk
every :data:`SYNC_EVERY` ticks (ten seconds), which bounds what a power cut can
lose without stalling a frame on every flush.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from ..core.fileio import FileProblem, atomic_write, read_text
from .actions import ActionRuns, Actions
from .replay_format import (
    FORMAT,
    HASH_EVERY,
    JOURNAL_FORMAT,
    MAX_BYTES,
    MAX_TICKS,
    VERSION,
    ReplayError,
    dumps,
    read_document,
)
from .replay_level import level_identity
from .sim import TICK_RATE, Game

#: Ticks between flushes of a recording in progress (one simulated second).
FLUSH_EVERY = TICK_RATE
#: Ticks between forcing a recording in progress to the disk (fsync).
SYNC_EVERY = 10 * TICK_RATE


@dataclass
class Replay:
    """A recorded run.

    ``actions`` may be given as any iterable of :class:`Actions`; it is kept
    as :class:`ActionRuns`. ``recovered`` is true for a replay read back from
    the journal of a recording that was cut short (it has no final hash).
    ``bakes`` (asset name -> bake digest) is None for a replay of a version
    before 3, whose ``level_hash`` is the level file's alone. ``arsenal`` (the weapons
    owned at the start) is None for a replay of a version before 4: it plays with the
    campaign's arsenal for its level.
    """

    level: str
    level_hash: str
    seed: int = 0
    tick_rate: int = TICK_RATE
    hash_every: int = HASH_EVERY
    actions: ActionRuns = field(default_factory=ActionRuns)
    hashes: dict[int, str] = field(default_factory=dict)
    final_ticks: int = 0
    final_hash: str = ""
    outcome: str | None = None
    recovered: bool = False
    bakes: dict[str, str] | None = None
    arsenal: tuple[str, ...] | None = None

    def __post_init__(self):
        if not isinstance(self.actions, ActionRuns):
            self.actions = ActionRuns(self.actions)

    def header(self, fmt: str = FORMAT) -> dict:
        # A replay read from a version without the arsenal is written back as that version: "no
        # arsenal" (the campaign's) and "none owned" ([]) are different starts.
        arsenal = {} if self.arsenal is None else {"arsenal": list(self.arsenal)}
        return {
            "format": fmt,
            "version": VERSION if arsenal else 3,
            "level": self.level,
            "level_hash": self.level_hash,
            "bakes": dict(sorted((self.bakes or {}).items())),
            **arsenal,
            "seed": self.seed,
            "tick_rate": self.tick_rate,
            "hash_every": self.hash_every,
        }

    def to_json(self) -> dict:
        return {
            **self.header(),
            "actions": [[c, a.to_row()] for c, a in self.actions.runs],
            "hashes": {str(k): v for k, v in sorted(self.hashes.items())},
            "final": {"ticks": self.final_ticks, "hash": self.final_hash, "outcome": self.outcome},
        }

    def save(self, path) -> None:
        """Write strict JSON whole or not at all (see :func:`core.fileio.atomic_write`).

        Raises
        ------
        FileProblem
            The folder is missing, the file cannot be written, or an action
            is not finite (strict JSON has no NaN; the file is left untouched).
        """
        try:
            text = dumps(self.to_json())
        except ValueError as e:
            raise FileProblem(f"{path}: cannot save this replay ({e})") from None
        atomic_write(path, text + "\n")

    @classmethod
    def load(cls, path) -> Replay:
        """Read and check a replay file, or the journal of a cut-short recording.

        Raises
        ------
        ReplayError
            One line naming the file and the entry, for anything that is not
            a replay within the limits in the module docstring.
        """
        path = Path(path)
        try:
            text = read_text(path, limit=MAX_BYTES, what="replay")
        except FileProblem as e:
            raise ReplayError(str(e)) from None
        return cls(**read_document(path, text))


# --------------------------------------------------------------- recording
class Recorder:
    """Collects a replay while a game is played (in a window or headless).

    Parameters
    ----------
    game : Game
        At tick 0: a replay always starts from the level's start.
    level_name : str
        What the replay's ``level`` entry says.
    path : str or Path, optional
        Where the replay goes. When given, the file holds the recording's
        journal from the start, grown every ``flush_every`` ticks, and
        :meth:`finish` replaces it by the replay. Its folder must exist.
    flush_every, sync_every : int
        Ticks between handing new lines to the operating system, and between
        forcing them to the disk.

    Raises
    ------
    FileProblem
        The journal cannot be created.
    """

    def __init__(
        self, game: Game, level_name: str, path=None, *, flush_every: int = FLUSH_EVERY, sync_every: int = SYNC_EVERY
    ):
        if game.tick != 0:
            raise ValueError(f"a recording starts at tick 0, the game is at tick {game.tick}")
        level_hash, bakes = level_identity(game.level)
        arsenal = tuple(getattr(game.level, "arsenal", ()))  # the Flatland prologue owns no weapons
        self.replay = Replay(level_name, level_hash, game.seed, bakes=bakes, arsenal=arsenal)
        self.game = game
        self.path = None if path is None else Path(path)
        self.flush_every = flush_every
        self.sync_every = sync_every
        self._file = None
        self._cursor = (0, 0)  # (run index, ticks of that run already in the journal)
        self._hash_lines: list[str] = []
        self._synced_at = 0
        if self.path is not None:
            atomic_write(self.path, dumps(self.replay.header(JOURNAL_FORMAT)) + "\n")
            try:
                self._file = open(self.path, "a", encoding="utf-8", newline="\n")  # noqa: SIM115 - kept open
            except OSError as e:
                raise FileProblem(f"{self.path}: cannot write it ({e.strerror or e})") from None

    def record(self, actions: Actions) -> None:
        """Call right after ``game.step(actions)``."""
        self.replay.actions.append(actions)
        tick = self.game.tick
        if tick % self.replay.hash_every == 0:
            h = self.game.state_hash()
            self.replay.hashes[tick] = h
            if self._file is not None:
                self._hash_lines.append(dumps({"tick": tick, "hash": h}))
        if self._file is not None and tick % self.flush_every == 0:
            self.flush()

    def flush(self, sync: bool | None = None) -> None:
        """Append what was recorded since the last flush to the journal.

        The run still being held is written up to now; the next flush
        continues it as a new line, which loading merges back.

        Raises
        ------
        FileProblem
            The journal cannot be written (the disk is full, the file is gone).
        """
        if self._file is None:
            return
        runs = self.replay.actions._runs
        lines = []
        i, done = self._cursor
        while i < len(runs):
            count, a = runs[i]
            if count > done:
                lines.append(dumps([count - done, a.to_row()]))
            if i == len(runs) - 1:
                done = count
                break
            i, done = i + 1, 0
        lines += self._hash_lines
        tick = self.game.tick
        if sync is None:
            sync = tick - self._synced_at >= self.sync_every
        try:
            if lines:
                self._file.write("\n".join(lines) + "\n")
                self._file.flush()
            if sync:
                os.fsync(self._file.fileno())
                self._synced_at = tick
        except OSError as e:
            raise FileProblem(f"{self.path}: cannot write the recording ({e.strerror or e})") from None
        self._cursor = (i, done)
        self._hash_lines = []

    def finish(self) -> Replay:
        """End the recording: the replay, saved over the journal when there is a path."""
        r = self.replay
        r.final_ticks = self.game.tick
        r.final_hash = self.game.state_hash()
        r.outcome = self.game.outcome
        if self._file is not None:
            try:
                self.flush(sync=False)  # if saving fails below, the journal still holds everything
            finally:
                self._file.close()
                self._file = None
            r.save(self.path)
        return r

    def close(self) -> None:
        """Stop writing without finishing (the journal stays, loadable)."""
        if self._file is not None:
            try:
                self.flush()
            finally:
                self._file.close()
                self._file = None


__all__ = [
    "FORMAT",
    "JOURNAL_FORMAT",
    "MAX_BYTES",
    "MAX_TICKS",
    "ActionRuns",
    "Recorder",
    "Replay",
    "ReplayError",
]
