"""Time trials: a finished run's track, raced as a ghost, and the split times at checkpoints.

The ghost of a level is the player's best run from its start to its goal, kept as a *track*:
where the player's feet were (4D world coordinates) and where they looked (yaw), read after
the ticks of the run and kept every :data:`EVERY` ticks, and the tick each checkpoint was first
reached at. Racing it reads the track at the live game's tick, so a ghost never touches the
simulation: no entity, no collider, nothing in the state hash. (The run's replay is kept beside
it; re-simulating it while racing would cost a second game's ticks on every frame.)

File format (JSON, strict)::

    {"format": "across-dimensions-ghost", "version": 1,
     "level": "00_arrival", "level_hash": "<the replay header's level_hash>",
     "ticks": 1320,                  # the run's length: ticks from the start to the goal
     "every": 2,                     # ticks between two rows of the track
     "splits": [[0, 610]],           # [checkpoint index, tick first reached], in order
     "track": [[x, y, z, w, yaw], ...]}   # rows at ticks 0, every, 2 every, ... and the last at ticks

Anything else is refused by :meth:`GhostTrack.from_json` with a ``ValueError`` naming the entry.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from .replay_format import MAX_TICKS
from .sim import TICK_RATE

FORMAT = "across-dimensions-ghost"
VERSION = 1
#: Ticks between two rows of a track (30 a second: a figure moving between them is interpolated).
EVERY = 2
#: Largest coordinate a track holds, metres (a level is far smaller): beyond it, a corrupt file.
MAX_COORD = 1.0e6


@dataclass
class GhostTrack:
    """A finished run as a ghost.

    Attributes
    ----------
    level : str
        The level's stem.
    level_hash : str
        The level's identity when it was run (:func:`~.replay_level.level_identity`): a ghost of
        another version of the level is not raced.
    ticks : int
        Ticks from the start to the goal.
    track : (n, 5) float64
        ``x, y, z, w`` of the feet (world coordinates) and yaw (radians), at ticks
        ``0, every, 2 every, ...``; the last row is at ``ticks``.
    splits : dict of int to int
        Checkpoint index -> the tick it was first reached at.
    every : int
    """

    level: str
    level_hash: str
    ticks: int
    track: np.ndarray
    splits: dict[int, int] = field(default_factory=dict)
    every: int = EVERY

    @property
    def seconds(self) -> float:
        """The run's time."""
        return self.ticks / TICK_RATE

    def pose_at(self, tick: float) -> tuple[np.ndarray, float]:
        """Feet ``(4,) float64`` and yaw at ``tick`` (fractional: between two rows, interpolated;
        after the goal, where the run ended)."""
        last = len(self.track) - 1
        i = min(max(tick, 0.0) / self.every, float(last))
        lo = min(int(i), last)
        hi = min(lo + 1, last)
        f = i - lo
        a, b = self.track[lo], self.track[hi]
        turn = (b[4] - a[4] + math.pi) % (2 * math.pi) - math.pi  # the short way round
        return a[:4] + f * (b[:4] - a[:4]), float(a[4] + f * turn)

    def split(self, index: int, tick: int) -> float | None:
        """Seconds the live run is behind (+) or ahead (-) of the ghost at checkpoint ``index``
        reached at ``tick``; None when the ghost never reached it."""
        mine = self.splits.get(index)
        return None if mine is None else (tick - mine) / TICK_RATE

    def to_json(self) -> str:
        rows = [[round(float(v), 4) for v in row] for row in self.track]
        return json.dumps(
            {
                "format": FORMAT,
                "version": VERSION,
                "level": self.level,
                "level_hash": self.level_hash,
                "ticks": self.ticks,
                "every": self.every,
                "splits": [[i, t] for i, t in sorted(self.splits.items(), key=lambda kv: kv[1])],
                "track": rows,
            },
            separators=(",", ":"),
            allow_nan=False,
        )

    @classmethod
    def from_json(cls, text: str) -> GhostTrack:
        """Parse a ghost file; raises ``ValueError`` naming the entry that is wrong."""
        data = json.loads(text)
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise ValueError(f"expected a JSON object with format {FORMAT!r}")
        if data.get("version") != VERSION:
            raise ValueError(f"version {data.get('version')!r}, expected {VERSION}")
        for key in ("level", "level_hash"):
            if not isinstance(data.get(key), str) or not data[key]:
                raise ValueError(f"{key}: expected a name, got {data.get(key)!r}")
        ticks, every = data.get("ticks"), data.get("every")
        if type(ticks) is not int or not 0 < ticks <= MAX_TICKS:
            raise ValueError(f"ticks: expected a whole number from 1 to {MAX_TICKS}, got {ticks!r}")
        if type(every) is not int or not 0 < every <= TICK_RATE:
            raise ValueError(f"every: expected a whole number from 1 to {TICK_RATE}, got {every!r}")
        track = _track(data.get("track"), -(-ticks // every) + 1)
        splits = {}
        for pair in data.get("splits", []) if isinstance(data.get("splits", []), list) else [None]:
            ok = isinstance(pair, list) and len(pair) == 2 and all(type(n) is int for n in pair)
            if not ok or not (0 <= pair[0] and 0 < pair[1] <= ticks) or pair[0] in splits:
                raise ValueError(f"splits: expected [checkpoint index, tick] pairs within the run, got {pair!r}")
            splits[pair[0]] = pair[1]
        return cls(data["level"], data["level_hash"], ticks, track, splits, every)


def _track(rows, expected: int) -> np.ndarray:
    """The checked track: ``expected`` rows of five finite numbers within :data:`MAX_COORD`."""
    if not isinstance(rows, list) or len(rows) != expected:
        got = len(rows) if isinstance(rows, list) else type(rows).__name__
        raise ValueError(f"track: expected {expected} rows for the run's ticks, got {got}")
    for i, row in enumerate(rows):
        ok = isinstance(row, list) and len(row) == 5
        if not ok or not all(type(v) in (int, float) and math.isfinite(v) and abs(v) <= MAX_COORD for v in row):
            raise ValueError(f"track[{i}]: expected [x, y, z, w, yaw] finite numbers, got {row!r}")
    return np.array(rows, dtype=np.float64).reshape(-1, 5)


class TrackRecorder:
    """Reads a run's track while it is played; never writes to the game.

    Parameters
    ----------
    game : Game
        At tick 0 (a track, as a replay, runs from the level's start).
    every : int
        Ticks between rows.
    """

    def __init__(self, game, every: int = EVERY):
        if game.tick != 0:
            raise ValueError(f"a track starts at tick 0, the game is at tick {game.tick}")
        self.every = every
        self.rows: list[list[float]] = [_pose(game)]
        self.splits: dict[int, int] = {}

    def record(self, game) -> int | None:
        """Call after each tick; returns the index of a checkpoint first reached on it, or None."""
        if game.tick % self.every == 0:
            self.rows.append(_pose(game))
        reached = game.checkpoint
        if reached is None or reached in self.splits:
            return None
        self.splits[reached] = game.tick
        return reached

    def finish(self, game, level: str, level_hash: str) -> GhostTrack:
        """The run as a ghost, ended at the game's tick (at its goal)."""
        rows = self.rows if game.tick % self.every == 0 else [*self.rows, _pose(game)]
        return GhostTrack(level, level_hash, game.tick, np.array(rows, dtype=np.float64), dict(self.splits), self.every)


def _pose(game) -> list[float]:
    """The player's feet in world coordinates and yaw (the turned slice's player lives in slice space)."""
    p = game.player
    feet = game.camera.to_world(p.position) if game.camera is not None else p.position
    return [*(float(v) for v in feet), float(p.yaw)]
