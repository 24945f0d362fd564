"""The ``across-dimensions`` command.

``across-dimensions`` alone opens the title screen in a window. Subcommands::

    play [LEVEL] [--record FILE]       play a level in a window
    demo [--screenshots DIR]           the headless demo (no window needed)
    replay LEVEL REPLAY [--json] [--screenshots DIR --every N] [--update-hashes]
    check-level FILE...                check level files, report every problem
    probe [LEVEL...] [--json] [--workers N]  naive strategies against levels: bypasses, soft-locks
    level-schema [-o FILE.json]        the level format as a JSON Schema
    slice SHAPE|FILE [--rotate xw=30 ...] [--translate w=0.3 ...] [--mode section|frustum] -o OUT
    shape NAME [--param k=v ...] -o OUT.npz
    lift MESH --depth D -o OUT.npz
    bench [--quick] [--no-physics]
    bench scene [--n 1,10,100] [--json] [--out PLOT.png]   FPS against rotating 120-cells
    bench levels [--render-scale S] [--json]               worst frame of every shipped level
    bench start [--busy N] [--json]                        first start: title and first level frame
    edit LEVEL                         the level editor (the optional extra 'editor')

Errors a user can cause (bad arguments, files, levels, replays, meshes) are
:class:`~across_dimensions.core.errors.InputError` and print one ``error:`` line
with exit status 2. Anything else is a bug: one ``internal error`` line and
status 1. Nothing here prints a traceback unless ``--debug``. pyglet is
imported only by ``play``, so everything else runs with no display.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import threading

from ..core.errors import InputError
from . import commands
from .options import PROG, UserError, fov_degrees, length, positive_float, positive_int

__all__ = ["PROG", "UserError", "main"]


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, not usage + error
        raise UserError(f"{self.prog}: {message} (see {self.prog} --help)")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog=PROG, description="Across Dimensions: a 3D/4D first-person game and its 4D projection core.")
    p.add_argument("--debug", action="store_true", help="show tracebacks for errors")
    p.set_defaults(func=None)
    sub = p.add_subparsers(dest="command", parser_class=_Parser)
    for add in (_add_play_commands, _add_level_commands, _add_mesh_commands, _add_bench_command, _add_edit_command):
        add(sub)
    return p


def _add_play_commands(sub) -> None:
    """``play``, ``demo`` and ``replay``: the commands that run the game."""
    play = sub.add_parser("play", help="play a level in a window (the default)")
    _add_play_args(play)
    play.set_defaults(func=_play)

    demo = sub.add_parser("demo", help="run the headless demo: a recorded play-through, no window")
    demo.add_argument("--screenshots", metavar="DIR", help="write PNG frames to DIR (offscreen EGL)")
    demo.add_argument("--every", type=positive_int, default=30, metavar="N", help="one screenshot every N ticks (30)")
    demo.add_argument("--size", default="640x360", metavar="WxH", help="screenshot size (640x360)")
    demo.set_defaults(func=commands.demo)

    rp = sub.add_parser("replay", help="play a recorded replay headless and print the outcome")
    rp.add_argument("level", help="level file or shipped level name")
    rp.add_argument("replay", help="replay file (.json)")
    rp.add_argument("--screenshots", metavar="DIR", help="write PNG frames to DIR (offscreen EGL)")
    rp.add_argument("--every", type=positive_int, default=30, metavar="N", help="one screenshot every N ticks (30)")
    rp.add_argument("--size", default="640x360", metavar="WxH", help="screenshot size (640x360)")
    rp.add_argument("--no-check", action="store_true", help="do not compare state hashes")
    rp.add_argument(
        "--json",
        action="store_true",
        help="print one JSON object (outcome, ticks, hash, events, energy, position, ...) and nothing else",
    )
    rp.add_argument(
        "--update-hashes",
        action="store_true",
        help=(
            "after a deliberate simulation change: record the state hashes again and rewrite REPLAY "
            "(actions unchanged), only if it still ends with the same outcome at the same tick"
        ),
    )
    rp.set_defaults(func=_replay(rp))


def _add_level_commands(sub) -> None:
    """``check-level``, ``probe`` and ``level-schema``: the tools for level authors."""
    ck = sub.add_parser("check-level", help="check level files and list every problem")
    ck.add_argument("files", nargs="+", metavar="FILE")
    ck.set_defaults(func=commands.check_level)

    pb = sub.add_parser("probe", help="run naive strategies against levels: bypasses and soft-locks")
    pb.add_argument(
        "levels", nargs="*", metavar="LEVEL", help="level files or shipped level names (default: all shipped)"
    )
    pb.add_argument("--json", action="store_true", help="print one JSON list of rows, one per level, and nothing else")
    pb.add_argument(
        "--workers", type=positive_int, default=None, metavar="N", help="processes to run strategies in (the CPU count)"
    )
    pb.set_defaults(func=commands.probe)

    sc = sub.add_parser("level-schema", help="the level format as a JSON Schema, for editors that check as you type")
    sc.add_argument("-o", "--output", metavar="FILE.json", help="write it to FILE.json (default: print it)")
    sc.set_defaults(func=commands.level_schema)


def _add_mesh_commands(sub) -> None:
    """``slice``, ``shape`` and ``lift``: the 4D projection core on meshes, without the game."""
    sl = sub.add_parser("slice", help="project a 4D shape or .npz mesh to a 3D mesh file")
    sl.add_argument("source", metavar="SHAPE|FILE", help="a shape name (see 'shape --list') or a .npz 4D mesh")
    sl.add_argument("--rotate", action="append", default=[], metavar="PLANE=DEG", help="rotate the object, e.g. xw=30")
    sl.add_argument("--translate", action="append", default=[], metavar="AXIS=V", help="move the object, e.g. w=0.3")
    sl.add_argument("--mode", choices=("section", "frustum"), default="section")
    sl.add_argument("--fov", type=fov_degrees, default=60.0, help="frustum field of view, degrees in (0, 180) (60)")
    sl.add_argument("--distance", type=positive_float, default=3.0, help="frustum camera distance along -w (3)")
    sl.add_argument("-o", "--output", required=True, metavar="OUT", help=".obj, .ply or .glb")
    sl.set_defaults(func=commands.slice)

    sh = sub.add_parser("shape", help="write a shape's 4D mesh as .npz")
    sh.add_argument("name", nargs="?", help="shape name")
    sh.add_argument("--param", action="append", default=[], metavar="K=V", help="shape parameter, e.g. subdivisions=2")
    sh.add_argument("--list", action="store_true", help="list the shapes")
    sh.add_argument("-o", "--output", metavar="OUT.npz")
    sh.set_defaults(func=commands.shape)

    lf = sub.add_parser("lift", help="lift a 3D mesh (OBJ, GLB, STL) into a 4D prism, baked to .npz")
    lf.add_argument("mesh")
    lf.add_argument("--depth", type=length, required=True, help="hyper-depth: extent along w (0.001 to 10000)")
    lf.add_argument("--profile", choices=("prism", "round", "taper"), default="prism")
    lf.add_argument("-o", "--output", required=True, metavar="OUT.npz")
    lf.set_defaults(func=commands.lift)


def _add_bench_command(sub) -> None:
    bn = sub.add_parser("bench", help="measure projection (and physics) speed")
    bn.add_argument(
        "what",
        nargs="?",
        choices=("scene", "levels", "play", "start"),
        help=(
            "scene: FPS against rotating 120-cells (the paper's figure); levels: worst frame of each shipped "
            "level; play: every frame of each shipped replay, and the stutters; start: seconds to the title "
            "and the first level frame from a fresh install"
        ),
    )
    bn.add_argument("--quick", action="store_true", help="smaller meshes, fewer repeats")
    bn.add_argument("--no-physics", action="store_true", help="skip the physics benchmark")
    _add_bench_scene_args(bn)
    bn.set_defaults(func=commands.bench)


def _add_edit_command(sub) -> None:
    ed = sub.add_parser("edit", help="open a level in the level editor (needs the optional extra 'editor')")
    ed.add_argument("level", help="level file or shipped level name")
    ed.add_argument("--seed", type=int, default=0, help="seed of the games played from the editor")
    ed.add_argument("--settings", metavar="FILE", help="settings file (default: the user's config folder)")
    ed.add_argument("--screenshot-after", type=positive_float, metavar="SECONDS", help=argparse.SUPPRESS)
    ed.add_argument("--quit-after", type=positive_float, metavar="SECONDS", help="close the window after SECONDS")
    ed.set_defaults(func=_edit, record=None, fullscreen=None)


def _replay(parser: argparse.ArgumentParser):
    """``replay``, refusing option pairs that contradict each other as argparse refuses them."""

    def run(args) -> int:
        if args.update_hashes:
            # --update-hashes takes the hashes from a plain run: nothing to skip, nothing to draw.
            for flag, given in (("--no-check", args.no_check), ("--screenshots", args.screenshots)):
                if given:
                    parser.error(f"argument --update-hashes: not allowed with argument {flag}")
        return commands.replay(args)

    return run


def _add_bench_scene_args(p):
    from .bench_commands import add_arguments

    add_arguments(p)


def _add_play_args(p):
    p.add_argument("level", nargs="?", help="level file or shipped level name (default: the title screen)")
    p.add_argument("--record", metavar="FILE", help="record a replay to FILE (F9 toggles recording in game)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--settings", metavar="FILE", help="settings file (default: the user's config folder)")
    p.add_argument("--fullscreen", action="store_true", default=None)
    p.add_argument(
        "--screenshot-after",
        type=positive_float,
        metavar="SECONDS",
        help=(
            "save a screenshot this many seconds after the level's first frame (or the window's, "
            "with no level), then keep playing (for testing)"
        ),
    )
    p.add_argument(
        "--quit-after",
        type=positive_float,
        metavar="SECONDS",
        help="close the window this many seconds after the level's first frame (or the window's, with no level)",
    )


#: The termination signal received, if any: code that catches every exception (numba's
#: compiler turns one raised inside it into a RuntimeError) must not make it an internal error.
_terminated_by: int | None = None


def _exit_on_signal(signum, frame):
    # SIGTERM and SIGHUP would end the process without unwinding, leaving the
    # temporary file of a write in progress; as SystemExit every ``finally``
    # and the atomic writer's cleanup run first.
    global _terminated_by
    _terminated_by = signum
    raise SystemExit(128 + signum)


def _catch_termination() -> None:
    if threading.current_thread() is not threading.main_thread():
        return  # signal handlers can only be set from the main thread (main() called from a test thread)
    for name in ("SIGTERM", "SIGHUP"):
        sig = getattr(signal, name, None)
        if sig is not None and signal.getsignal(sig) is signal.SIG_DFL:
            signal.signal(sig, _exit_on_signal)


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    _catch_termination()
    try:
        args = _parser().parse_args(argv)
        if args.func is None:  # bare command: play with no level named, i.e. the title screen
            args = _parser().parse_args(["play"])
        return args.func(args)
    except UserError as e:
        return _fail(argv, str(e) if str(e).startswith(PROG) else f"{PROG}: error: {e}", 2)
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        # The reader went away (``... --json | head``): nothing more to say to it, and Python's
        # flush of stdout at exit must not fail again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except Exception as e:
        if _terminated_by is not None:  # stopped by a signal mid-way (e.g. while compiling kernels)
            return _fail(argv, f"{PROG}: stopped by {signal.Signals(_terminated_by).name}", 128 + _terminated_by)
        if debug:
            raise
        if isinstance(e, InputError):  # every error written for the user derives from it
            return _fail(argv, f"{PROG}: error: {e}", 2)
        return _fail(argv, f"{PROG}: internal error: {type(e).__name__}: {e} (run with --debug for details)", 1)


def _fail(argv: list[str], line: str, status: int) -> int:
    """Say ``line`` on stderr and return ``status``; ``replay --json`` also prints it as JSON on
    stdout (``{"error": line, "status": status}``), so a tool reading stdout is never left empty."""
    print(line, file=sys.stderr)
    command = next((a for a in argv if not a.startswith("-")), None)
    if command == "replay" and "--json" in argv:
        import json

        print(json.dumps({"error": line, "status": status}), flush=True)
    return status


def _play(args) -> int:
    from ..world.resources import resolve_level
    from .display import display_problem

    if args.record:  # refused before anything else, display or not: folders are never created for it
        from ..core.fileio import check_folder

        check_folder(args.record)
    if args.level:
        try:
            args.level = str(resolve_level(args.level))  # a typo is reported before any window work
        except FileNotFoundError as e:
            raise UserError(str(e)) from None
    problem = display_problem()
    if problem:
        print(f"{PROG}: {problem}; try the headless demo: {PROG} demo --screenshots out/", file=sys.stderr)
        return 1
    try:
        from .window import run_window  # imports pyglet

        return run_window(args)
    except Exception as e:
        # The display answered display_problem's check but the window still
        # could not open (a server that went away, or refused us).
        if type(e).__name__ == "NoSuchDisplayException":
            print(
                f"{PROG}: cannot open the display ({e}); try the headless demo: {PROG} demo --screenshots out/",
                file=sys.stderr,
            )
            return 1
        raise


def _edit(args) -> int:
    """``edit LEVEL``: the game's window opened in the level editor."""
    from .editor import missing_message

    problem = missing_message()
    if problem:
        raise UserError(problem)
    args.edit = True
    return _play(args)


if __name__ == "__main__":
    sys.exit(main())
