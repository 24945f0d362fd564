"""The ``across-dimensions`` command.

``across-dimensions`` alone starts the first level in a window. Subcommands::

    play [LEVEL] [--record FILE]       play a level in a window
    demo [--screenshots DIR]           the headless demo (no window needed)
    replay LEVEL REPLAY [--json] [--screenshots DIR --every N]
    check-level FILE...                check level files, report every problem
    slice SHAPE|FILE [--rotate xw=30 ...] [--translate w=0.3 ...] [--mode section|frustum] -o OUT
    shape NAME [--param k=v ...] -o OUT.npz
    lift MESH --depth D -o OUT.npz
    bench [--quick] [--no-physics]

Errors a user can cause (bad arguments, files, levels, replays) print one line
and exit with status 2; nothing here prints a traceback unless ``--debug``.
pyglet is imported only by ``play``, so everything else runs with no display.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

PROG = "across-dimensions"


class UserError(Exception):
    """A problem the user can fix; printed as one line."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, not usage + error
        raise UserError(f"{self.prog}: {message} (see {self.prog} --help)")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog=PROG, description="Across Dimensions: a 3D/4D first-person game and its 4D projection core.")
    p.add_argument("--debug", action="store_true", help="show tracebacks for errors")
    sub = p.add_subparsers(dest="command", parser_class=_Parser)

    play = sub.add_parser("play", help="play a level in a window (the default)")
    _add_play_args(play)

    demo = sub.add_parser("demo", help="run the headless demo: a recorded play-through, no window")
    demo.add_argument("--screenshots", metavar="DIR", help="write PNG frames to DIR (offscreen EGL)")
    demo.add_argument("--every", type=int, default=30, metavar="N", help="one screenshot every N ticks (30)")
    demo.add_argument("--size", default="640x360", metavar="WxH", help="screenshot size (640x360)")

    rp = sub.add_parser("replay", help="play a recorded replay headless and print the outcome")
    rp.add_argument("level", help="level file or shipped level name")
    rp.add_argument("replay", help="replay file (.json)")
    rp.add_argument("--screenshots", metavar="DIR", help="write PNG frames to DIR (offscreen EGL)")
    rp.add_argument("--every", type=int, default=30, metavar="N", help="one screenshot every N ticks (30)")
    rp.add_argument("--size", default="640x360", metavar="WxH", help="screenshot size (640x360)")
    rp.add_argument("--no-check", action="store_true", help="do not compare state hashes")
    rp.add_argument("--json", action="store_true",
                    help="print one JSON object (outcome, ticks, hash, events, energy, position, ...) and nothing else")

    ck = sub.add_parser("check-level", help="check level files and list every problem")
    ck.add_argument("files", nargs="+", metavar="FILE")

    sl = sub.add_parser("slice", help="project a 4D shape or .npz mesh to a 3D mesh file")
    sl.add_argument("source", metavar="SHAPE|FILE", help="a shape name (see 'shape --list') or a .npz 4D mesh")
    sl.add_argument("--rotate", action="append", default=[], metavar="PLANE=DEG", help="rotate the object, e.g. xw=30")
    sl.add_argument("--translate", action="append", default=[], metavar="AXIS=V", help="move the object, e.g. w=0.3")
    sl.add_argument("--mode", choices=("section", "frustum"), default="section")
    sl.add_argument("--fov", type=float, default=60.0, help="frustum field of view, degrees (60)")
    sl.add_argument("--distance", type=float, default=3.0, help="frustum camera distance along -w (3)")
    sl.add_argument("-o", "--output", required=True, metavar="OUT", help=".obj, .ply or .glb")

    sh = sub.add_parser("shape", help="write a shape's 4D mesh as .npz")
    sh.add_argument("name", nargs="?", help="shape name")
    sh.add_argument("--param", action="append", default=[], metavar="K=V", help="shape parameter, e.g. subdivisions=2")
    sh.add_argument("--list", action="store_true", help="list the shapes")
    sh.add_argument("-o", "--output", metavar="OUT.npz")

    lf = sub.add_parser("lift", help="lift a 3D mesh (OBJ, GLB, STL) into a 4D prism, baked to .npz")
    lf.add_argument("mesh")
    lf.add_argument("--depth", type=float, required=True, help="hyper-depth: extent along w")
    lf.add_argument("--profile", choices=("prism", "round", "taper"), default="prism")
    lf.add_argument("-o", "--output", required=True, metavar="OUT.npz")

    bn = sub.add_parser("bench", help="measure projection (and physics) speed")
    bn.add_argument("--quick", action="store_true", help="smaller meshes, fewer repeats")
    bn.add_argument("--no-physics", action="store_true", help="skip the physics benchmark")
    return p


def _add_play_args(p):
    p.add_argument("level", nargs="?", help="level file or shipped level name (default: the first level)")
    p.add_argument("--record", metavar="FILE", help="record a replay to FILE (F9 toggles recording in game)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--settings", metavar="FILE", help="settings file (default: the user's config folder)")
    p.add_argument("--fullscreen", action="store_true", default=None)
    p.add_argument("--screenshot-after", type=float, metavar="SECONDS",
                   help="save a screenshot after this many seconds, then keep playing (for testing)")
    p.add_argument("--quit-after", type=float, metavar="SECONDS", help="close the window after this many seconds")


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
        if w < 16 or h < 16 or w > 8192 or h > 8192:
            raise ValueError
    except ValueError:
        raise UserError(f"--size: expected WIDTHxHEIGHT between 16 and 8192, got {text!r}") from None
    return w, h


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    try:
        args = _parser().parse_args(argv)
        return _dispatch(args)
    except UserError as e:
        print(f"{PROG}: error: {e}" if not str(e).startswith(PROG) else f"{str(e)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except Exception as e:  # known error types carry user-facing messages
        from ..core.mesh import MeshError
        from ..game.replay import ReplayError
        from ..world.level import LevelError

        if debug:
            raise
        if isinstance(e, (LevelError, ReplayError, MeshError, ValueError, FileNotFoundError)):
            print(f"{PROG}: error: {e}", file=sys.stderr)
            return 2
        print(f"{PROG}: internal error: {type(e).__name__}: {e} (run with --debug for details)", file=sys.stderr)
        return 1


def _dispatch(args) -> int:
    cmd = args.command or "play"
    if cmd == "play":
        if args.command is None:  # bare command: defaults for the play options
            args = _parser().parse_args(["play"])
        return _play(args)
    from . import commands

    return getattr(commands, cmd.replace("-", "_"))(args)


def _play(args) -> int:
    from .display import display_problem

    if args.record:  # refused before anything else, display or not: folders are never created for it
        from ..core.fileio import check_folder

        check_folder(args.record)

    problem = display_problem()
    if problem:
        print(f"{PROG}: {problem}; try the headless demo: {PROG} demo --screenshots out/", file=sys.stderr)
        return 1
    from .window import run_window  # imports pyglet

    return run_window(args)


if __name__ == "__main__":
    sys.exit(main())
