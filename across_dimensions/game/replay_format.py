"""The replay file format, its limits, and reading a file into checked entries.

File format (JSON, UTF-8, strict: no NaN or Infinity)::

    {
      "format": "across-dimensions-replay",
      "version": 4,
      "level": "01_first_steps",        # shipped level name or path
      "level_hash": "<the level's hash: 64 lowercase hex digits>",
      "bakes": {"meshes/tree.obj": "<sha256 of its bake>"},   # version 3; {} when it lifts none
      "arsenal": ["gun"],                # version 4: the weapons owned at the start
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

``arsenal`` (version 4) is what the player owned at the start (what the campaign had
given by that level, :mod:`across_dimensions.world.pickups`), so a replay plays the
same wherever the campaign puts the level later. Earlier versions play with the
campaign's arsenal of today.

``actions`` is run-length encoded: held keys repeat the same row. A row ends
with ``{action: presses}`` on the ticks that one-shot actions were pressed
(:data:`.actions.PRESSES`, version 2); version-1 replays, which have none, still
play, and one that has them is refused. Floats are written with Python's shortest round-trip repr, so a replay read
back is bit-identical to the one recorded. A recording in progress is a journal
instead (see :mod:`.replay`).

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
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from ..core.errors import InputError
from ..core.fileio import MiB
from ..world.pickups import arsenal_problem
from .actions import ActionRuns, Actions, short_repr
from .sim import TICK_RATE

FORMAT = "across-dimensions-replay"
JOURNAL_FORMAT = "across-dimensions-replay-journal"
VERSION = 4  # written; 2 added one-shot presses to action rows, 3 the bakes, 4 the arsenal
READS = (1, 2, 3, 4)  # versions this game plays
HASH_EVERY = 60
#: Longest replay, in ticks: two hours at 60 Hz.
MAX_TICKS = 2 * 3600 * TICK_RATE
#: Largest replay file. A two-hour recording with the mouse moving on every tick
#: (a new run each tick, ~66 bytes) is about 28 MB.
MAX_BYTES = 32 * MiB
MAX_SEED = 2**64 - 1
_MAX_DIGITS = 20
_HEADER = ("format", "version", "level", "level_hash", "seed", "tick_rate", "hash_every")
#: Header entries each version added to those before it.
_HEADER_ADDED = {3: ("bakes",), 4: ("arsenal",)}
_BODY = ("actions", "hashes", "final")
_FINAL_KEYS = frozenset(("ticks", "hash", "outcome"))
_LEVEL_HASH = re.compile(r"[0-9a-f]{64}")
_STATE_HASH = re.compile(r"[0-9a-f]{8,64}")
_OUTCOME = re.compile(r"[a-z][a-z0-9_]{0,31}")
_TICK_KEY = re.compile(r"[1-9][0-9]{0,19}")


class ReplayError(InputError):
    """A replay file that cannot be used, with a message naming file and entry."""


def dumps(data) -> str:
    """``data`` as one line of strict JSON (no NaN: a ValueError instead)."""
    return json.dumps(data, separators=(",", ":"), allow_nan=False)


def read_document(path: Path, text: str) -> dict:
    """The checked entries of a replay file or a recording's journal, ``text`` read from
    ``path``: the keyword arguments of a :class:`.replay.Replay`.

    Raises
    ------
    ReplayError
        One line naming the file and the entry, for anything that is not a replay within
        the limits above.
    """
    head, _, rest = text.partition("\n")
    first = _parse(path, head, quiet=True)
    if isinstance(first, dict) and first.get("format") == JOURNAL_FORMAT:
        return _Checker(path).journal(first, rest)
    if first is _UNPARSED or rest.strip():
        first = _parse(path, text)
    return _Checker(path).document(first)


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
    """A replay's entries from parsed JSON, refusing anything out of type or range."""

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
            "arsenal": self.arsenal(data["arsenal"]) if "arsenal" in keys else None,
        }

    def arsenal(self, value) -> tuple[str, ...]:
        problem = arsenal_problem(value)
        if problem is not None:
            self.fail("entry 'arsenal'", problem)
        return tuple(value)

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

    def document(self, data) -> dict:
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
        found = {"actions": runs, "hashes": hashes, "final_ticks": ticks, "final_hash": final_hash, "outcome": outcome}
        return head | found

    def journal(self, first: dict, rest: str) -> dict:
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
        return {**head, "actions": runs, "hashes": hashes, "final_ticks": len(runs), "recovered": True}
