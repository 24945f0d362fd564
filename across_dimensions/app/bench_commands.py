"""``bench scene``, ``bench levels`` and ``bench start`` on the command line.

``bench scene`` reproduces the paper's "Rendering performance" figure (see
:mod:`across_dimensions.bench.scene`); ``bench levels`` renders every
shipped level from a grid of standing points and directions (see
:mod:`across_dimensions.bench.levels`); ``bench start`` times a fresh install's first start
(see :mod:`.bench_start`). Each prints a table and the
issue's targets next to the measured figures, or with ``--json`` only the rows
as one JSON list on stdout (targets then go to stderr).
"""

from __future__ import annotations

import json
import sys

from .options import PROG, UserError, positive_int


def _ns(text: str) -> tuple[int, ...]:
    try:
        ns = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise UserError(f"--n: expected numbers of objects separated by commas (e.g. 1,10,100), got {text!r}") from None
    if not ns or min(ns) < 1 or max(ns) > 10_000:
        raise UserError(f"--n: expected numbers of objects from 1 to 10000, got {text!r}")
    return ns


def _scale(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        x = float("nan")
    if not 0.5 <= x <= 1.0:
        raise UserError(f"--render-scale: expected a number from 0.5 to 1.0, got {text!r}")
    return x


def add_arguments(p) -> None:
    """The options of ``bench scene`` and ``bench levels`` (on the ``bench`` parser)."""
    g = p.add_argument_group("bench scene / bench levels")
    g.add_argument("--n", type=_ns, metavar="N,N,...", help="scene: numbers of 120-cells (1,2,5,10,20,50,100,200)")
    g.add_argument("--modes", default="section,frustum", metavar="M,M", help="scene: section, frustum or both")
    g.add_argument("--frames", type=positive_int, metavar="F", help="frames measured per row (scene 30, levels 3)")
    g.add_argument("--json", action="store_true", help="print the rows as one JSON list and nothing else on stdout")
    g.add_argument("--out", metavar="PLOT.png", help="scene: also write the plot (needs the optional extra 'plot')")
    g.add_argument(
        "--render-scale",
        type=_scale,
        metavar="S",
        help="draw at S (0.5 to 1.0) of 1280x720, upscaled (default: what the game picks for this GL renderer)",
    )
    g.add_argument("--per-object", action="store_true", help="scene: also measure the per-object path it replaces")
    g.add_argument("--level", action="append", metavar="LEVEL", help="levels, play: only these levels (repeatable)")
    g.add_argument("--grid", type=positive_int, metavar="K", help="levels: standing points per axis (6)")
    g.add_argument("--no-memory", action="store_true", help="levels: skip the peak memory of play on the largest level")
    g.add_argument("--busy", type=int, default=4, metavar="N", help="start: also with N busy processes (4; 0 skips it)")


def run(args) -> int:
    return {"scene": _scene, "levels": _levels, "play": _play, "start": _start}[args.what](args)


def _say(args):
    def out(msg: str = "") -> None:
        print(msg, file=sys.stderr if args.json else sys.stdout, flush=True)

    return out


def _scene(args) -> int:
    from ..bench import scene as bench_scene

    modes = tuple(m.strip() for m in args.modes.split(",") if m.strip())
    bad = [m for m in modes if m not in bench_scene.MODES]
    if bad or not modes:
        raise UserError(f"--modes: expected section, frustum or both, got {args.modes!r}")
    plot_ok = True
    if args.out:
        from ..core.fileio import check_folder

        if not args.out.lower().endswith(".png"):
            raise UserError(f"--out: the plot is a PNG; expected a name ending in .png, got {args.out!r}")
        check_folder(args.out)
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            plot_ok = False
    out = _say(args)
    rows = bench_scene.run(
        ns=args.n or bench_scene.DEFAULT_NS,
        modes=modes,
        frames=args.frames or 30,
        render_scale=args.render_scale or "auto",
        per_object=args.per_object,
        out=out,
    )
    big = max(rows, key=lambda r: (r["mode"] == "section", r["n"]))
    out(
        f"Peak memory: {big['peak_rss_mb']:.0f} MB resident (whole process, after N = {big['n']}); "
        f"GPU buffers of that scene: {big['gpu_bytes'] / 2**20:.1f} MiB"
    )
    bench_scene.print_targets(rows, out=out)
    if args.out:
        if plot_ok:
            bench_scene.plot(rows, args.out)
            out(f"plot written: {args.out}")
        else:
            out(f"the plot needs matplotlib: pip install {PROG}[plot]")
    if args.json:
        print(json.dumps(rows), flush=True)
    return 0


def _levels(args) -> int:
    from ..bench import levels as bench_levels

    out = _say(args)
    rows = bench_levels.run(
        levels=args.level,
        grid=args.grid or 6,
        frames=args.frames or 3,
        render_scale=args.render_scale,
        out=out,
    )
    memory = None
    if not args.no_memory:
        from ..bench.memory import play_peak_mb

        big = bench_levels.largest(rows)["level"]
        out(f"Peak memory: play {big} (the largest level measured) in a child process ...")
        memory = play_peak_mb(big)
        for r in rows:
            r["play_peak_mb"] = memory[0] if r["level"] == big else None
    bench_levels.print_targets(rows, memory, out=out)
    if args.json:
        print(json.dumps(rows), flush=True)
    return 0


def _play(args) -> int:
    from ..bench import play as bench_play
    from .warmup import warm_up

    try:
        pairs = bench_play.replays(args.level)
    except (FileNotFoundError, ValueError) as e:
        raise UserError(f"--level: {e}") from None
    out = _say(args)
    warm_up()  # as the title screen does before any level
    rows = bench_play.run(pairs, render_scale=args.render_scale, out=out)
    if args.json:
        print(json.dumps(rows), flush=True)
    return 0


def _start(args) -> int:
    from . import bench_start

    if not 0 <= args.busy <= 64:
        raise UserError(f"--busy: expected a number of busy processes from 0 to 64, got {args.busy}")
    out = _say(args)
    rows = bench_start.run(busy_n=args.busy, out=out)
    bench_start.print_targets(rows, out=out)
    if args.json:
        print(json.dumps(rows), flush=True)
    return 0
