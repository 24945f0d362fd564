"""Fuzz cases: what file to write, which command to run on it, what must hold.

A case is a pure function of ``(seed, index)``: :func:`build_case` derives its
own ``numpy.random.default_rng([seed, index])``, so any single case can be
rebuilt and rerun without generating the ones before it. Which mutation a case
applies comes from a fixed schedule (:func:`schedule`) that cycles through the
whole :data:`CATALOGUE`, so a few hundred cases already try every mutation of
every input kind at least twice.

Steps are plain data for the worker process (see :mod:`.worker`); paths in
them use the placeholders ``{in}`` (the case's input folder), ``{out}`` (its
output and working folder) and ``{repo}`` (the checkout under test).
"""

from __future__ import annotations

import copy
import functools
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from across_dimensions.world.resources import is_prologue_file

from . import mutate as M
from . import npzgen
from .emit import Raw, json_dumps, no_int_digit_limit, toml_dumps
from .mutate import pick

__all__ = ["Case", "CATALOGUE", "schedule", "build_case", "write_case", "SPECIAL_KINDS"]

REPO = Path(__file__).resolve().parents[2]
# The 4D levels: the mutations below follow their format (the prologue's gravity is no 4-vector).
LEVELS = [p for p in sorted((REPO / "levels").glob("*.toml")) if p.name != "campaign.toml" and not is_prologue_file(p)]
REPLAYS = sorted((REPO / "levels" / "replays").glob("*.json"))
SMALL_MESHES = [REPO / "assets" / "meshes" / "crate.obj", REPO / "assets" / "meshes" / "arch.obj"]

#: Time limit of a ``lift`` step: pytetwild may take several seconds on a broken
#: surface of 44 triangles, which is slow but bounded, not a hang.
BAKE_TIMEOUT = 30.0

#: Special files made in place of an input.
SPECIAL_KINDS = (
    "fifo",
    "dev_zero",
    "dev_null",
    "folder",
    "symlink_to_folder",
    "dangling_symlink",
    "symlink_loop",
    "empty",
)


@dataclass
class Case:
    """One generated input and the commands run on it.

    Attributes
    ----------
    files : dict of str to bytes or str
        File name in the input folder -> contents, or a special kind from
        :data:`SPECIAL_KINDS` given as ``"special:<kind>"``.
    steps : list of dict
        What the worker runs, in order (see :mod:`.worker`).
    names : tuple of str
        A refusal must mention at least one of these (the file's name, or the
        option it is about).
    must_refuse : bool
        The input is certainly invalid: accepting it is a failure.
    """

    seed: int
    index: int
    kind: str
    mutation: str
    detail: str = ""
    files: dict = field(default_factory=dict)
    steps: list = field(default_factory=list)
    names: tuple = ()
    must_refuse: bool = False

    @property
    def label(self) -> str:
        return f"{self.index:05d}-{self.kind}-{self.mutation}"


# ------------------------------------------------------------------ schedule
#: (kind, mutation, weight): the weight is how often an entry comes up per cycle.
CATALOGUE: tuple = (
    # levels
    ("level", "number_extreme", 4),
    ("level", "targeted_extreme", 7),
    ("level", "type_swap", 3),
    ("level", "delete_entry", 2),
    ("level", "duplicate_tables", 1),
    ("level", "table_flood", 1),
    ("level", "deep_nesting", 1),
    ("level", "long_string", 1),
    ("level", "unknown_field", 1),
    ("level", "truncate", 1),
    ("level", "random_bytes", 1),
    ("level", "bit_flips", 2),
    ("level", "duplicate_line", 1),
    ("level", "delete_lines", 1),
    ("level", "bad_encoding", 1),
    ("level", "heavy_level", 1),
    ("level", "asset_path", 1),
    ("level", "long_run", 1),
    # replays
    ("replay", "number_extreme", 2),
    ("replay", "type_swap", 2),
    ("replay", "delete_entry", 1),
    ("replay", "duplicate_tables", 1),
    ("replay", "table_flood", 1),
    ("replay", "deep_nesting", 1),
    ("replay", "long_string", 1),
    ("replay", "unknown_field", 1),
    ("replay", "truncate", 1),
    ("replay", "random_bytes", 1),
    ("replay", "bit_flips", 1),
    ("replay", "bad_encoding", 1),
    ("replay", "run_length", 3),
    ("replay", "nan_row", 2),
    ("replay", "header", 3),
    ("replay", "hash_keys", 1),
    # settings
    ("settings", "number_extreme", 2),
    ("settings", "type_swap", 2),
    ("settings", "delete_entry", 1),
    ("settings", "deep_nesting", 1),
    ("settings", "long_string", 1),
    ("settings", "unknown_field", 1),
    ("settings", "truncate", 1),
    ("settings", "random_bytes", 1),
    ("settings", "bit_flips", 1),
    ("settings", "duplicate_line", 1),
    ("settings", "bad_encoding", 1),
    ("settings", "bad_binding", 2),
    # .npz meshes
    *(("npz", m, 1) for m in npzgen.ARRAY_MUTATIONS),
    ("npz", "bad_index", 1),
    ("npz", "dtype_swap", 1),
    ("npz", "zip_bomb", 1),
    ("npz", "lying_header", 1),
    ("npz", "nested_zip", 1),
    ("npz", "truncate", 1),
    ("npz", "bit_flips", 1),
    ("npz", "random_bytes", 1),
    # 3D meshes, lifted (baking takes about a second, so few of these)
    ("obj", "vertex_extreme", 1),
    ("obj", "bad_face", 1),
    ("obj", "bytes", 1),
    ("obj", "flood", 1),
    ("obj", "gltf_uri", 1),
    ("obj", "stl", 1),
    # special files in place of each kind of input
    ("special", "level", 2),
    ("special", "replay", 1),
    ("special", "replay_level", 1),
    ("special", "npz", 1),
    ("special", "obj", 1),
    ("special", "settings", 2),
    # command-line options
    ("args", "slice", 4),
    ("args", "shape", 3),
    ("args", "lift", 1),
    ("args", "replay_options", 1),
    ("args", "output_path", 2),
    ("args", "empty_section", 1),
    ("args", "tmp_squatter", 1),
)


def schedule(seed: int) -> list[tuple[str, str]]:
    """One cycle of (kind, mutation) pairs, each repeated by its weight, shuffled by ``seed``."""
    cycle = [(k, m) for k, m, w in CATALOGUE for _ in range(w)]
    order = np.random.default_rng([seed, 2**31]).permutation(len(cycle))
    return [cycle[i] for i in order]


def plan(seed: int, index: int) -> tuple[str, str]:
    """The (kind, mutation) of case ``index``."""
    cycle = schedule(seed)
    return cycle[index % len(cycle)]


def build_case(seed: int, index: int) -> Case:
    """Case ``index`` of the run with ``seed`` (deterministic)."""
    kind, mutation = plan(seed, index)
    rng = np.random.default_rng([seed, index])
    case = Case(seed, index, kind, mutation)
    with no_int_digit_limit():  # 10**5000 is one of the values written
        _BUILDERS[kind](rng, case)
    return case


# ------------------------------------------------------------------ helpers
def _mutate_tree(rng, mutation: str, tree, *, json_style=False, flood=(10_000, 100_000, 1_000_000)):
    """Apply one of the generic tree mutations; returns (tree, detail)."""
    if mutation == "number_extreme":
        return M.number_extreme(rng, tree)
    if mutation == "type_swap":
        return M.type_swap(rng, tree)
    if mutation == "delete_entry":
        return M.delete_entry(rng, tree)
    if mutation == "duplicate_tables":
        return M.duplicate_tables(rng, tree)
    if mutation == "table_flood":
        # 10**6 copies only now and then: generating and refusing them is the slow part of a run
        counts = [c for c in flood for _ in range({10_000: 6, 100_000: 3}.get(c, 1))]
        return M.duplicate_tables(rng, tree, counts=counts)
    if mutation == "deep_nesting":
        return M.deep_nesting(rng, tree, json_style=json_style)
    if mutation == "long_string":
        return M.long_string(rng, tree)
    if mutation == "unknown_field":
        return M.unknown_field(rng, tree)
    raise KeyError(mutation)


_BYTE_MUTATIONS = {
    "truncate": M.truncate,
    "random_bytes": M.random_bytes,
    "bit_flips": M.bit_flips,
    "duplicate_line": M.duplicate_line,
    "delete_lines": M.delete_lines,
    "bad_encoding": M.bad_encoding,
}


def _short_replay_rows(rng, ticks: int = 120) -> list:
    """Seeded random actions as ``[count, [forward, right, yaw, pitch, w, buttons]]`` runs."""
    runs, left = [], ticks
    while left > 0:
        n = min(left, int(rng.integers(1, 31)))
        row = [
            float(np.round(rng.uniform(-1, 1), 3)),
            float(np.round(rng.uniform(-1, 1), 3)),
            float(np.round(rng.normal(0, 0.05), 4)),
            float(np.round(rng.normal(0, 0.02), 4)),
            float(np.round(rng.uniform(-1, 1), 3)),
            int(rng.integers(0, 2)),
        ]
        runs.append([n, row])
        left -= n
    return runs


# ------------------------------------------------------------------- levels
#: Finite values that break physics and geometry (NaN, inf and huge integers are
#: left to ``number_extreme``: the loader's finiteness check already stops them).
_TARGET_VALUES = (1e300, -1e300, 1e308, -1e308, 1e-300, 5e-324, 1e150, 1e5, -1e5, -9.81e4)


def _level_targets(doc: dict) -> list[tuple]:
    """Paths of the numbers a level's physics and geometry depend on (bodies' fields when it has bodies)."""
    paths = [
        ("physics", "gravity", 1),
        ("physics", "gravity", 0),
        ("physics", "gravity", 3),
        ("physics", "inverse_cube_g"),
        ("spawn", "position", 1),
        ("spawn", "position", 3),
        ("goal", "size", 1),
    ]
    for i in range(len(doc.get("box", [])[:2])):
        paths += [("box", i, "center", 0), ("box", i, "size", 1)]
    for i in range(len(doc.get("world", []))):
        paths += [("world", i, "w"), ("world", i, "depth"), ("world", i, "box", 0, "center", 0)]
    objects = doc.get("object", [])
    bodies = [i for i, o in enumerate(objects) if o.get("body", "none") != "none"]
    for i in bodies or range(len(objects)):
        paths += [("object", i, f) for f in ("scale", "mass")]
        paths += [
            ("object", i, "velocity", 0),
            ("object", i, "velocity", 3),
            ("object", i, "spin", "xw"),
            ("object", i, "position", 1),
        ]
    return paths


def _set_creating(doc: dict, path: tuple, value) -> None:
    """Set ``path`` in ``doc``, creating the tables and 4-vectors on the way."""
    node = doc
    for k, nxt in zip(path[:-1], path[1:]):
        if isinstance(node, dict) and k not in node:
            node[k] = [0.0, 0.0, 0.0, 0.0] if isinstance(nxt, int) else {}
        node = node[k]
    node[path[-1]] = value


def _heavy_level(rng, doc: dict) -> str:
    kind = pick(rng, ("120-cells", "duoprisms", "spheres", "boxes"))
    if kind == "120-cells":
        n = 200
        objs = [
            {"name": f"c{i}", "shape": "120-cell", "position": [i % 10, 1.0, i // 10, 0.0], "scale": 0.3}
            for i in range(n)
        ]
    elif kind == "duoprisms":
        n = 10
        objs = [
            {"name": f"d{i}", "shape": "duoprism", "params": {"p": 128, "q": 128}, "position": [i, 1.0, 0.0, 0.0]}
            for i in range(n)
        ]
    elif kind == "spheres":
        n = 100
        objs = [
            {
                "name": f"s{i}",
                "shape": "hypersphere",
                "params": {"subdivisions": 3},
                "body": "hypersphere",
                "position": [i % 10, 2.0 + i // 10, 0.0, 0.0],
                "scale": 0.3,
                "mass": 1.0,
            }
            for i in range(n)
        ]
    else:
        n = 20_000
        doc.setdefault("box", []).extend(
            {"center": [i % 100, 0.5, i // 100], "size": [0.5, 0.5, 0.5]} for i in range(n)
        )
        return f"{n} extra boxes"
    doc.setdefault("object", []).extend(objs)
    return f"{n} extra {kind}"


_HOSTILE_ASSETS = (
    "../levels/01_first_steps.toml",
    "/etc/passwd",
    "meshes/../../pyproject.toml",
    "meshes/crate.obj/..",
    "C:/x.obj",
    "meshes/crate.obj\x00.png",
    "meshes/" + "a" * 5000 + ".obj",
    "~/x.obj",
    "meshes",
    "../../../../../../../../dev/zero",
    "meshes/make_assets.py",
    "file:///dev/zero",
    "\\\\host\\x.obj",
)


def _build_level(rng, case: Case) -> None:
    m = case.mutation
    if m == "long_run" or (m == "targeted_extreme" and rng.random() < 0.6):
        src = LEVELS[-1]  # the level with rigid bodies, where physics values matter most
    else:
        src = pick(rng, LEVELS)
    raw = src.read_bytes()
    doc = tomllib.loads(raw.decode("utf-8"))
    ticks, extra = 120, {}
    if m in _BYTE_MUTATIONS:
        data, detail = _BYTE_MUTATIONS[m](rng, raw)
    else:
        if m == "targeted_extreme":
            path = pick(rng, _level_targets(doc))
            value = pick(rng, _TARGET_VALUES)
            doc = copy.deepcopy(doc)
            _set_creating(doc, path, value)
            detail = f"{M.where(path)} = {M.describe(value)}"
        elif m == "heavy_level":
            doc = copy.deepcopy(doc)
            detail = _heavy_level(rng, doc)
        elif m == "asset_path":
            doc = copy.deepcopy(doc)
            bad = pick(rng, _HOSTILE_ASSETS)
            if rng.random() < 0.5 and doc.get("object"):
                obj = doc["object"][0]
                obj.pop("shape", None)
                obj.pop("params", None)
                obj["asset"] = bad
                detail = f"object[0].asset = {M.describe(bad)}"
            else:
                doc.setdefault("mesh", []).append({"asset": bad, "position": [0.0, 0.0, 0.0]})
                detail = f"[[mesh]] asset = {M.describe(bad)}"
            case.must_refuse = True
        elif m == "long_run":
            # Bodies pushed along w must stay in the level's w range (and may sleep), not roll away for good.
            doc = copy.deepcopy(doc)
            speeds = []
            for obj in doc.get("object", []):
                if obj.get("body", "none") != "none":
                    v = obj.setdefault("velocity", [0.0, 0.0, 0.0, 0.0])
                    v[3] = float(np.round(rng.uniform(-2, 2), 2))
                    speeds.append(v[3])
            ticks, extra = 480, {"bodies_in_w": True, "timeout": 30.0}  # 8 s of play; about 3 s to run
            detail = f"bodies given w velocities {speeds}, then {ticks} ticks"
        else:
            doc, detail = _mutate_tree(rng, m, doc)
        data = toml_dumps(doc).encode("utf-8", "surrogatepass")
    case.detail = f"{src.name}: {detail}"
    case.files = {"level.toml": data}
    case.names = ("level.toml",)
    seed = int(rng.integers(0, 2**31))
    case.steps = [
        {
            "op": "cli",
            "argv": ["check-level", "{in}/level.toml"],
            "allowed": [0, 2],
            "warn_or_refuse": m == "heavy_level",
        },
        {
            "op": "write_replay",
            "path": "{in}/actions.json",
            "runs": _short_replay_rows(rng, ticks),
            "seed": seed,
            "needs": 0,
        },
        {
            "op": "cli",
            "argv": ["replay", "{in}/level.toml", "{in}/actions.json", "--no-check"],
            "allowed": [0],
            "game_checks": True,
            "needs": 0,
            **extra,
            "why": f"check-level accepted the level, so a headless run of {ticks} ticks of random actions must work",
        },
    ]


# ------------------------------------------------------------------- replays
_RUN_LENGTHS = (0, -1, 10**9, 10**7, 10**30, 10**5000, 1.5, True, "5", None, 2**63)


def _build_replay(rng, case: Case) -> None:
    src = pick(rng, REPLAYS)
    raw = src.read_bytes()
    doc = json_loads(raw)
    m = case.mutation
    refuse = False
    if m in _BYTE_MUTATIONS:
        data, detail = _BYTE_MUTATIONS[m](rng, raw)
    else:
        doc = copy.deepcopy(doc)
        if m == "run_length":
            i = int(rng.integers(len(doc["actions"])))
            value = pick(rng, _RUN_LENGTHS)
            doc["actions"][i][0] = value
            detail = f"actions[{i}] run length = {M.describe(value)}"
            refuse = not (isinstance(value, int) and not isinstance(value, bool) and 0 < value <= 10**7)
        elif m == "nan_row":
            i, j = int(rng.integers(len(doc["actions"]))), int(rng.integers(5))
            value = pick(rng, (math.nan, math.inf, -math.inf, 1e308))
            doc["actions"][i][1][j] = value
            detail = f"actions[{i}] row[{j}] ({'forward right yaw pitch w'.split()[j]}) = {value!r}"
            refuse = j in (0, 1, 4) or not math.isfinite(value)
        elif m == "header":
            key = pick(
                rng,
                (
                    "format",
                    "version",
                    "level",
                    "level_hash",
                    "seed",
                    "tick_rate",
                    "hash_every",
                    "final",
                    "hashes",
                    "actions",
                ),
            )
            value = pick(
                rng,
                (
                    *M.EXTREMES,
                    *M.TYPE_SWAPS,
                    Raw("[" * 10_000 + "]" * 10_000, "10000 nested lists"),
                    {"ticks": 10**30, "hash": 5, "outcome": ["x"]},
                ),
            )
            doc[key] = copy.deepcopy(value)
            detail = f"header {key} = {M.describe(value)}"
        elif m == "hash_keys":
            value = pick(
                rng,
                (
                    {"1e9": "x"},
                    {"-5": "00"},
                    {"NaN": "00"},
                    {"9" * 5000: "00"},
                    {str(i): "0" * 16 for i in range(0, 6_000_000, 60)},
                ),
            )
            doc["hashes"] = value
            detail = f"hashes = {M.describe(value) if len(value) < 5 else f'{len(value)} entries'}"
        else:
            doc, detail = _mutate_tree(rng, m, doc, json_style=True, flood=(10_000, 100_000, 1_000_000))
        data = json_dumps(doc).encode("utf-8", "surrogatepass")
    level = "01_first_steps.toml" if src.stem.startswith("01") else f"{src.stem}.toml"
    case.detail = f"{src.name}: {detail}"
    case.must_refuse = refuse
    case.files = {"replay.json": data}
    case.names = ("replay.json",)
    case.steps = [
        {
            "op": "cli",
            "argv": ["replay", f"{{repo}}/levels/{level}", "{in}/replay.json"],
            "allowed": [0, 2, 3],
            "game_checks": True,
        },
        {
            "op": "replay_roundtrip",
            "path": "{in}/replay.json",
            "out": "{out}/saved.json",
            "needs": 0,
            "needs_exit": [0, 3],
        },
    ]


def json_loads(raw: bytes):
    import json

    return json.loads(raw.decode("utf-8"))


# ------------------------------------------------------------------ settings
def _settings_doc(rng) -> dict:
    from dataclasses import fields

    from across_dimensions.app.settings import Settings

    doc = {f.name: f.default for f in fields(Settings) if f.name != "bindings"}
    doc["preset"] = pick(rng, ("qwerty", "azerty"))
    doc["bindings"] = {"jump": ["SPACE", "MOUSE_RIGHT"], "w_ana": ["E"], "fire": ["MOUSE_LEFT"]}
    return doc


def _build_settings(rng, case: Case) -> None:
    doc = _settings_doc(rng)
    raw = toml_dumps(doc).encode()
    m = case.mutation
    if m in _BYTE_MUTATIONS:
        data, detail = _BYTE_MUTATIONS[m](rng, raw)
    else:
        if m == "bad_binding":
            doc = copy.deepcopy(doc)
            action = pick(rng, ("jump", "w_ana", "nonexistent", "", "move_forward"))
            value = pick(
                rng,
                (["NOT_A_KEY"], "SPACE", [["SPACE"]], [1], ["SPACE"] * 100_000, [""], {"k": "v"}, ["\x00"], ["space"]),
            )
            doc["bindings"][action] = value
            detail = f"bindings.{action} = {M.describe(value)}"
        else:
            doc, detail = _mutate_tree(rng, m, doc)
        data = toml_dumps(doc).encode("utf-8", "surrogatepass")
    case.detail = detail
    case.files = {"settings.toml": data}
    case.names = ("settings.toml",)
    case.steps = [{"op": "settings", "path": "{in}/settings.toml", "out": "{out}/settings.toml"}]


# ----------------------------------------------------------------------- npz
def _slice_step(rng, src: str, names=None) -> dict:
    suffix = pick(rng, (".obj", ".obj", ".ply", ".glb"))
    argv = ["slice", src, "-o", f"{{out}}/sliced{suffix}"]
    if rng.random() < 0.4:
        argv += ["--mode", "frustum"]
    if rng.random() < 0.5:
        argv += ["--rotate", f"xw={int(rng.integers(0, 90))}"]
    return {"op": "cli", "argv": argv, "allowed": [0, 2], "check_obj": f"{{out}}/sliced{suffix}"}


def _build_npz(rng, case: Case) -> None:
    shape, arrays = npzgen.base_arrays(rng)
    m = case.mutation
    refuse = True
    if m in npzgen.ARRAY_MUTATIONS:
        arrays, detail, refuse = npzgen.ARRAY_MUTATIONS[m](rng, arrays)
        data = npzgen.savez(arrays, compressed=bool(rng.random() < 0.5))
    elif m in npzgen.FILE_MUTATIONS:
        data, detail = npzgen.FILE_MUTATIONS[m](rng, arrays)
    else:
        data, detail = _BYTE_MUTATIONS[m](rng, npzgen.savez(arrays))
        refuse = False  # a flipped bit may land in padding or a colour
    case.detail = f"{shape}: {detail}"
    case.must_refuse = refuse
    case.files = {"mesh.npz": data}
    case.names = ("mesh.npz",)
    case.steps = [_slice_step(rng, "{in}/mesh.npz")]


# ----------------------------------------------------------------------- obj
_OBJ_VALUES = (math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, 1e30, 0.0)


@functools.cache
def _crate_exports() -> tuple[dict, bytes]:
    import trimesh

    mesh = trimesh.load(SMALL_MESHES[0], force="mesh")
    return mesh.export(file_type="gltf"), mesh.export(file_type="stl")


_HOSTILE_URIS = (
    ("/dev/zero", True),
    ("file:///dev/zero", True),
    ("../../../../../../../../etc/passwd", True),
    ("/etc/passwd", True),
    ("fifo.bin", True),
    ("zero.bin", True),
    ("missing.bin", True),
    ("gltf_buffer_1.bin", False),
    ("data:application/octet-stream;base64,AAAA", False),
    ("https://example.invalid/x.bin", True),
    ("", True),
)


def _build_gltf(rng, case: Case) -> None:
    files, _ = _crate_exports()
    doc = json_loads(files["model.gltf"])
    i = int(rng.integers(len(doc["buffers"])))
    uri, refuse = pick(rng, _HOSTILE_URIS[:6] if rng.random() < 0.6 else _HOSTILE_URIS)
    doc["buffers"][i]["uri"] = uri
    if rng.random() < 0.3:
        doc["buffers"][i]["byteLength"] = pick(rng, (2**40, -1, 0, 1e308))
    case.files = {"mesh.gltf": json_dumps(doc).encode(), **{k: v for k, v in files.items() if k.endswith(".bin")}}
    if uri == "fifo.bin":
        case.files["fifo.bin"] = "special:fifo"
    elif uri == "zero.bin":
        case.files["zero.bin"] = "special:dev_zero"
    case.detail = f"crate as glTF, buffers[{i}].uri = {uri!r}, byteLength {doc['buffers'][i]['byteLength']}"
    case.must_refuse = refuse
    case.names = ("mesh.gltf", uri.rsplit("/", 1)[-1] or "mesh.gltf")
    case.steps = [
        {
            "op": "cli",
            "argv": ["lift", "{in}/mesh.gltf", "--depth", "1", "-o", "{out}/lifted.npz"],
            "allowed": [0, 2],
            **({} if refuse else {"timeout": BAKE_TIMEOUT}),
        }
    ]  # refusals need no bake


def _build_stl(rng, case: Case) -> None:
    import struct

    _, stl = _crate_exports()
    kind = pick(rng, ("count", "truncate", "bit_flips", "random_bytes", "ascii_garbage"))
    refuse = False
    if kind == "count":
        count = int(pick(rng, (2**32 - 1, 10**8, 0, 45)))
        data = stl[:80] + struct.pack("<I", count) + stl[84:]
        detail = f"binary STL header claims {count} triangles (file has 44)"
        refuse = count != 44
    elif kind == "ascii_garbage":
        data = b"solid x\n facet normal nan inf 0\n outer loop\n vertex 1e999 0 0\n" * 3 + b"endsolid\n"
        detail = "ASCII STL with NaN normals, 1e999 vertices and no endloop"
        refuse = True
    else:
        fn = {"truncate": M.truncate, "bit_flips": M.bit_flips, "random_bytes": M.random_bytes}[kind]
        data, detail = fn(rng, stl)
    case.detail = f"crate as STL: {detail}"
    case.must_refuse = refuse
    case.files = {"mesh.stl": data}
    case.names = ("mesh.stl",)
    case.steps = [
        {
            "op": "cli",
            "argv": ["lift", "{in}/mesh.stl", "--depth", "1", "-o", "{out}/lifted.npz"],
            "allowed": [0, 2],
            **({} if refuse else {"timeout": BAKE_TIMEOUT}),
        }
    ]


def _build_obj(rng, case: Case) -> None:
    if case.mutation == "gltf_uri":
        return _build_gltf(rng, case)
    if case.mutation == "stl":
        return _build_stl(rng, case)
    src = SMALL_MESHES[0] if rng.random() < 0.8 else SMALL_MESHES[1]
    raw = src.read_bytes()
    lines = raw.decode().split("\n")
    vs = [i for i, ln in enumerate(lines) if ln.startswith("v ")]
    fs = [i for i, ln in enumerate(lines) if ln.startswith("f ")]
    m = case.mutation
    refuse = False
    if m == "vertex_extreme":
        i = pick(rng, vs)
        parts = lines[i].split()
        k = int(rng.integers(1, 4))
        value = pick(rng, _OBJ_VALUES)
        parts[k] = repr(value)
        lines[i] = " ".join(parts)
        detail = f"line {i + 1}: {lines[i]}"
        refuse = not math.isfinite(value) or abs(value) > 1e300
    elif m == "bad_face":
        i = pick(rng, fs)
        parts = lines[i].split()
        k = int(rng.integers(1, len(parts)))
        value = pick(rng, ("0", "-1", "-100000", str(len(vs) + 1), "999999999999", str(10**30), "1.5", "x", "1//"))
        parts[k] = value
        lines[i] = " ".join(parts)
        detail = f"line {i + 1}: {lines[i]}"
        refuse = value in ("-100000", str(len(vs) + 1), "999999999999", str(10**30), "x")
    elif m == "flood":
        i = pick(rng, vs + fs)
        n = int(pick(rng, (10_000, 100_000)))
        lines[i + 1 : i + 1] = [lines[i]] * n
        detail = f"line {i + 1} repeated {n} times: {lines[i]}"
    else:
        fn = pick(rng, (M.truncate, M.random_bytes, M.bit_flips, M.bad_encoding))
        data, detail = fn(rng, raw)
        lines = None
    data = "\n".join(lines).encode() if lines is not None else data
    depth = pick(rng, ("1", "0.5", "2.5"))
    profile = pick(rng, ("prism", "round", "taper"))
    case.detail = f"{src.name}: {detail}"
    case.must_refuse = refuse
    case.files = {"mesh.obj": data}
    case.names = ("mesh.obj",)
    case.steps = [
        {
            "op": "cli",
            "argv": ["lift", "{in}/mesh.obj", "--depth", depth, "--profile", profile, "-o", "{out}/lifted.npz"],
            "allowed": [0, 2],
            # a flood of 10**5 lines must be refused quickly, not baked
            **({} if m == "flood" else {"timeout": BAKE_TIMEOUT}),
        }
    ]


# ------------------------------------------------------------------- special
def _build_special(rng, case: Case) -> None:
    target = case.mutation
    # Half the time one of the two that hang or exhaust memory in a naive reader.
    special = pick(rng, ("fifo", "dev_zero")) if rng.random() < 0.5 else pick(rng, SPECIAL_KINDS)
    must = special not in ("dangling_symlink", "empty") if target == "settings" else True
    level = "{repo}/levels/01_first_steps.toml"
    replay = "{repo}/levels/replays/01_first_steps.json"
    name, step = {
        "level": ("level.toml", {"op": "cli", "argv": ["check-level", "{in}/level.toml"], "allowed": [0, 2]}),
        "replay": ("replay.json", {"op": "cli", "argv": ["replay", level, "{in}/replay.json"], "allowed": [0, 2, 3]}),
        "replay_level": (
            "level.toml",
            {"op": "cli", "argv": ["replay", "{in}/level.toml", replay], "allowed": [0, 2, 3]},
        ),
        "npz": ("mesh.npz", _slice_step(rng, "{in}/mesh.npz")),
        "obj": (
            "mesh.obj",
            {"op": "cli", "argv": ["lift", "{in}/mesh.obj", "--depth", "1", "-o", "{out}/l.npz"], "allowed": [0, 2]},
        ),
        "settings": ("settings.toml", {"op": "settings", "path": "{in}/settings.toml", "out": "{out}/settings.toml"}),
    }[target]
    case.detail = f"{name} is {special.replace('_', ' ')}"
    case.must_refuse = must
    case.files = {name: f"special:{special}"}
    case.names = (name,)
    case.steps = [step]


# ---------------------------------------------------------------------- args
_BAD_FLOATS = (
    "nan",
    "inf",
    "-inf",
    "1e308",
    "1e309",
    "-1e308",
    "5e-324",
    "0",
    "-0",
    "",
    "abc",
    "1e5000",
    "NaN",
    "30deg",
    " 30",
    "0x1p3",
)
_NON_FINITE = ("nan", "inf", "-inf", "1e309", "NaN", "1e5000")


def _build_args(rng, case: Case) -> None:
    m = case.mutation
    refuse = False
    out = "{out}/out.obj"
    if m == "slice":
        option = pick(rng, ("--rotate", "--translate", "--fov", "--distance"))
        value = pick(rng, _BAD_FLOATS + ("179.9", "180", "-1", "1e-300", "360"))
        if option == "--rotate":
            plane = pick(rng, ("xw", "yz", "XW", "wx", "xq", ""))
            arg = f"{plane}={value}"
        elif option == "--translate":
            axis = pick(rng, ("w", "x", "W", "q", ""))
            arg = f"{axis}={value}"
        else:
            arg = value
        argv = ["slice", pick(rng, ("tesseract", "24-cell", "hypersphere")), option, arg, "-o", out]
        if option in ("--fov", "--distance") or rng.random() < 0.3:
            argv += ["--mode", "frustum"]
        refuse = value in _NON_FINITE or (option == "--fov" and value in ("0", "-0", "180", "-1", "360", "-1e308"))
        names = (option, option.lstrip("-"))
        detail = f"{option} {arg!r}"
    elif m == "shape":
        shape, params = pick(
            rng,
            (
                ("hypersphere", ("radius", "subdivisions")),
                ("duoprism", ("p", "q", "r1", "r2")),
                ("cubinder", ("segments", "radius", "height")),
                ("tesseract", ("size",)),
                ("spherinder", ("radius", "height", "subdivisions")),
                ("duocylinder", ("segments", "radius")),
            ),
        )
        param = pick(rng, params + ("bogus",))
        value = pick(
            rng,
            (
                "nan",
                "inf",
                "-1",
                "0",
                "1e308",
                "5e-324",
                "abc",
                "",
                "50",
                "100000",
                str(10**30),
                str(10**5000),
                "3",
                "2.5",
            ),
        )
        argv = ["shape", shape, "--param", f"{param}={value}", "-o", "{out}/shape.npz"]
        refuse = (
            param == "bogus"
            or value in ("nan", "inf", "-1", "abc", "", str(10**30), str(10**5000))
            or (param in ("subdivisions", "p", "q", "segments") and value in ("50", "100000", "1e308"))
        )
        names = ("--param", param)
        detail = f"shape {shape} --param {param}={M.describe(value)}"
    elif m == "lift":
        depth = pick(rng, ("0", "-1", "nan", "inf", "1e308", "5e-324", "1e-300", "1e30", "abc"))
        argv = ["lift", str(SMALL_MESHES[0]), "--depth", depth, "-o", "{out}/lifted.npz"]
        refuse = depth in ("0", "-1", "nan", "inf", "abc")
        names = ("--depth", "depth")
        detail = f"lift --depth {depth}"
    elif m == "replay_options":
        option, value = pick(
            rng,
            (
                ("--every", "0"),
                ("--every", "-5"),
                ("--every", str(10**30)),
                ("--size", "0x0"),
                ("--size", "99999x99999"),
                ("--size", "nanxnan"),
                ("--size", "640"),
                ("--size", "-640x-360"),
            ),
        )
        argv = [
            "replay",
            "{repo}/levels/01_first_steps.toml",
            "{repo}/levels/replays/01_first_steps.json",
            "--screenshots",
            "{out}/shots",
            option,
            value,
        ]
        if option == "--every":
            argv += ["--size", "1x1"]  # refused before anything is drawn, whatever --every says
        refuse = True
        names = (option, option.lstrip("-"), "--size")  # with --every, the 1x1 --size may be named first
        detail = f"replay {option} {value}"
    elif m == "empty_section":
        suffix = pick(rng, (".obj", ".ply", ".glb"))
        out = f"{{out}}/empty{suffix}"
        argv = ["slice", pick(rng, ("tesseract", "5-cell", "24-cell")), "--translate", "w=5", "-o", out]
        if rng.random() < 0.5:
            argv += ["--mode", "frustum", "--distance", "0.01"]
        names = ("-o", "empty" + suffix)
        detail = f"a hyperplane that misses the shape, written as {suffix}"
    elif m == "tmp_squatter":
        kind = pick(rng, ("folder", "symlink", "fifo"))
        command = pick(rng, ("slice", "shape"))
        target = "{out}/out.obj" if command == "slice" else "{out}/out.npz"
        name = target.rsplit("/", 1)[1] + ".tmp"
        case.files = {
            "victim.txt": b"precious\n",
            f"out/{name}": {"folder": "special:folder", "symlink": "special:victim_link", "fifo": "special:fifo"}[kind],
        }
        argv = ["slice", "tesseract", "-o", target] if command == "slice" else ["shape", "5-cell", "-o", target]
        names = ("-o",)
        detail = f"{command} -o {target.rsplit('/', 1)[1]} while {name} already exists as a {kind}"
        case.must_refuse = False
        case.detail, case.names = detail, names
        case.steps = [
            {
                "op": "cli",
                "argv": argv,
                "allowed": [0],
                "must_create": target,
                "unchanged": {"{in}/victim.txt": "precious\n"},
                "why": "a stale or hostile temporary file must not stop or redirect the write",
            }
        ]
        return
    else:  # output_path
        kind = pick(rng, ("missing_folder", "is_folder", "bad_suffix", "file_as_folder", "empty"))
        target = {
            "missing_folder": "{out}/no/such/dir/out",
            "is_folder": "{out}",
            "bad_suffix": "{out}/out.txt",
            "file_as_folder": "{in}/file/out",
            "empty": "",
        }[kind]
        command = pick(rng, ("slice", "shape", "lift"))
        suffix = {"slice": ".obj", "shape": ".npz", "lift": ".npz"}[command]
        if kind in ("missing_folder", "file_as_folder"):
            target += suffix
        argv = {
            "slice": ["slice", "tesseract", "-o", target],
            "shape": ["shape", "5-cell", "-o", target],
            "lift": ["lift", str(SMALL_MESHES[0]), "--depth", "1", "-o", target],
        }[command]
        case.files = {"file": b"a plain file\n"}
        refuse = True
        names = (target.replace("{out}", "").replace("{in}", "").lstrip("/") or "-o", "-o", "--output", "output")
        names = tuple(n for n in names if n)
        detail = f"{command} -o {target!r} ({kind})"
    case.detail = detail
    case.must_refuse = refuse
    case.names = names
    case.steps = [
        {"op": "cli", "argv": argv, "allowed": [0, 2], "check_obj": out if argv[0] == "slice" and out in argv else None}
    ]


_BUILDERS = {
    "level": _build_level,
    "replay": _build_replay,
    "settings": _build_settings,
    "npz": _build_npz,
    "obj": _build_obj,
    "special": _build_special,
    "args": _build_args,
}


# --------------------------------------------------------------------- files
def resolve(value, folder: Path):
    """Replace the ``{in}``, ``{out}`` and ``{repo}`` placeholders in strings inside ``value``."""
    if isinstance(value, str):
        return (
            value.replace("{in}", str(folder / "in")).replace("{out}", str(folder / "out")).replace("{repo}", str(REPO))
        )
    if isinstance(value, list):
        return [resolve(v, folder) for v in value]
    if isinstance(value, dict):
        return {resolve(k, folder): resolve(v, folder) for k, v in value.items()}
    return value


def _make_special(path: Path, kind: str) -> None:
    import os

    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "dev_zero":
        os.symlink("/dev/zero", path)
    elif kind == "dev_null":
        os.symlink("/dev/null", path)
    elif kind == "folder":
        path.mkdir()
    elif kind == "symlink_to_folder":
        os.symlink(path.parent, path)
    elif kind == "dangling_symlink":
        os.symlink(path.parent / "does-not-exist", path)
    elif kind == "symlink_loop":
        os.symlink(path.name + ".loop", path)
        os.symlink(path.name, path.with_name(path.name + ".loop"))
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "victim_link":  # a temporary name squatted by a link to another file
        os.symlink(path.parent.parent / "in" / "victim.txt", path)
    else:
        raise ValueError(kind)


def write_case(case: Case, folder: Path) -> list[dict]:
    """Write the case's inputs under ``folder/in`` (``folder/out`` is made empty) and return its resolved steps."""
    (folder / "in").mkdir(parents=True)
    (folder / "out").mkdir()
    for name, content in case.files.items():
        path = folder / name if name.startswith("out/") else folder / "in" / name
        if isinstance(content, str) and content.startswith("special:"):
            _make_special(path, content.split(":", 1)[1])
        else:
            path.write_bytes(content)
    return resolve(case.steps, folder)


def command_line(step: dict) -> str:
    """The shell command a developer types to rerun a CLI step."""
    import shlex

    def short(a: str) -> str:
        return a if len(a) <= 200 else f"{a[:60]}...({len(a)} chars)"

    with no_int_digit_limit():
        return "across-dimensions " + " ".join(shlex.quote(short(str(a))) for a in step["argv"])
