"""Runs kept as ghosts, and time trials against them.

Every 4D level played from its start is logged (:class:`RunLog`): its replay, in memory, and
its track (:class:`~across_dimensions.game.ghost_run.TrackRecorder`). When it reaches the goal,
the level-complete view keeps it as the level's ghost if it beats the one kept
(:func:`keep_ghost`). A time trial (:class:`Race`) is the level played against its ghost: the
figure drawn where the best run was at this tick, the split at each checkpoint said against the
best run's, a clock. None of it writes to the game: a replay of a time trial is the replay of
the same inputs played alone.
"""

from __future__ import annotations

from ..core.fileio import FileProblem
from ..game.ghost_run import GhostTrack, TrackRecorder
from ..game.replay import Recorder
from ..game.sim import TICK_RATE
from ..render.ghost_figure import ghost_drawable
from .ghost_saves import load_ghost, save_ghost
from .menu import format_time


class RunLog:
    """The run being played from its level's start, kept to become the level's ghost.

    Parameters
    ----------
    game : Game
        At tick 0.
    level : str
        The level's stem.
    """

    def __init__(self, game, level: str):
        self.level = level
        self.replay = Recorder(game, level)  # in memory: saved only if it becomes the ghost
        self.track = TrackRecorder(game)
        #: The finished run, ``(ghost, replay)``, once the goal is reached; None until then.
        self.finished = None

    @property
    def level_hash(self) -> str:
        return self.replay.replay.level_hash

    def record(self, game, actions) -> int | None:
        """Call after each tick; returns the index of a checkpoint first reached on it, or None.
        On the tick the goal is reached the run is finished, and nothing after it is logged."""
        if self.finished is not None:
            return None
        self.replay.record(actions)
        reached = self.track.record(game)
        if game.outcome == "complete":
            self.finished = (self.track.finish(game, self.level, self.level_hash), self.replay.finish())
        return reached


def keep_ghost(log: RunLog | None, warn) -> tuple[GhostTrack | None, bool]:
    """Keep ``log``'s finished run as its level's ghost when it beats the one kept (or that one is
    of another version of the level, or there is none).

    Parameters
    ----------
    log : RunLog or None
        None (a run not from the level's start, or not finished): nothing is kept.
    warn : callable
        ``warn(text)``: a ghost that cannot be read or saved, said once.

    Returns
    -------
    before : GhostTrack or None
        The ghost raced against before this run (of this version of the level).
    kept : bool
        This run is the level's ghost now.
    """
    if log is None or log.finished is None:
        return None, False
    ghost, replay = log.finished
    before, warnings = load_ghost(ghost.level)
    for w in warnings:
        warn(w)
    if before is not None and before.level_hash != ghost.level_hash:
        before = None  # the level changed since: that run raced another course
    if before is not None and before.ticks <= ghost.ticks:
        return before, False
    try:
        save_ghost(ghost, replay)
    except FileProblem as e:
        warn(f"Ghost not saved: {e}")
        return before, False
    return before, True


class Race:
    """A time trial: the level's ghost raced by the player.

    Parameters
    ----------
    ghost : GhostTrack or None
        The best run kept; None when the level has none yet (the trial is then a timed run
        that becomes the first ghost).
    """

    def __init__(self, ghost: GhostTrack | None):
        self.ghost = ghost

    @classmethod
    def of_level(cls, level: str, level_hash: str, warn) -> tuple[Race, str]:
        """The race of ``level`` (its stem; ``level_hash`` its identity now), and what to say as it starts."""
        ghost, warnings = load_ghost(level)
        for w in warnings:
            warn(w)
        if warnings:
            return cls(None), "Time trial: your ghost could not be read (kept aside), no ghost to race"
        if ghost is not None and ghost.level_hash != level_hash:
            return cls(None), "Time trial: your best run was on an older version of this level, no ghost to race"
        if ghost is None:
            return cls(None), "Time trial: no ghost yet - finish the level to race your best run"
        return cls(ghost), f"Time trial: race your best run, {format_time(ghost.seconds)}"

    def split(self, index: int, tick: int, name: str) -> str:
        """The line said when the player first reaches checkpoint ``index`` (``name``) at ``tick``."""
        line = f"Checkpoint {name or index + 1}: {format_time(tick / TICK_RATE)}"
        delta = self.ghost.split(index, tick) if self.ghost is not None else None
        return line if delta is None else f"{line}   {signed(delta)} s"

    def clock(self, tick: int) -> str:
        """The race's line on the HUD: the time run, and the ghost's."""
        best = f" / ghost {format_time(self.ghost.seconds)}" if self.ghost is not None else ""
        return f"TIME TRIAL  {format_time(tick / TICK_RATE)}{best}"

    def figure(self, game, frame, alpha: float) -> None:
        """Add the ghost's figure to ``frame`` (drawn ``alpha`` of the way from the last tick)."""
        if self.ghost is None:
            return
        feet, yaw = self.ghost.pose_at(game.tick - 1 + alpha)
        feet = game.camera.to_slice(feet) if game.camera is not None else feet
        drawable = ghost_drawable(feet, yaw, frame.camera.w)
        if drawable is not None:
            frame.drawables.append(drawable)


def signed(seconds: float) -> str:
    """``-1.25`` -> ``"-1.2"``, ``0.5`` -> ``"+0.5"``: behind (+) or ahead (-) of the ghost."""
    return f"{seconds:+.1f}"
