"""The command-line subcommands that need no window.

Each takes the parsed ``argparse.Namespace`` and returns the exit status;
:mod:`.cli` wires them to the subcommands with ``set_defaults(func=...)``.
Problems the user can fix raise :class:`~.options.UserError` (or another
:class:`~across_dimensions.core.errors.InputError`), never print a traceback.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from .options import PROG, UserError, axis_values
from .options import parse_size as _size


def _out(msg: str = "") -> None:
    print(msg, flush=True)


# ------------------------------------------------------------------ levels
def check_level(args) -> int:
    """Check level files: ``ok`` lines on stdout, problems on stderr (exit 2).

    A level that loads but will likely not keep 60 Hz gets a warning on
    stderr and still exits 0 (the estimate is rough; see world/limits.py).
    """
    from ..world.campaign import CAMPAIGN_FILE, CampaignError, load_campaign
    from ..world.flat_level import load_flat_level
    from ..world.level import LevelError, load_level
    from ..world.limits import FRAME_MS
    from ..world.resources import is_prologue_file

    bad = 0
    for f in args.files:
        if Path(f).name == CAMPAIGN_FILE:  # the campaign's order, beside the levels: checked as such
            try:
                entries = load_campaign(Path(f))
            except CampaignError as e:
                bad += 1
                print(str(e), file=sys.stderr)
                continue
            _out(f"{f}: ok - the campaign, {len(entries)} levels: {', '.join(e.stem for e in entries)}")
            continue
        prologue = is_prologue_file(f)
        try:
            level = (load_flat_level if prologue else load_level)(f)
        except LevelError as e:
            bad += 1
            print(f"{f}: {len(e.problems)} problem(s)", file=sys.stderr)
            for p in e.problems:
                print(f"  {p}", file=sys.stderr)
            continue
        if prologue:
            _out(f"{f}: ok - {_prologue_summary(level)}")
            continue
        extra = ""
        if level.crystals:
            extra += f", {len(level.crystals)} crystals"
        if level.energy.enabled:
            extra += (
                f", energy {level.energy.start:g}/{level.energy.maximum:g} (w costs {level.energy.w_cost:g} a unit"
                + (f", the slice {level.energy.slice_cost:g} a degree)" if level.energy.slice_cost > 0 else ")")
            )
        if level.radar is not None:
            extra += f", radar {level.radar.range:g} m"
        if level.needs:
            extra += f", needs {' '.join(level.needs)}"
        _out(
            f"{f}: ok - '{level.name}', {len(level.boxes)} boxes, {len(level.worlds)} worlds, "
            f"{len(level.objects)} 4D objects{extra}, w in {list(level.w_range)}"
        )
        cost = level.frame_cost_ms()
        if cost > FRAME_MS:
            print(
                f"{f}: warning: will likely not keep 60 Hz on a typical 2-core machine: about {cost:.0f} ms "
                f"per frame while moving along w ({FRAME_MS:.1f} ms allowed) for {level.tets:,} tetrahedra in "
                f"{len(level.worlds) + len(level.objects)} 4D objects and worlds, {level.bodies} rigid bodies, "
                f"{len(level.enemies)} enemies and {len(level.crystals)} crystals",
                file=sys.stderr,
            )
    return 2 if bad else 0


def _prologue_summary(level) -> str:
    """One line on a Flatland prologue level for ``check-level``."""
    kinds = [(level.solids, "3D solid"), (level.balls, "ball"), (level.crates, "crate"), (level.items, "item")]
    counts = ", ".join(f"{len(x)} {what}{'s' * (len(x) != 1)}" for x, what in kinds + [(level.hints, "hint")] if x)
    return f"'{level.name}', a Flatland prologue level: {counts}, z in {list(level.z_range)}"


def probe(args) -> int:
    """``probe``: the design probe (:mod:`across_dimensions.probe`) on the named levels, or on
    every shipped one. Exit 0 when no level has a bypass or a soft-lock, 1 when one has."""
    import json
    import os
    import time

    from ..probe.runner import probe as run_probe
    from ..world.flat_level import load_flat_level
    from ..world.level import load_level
    from ..world.resources import is_prologue_file, level_files, prologue_files, resolve_level

    paths = []
    for name in args.levels or [str(p) for p in prologue_files() + level_files()]:
        try:
            paths.append(resolve_level(name))
        except FileNotFoundError as e:
            raise UserError(str(e)) from None
    for p in paths:  # a bad level is refused before any strategy runs
        load_flat_level(p) if is_prologue_file(p) else load_level(p)
    workers = args.workers or os.cpu_count() or 1
    t0 = time.perf_counter()
    rows = run_probe(paths, workers=min(workers, 64))
    took = time.perf_counter() - t0
    if args.json:
        _out(json.dumps(rows, allow_nan=False))
    else:
        for row in rows:
            _out(_probe_lines(row))
        found = sum(len(r["bypasses"]) + len(r["softlocks"]) for r in rows)
        _out(f"{len(rows)} level(s), {found} finding(s), {took:.1f} s with {workers} worker(s)")
    return 1 if any(r["bypasses"] or r["softlocks"] for r in rows) else 0


def _probe_lines(row: dict) -> str:
    """A level's probe row as text: a head line, then one line per finding."""
    needs = ", ".join(row["needs"]) or "nothing declared"
    lines = [
        f"{row['level']} (needs {needs}): {len(row['strategies_run'])} strategies, "
        f"{len(row['bypasses'])} bypass(es), {len(row['softlocks'])} soft-lock(s), {row['seconds']:.1f} s"
    ]
    for b in row["bypasses"]:
        lines.append(f"  bypass: {b['strategy']} won at {b['seconds']:.2f} s without {', '.join(b['avoided'])}")
    for s in row["softlocks"]:
        lines.append(f"  soft-lock: after {s['strategy']}: {s['proof']}")
    return "\n".join(lines)


def level_schema(args) -> int:
    """Print the level format's JSON Schema, or write it to ``-o FILE`` (atomically)."""
    import json

    from ..core.fileio import atomic_write
    from ..world.json_schema import level_schema as schema

    text = json.dumps(schema(), indent=2) + "\n"
    if args.output:
        atomic_write(args.output, text)
        _out(f"{args.output}: JSON Schema of the level format")
    else:
        sys.stdout.write(text)
    return 0


# ----------------------------------------------------------------- replays
def _load_game(level_arg: str, seed: int, arsenal=None):
    """The game of a level: a 4D one (started with the weapons ``arsenal``; None: the
    campaign's), or the Flatland prologue's for a ``format = "flatland"`` file."""
    from ..world.resources import is_prologue_file, resolve_level

    try:
        path = resolve_level(level_arg)
    except FileNotFoundError as e:
        raise UserError(str(e)) from None
    if is_prologue_file(path):
        from ..game.flatland import FlatGame
        from ..world.flat_level import load_flat_level

        return FlatGame(load_flat_level(path), seed=seed)
    from ..game.sim import Game
    from ..world.level import load_level

    return Game(load_level(path, arsenal=arsenal), seed=seed)


def _summary(game, result) -> dict:
    from ..game.flatland import FlatGame

    if isinstance(game, FlatGame):
        from ..game.flatland.sim import summary
    else:
        from ..game.playback import summary
    return summary(game, result)


def replay(args) -> int:
    """Play a replay headless; print the outcome and final hash, or with
    ``--json`` exactly one JSON object on stdout (see ``game.playback.summary``).
    Exit status 3 when the run diverges from the recorded hashes."""
    import json

    from ..game.flatland import FlatGame
    from ..game.playback import play
    from ..game.replay import Replay
    from .warmup import warm_up

    as_json = getattr(args, "json", False)
    update = getattr(args, "update_hashes", False)
    rep = Replay.load(args.replay)
    if update and rep.recovered:
        raise UserError(
            f"{args.replay}: a recording that was cut short has no final outcome to keep; "
            "--update-hashes rewrites finished replays only"
        )
    if rep.recovered:
        print(
            f"{PROG}: note: {args.replay} is a recording that was cut short ({len(rep.actions)} ticks kept); "
            "it has no final hash to check",
            file=sys.stderr,
        )
    game = _load_game(args.level, rep.seed, rep.arsenal)
    if not getattr(args, "no_check", False):  # --no-check plays any actions on any level
        _refuse_other_level(args, rep, game.level)
    if not isinstance(game, FlatGame):  # the prologue compiles no 4D kernels
        warm_up()
    if update:
        return _update_hashes(args, rep, game, as_json)
    shooter = _screenshotter(args, game) if args.screenshots else None
    result = play(rep, game, on_tick=shooter, check=not args.no_check)
    say = (lambda msg: print(msg, file=sys.stderr, flush=True)) if as_json else _out  # stdout is the JSON's alone
    if shooter is not None:
        shooter.close()
        say(f"screenshots: {shooter.count} PNG files in {args.screenshots}")
    if as_json:
        _out(json.dumps(_summary(game, result), allow_nan=False))
    else:
        outcome = result.outcome or "not finished"
        _out(f"level '{game.level.name}': {outcome} after {result.ticks} ticks ({result.ticks / 60:.2f} s)")
        _out(f"final state hash: {result.final_hash}")
    if result.divergence:
        print(f"{PROG}: {result.divergence}", file=sys.stderr)
        return 3
    return 0


def _refuse_other_level(args, rep, level) -> None:
    """A replay of another level is named before a tick is played (exit 2)."""
    from ..game.replay_level import other_level

    other = other_level(rep, level)
    if other is not None:
        raise UserError(
            f"{args.replay}: recorded on the level '{other}', not on {args.level}; "
            f"play it with: {PROG} replay {other} {args.replay}"
        )


def _update_hashes(args, rep, game, as_json: bool) -> int:
    """``replay --update-hashes``: record the replay's state hashes afresh.

    After a deliberate change of the simulation (same behaviour, different
    last bits) the recorded actions still hold but the hashes do not. The
    actions are played unchecked; when the run ends as recorded (same
    outcome, same tick) the file is rewritten atomically with the new hashes
    and its actions unchanged (exit 0). A different ending leaves the file
    untouched (exit 1); a changed level file is refused as ``replay`` refuses
    it (exit 3), unless every state plays as recorded (an edit of its hints or
    comments): then only the header's level hash changes. The bakes of the level's assets are recorded again with the
    hashes (and a replay of an older format gets them for the first time).
    """
    import json
    from dataclasses import replace

    from ..game.playback import changed_hashes, level_divergence, rehash
    from ..game.replay_level import same_file

    result, fresh = rehash(rep, game)
    changed, total = changed_hashes(rep, fresh)
    # A level file edited without touching the simulation (its hints, comments) plays every
    # recorded state as recorded: then its header takes the file's new hash.
    same_play = not changed and (result.outcome, result.ticks) == (rep.outcome, rep.final_ticks)
    same_bakes = rep.bakes is None or rep.bakes == fresh.bakes
    refused = None if same_file(rep, game.level) or (same_play and same_bakes) else level_divergence(rep, game)
    problem = None
    if refused is None and (result.outcome, result.ticks) != (rep.outcome, rep.final_ticks):
        problem = (
            f"{PROG}: {args.replay}: hashes not updated: expected outcome {_outcome(rep.outcome)} at tick "
            f"{rep.final_ticks}, got {_outcome(result.outcome)} at tick {result.ticks}"
        )
    updated = False
    header = (rep.level_hash, rep.bakes, rep.arsenal) != (fresh.level_hash, fresh.bakes, fresh.arsenal)
    if refused is None and problem is None and (changed or header):
        _check_actions_kept(args.replay, fresh)
        fresh.save(args.replay)  # temporary file in the same folder, then os.replace
        updated = True
    if as_json:
        _out(json.dumps({**_summary(game, replace(result, divergence=refused)), "updated": updated}, allow_nan=False))
    if refused is not None:
        print(f"{PROG}: {refused}", file=sys.stderr)
        return 3
    if problem is not None:
        print(problem, file=sys.stderr)
        return 1
    say = (lambda msg: print(msg, file=sys.stderr, flush=True)) if as_json else _out  # stdout is the JSON's alone
    said = f"hashes updated ({changed} of {total} changed)" if updated and changed else "hashes unchanged"
    if updated and header:
        said += f"; level hash and bakes recorded ({', '.join(sorted(fresh.bakes)) or 'the level bakes no mesh'})"
    say(f"{args.replay}: {said}")
    return 0


def _outcome(outcome) -> str:
    return f'"{outcome}"' if outcome else "no outcome (not finished)"


def _check_actions_kept(path, fresh) -> None:
    """Refuse to rewrite ``path`` unless its actions would be written back as they are.

    The writer is the recorder's, so a recorded file always passes; a file
    edited by hand (``1`` for ``1.0``, two equal runs side by side) would have
    its actions re-spelled, and ``--update-hashes`` never changes actions.
    """
    import json

    from ..core.fileio import read_text
    from ..game.replay import MAX_BYTES, ReplayError

    dumps = {"separators": (",", ":"), "allow_nan": False}
    before = json.dumps(json.loads(read_text(path, limit=MAX_BYTES, what="replay"))["actions"], **dumps)
    if before != json.dumps(fresh.to_json()["actions"], **dumps):
        raise ReplayError(
            f"{path}: entry 'actions': not written as a recording writes it (runs merged, floats as floats); "
            "--update-hashes would change it, so the file is left untouched"
        )


def demo(args) -> int:
    from ..world.resources import levels_dir

    args.level = "01_first_steps"
    args.replay = str(levels_dir() / "replays" / "01_first_steps.json")
    args.no_check = False
    args.json = False
    _out("Across Dimensions headless demo: a recorded play-through of 'First Steps', the first level with w.")
    return replay(args)


def _screenshotter(args, game):
    from ..game.flatland import FlatGame
    from .headless import FlatScreenshotter, Screenshotter

    if args.every < 1:
        raise UserError(f"--every: expected a positive number of ticks, got {args.every}")
    kind = FlatScreenshotter if isinstance(game, FlatGame) else Screenshotter
    return kind(game, Path(args.screenshots), _size(args.size), args.every)


# ------------------------------------------------------------------- core
def _parse_params(items) -> dict:
    params = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise UserError(f"--param {item!r}: expected NAME=VALUE")
        for conv in (int, float):
            try:
                params[key] = conv(value)
                break
            except ValueError:
                continue
        else:
            params[key] = value
    return params


def _make_shape(name: str, params: dict):
    from ..core.shapes import make_shape  # raises InputError naming the shape, parameter and range

    return make_shape(name, **params)


def _output(path: str, suffixes: tuple[str, ...], command: str) -> Path:
    """The -o path, refused before any work if its type or folder is wrong."""
    from ..core.fileio import check_folder

    if Path(path).suffix.lower() not in suffixes:
        raise UserError(f"{command}: output must end in {' or '.join(suffixes)}, got {path!r}")
    return check_folder(path)


def shape(args) -> int:
    from ..core.shapes import SHAPES

    if args.list or not args.name:
        for n in SHAPES:
            _out(n)
        return 0
    if not args.output:
        raise UserError("shape: -o OUT.npz is required")
    out = _output(args.output, (".npz",), "shape")
    mesh = _make_shape(args.name, _parse_params(args.param))
    mesh.save(out)
    _out(
        f"{args.output}: {mesh.name}, {len(mesh.vertices)} vertices, {len(mesh.tets)} tets, "
        f"hyper-volume {mesh.hypervolume():.4g}"
    )
    return 0


def slice(args) -> int:
    from ..core import cross_section, frustum_project
    from ..core.mesh import TetMesh4
    from ..core.transform import angles_to_rotation, translation

    out = _output(args.output, (".obj", ".ply", ".glb"), "slice")
    rot = axis_values(args.rotate, "plane", "--rotate")
    move = axis_values(args.translate, "axis", "--translate")
    src = Path(args.source)
    mesh = TetMesh4.load(src) if src.suffix.lower() == ".npz" else _make_shape(args.source, {})
    model = translation([move.get(a, 0.0) for a in "xyzw"])
    model[:4, :4] = angles_to_rotation({k: np.radians(v) for k, v in rot.items()})
    if args.mode == "section":
        tri = cross_section(mesh, model=model)
    else:
        tri = frustum_project(mesh, translation((0, 0, 0, -args.distance)), fov_deg=args.fov, model=model)
    n_vertices, n_triangles = tri.save(out)
    if tri.is_empty:
        _out(f"{args.output}: empty - the hyperplane misses {mesh.name or src}")
    else:
        _out(
            f"{args.output}: {n_triangles} triangles, {n_vertices} vertices ({args.mode}; "
            f"{len(tri)} triangles before welding)"
        )
    return 0


def lift(args) -> int:
    from ..core.lift import HyperDepth
    from ..core.mesh import TetMesh4
    from ..world.bake import lift_to_file

    out = _output(args.output, (".npz",), "lift")
    written = lift_to_file(args.mesh, HyperDepth(0.0, args.depth, args.profile), out)
    mesh = TetMesh4.load(written, validate=False)  # for the summary; lift_to_file validated it
    _out(f"{args.output}: {len(mesh.vertices)} vertices, {len(mesh.tets)} tets")
    return 0


def bench(args) -> int:
    if args.what is not None:  # bench scene / bench levels
        from . import bench_commands

        return bench_commands.run(args)
    from ..bench import report

    report.run(out=_out, quick=args.quick, physics=not args.no_physics)
    return 0
