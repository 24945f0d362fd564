"""Replays: recorded per-tick actions that drive the same simulation again.

File format (JSON, UTF-8, strict: no NaN or Infinity)::

    {
      "format": "across-dimensions-replay",
      "version": 3,
      "level": "01_first_steps",        # shipped level name or path
      "level_hash": "<the level's hash: 64 lowercase hex digits>",
      "bakes": {"meshes/tree.obj": "<sha256 of its bake>"},   # version 3; {} when it lifts none
      "seed": 0,                         # 0 <= seed < 2**64
      "tick_rate": 60,
      "hash_every": 60,
      "actions": [[count, [forward, right, yaw, pitch, w, buttons, {action: presses}?]], ...],
      "hashes": {"60": "<state hash after tick 60>", ...},
      "final": {"ticks": 930, "hash": "...", "outcome": "complete"}
    }

``level_hash`` is the level file's sha256 folded with the digest of every mesh
the level bakes (``bakes``; see :mod:`across_dimensions.world.level_bakes`), so
a replay names a different bake as the cause of a mismatch. Versions 1 and 2,
which have no ``bakes``, hash the file alone and still play.

``actions`` is run-length encoded: held keys repeat the same row. A row ends
with ``{action: presses}`` on the ticks that one-shot actions were pressed
(:data:`.actions.PRESSES`, version 2); version-1 replays, which have none, still
play, and one that has them is refused. Floats are
written with Python's shortest round-trip repr, so a replay read back is
bit-identical to the one recorded. The runs stay runs in memory
(:class:`ActionRuns`): a replay costs memory in proportion to its number of
runs, never to its length in ticks.

Limits (a replay is a file anyone can hand the game, so every entry is typed
and bounded, and anything else is refused with one line naming the file and
the entry):

- the file is at most :data:`MAX_BYTES` (32 MiB) and a regular file (the JSON
  is parsed whole, which takes up to about 15 times the file's size in memory,
  under half a gigabyte at the limit; the loader itself adds O(runs));
- a replay is at most :data:`MAX_TICKS` ticks long (two hours at 60 Hz),
  checked on the sum of the run lengths as they are read, before anything
  is built;
- rows hold finite numbers: forward, right and w in [-1, 1], yaw and pitch in
  [-pi, pi] radians per tick (see :data:`.actions.MAX_LOOK`), known button
  bits, and presses of known actions from 1 to :data:`.actions.MAX_PRESSES`; NaN, Infinity
  and numbers too large for a float are refused;
- whole numbers have at most 20 digits (the seed needs 20);
- ``hashes`` keys are tick numbers (multiples of ``hash_every`` up to the
  replay's length) and values 8 to 64 lowercase hex digits;
- ``final.ticks`` equals the replay's length; ``final.outcome`` is null or a
  snake_case word; no entry is unknown or given twice.

Recording survives a crash. While a recording is in progress, its file holds a
*journal* (JSON Lines, append-only) that grows once per simulated second::

    {"format": "across-dimensions-replay-journal", "version": 3, "level": ..., "level_hash": ...,
     "bakes": {...}, "seed": 0, "tick_rate": 60, "hash_every": 60}
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

import itertools
import json
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from ..core.errors import InputError
from ..core.fileio import FileProblem, MiB, atomic_write, read_text
from .actions import Actions, short_repr
from .energy import MILLI
from .events import event_kinds
from .replay_level import level_divergence, level_identity
from .sim import TICK_RATE, Game

FORMAT = "across-dimensions-replay"
JOURNAL_FORMAT = "across-dimensions-replay-journal"
VERSION = 3  # written; 2 added one-shot presses to action rows, 3 the bakes
READS = (1, 2, 3)  # versions this game plays
HASH_EVERY = 60
#: Longest replay, in ticks: two hours at 60 Hz.
MAX_TICKS = 2 * 3600 * TICK_RATE
#: Largest replay file. A two-hour recording with the mouse moving on every tick
#: (a new run each tick, ~66 bytes) is about 28 MB.
MAX_BYTES = 32 * MiB
#: Ticks between flushes of a recording in progress (one simulated second).
FLUSH_EVERY = TICK_RATE
#: Ticks between forcing a recording in progress to the disk (fsync).
SYNC_EVERY = 10 * TICK_RATE
MAX_SEED = 2**64 - 1
_MAX_DIGITS = 20
_HEADER = ("format", "version", "level", "level_hash", "seed", "tick_rate", "hash_every")
#: Header entries each version added to those before it.
_HEADER_ADDED = {3: ("bakes",)}
_BODY = ("actions", "hashes", "final")
_FINAL_KEYS = frozenset(("ticks", "hash", "outcome"))
_LEVEL_HASH = re.compile(r"[0-9a-f]{64}")
_STATE_HASH = re.compile(r"[0-9a-f]{8,64}")
_OUTCOME = re.compile(r"[a-z][a-z0-9_]{0,31}")
_TICK_KEY = re.compile(r"[1-9][0-9]{0,19}")


class ReplayError(InputError):
    """A replay file that cannot be used, with a message naming file and entry."""


# ------------------------------------------------------------------ runs
class ActionRuns:
    """Per-tick actions kept as runs of equal frames.

    Iterating yields one :class:`Actions` per tick, lazily; ``len`` is the
    number of ticks. Memory is O(number of runs), whatever the length.

    Parameters
    ----------
    frames : iterable of Actions, optional
        Ticks to start with.
    """

    __slots__ = ("_runs", "_ticks")

    def __init__(self, frames=()):
        self._runs: list[list] = []  # [count, Actions], adjacent rows differ
        self._ticks = 0
        for a in frames:
            self.append(a)

    def append(self, actions: Actions, count: int = 1) -> None:
        """Add ``count`` ticks of ``actions`` (merged into the last run when equal)."""
        if count < 1:
            raise ValueError(f"count must be positive, got {count}")
        if self._runs and self._runs[-1][1].same_row(actions):
            self._runs[-1][0] += count
        else:
            self._runs.append([count, actions])
        self._ticks += count

    @property
    def runs(self) -> list[tuple[int, Actions]]:
        """The runs as ``(count, actions)`` pairs."""
        return [(c, a) for c, a in self._runs]

    def __len__(self) -> int:
        return self._ticks

    def __iter__(self):
        return itertools.chain.from_iterable(itertools.repeat(a, c) for c, a in self._runs)

    def __eq__(self, other) -> bool:
        if not isinstance(other, ActionRuns):
            return NotImplemented
        return len(self._runs) == len(other._runs) and all(
            c == d and a.same_row(b) for (c, a), (d, b) in zip(self._runs, other._runs)
        )

    def __repr__(self) -> str:
        return f"ActionRuns({self._ticks} ticks in {len(self._runs)} runs)"


# ------------------------------------------------------------------ replay
@dataclass
class Replay:
    """A recorded run.

    ``actions`` may be given as any iterable of :class:`Actions`; it is kept
    as :class:`ActionRuns`. ``recovered`` is true for a replay read back from
    the journal of a recording that was cut short (it has no final hash).
    ``bakes`` (asset name -> bake digest) is None for a replay of a version
    before 3, whose ``level_hash`` is the level file's alone.
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

    def __post_init__(self):
        if not isinstance(self.actions, ActionRuns):
            self.actions = ActionRuns(self.actions)

    def header(self, fmt: str = FORMAT) -> dict:
        return {
            "format": fmt,
            "version": VERSION,
            "level": self.level,
            "level_hash": self.level_hash,
            "bakes": dict(sorted((self.bakes or {}).items())),
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
            text = _dumps(self.to_json())
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
        head, _, rest = text.partition("\n")
        first = _parse(path, head, quiet=True)
        if isinstance(first, dict) and first.get("format") == JOURNAL_FORMAT:
            return _Checker(path).journal(first, rest)
        if first is _UNPARSED or rest.strip():
            first = _parse(path, text)
        return _Checker(path).document(first)


def _dumps(data) -> str:
    return json.dumps(data, separators=(",", ":"), allow_nan=False)


# ----------------------------------------------------------------- parsing
class _Unusable:
    """What NaN, Infinity and -Infinity parse to: not a float, so any check
    expecting a number refuses it and names the entry."""

    def __init__(self, text: str):
        self.text = text

    def __repr__(self) -> str:
        return self.text


class _DuplicateKey(ValueError):
    pass


def _unique_keys(pairs):
    obj = dict(pairs)
    if len(obj) != len(pairs):
        seen = set()
        for k, _ in pairs:
            if k in seen:
                raise _DuplicateKey(k)
            seen.add(k)
    return obj


_UNPARSED = object()


def _parse(path: Path, text: str, quiet: bool = False):
    """``text`` as JSON; problems raise ReplayError (or give ``_UNPARSED`` when quiet)."""
    # Numbers are left to json's C scanner (a Python hook per number would make
    # a large file several times slower): 1e999 becomes inf, which every check
    # refuses at its entry, and whole numbers beyond Python's 4300-digit limit
    # raise ValueError, located below.
    try:
        return json.loads(text, parse_constant=_Unusable, object_pairs_hook=_unique_keys)
    except _DuplicateKey as e:
        problem = f"the key {short_repr(str(e))} appears twice in one object"
    except json.JSONDecodeError as e:
        problem = f"not a replay (invalid JSON at line {e.lineno} column {e.colno}: {e.msg})"
    except RecursionError:
        problem = "not a replay (JSON nested too deeply)"
    except ValueError as e:
        problem = _too_long_number(text) or f"not a replay ({short_repr(str(e), 80)})"
    if quiet:
        return _UNPARSED
    raise ReplayError(f"{path}: {problem}")


def _too_long_number(text: str) -> str | None:
    """Where the first whole number of more than 4300 digits is, if any."""
    m = re.search(r"[0-9]{4301,}", text)
    if m is None:
        return None
    line = text.count("\n", 0, m.start()) + 1
    column = m.start() - (text.rfind("\n", 0, m.start()) + 1) + 1
    return (
        f"a number of {len(m.group())} digits at line {line} column {column} "
        f"(no entry of a replay needs more than {_MAX_DIGITS})"
    )


def _is_int(v) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


class _Checker:
    """Builds a Replay from parsed JSON, refusing anything out of type or range."""

    def __init__(self, path: Path):
        self.path = path
        self.version = VERSION

    def fail(self, where: str, msg: str):
        raise ReplayError(f"{self.path}: {where}: {msg}")

    def whole(self, where, v, lo, hi):
        if not _is_int(v) or not lo <= v <= hi:
            self.fail(where, f"expected a whole number from {lo} to {hi}, got {short_repr(v)}")
        return v

    def text(self, where, v, pattern=None, expected="text"):
        if not isinstance(v, str) or (pattern is not None and not pattern.fullmatch(v)):
            self.fail(where, f"expected {expected}, got {short_repr(v)}")
        return v

    def header(self, data: dict, body: tuple, fmt: str) -> dict:
        """The checked header fields of a replay or journal object ``data`` (``body``: its other entries)."""
        if data.get("format") != fmt:
            self.fail("entry 'format'", f'not a replay (expected "format": "{FORMAT}")')
        version = data.get("version")
        if not _is_int(version):
            self.fail("entry 'version'", f"expected a whole number, got {short_repr(version)}")
        if version not in READS:
            raise ReplayError(
                f"{self.path}: replay format version {short_repr(version)}; "
                f"this game reads versions {', '.join(map(str, READS[:-1]))} and {READS[-1]}"
            )
        self.version = version
        keys = frozenset(_HEADER + body).union(*(k for v, k in _HEADER_ADDED.items() if v <= version))
        for key in data:
            if key not in keys:
                later = [v for v, k in _HEADER_ADDED.items() if key in k]
                why = f"version {later[0]} of the format has it, this replay says version {version}" if later else ""
                self.fail(
                    f"entry {short_repr(key)}",
                    f"unknown entry ({why or 'expected only ' + ', '.join(sorted(keys))})",
                )
        for key in sorted(keys):
            if key not in data:
                self.fail(f"entry '{key}'", "missing")
        level = data["level"]
        if not isinstance(level, str) or not 0 < len(level) <= 255 or not level.isprintable():
            self.fail(
                "entry 'level'",
                f"expected a level name or path (1 to 255 printable characters), got {short_repr(level)}",
            )
        tick_rate = data["tick_rate"]
        if not _is_int(tick_rate):
            self.fail("entry 'tick_rate'", f"expected a whole number, got {short_repr(tick_rate)}")
        if tick_rate != TICK_RATE:
            self.fail("entry 'tick_rate'", f"recorded at {short_repr(tick_rate)} Hz, the game runs at {TICK_RATE} Hz")
        return {
            "level": level,
            "level_hash": self.text(
                "entry 'level_hash'", data["level_hash"], _LEVEL_HASH, "a sha256 hash (64 lowercase hex digits)"
            ),
            "seed": self.whole("entry 'seed'", data["seed"], 0, MAX_SEED),
            "tick_rate": tick_rate,
            "hash_every": self.whole("entry 'hash_every'", data["hash_every"], 1, MAX_TICKS),
            "bakes": self.bakes(data["bakes"]) if "bakes" in keys else None,
        }

    def bakes(self, value) -> dict[str, str]:
        if not isinstance(value, dict) or len(value) > 256:
            self.fail("entry 'bakes'", f"expected an object of asset name: bake hash, got {short_repr(value)}")
        for name, digest in value.items():
            if not 0 < len(name) <= 255 or not name.isprintable():
                self.fail(
                    "entry 'bakes'", f"expected asset names (1 to 255 printable characters), got {short_repr(name)}"
                )
            self.text(
                f"entry 'bakes' {short_repr(name)}", digest, _LEVEL_HASH, "a sha256 hash (64 lowercase hex digits)"
            )
        return dict(value)

    def run(self, where: str, index: int, run, runs: ActionRuns) -> None:
        """Check one ``[count, row]`` and add it to ``runs``; the tick limit first.

        ``where.format(index)`` names it in a message; the text is only built
        for a message (a replay may have 432,000 runs).
        """
        if type(run) is list and len(run) == 2:
            count = run[0]
            if self.version == 1 and type(run[1]) is list and len(run[1]) == 7:
                self.fail(
                    where.format(index),
                    "{action: presses} after the row is version 2 of the format; this replay says version 1",
                )
            if type(count) is int and 1 <= count and len(runs) + count <= MAX_TICKS:
                try:
                    actions = Actions.from_row(run[1])
                except ValueError as e:
                    self.fail(where.format(index), str(e))
                runs.append(actions, count)
                return
        where = where.format(index)
        if not isinstance(run, list) or len(run) != 2:
            self.fail(where, f"expected [count, [forward, right, yaw, pitch, w, buttons]], got {short_repr(run)}")
        count = self.whole(f"{where} count", run[0], 1, MAX_TICKS)
        if len(runs) + count > MAX_TICKS:
            self.fail(
                where,
                f"the replay would be longer than {MAX_TICKS} ticks "
                f"({MAX_TICKS // TICK_RATE // 3600} hours at {TICK_RATE} Hz), the longest a replay may be",
            )
        try:
            actions = Actions.from_row(run[1])
        except ValueError as e:
            self.fail(where, str(e))
        runs.append(actions, count)

    def hash_entry(self, where: str, tick, value, hash_every: int, ticks: int, hashes: dict) -> None:
        if tick % hash_every or tick > ticks:
            self.fail(
                where, f"tick {tick}: expected a multiple of hash_every ({hash_every}) up to the replay's {ticks} ticks"
            )
        hashes[tick] = self.text(where, value, _STATE_HASH, "a state hash (8 to 64 lowercase hex digits)")

    def document(self, data) -> Replay:
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise ReplayError(f'{self.path}: not a replay (expected "format": "{FORMAT}")')
        head = self.header(data, _BODY, FORMAT)
        if not isinstance(data["actions"], list):
            self.fail("entry 'actions'", f"expected a list of [count, row] runs, got {short_repr(data['actions'])}")
        if len(data["actions"]) > MAX_TICKS:
            self.fail(
                "entry 'actions'", f"{len(data['actions'])} runs, more than the {MAX_TICKS} ticks a replay may be"
            )
        runs = ActionRuns()
        for i, run in enumerate(data["actions"]):
            self.run("entry 'actions' #{}", i, run, runs)
        ticks = len(runs)
        hashes: dict[int, str] = {}
        if not isinstance(data["hashes"], dict):
            self.fail("entry 'hashes'", f"expected an object of tick: hash, got {short_repr(data['hashes'])}")
        for key, value in data["hashes"].items():
            where = f"entry 'hashes' {short_repr(key)}"
            if not _TICK_KEY.fullmatch(key):
                self.fail(where, "expected a tick number as the key (digits, no sign or leading zero)")
            self.hash_entry(where, int(key), value, head["hash_every"], ticks, hashes)
        final = data["final"]
        if not isinstance(final, dict) or set(final) != _FINAL_KEYS:
            self.fail("entry 'final'", f'expected {{"ticks", "hash", "outcome"}}, got {short_repr(final)}')
        if not _is_int(final["ticks"]) or final["ticks"] != ticks:
            self.fail(
                "entry 'final' 'ticks'",
                f"expected {ticks} (the sum of the run lengths), got {short_repr(final['ticks'])}",
            )
        final_hash = final["hash"]
        if final_hash != "":
            self.text("entry 'final' 'hash'", final_hash, _STATE_HASH, "a state hash (8 to 64 lowercase hex digits)")
        outcome = final["outcome"]
        if outcome is not None:
            self.text("entry 'final' 'outcome'", outcome, _OUTCOME, "null or a snake_case word")
        return Replay(
            head["level"],
            head["level_hash"],
            head["seed"],
            head["tick_rate"],
            head["hash_every"],
            runs,
            hashes,
            ticks,
            final_hash,
            outcome,
            bakes=head["bakes"],
        )

    def journal(self, first: dict, rest: str) -> Replay:
        """A recording's journal: the header line ``first``, then ``rest``.

        A last line without its newline was being written when the game
        stopped: it is left out. Every complete line must be valid.
        """
        head = self.header(first, (), JOURNAL_FORMAT)
        runs = ActionRuns()
        hash_lines: list[tuple[str, int, object]] = []
        lines = rest.split("\n")
        for number, line in enumerate(lines[:-1], start=2):  # lines[-1] is empty or cut short
            if not line.strip():
                continue
            item = _parse(self.path, line, quiet=True)
            if isinstance(item, list):
                self.run("line {}", number, item, runs)
                continue
            where = f"line {number}"
            if isinstance(item, dict) and set(item) == {"tick", "hash"}:
                tick = self.whole(f"{where} 'tick'", item["tick"], 1, MAX_TICKS)
                hash_lines.append((where, tick, item["hash"]))
            else:
                self.fail(where, 'expected a run [count, row] or {"tick": t, "hash": h}')
        hashes: dict[int, str] = {}
        for where, tick, value in hash_lines:
            self.hash_entry(where, tick, value, head["hash_every"], len(runs), hashes)
        return Replay(
            head["level"],
            head["level_hash"],
            head["seed"],
            head["tick_rate"],
            head["hash_every"],
            runs,
            hashes,
            len(runs),
            "",
            None,
            recovered=True,
            bakes=head["bakes"],
        )


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
        self.replay = Replay(level_name, level_hash, game.seed, bakes=bakes)
        self.game = game
        self.path = None if path is None else Path(path)
        self.flush_every = flush_every
        self.sync_every = sync_every
        self._file = None
        self._cursor = (0, 0)  # (run index, ticks of that run already in the journal)
        self._hash_lines: list[str] = []
        self._synced_at = 0
        if self.path is not None:
            atomic_write(self.path, _dumps(self.replay.header(JOURNAL_FORMAT)) + "\n")
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
                self._hash_lines.append(_dumps({"tick": tick, "hash": h}))
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
                lines.append(_dumps([count - done, a.to_row()]))
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


# ---------------------------------------------------------------- playback
@dataclass
class PlayResult:
    """How a replay ended."""

    ticks: int
    outcome: str | None
    final_hash: str
    divergence: str | None  # None when every recorded hash matched


def play(replay: Replay, game: Game, on_tick=None, check: bool = True) -> PlayResult:
    """Drive ``game`` with the replay's actions.

    Parameters
    ----------
    replay : Replay
    game : Game
        Fresh, built from the replay's level and seed.
    on_tick : callable, optional
        ``on_tick(game)`` after every tick (screenshots, progress).
    check : bool
        Compare state hashes; the first mismatch is reported in ``divergence``
        and the run continues so the outcome is still known.
    """
    divergence = level_divergence(replay, game) if check else None
    for a in replay.actions:
        game.step(a)
        if on_tick is not None:
            on_tick(game)
        if check and divergence is None:
            expected = replay.hashes.get(game.tick)
            if expected is not None and expected != game.state_hash():
                divergence = (
                    f"replay diverges at tick {game.tick} ({game.tick / TICK_RATE:.2f} s): "
                    f"expected state {expected}, got {game.state_hash()}"
                )
    final = game.state_hash()
    if check and divergence is None and replay.final_hash and replay.final_hash != final:
        divergence = f"replay diverges at the end (tick {game.tick}): expected state {replay.final_hash}, got {final}"
    return PlayResult(game.tick, game.outcome, final, divergence)


def rehash(replay: Replay, game: Game) -> tuple[PlayResult, Replay]:
    """Play the replay's actions unchecked and record its state hashes afresh.

    For a deliberate change of the simulation that keeps behaviour but not
    the last bits: the actions stay, the hashes are taken again by the same
    :class:`Recorder` a recording uses (a hash every ``hash_every`` ticks and
    a final one), so the new replay has exactly the layout a recording would.

    Parameters
    ----------
    replay : Replay
        A finished replay (not a recovered journal).
    game : Game
        Fresh, built from the replay's level and seed.

    Returns
    -------
    result : PlayResult
        How the run ended now (``divergence`` is None: nothing is compared).
    fresh : Replay
        ``replay`` with the new hashes, final hash, ticks and outcome, and the
        level hash and bakes of ``game``'s level (written only when its file is
        the one recorded, see :func:`.replay_level.same_file`); its level name,
        seed, hash_every and actions are the replay's own.
    """
    recorder = Recorder(game, replay.level)
    fresh = recorder.replay
    fresh.seed = replay.seed
    fresh.hash_every = replay.hash_every
    for a in replay.actions:
        game.step(a)
        recorder.record(a)
    recorder.finish()
    return PlayResult(game.tick, game.outcome, fresh.final_hash, None), fresh


def changed_hashes(old: Replay, new: Replay) -> tuple[int, int]:
    """``(changed, total)``: how many of ``new``'s state hashes, the final one
    included, differ from (or are missing in) ``old``."""
    changed = sum(old.hashes.get(tick) != h for tick, h in new.hashes.items())
    changed += old.final_hash != new.final_hash
    return changed, len(new.hashes) + 1


# ----------------------------------------------------------------- summary
def summary(game: Game, result: PlayResult) -> dict:
    """What ``replay --json`` prints: one JSON object for tools.

    Keys: ``level`` (the level's name), ``outcome`` (null when not finished),
    ``ticks``, ``hash`` (the final state hash), ``events`` (a count for every
    event kind the game defines, 0 for those that did not happen; see
    ``game.events``), ``energy`` (``{"min", "max", "end"}`` in energy units over
    the run, or null when the level has no energy bar), ``position`` (the
    player's final ``[x, y, z, w]``), ``respawns`` and ``divergence`` (null, or
    the message).
    """
    position = [float(v) if math.isfinite(v) else None for v in game.player.position]
    bar = game.energy
    energy = (
        None if bar is None else {"min": bar.low_milli / MILLI, "max": bar.high_milli / MILLI, "end": bar.milli / MILLI}
    )
    events = {kind: game.event_counts.get(kind, 0) for kind in event_kinds()}
    return {
        "level": game.level.name,
        "outcome": result.outcome,
        "ticks": result.ticks,
        "hash": result.final_hash,
        "events": events,
        "energy": energy,
        "position": position,
        "respawns": game.respawns,
        "divergence": result.divergence,
    }
