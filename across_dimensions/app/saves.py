"""The player's progress: levels finished, best times, crystals found, where to continue.

One JSON file, ``progress.json`` in the platform's per-user data folder
(``platformdirs.user_data_dir("across-dimensions")``; ``$ACROSS_DIMENSIONS_DATA_DIR``
replaces the folder, for tests and portable installs)::

    {"format": "across-dimensions-progress", "version": 1,
     "finished": {"01_first_steps": 41.5},            # level -> best time, seconds
     "crystals": {"02_crystal_cache": [3, 3]},        # level -> [most found in one run, in the level]
     "secrets": {"10_x": {"found": ["the garden"], "total": 2}},  # level -> secrets ever found, of how many
     "current": {"level": "03_tumbling_hall", "checkpoint": null}}

``current`` is where *Continue* resumes: the level being played when the game
was left, and the index of the last checkpoint reached in it (``null``: the
level's start, also when the level has no checkpoints).

Writing is atomic (:func:`~across_dimensions.core.fileio.atomic_write`): a crash
leaves the old file or the new one. A file that cannot be read as a progress
file of this version is never overwritten: it is moved aside as
``progress.corrupt-N.json``, one warning names both files, and the player
starts fresh.

Two games may share one data folder (two windows, a second one started by
mistake). Each write holds a lock (``.progress.lock``, ``flock``) while it reads
the file again and merges it with what it has in memory: every finished level
and its best time, the most crystals of each level, every secret found; only *Continue*'s place is
the writer's own. So no game loses another's progress. A game killed in the
middle of a write leaves its temporary file (``.progress.json.XXXXXXXX.tmp``);
the next start removes those, under the same lock, so never one being written.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..core.fileio import FileProblem, atomic_write, read_text

FORMAT = "across-dimensions-progress"
#: Bumped when the file's meaning changes; an older reader refuses (and keeps aside) a newer file.
VERSION = 1
DATA_DIR_ENV = "ACROSS_DIMENSIONS_DATA_DIR"
PROGRESS_FILE = "progress.json"
LOCK_FILE = ".progress.lock"
#: The temporary files of :func:`~across_dimensions.core.fileio.atomic_write` for the progress file
#: (``tempfile.mkstemp``'s eight characters): a killed save leaves one of these, and only these are ours.
STALE_TEMP = re.compile(r"\.progress\.json\.[a-z0-9_]{8}\.tmp")
#: Largest progress file read, in bytes: a full campaign's is well under 2 kB.
PROGRESS_MAX_BYTES = 1024 * 1024
#: Longest best time kept, seconds (a day): beyond it a time is a corrupt file, not a run.
MAX_TIME = 86400.0
#: Level files renamed since a progress file may have been written: old stem -> new stem.
#: Applied once when loading, so a player's finished levels, crystals and place survive
#: the campaign's renumbering (a "Blast and Field" level came in as 05).
RENAMED = {
    "05_bridge": "06_bridge",
    "06_orthogonal_worlds": "07_orthogonal_worlds",
    "07_around_the_corner": "08_around_the_corner",
    "08_hive": "09_hive",
}


def renamed(level: str) -> str:
    """The level's stem today (see :data:`RENAMED`)."""
    return RENAMED.get(level, level)


def data_folder() -> Path:
    """The game's per-user data folder (``$ACROSS_DIMENSIONS_DATA_DIR`` when set and non-empty)."""
    override = os.environ.get(DATA_DIR_ENV, "").strip()
    if override:
        return Path(override).expanduser()
    import platformdirs

    return Path(platformdirs.user_data_dir("across-dimensions"))


def progress_path() -> Path:
    """Where the progress file lives (see :func:`data_folder`)."""
    return data_folder() / PROGRESS_FILE


def replay_folder() -> Path:
    """Where F9 recordings go: ``replays/`` in :func:`data_folder`."""
    return data_folder() / "replays"


@dataclass
class Progress:
    """What the player has done.

    Attributes
    ----------
    finished : dict of str to float
        Level stem -> best time in seconds from the level's start to its goal.
    crystals : dict of str to (int, int)
        Level stem -> (most crystals found in one run, crystals in the level).
    secrets : dict of str to (tuple of str, int)
        Level stem -> (the names of its secrets found in any run, sorted; secrets in the level).
    current : str or None
        The level *Continue* resumes.
    checkpoint : int or None
        The last checkpoint reached in ``current`` (None: its start).
    """

    finished: dict[str, float] = field(default_factory=dict)
    crystals: dict[str, tuple[int, int]] = field(default_factory=dict)
    secrets: dict[str, tuple[tuple[str, ...], int]] = field(default_factory=dict)
    current: str | None = None
    checkpoint: int | None = None

    def finish(self, level: str, seconds: float) -> bool:
        """Record a finished run; returns True when it is a new best time."""
        best = self.finished.get(level)
        if best is None or seconds < best:
            self.finished[level] = float(seconds)
            return True
        return False

    def found_crystals(self, level: str, found: int, total: int) -> None:
        """Keep the most crystals found in one run of ``level`` (capped by ``total``)."""
        old = self.crystals.get(level, (0, total))[0]
        self.crystals[level] = (max(old, min(found, total)), total)

    def found_secrets(self, level: str, names, total: int) -> bool:
        """Add the secrets ``names`` found in ``level`` (which has ``total``; no names: the level was
        started, so the level select can say ``0/total``). Returns whether anything was new."""
        old, known = self.secrets.get(level, ((), None))
        found = tuple(sorted(set(old) | set(names)))[: max(total, 0)]
        self.secrets[level] = (found, total)
        return found != old or known != total

    def unlocked(self, stems: list[str], optional=frozenset()) -> list[bool]:
        """Which campaign levels may be played: the first, every finished one, and the one after
        each; the one after an ``optional`` level (the prologue) is open whenever that one is."""
        result = []
        for i, stem in enumerate(stems):
            before = stems[i - 1] if i else None
            result.append(
                i == 0 or stem in self.finished or before in self.finished or (before in optional and result[-1])
            )
        return result

    def play(self, level: str, checkpoint: int | None, stems: list[str], optional=frozenset()) -> bool:
        """``level`` starts (at ``checkpoint``): it becomes where *Continue* resumes when it is an
        unlocked level of the campaign ``stems``. A locked level, or one outside the campaign
        (played from the command line), leaves *Continue* where it was. Returns whether it moved."""
        if level not in stems or not self.unlocked(stems, optional)[stems.index(level)]:
            return False
        self.current, self.checkpoint = level, checkpoint
        return True

    def continue_level(self, stems: list[str], optional=frozenset()) -> tuple[str | None, int | None]:
        """Where *Continue* goes: the level left mid-way and its checkpoint, else the first
        unfinished level (an ``optional`` one only before any later level was finished: a
        skipped prologue is not offered again), else None (the campaign is done)."""
        if self.current in stems:
            return self.current, self.checkpoint
        for i, stem in enumerate(stems):
            skipped = stem in optional and any(s in self.finished for s in stems[i + 1 :])
            if stem not in self.finished and not skipped:
                return stem, None
        return None, None

    def merge(self, other: Progress) -> None:
        """Take in ``other``'s finished levels (the better time) and crystals (the most found);
        ``current`` and ``checkpoint`` stay this one's."""
        for level, t in other.finished.items():
            self.finished[level] = min(t, self.finished.get(level, math.inf))
        for level, (found, total) in other.crystals.items():
            mine = self.crystals.get(level)
            self.crystals[level] = (found, total) if mine is None else (max(mine[0], min(found, mine[1])), mine[1])
        for level, (names, total) in other.secrets.items():
            mine = self.secrets.get(level)
            self.found_secrets(level, names, total if mine is None else mine[1])

    def to_json(self) -> str:
        return json.dumps(
            {
                "format": FORMAT,
                "version": VERSION,
                "finished": self.finished,
                "crystals": {k: list(v) for k, v in self.crystals.items()},
                "secrets": {k: {"found": list(v[0]), "total": v[1]} for k, v in self.secrets.items()},
                "current": None if self.current is None else {"level": self.current, "checkpoint": self.checkpoint},
            },
            indent=1,
            sort_keys=True,
        )

    @classmethod
    def from_json(cls, text: str) -> Progress:
        """Parse a progress file; raises ``ValueError`` saying what is wrong."""
        data = json.loads(text)
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise ValueError(f"expected a JSON object with format {FORMAT!r}")
        if data.get("version") != VERSION:
            raise ValueError(f"version {data.get('version')!r}, expected {VERSION}")
        progress = cls()
        finished = data.get("finished", {})
        if not isinstance(finished, dict):
            raise ValueError("finished: expected an object of level -> seconds")
        for level, t in finished.items():
            if isinstance(t, bool) or not isinstance(t, (int, float)) or not (0 <= t <= MAX_TIME and math.isfinite(t)):
                raise ValueError(f"finished.{level}: expected seconds from 0 to {MAX_TIME:g}, got {t!r}")
            new = renamed(level)  # a run of the old file counts for the new name
            progress.finished[new] = min(float(t), progress.finished.get(new, math.inf))
        crystals = data.get("crystals", {})
        if not isinstance(crystals, dict):
            raise ValueError("crystals: expected an object of level -> [found, total]")
        for level, pair in crystals.items():
            ok = isinstance(pair, list) and len(pair) == 2 and all(type(n) is int and n >= 0 for n in pair)
            if not ok or pair[0] > pair[1]:
                raise ValueError(f"crystals.{level}: expected [found, total] with 0 <= found <= total, got {pair!r}")
            progress.crystals[renamed(level)] = (pair[0], pair[1])
        _read_secrets(progress, data.get("secrets", {}))
        current = data.get("current")
        if current is not None:
            level, cp = (current.get("level"), current.get("checkpoint")) if isinstance(current, dict) else (None, 0)
            if not isinstance(level, str) or not (cp is None or (type(cp) is int and cp >= 0)):
                raise ValueError('current: expected {"level": name, "checkpoint": null or an index}')
            progress.current, progress.checkpoint = renamed(level), cp
        return progress


def _read_secrets(progress: Progress, secrets) -> None:
    """``secrets`` of a progress file into ``progress``; raises ``ValueError`` saying what is wrong."""
    if not isinstance(secrets, dict):
        raise ValueError('secrets: expected an object of level -> {"found": [names], "total": n}')
    for level, entry in secrets.items():
        found = entry.get("found") if isinstance(entry, dict) else None
        total = entry.get("total") if isinstance(entry, dict) else None
        names = isinstance(found, list) and all(isinstance(n, str) for n in found) and len(set(found)) == len(found)
        if not names or type(total) is not int or not 0 <= len(found) <= total:
            raise ValueError(
                f'secrets.{level}: expected {{"found": [distinct names], "total": n >= found}}, got {entry!r}'
            )
        progress.secrets[renamed(level)] = (tuple(sorted(found)), total)


def checkpoint_of(game) -> int | None:
    """The index of the last checkpoint the player reached, or None (the level's start, or a
    level without checkpoints)."""
    return game.checkpoint


def resume_at_checkpoint(game, index: int | None) -> bool:
    """Put the player at checkpoint ``index``; False leaves them at the start (no index, or a
    level that has no such checkpoint since it changed after the save)."""
    if index is None:
        return False
    try:
        game.restart_at_checkpoint(index)
    except (IndexError, ValueError):  # the level changed since the save: its start, then
        return False
    return True


def _aside(path: Path) -> Path:
    """A free name beside ``path`` for keeping a corrupt file: progress.corrupt-N.json."""
    n = 1
    while True:
        candidate = path.with_name(f"{path.stem}.corrupt-{n}{path.suffix}")
        if not os.path.lexists(candidate):
            return candidate
        n += 1


def set_aside(path: Path) -> str:
    """Move a file that cannot be read out of the way (:func:`_aside`), never raising; says where
    it went, or that it could not be moved and will be overwritten."""
    try:
        kept = _aside(path)
        os.replace(path, kept)
        return f"kept as {kept.name}"
    except OSError as move:
        return f"could not be moved aside ({move.strerror or move}) and will be overwritten"


def load_progress(path: Path | None = None) -> tuple[Progress, list[str]]:
    """Read the progress file, never raising.

    Returns
    -------
    progress : Progress
        Fresh when the file is missing or corrupt.
    warnings : list of str
        Empty, or one line: the file was corrupt (or of another version), where
        it was kept aside, and that the player starts fresh.
    """
    path = Path(path) if path is not None else progress_path()
    remove_stale_temp(path.parent)
    if not os.path.lexists(path):
        return Progress(), []
    try:
        return Progress.from_json(read_text(path, limit=PROGRESS_MAX_BYTES, what="progress")), []
    except (FileProblem, ValueError, RecursionError) as e:  # json.JSONDecodeError is a ValueError
        why = str(e).replace(f"{path}: ", "").splitlines()[0]
        kept = set_aside(path)
        return Progress(), [f"{path}: not a progress file this game can read ({why}); {kept}; starting fresh"]


def save_progress(progress: Progress, path: Path | None = None) -> Path:
    """Merge ``progress`` with the file under the lock and write it atomically (see the module docstring).

    ``progress`` itself takes in what the file held (another game's finished
    levels), so what the player sees and what is saved agree. The game's own
    data folder is created when missing.

    Raises
    ------
    FileProblem
        When it cannot be written (the old file stays as it was).
    """
    own_folder = path is None
    path = Path(path) if path is not None else progress_path()
    if own_folder:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)  # the game's own folder: ours to create
        except OSError as e:
            raise FileProblem(f"{path.parent}: cannot create the game's data folder ({e.strerror or e})") from None
    try:
        with _locked(path.parent):
            with contextlib.suppress(FileProblem, ValueError, RecursionError):  # unreadable: load_progress's business
                if os.path.lexists(path):
                    progress.merge(Progress.from_json(read_text(path, limit=PROGRESS_MAX_BYTES, what="progress")))
            return atomic_write(path, progress.to_json() + "\n")
    except OSError as e:  # the lock file cannot be made (a read-only folder)
        raise FileProblem(f"{path}: cannot write it ({e.strerror or e})") from None


def remove_stale_temp(folder: Path | None = None) -> int:
    """Remove temporary files that killed saves left in ``folder`` (default :func:`data_folder`).

    Only names :data:`STALE_TEMP` matches, and under the lock, so never the
    file of a save in progress. Never raises.

    Returns
    -------
    int
        How many were removed.
    """
    folder = Path(folder) if folder is not None else data_folder()
    removed = 0
    with contextlib.suppress(OSError):
        stale = [p for p in folder.iterdir() if STALE_TEMP.fullmatch(p.name)] if folder.is_dir() else []
        if stale:
            with _locked(folder):
                for p in stale:
                    with contextlib.suppress(FileNotFoundError):
                        p.unlink()
                        removed += 1
    return removed


@contextlib.contextmanager
def _locked(folder: Path):
    """Hold the exclusive lock on ``folder``'s progress (``flock``; none where there is no ``fcntl``).

    Raises
    ------
    OSError
        The lock file cannot be opened.
    """
    try:
        import fcntl
    except ImportError:  # Windows: writes stay atomic, two games at once are not merged
        yield
        return
    fd = os.open(folder / LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # closing releases the lock
