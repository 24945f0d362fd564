"""The worker process: runs fuzz cases in-process, one JSON line in, one out.

Started once per session by :class:`.harness.Worker` (``python -m fuzz.worker
LIMIT_BYTES``), it caps its own address space with ``RLIMIT_AS`` so a zip bomb
or a runaway allocation ends in ``MemoryError`` here instead of taking the
machine down, imports the game and compiles its kernels once, then serves
cases: each request is ``{"steps": [...], "timeout": seconds}`` and each reply
``{"steps": [result, ...]}``.

A step runs the real entry point, ``across_dimensions.app.cli.main(argv)`` or
the settings loader, with file descriptors 1 and 2 redirected to files, so
everything a user would see (``print``, warnings, C libraries) is captured.
A ``SIGALRM`` timer ends a step that runs too long by raising
:class:`CaseTimeout`, a ``BaseException`` the code under test does not catch;
a step stuck in C code that never returns to Python is killed by the parent.

Step kinds (``op``):

``cli``
    ``main(argv)``; with ``game_checks``, every :class:`Game` built during the
    step must end with a finite state, finite body poses and the player's
    ``w`` inside the level's range.
``write_replay``
    Write a replay of the given action runs with the game's own
    :class:`Replay` (so the file follows the current format).
``replay_roundtrip``
    Load an accepted replay and save it again: the file written must be strict
    JSON (no ``NaN``) and the temporary file must be gone.
``settings``
    ``load_settings(path)`` must not raise, every warning must name the file,
    the result must pass the settings' own validation and survive a
    save/load round trip.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import resource
import signal
import sys
import tempfile
import time
import traceback
import warnings


class CaseTimeout(BaseException):
    """The step ran past its time limit (raised from the SIGALRM handler)."""


def _on_alarm(signum, frame):
    raise CaseTimeout()


_GAMES: list = []


def _install_game_hook() -> None:
    """Remember every Game built, so a CLI step's game can be inspected after ``main`` returns."""
    from across_dimensions.game.sim import Game

    original = Game.__init__

    def init(self, *a, **kw):
        original(self, *a, **kw)
        _GAMES.append(self)

    Game.__init__ = init


#: How far (in w) a body's centre may stray outside the level's w range: about a body's size.
W_MARGIN = 1.0


def _game_problems(game, bodies_in_w: bool = False) -> list[list[str]]:
    """``[category, message]`` for each way the game's state went wrong."""
    import numpy as np

    out = []
    state = np.asarray(game.state_array(), dtype=np.float64)
    if not np.isfinite(state).all():
        out.append(
            [
                "non-finite state",
                f"Game.state_array() not finite after {game.tick} ticks: player position "
                f"{np.asarray(game.player.position).tolist()}, yaw {game.player.yaw}, pitch {game.player.pitch}",
            ]
        )
    lo, hi = game.level.w_range
    w = float(game.player.position[3])
    if math.isfinite(w) and not lo - 1e-9 <= w <= hi + 1e-9:
        out.append(
            ["non-finite state", f"player w = {w} outside the level's w_range [{lo}, {hi}] after {game.tick} ticks"]
        )
    physics = game.physics
    if physics is not None:
        for b in physics.body_ids:
            pose = physics.body_pose(b)
            if not np.isfinite(pose).all():
                out.append(
                    [
                        "non-finite state",
                        f"body {b} pose not finite after {game.tick} ticks: position {pose[:4, 4].tolist()}",
                    ]
                )
                break
            bw = float(pose[3, 4])
            if bodies_in_w and not lo - W_MARGIN <= bw <= hi + W_MARGIN:
                out.append(
                    [
                        "body left w range",
                        f"body {b} at w = {bw:.3g} after {game.tick} ticks, outside the "
                        f"level's w_range [{lo}, {hi}] (+- {W_MARGIN})",
                    ]
                )
                break
    return out


@contextlib.contextmanager
def _captured(folder: str):
    """Send fds 1 and 2 (and sys.stdout/err) to files; yields a dict filled with the text on exit."""
    got = {}
    out_path, err_path = os.path.join(folder, "stdout"), os.path.join(folder, "stderr")
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with open(out_path, "wb") as fo, open(err_path, "wb") as fe:
        os.dup2(fo.fileno(), 1)
        os.dup2(fe.fileno(), 2)
    try:
        yield got
    finally:
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        os.close(saved[0])
        os.close(saved[1])
        for key, p in (("stdout", out_path), ("stderr", err_path)):
            with open(p, "rb") as f:
                data = f.read(200_001)
            got[key] = data[:200_000].decode("utf-8", "replace") + ("\n[... cut]" if len(data) > 200_000 else "")


def _user_warning_filters() -> None:
    """The filters a user's interpreter starts with, with 'once per place' reset for this step."""
    warnings.resetwarnings()
    warnings.simplefilter("default")
    for cat in (DeprecationWarning, PendingDeprecationWarning, ImportWarning, ResourceWarning):
        warnings.simplefilter("ignore", cat)


def _run_cli(step: dict, result: dict) -> None:
    from across_dimensions.app.cli import main

    try:
        result["exit"] = main(list(step["argv"]))
    except SystemExit as e:
        result["exit"] = e.code if isinstance(e.code, int) else 1
    if step.get("game_checks"):
        for g in _GAMES:
            result["problems"] += _game_problems(g, step.get("bodies_in_w", False))


def _write_replay(step: dict, result: dict) -> None:
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.replay import Replay

    actions = []
    for count, row in step["runs"]:
        actions.extend([Actions.from_row(row)] * count)
    try:
        rep = Replay(level="fuzz", level_hash="0" * 64, seed=step.get("seed", 0), actions=actions)
        rep.final_ticks = len(actions)
        rep.save(step["path"])
    except Exception:  # the replay API changed: write format 1 by hand, a stale file is still a useful test
        doc = {
            "format": "across-dimensions-replay",
            "version": 1,
            "level": "fuzz",
            "level_hash": "0" * 64,
            "seed": step.get("seed", 0),
            "tick_rate": 60,
            "hash_every": 60,
            "actions": step["runs"],
            "hashes": {},
            "final": {"ticks": len(actions), "hash": "", "outcome": None},
        }
        with open(step["path"], "w", encoding="utf-8") as f:
            json.dump(doc, f)
    result["exit"] = 0


def _strict_json(text: str):
    def refuse(name):
        raise ValueError(f"{name} is not valid JSON")

    return json.loads(text, parse_constant=refuse)


def _replay_roundtrip(step: dict, result: dict) -> None:
    from across_dimensions.game.replay import Replay

    rep = Replay.load(step["path"])
    rep.save(step["out"])
    with open(step["out"], "rb") as f:
        text = f.read().decode("utf-8")
    try:
        _strict_json(text)
    except ValueError as e:
        result["problems"].append(["invalid JSON written", f"Replay.save wrote {step['out']}: {e}"])
    result["exit"] = 0


def _settings(step: dict, result: dict) -> None:
    from dataclasses import replace

    from across_dimensions.app.settings import load_settings, save_settings

    path = step["path"]
    settings, warns = load_settings(path)
    result["exit"] = 0
    result["warnings"] = [str(w) for w in warns]
    name = os.path.basename(path)
    for w in warns:
        if not isinstance(w, str) or (path not in w and name not in w):
            result["problems"].append(["unnamed file", f"settings warning does not name the file: {w!r}"])
    try:
        replace(settings)
    except Exception as e:  # the loader handed out settings its own validation rejects
        result["problems"].append(["invalid settings accepted", f"{type(e).__name__}: {e}"])
        return
    save_settings(settings, step["out"])
    again, warns2 = load_settings(step["out"])
    if again != settings:
        result["problems"].append(["settings round trip", "saved and reloaded settings differ from those loaded"])
    bad2 = [w for w in warns2 if "bound to" not in w]
    if bad2:
        result["problems"].append(["settings round trip", f"reloading the saved file warns: {bad2[0]}"])


def _selftest(step: dict, result: dict) -> None:
    """Misbehave on purpose, to test the harness's limits."""
    if step["what"] == "sleep":
        time.sleep(1e6)
    elif step["what"] == "deaf":  # like C code that never returns to Python: the alarm cannot stop it
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM})
        time.sleep(1e6)
    elif step["what"] == "allocate":
        result["size"] = len(bytearray(16 * 2**30))
    elif step["what"] == "print":
        print("to stdout")
        os.write(2, b"to fd 2\n")
    result["exit"] = 0


_OPS = {
    "selftest": _selftest,
    "cli": _run_cli,
    "write_replay": _write_replay,
    "replay_roundtrip": _replay_roundtrip,
    "settings": _settings,
}


def run_step(step: dict, timeout: float, scratch: str) -> dict:
    result = {
        "op": step["op"],
        "exit": None,
        "stdout": "",
        "stderr": "",
        "exception": None,
        "traceback": None,
        "timed_out": False,
        "seconds": 0.0,
        "problems": [],
    }
    _GAMES.clear()
    cwd = os.getcwd()
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        _user_warning_filters()
        with _captured(scratch) as got:
            try:
                if step.get("cwd"):
                    os.chdir(step["cwd"])
                signal.setitimer(signal.ITIMER_REAL, timeout)
                try:
                    _OPS[step["op"]](step, result)
                finally:
                    signal.setitimer(signal.ITIMER_REAL, 0)
            except CaseTimeout:
                result["timed_out"] = True
            except BaseException as e:  # noqa: BLE001 - everything escaping the entry point is a finding
                if isinstance(e, KeyboardInterrupt):
                    raise
                result["exception"] = f"{type(e).__name__}: {str(e)[:500]}"
                result["traceback"] = "".join(traceback.format_exception(type(e), e, e.__traceback__))[-4000:]
            finally:
                os.chdir(cwd)
    result["seconds"] = round(time.perf_counter() - t0, 3)
    result["stdout"], result["stderr"] = got.get("stdout", ""), got.get("stderr", "")
    _GAMES.clear()
    return result


def _needs_met(step: dict, done: list) -> bool:
    if "needs" not in step:
        return True
    prev = done[step["needs"]]
    return (
        not prev["timed_out"]
        and prev["exception"] is None
        and not prev.get("skipped")
        and prev["exit"] in step.get("needs_exit", [0])
    )


def main() -> None:
    limit = int(sys.argv[1])
    if limit > 0:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    proto = os.fdopen(os.dup(1), "w", buffering=1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)  # stray output must not corrupt the protocol
    signal.signal(signal.SIGALRM, _on_alarm)
    scratch = tempfile.mkdtemp(prefix="fuzz-worker-")

    from across_dimensions.app.warmup import warm_up

    with contextlib.redirect_stderr(io.StringIO()):
        warm_up()
    _install_game_hook()
    import across_dimensions.app.commands  # noqa: F401 - paid once, not in the first case's time

    proto.write(json.dumps({"ready": True, "pid": os.getpid()}) + "\n")
    for line in sys.stdin:
        request = json.loads(line)
        done = []
        for step in request["steps"]:
            if not _needs_met(step, done):
                done.append(
                    {
                        "op": step["op"],
                        "skipped": True,
                        "exit": None,
                        "timed_out": False,
                        "exception": None,
                        "problems": [],
                    }
                )
                continue
            done.append(run_step(step, max(step.get("timeout", 0), request["timeout"]), scratch))
            if done[-1]["timed_out"]:
                break
        proto.write(json.dumps({"steps": done}) + "\n")


if __name__ == "__main__":
    main()
