"""Replays: recorded per-tick actions that drive the same simulation again.

File format (JSON, UTF-8)::

    {
      "format": "across-dimensions-replay",
      "version": 1,
      "level": "01_first_steps",        # shipped level name or path
      "level_hash": "<sha256 of the level file>",
      "seed": 0,
      "tick_rate": 60,
      "hash_every": 60,
      "actions": [[count, [forward, right, yaw, pitch, w, buttons]], ...],
      "hashes": {"60": "<state hash after tick 60>", ...},
      "final": {"ticks": 930, "hash": "...", "outcome": "complete"}
    }

``actions`` is run-length encoded: held keys repeat the same row. Floats are
written with Python's shortest round-trip repr, so a replay read back is
bit-identical to the one recorded.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

from .actions import Actions
from .sim import TICK_RATE, Game

FORMAT = "across-dimensions-replay"
VERSION = 1
HASH_EVERY = 60


class ReplayError(ValueError):
    """A replay file that cannot be used, with a message naming file and entry."""


@dataclass
class Replay:
    """A recorded run."""

    level: str
    level_hash: str
    seed: int = 0
    tick_rate: int = TICK_RATE
    hash_every: int = HASH_EVERY
    actions: list[Actions] = field(default_factory=list)
    hashes: dict[int, str] = field(default_factory=dict)
    final_ticks: int = 0
    final_hash: str = ""
    outcome: str | None = None

    def to_json(self) -> dict:
        runs: list[list] = []
        for a in self.actions:
            row = a.to_row()
            if runs and runs[-1][1] == row:
                runs[-1][0] += 1
            else:
                runs.append([1, row])
        return {
            "format": FORMAT, "version": VERSION, "level": self.level, "level_hash": self.level_hash,
            "seed": self.seed, "tick_rate": self.tick_rate, "hash_every": self.hash_every, "actions": runs,
            "hashes": {str(k): v for k, v in sorted(self.hashes.items())},
            "final": {"ticks": self.final_ticks, "hash": self.final_hash, "outcome": self.outcome},
        }

    def save(self, path) -> None:
        """Write atomically (temporary file, then rename)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(json.dumps(self.to_json(), separators=(",", ":")) + "\n", encoding="utf-8")
        os.replace(tmp, path)

    @classmethod
    def load(cls, path) -> "Replay":
        """Read and check a replay file; problems raise :class:`ReplayError`."""
        path = Path(path)
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ReplayError(f"{path}: no such file") from None
        except (OSError, UnicodeDecodeError) as e:
            raise ReplayError(f"{path}: cannot read it ({e})") from None
        except json.JSONDecodeError as e:
            raise ReplayError(f"{path}: not a replay (invalid JSON at line {e.lineno}: {e.msg})") from None
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise ReplayError(f"{path}: not a replay (expected \"format\": \"{FORMAT}\")")
        if data.get("version") != VERSION:
            raise ReplayError(f"{path}: replay format version {data.get('version')!r}; this game reads version {VERSION}")
        for key, typ in (("level", str), ("level_hash", str), ("seed", int), ("tick_rate", int), ("hash_every", int),
                         ("actions", list), ("hashes", dict)):
            if not isinstance(data.get(key), typ):
                raise ReplayError(f"{path}: entry '{key}': expected {typ.__name__}, got {data.get(key)!r}")
        if data["tick_rate"] != TICK_RATE:
            raise ReplayError(f"{path}: entry 'tick_rate': recorded at {data['tick_rate']} Hz, the game runs at {TICK_RATE} Hz")
        actions: list[Actions] = []
        for i, run in enumerate(data["actions"]):
            if not (isinstance(run, list) and len(run) == 2 and isinstance(run[0], int) and run[0] > 0):
                raise ReplayError(f"{path}: entry 'actions' #{i}: expected [count, row] with count > 0, got {run!r}")
            try:
                a = Actions.from_row(run[1])
            except ValueError as e:
                raise ReplayError(f"{path}: entry 'actions' #{i}: {e}") from None
            actions.extend([a] * run[0])
        try:
            hashes = {int(k): str(v) for k, v in data["hashes"].items()}
        except ValueError:
            raise ReplayError(f"{path}: entry 'hashes': keys must be tick numbers") from None
        final = data.get("final") or {}
        return cls(data["level"], data["level_hash"], data["seed"], data["tick_rate"], data["hash_every"], actions,
                   hashes, int(final.get("ticks", len(actions))), str(final.get("hash", "")), final.get("outcome"))


class Recorder:
    """Collects a replay while a game is played (in a window or headless)."""

    def __init__(self, game: Game, level_name: str):
        self.replay = Replay(level_name, game.level.source_hash, game.seed)
        self.game = game

    def record(self, actions: Actions) -> None:
        """Call right after ``game.step(actions)``."""
        self.replay.actions.append(actions)
        if self.game.tick % self.replay.hash_every == 0:
            self.replay.hashes[self.game.tick] = self.game.state_hash()

    def finish(self) -> Replay:
        r = self.replay
        r.final_ticks = self.game.tick
        r.final_hash = self.game.state_hash()
        r.outcome = self.game.outcome
        return r


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
    if check and game.level.source_hash != replay.level_hash:
        divergence = ("the level file changed since this replay was recorded "
                      f"(level hash {game.level.source_hash[:12]}, replay expects {replay.level_hash[:12]})")
    else:
        divergence = None
    for a in replay.actions:
        game.step(a)
        if on_tick is not None:
            on_tick(game)
        if check and divergence is None:
            expected = replay.hashes.get(game.tick)
            if expected is not None and expected != game.state_hash():
                divergence = (f"replay diverges at tick {game.tick} ({game.tick / TICK_RATE:.2f} s): "
                              f"expected state {expected}, got {game.state_hash()}")
    final = game.state_hash()
    if check and divergence is None and replay.final_hash and replay.final_hash != final:
        divergence = f"replay diverges at the end (tick {game.tick}): expected state {replay.final_hash}, got {final}"
    return PlayResult(game.tick, game.outcome, final, divergence)
