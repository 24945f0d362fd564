"""Level files: TOML data describing a 3D world with 4D content along w.

The format is documented with a complete example in ``levels/README.md``.
:func:`load_level` checks the whole file and raises :class:`LevelError` listing
every problem at once, each naming the file, the entry, the field and what was
expected. Level files are data only: nothing in them is executed, and asset
paths are confined to the assets folder.
"""

from __future__ import annotations

import hashlib
import inspect
import math
import string
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.transform import PLANES
from . import resources
from .gameplay import CrystalSpec, EnergySpec, RadarSpec, read_crystals, read_energy, read_radar

PROFILES = ("prism", "round", "taper")
OBJECT_BODIES = ("none", "hypersphere", "hypercube")
DEFAULT_COLOR = (0.7, 0.7, 0.72, 1.0)
MESH_SUFFIXES = (".obj", ".glb", ".gltf", ".stl")  # what world/bake.py reads
FORMATS = (1, 2)
FORMAT2_TABLES = ("crystal", "energy", "radar")  # what format 2 adds
_INT64 = (-2**63, 2**63 - 1)  # TOML integers are 64-bit; tomllib accepts any size


def _is_number(x) -> bool:
    """A finite int or float, not a bool."""
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _big_ints(value, where=""):
    """Dotted paths of integers outside TOML's 64-bit range."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _big_ints(v, f"{where}.{k}" if where else k)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _big_ints(v, f"{where}[{i}]")
    elif isinstance(value, int) and not isinstance(value, bool) and not _INT64[0] <= value <= _INT64[1]:
        yield where


# Shape parameters: how each is checked (the builders in core/shapes.py take these names).
_PARAM_RULES = {
    "radius": ("positive", None), "size": ("positive", None), "height": ("positive", None),
    "r1": ("positive", None), "r2": ("positive", None),
    "p": ("whole", (3, 128)), "q": ("whole", (3, 128)), "segments": ("whole", (3, 128)),
    "subdivisions": ("whole", (0, 3)),
}


def _param_problem(name, value) -> str | None:
    if name == "color":
        return "set the colour with the object's 'color' field, not in 'params'"
    kind, rng = _PARAM_RULES.get(name, (None, None))
    if kind == "positive" and not (_is_number(value) and value > 0):
        return f"'{name}' must be a positive number, got {value!r}"
    if kind == "whole" and not (isinstance(value, int) and not isinstance(value, bool) and rng[0] <= value <= rng[1]):
        return f"'{name}' must be a whole number from {rng[0]} to {rng[1]}, got {value!r}"
    return None


def _hint_problem(hint: str) -> str | None:
    """Why the window cannot show ``hint`` ({action} placeholders, {{ }} for braces)."""
    try:
        parts = list(string.Formatter().parse(hint))
    except ValueError as e:
        return f"{e} (write {{{{ and }}}} for a brace)"
    for _, name, spec, conv in parts:
        if name is not None and (not name.isidentifier() or spec or conv):
            return f"'{{{name}{'!' + conv if conv else ''}{':' + spec if spec else ''}}}' is not an {{action}} placeholder"
    return None


class LevelError(ValueError):
    """Every problem found in one level file, one per line."""

    def __init__(self, path, problems: list[str]):
        self.path = Path(path)
        self.problems = problems
        super().__init__("\n".join(problems))


@dataclass
class BoxSpec:
    """An axis-aligned 3D box: ``center (3,)``, ``size (3,)``, ``color (4,)``."""

    center: np.ndarray
    size: np.ndarray
    color: tuple


@dataclass
class MeshSpec:
    """A 3D asset placed in the world."""

    asset: Path
    position: np.ndarray
    scale: np.ndarray
    yaw_deg: float
    color: tuple


@dataclass
class WorldSpec:
    """A 3D world extended along w: present around ``w`` over ``depth``."""

    name: str
    w: float
    depth: float
    profile: str
    color: tuple
    boxes: list[BoxSpec] = field(default_factory=list)
    meshes: list[MeshSpec] = field(default_factory=list)


@dataclass
class ObjectSpec:
    """A 4D object: a named shape or a lifted 3D asset, with a 4D pose."""

    name: str
    shape: str | None
    params: dict
    asset: Path | None
    depth: float
    position: np.ndarray
    rotation_deg: dict
    scale: np.ndarray
    color: tuple
    spin_deg: dict
    solid: bool
    body: str
    mass: float
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(4))


@dataclass
class GoalSpec:
    """The exit: an axis-aligned box, optionally only over a w interval."""

    center: np.ndarray
    size: np.ndarray
    w_range: tuple[float, float] | None


@dataclass
class Level:
    """A parsed, checked level."""

    path: Path
    name: str
    description: str
    w_range: tuple[float, float]
    spawn: np.ndarray
    spawn_yaw_deg: float
    goal: GoalSpec
    gravity: np.ndarray
    inverse_cube_g: float
    boxes: list[BoxSpec]
    meshes: list[MeshSpec]
    worlds: list[WorldSpec]
    objects: list[ObjectSpec]
    source_hash: str
    hints: list[str] = field(default_factory=list)
    crystals: list[CrystalSpec] = field(default_factory=list)
    energy: EnergySpec = field(default_factory=EnergySpec)
    radar: RadarSpec = field(default_factory=RadarSpec)


class _Reader:
    """Reads fields from TOML tables, collecting problems instead of raising."""

    def __init__(self, path: Path):
        self.path = path
        self.problems: list[str] = []

    def problem(self, where: str, msg: str) -> None:
        self.problems.append(f"{self.path}: {where}: {msg}")

    def table(self, data, key, where, required=False) -> dict:
        v = data.get(key)
        if v is None:
            if required:
                self.problem(where, f"missing table [{key}]")
            return {}
        if not isinstance(v, dict):
            self.problem(where, f"'{key}' must be a table, got {type(v).__name__}")
            return {}
        return v

    def array_of_tables(self, data, key, where) -> list[dict]:
        v = data.get(key, [])
        if not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
            self.problem(where, f"'{key}' must be an array of tables ([[{key}]]), got {type(v).__name__}")
            return []
        return v

    def unknown(self, data: dict, allowed, where) -> None:
        for k in data:
            if k not in allowed:
                self.problem(where, f"unknown field '{k}' (expected one of: {', '.join(sorted(allowed))})")

    def number(self, data, key, where, default=None, lo=-math.inf, hi=math.inf, lo_open=False):
        if key not in data:
            if default is None:
                self.problem(where, f"missing field '{key}' (a number)")
                return 0.0
            return float(default)
        v = data[key]
        if not _is_number(v):
            self.problem(where, f"field '{key}': expected a number, got {v!r}")
            return float(default or 0.0)
        if v < lo or v > hi or (lo_open and v == lo):
            rng = f"{'>' if lo_open else '>='} {lo}" if hi == math.inf else f"between {lo} and {hi}"
            self.problem(where, f"field '{key}': expected a number {rng}, got {v!r}")
            return float(default or lo)
        return float(v)

    def vector(self, data, key, where, n, default=None, positive=False, names="xyzw"):
        if key not in data:
            if default is None:
                self.problem(where, f"missing field '{key}' (a list of {n} numbers {list(names[:n])})")
                return np.zeros(n)
            return np.asarray(default, dtype=np.float64)
        v = data[key]
        ok = (isinstance(v, list) and len(v) == n
              and all(_is_number(x) for x in v))
        if ok and positive and any(x <= 0 for x in v):
            self.problem(where, f"field '{key}': expected {n} positive numbers, got {v!r}")
            return np.ones(n)
        if not ok:
            self.problem(where, f"field '{key}': expected a list of {n} numbers {list(names[:n])}, got {v!r}")
            return np.zeros(n) if not positive else np.ones(n)
        return np.asarray(v, dtype=np.float64)

    def scale(self, data, key, where, n):
        v = data.get(key, 1.0)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            if not _is_number(v) or v <= 0:
                self.problem(where, f"field '{key}': expected a positive number or {n} positive numbers, got {v!r}")
                return np.ones(n)
            return np.full(n, float(v))
        return self.vector(data, key, where, n, positive=True)

    def string(self, data, key, where, default=None, choices=None):
        if key not in data:
            if default is None:
                self.problem(where, f"missing field '{key}' (a string)")
                return ""
            return default
        v = data[key]
        if not isinstance(v, str):
            self.problem(where, f"field '{key}': expected a string, got {v!r}")
            return default or ""
        if choices and v not in choices:
            self.problem(where, f"field '{key}': expected one of {', '.join(choices)}, got {v!r}")
            return default or choices[0]
        return v

    def boolean(self, data, key, where, default):
        v = data.get(key, default)
        if not isinstance(v, bool):
            self.problem(where, f"field '{key}': expected true or false, got {v!r}")
            return default
        return v

    def color(self, data, where, default=DEFAULT_COLOR):
        if "color" not in data:
            return tuple(default)
        v = data["color"]
        if (isinstance(v, list) and len(v) in (3, 4)
                and all(isinstance(x, (int, float)) and not isinstance(x, bool) and 0 <= x <= 1 for x in v)):
            return tuple(float(x) for x in v) + ((1.0,) if len(v) == 3 else ())
        self.problem(where, f"field 'color': expected 3 or 4 numbers between 0 and 1 (RGB[A]), got {v!r}")
        return tuple(default)

    def angles(self, data, key, where) -> dict:
        v = data.get(key, {})
        if not isinstance(v, dict):
            self.problem(where, f"field '{key}': expected a table of plane = degrees with planes {', '.join(PLANES)}, got {v!r}")
            return {}
        out = {}
        for plane, deg in v.items():
            if plane not in PLANES:
                self.problem(where, f"field '{key}': unknown rotation plane '{plane}' (expected one of {', '.join(PLANES)})")
            elif not _is_number(deg):
                self.problem(where, f"field '{key}.{plane}': expected degrees as a number, got {deg!r}")
            else:
                out[plane] = float(deg)
        return out

    def asset(self, data, where, key="asset") -> Path | None:
        rel = self.string(data, key, where)
        if not rel:
            if isinstance(data.get(key), str):
                self.problem(where, f"field '{key}': expected a path inside the assets folder such as "
                                    f"\"meshes/crate.obj\", got an empty string")
            return None
        try:
            full = resources.resolve_asset(rel)
        except ValueError as e:
            self.problem(where, f"field '{key}': {e}")
            return None
        if full.suffix.lower() not in MESH_SUFFIXES:
            self.problem(where, f"field '{key}': expected a mesh file ({', '.join(MESH_SUFFIXES)}), got {rel!r}")
            return None
        return full


_BOX_FIELDS = {"center", "size", "color"}
_MESH_FIELDS = {"asset", "position", "scale", "yaw", "color"}


def _boxes(r: _Reader, data, where, color) -> list[BoxSpec]:
    out = []
    for i, b in enumerate(r.array_of_tables(data, "box", where), 1):
        w = f"{where} > box #{i}" if where != "top level" else f"[[box]] #{i}"
        r.unknown(b, _BOX_FIELDS, w)
        out.append(BoxSpec(r.vector(b, "center", w, 3), r.vector(b, "size", w, 3, positive=True), r.color(b, w, color)))
    return out


def _meshes(r: _Reader, data, where, color) -> list[MeshSpec]:
    out = []
    for i, m in enumerate(r.array_of_tables(data, "mesh", where), 1):
        w = f"{where} > mesh #{i}" if where != "top level" else f"[[mesh]] #{i}"
        r.unknown(m, _MESH_FIELDS, w)
        asset = r.asset(m, w)
        spec = MeshSpec(asset, r.vector(m, "position", w, 3, default=(0, 0, 0)), r.scale(m, "scale", w, 3),
                        r.number(m, "yaw", w, default=0.0), r.color(m, w, color))
        if asset is not None:
            out.append(spec)
    return out


def load_level(path) -> Level:
    """Read and check a level file.

    Raises
    ------
    LevelError
        Listing every problem, each naming the file, entry and field.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as e:
        raise LevelError(path, [f"{path}: cannot read the file ({e.strerror or e})"]) from None
    try:
        data = tomllib.loads(raw.decode("utf-8-sig"))  # -sig: skip a byte-order mark
    except UnicodeDecodeError:
        raise LevelError(path, [f"{path}: not a text file (expected UTF-8 TOML)"]) from None
    except (tomllib.TOMLDecodeError, ValueError) as e:  # ValueError: an integer over 4300 digits
        raise LevelError(path, [f"{path}: not valid TOML: {e}"]) from None
    big = list(_big_ints(data))
    if big:
        raise LevelError(path, [f"{path}: {b}: integer out of range (TOML integers are 64-bit; "
                                f"write a float like 1e30 for huge values)" for b in big])

    r = _Reader(path)
    r.unknown(data, {"level", "spawn", "goal", "box", "mesh", "world", "object", "physics", *FORMAT2_TABLES},
              "top level")
    meta = r.table(data, "level", "[level]", required=True)
    r.unknown(meta, {"name", "description", "w_range", "hints", "format"}, "[level]")
    name = r.string(meta, "name", "[level]", default=path.stem)
    description = r.string(meta, "description", "[level]", default="")
    fmt = r.number(meta, "format", "[level]", default=1)
    if fmt not in FORMATS:
        r.problem("[level]", f"field 'format': this game reads formats 1 and 2, the file says {fmt:g}")
    elif fmt == 1:
        for t in FORMAT2_TABLES:
            if t in data:
                r.problem("top level", f"'{t}' needs format 2 (set format = 2 in [level])")
    n = len(r.problems)
    w_range = r.vector(meta, "w_range", "[level]", 2, default=(-1.0, 1.0), names="ab")
    w_ok = len(r.problems) == n
    if w_ok and w_range[0] >= w_range[1]:
        r.problem("[level]", f"field 'w_range': expected [low, high] with low < high, got {w_range.tolist()}")
        w_ok = False
    hints = meta.get("hints", [])
    if not (isinstance(hints, list) and all(isinstance(h, str) for h in hints)):
        r.problem("[level]", "field 'hints': expected a list of strings")
        hints = []
    for i, h in enumerate(hints, 1):
        why = _hint_problem(h)
        if why:
            r.problem("[level]", f"field 'hints': hint #{i}: {why}")

    n = len(r.problems)
    spawn_t = r.table(data, "spawn", "[spawn]", required=True)
    spawn, spawn_yaw = np.zeros(4), 0.0
    if len(r.problems) == n:  # a missing [spawn] is one problem, not one per field
        r.unknown(spawn_t, {"position", "yaw"}, "[spawn]")
        n = len(r.problems)
        spawn = r.vector(spawn_t, "position", "[spawn]", 4)
        if len(r.problems) == n and w_ok and not w_range[0] <= spawn[3] <= w_range[1]:
            r.problem("[spawn]", f"field 'position': w = {spawn[3]:g} is outside the level's w_range {w_range.tolist()}")
        spawn_yaw = r.number(spawn_t, "yaw", "[spawn]", default=0.0)

    n = len(r.problems)
    goal_t = r.table(data, "goal", "[goal]", required=True)
    goal = GoalSpec(np.zeros(3), np.ones(3), None)
    if len(r.problems) == n:
        r.unknown(goal_t, {"center", "size", "w_range"}, "[goal]")
        goal_w = None
        if "w_range" in goal_t:
            n = len(r.problems)
            gw = r.vector(goal_t, "w_range", "[goal]", 2, names="ab")
            goal_w = (float(gw[0]), float(gw[1]))
            if len(r.problems) == n and gw[0] > gw[1]:
                r.problem("[goal]", f"field 'w_range': expected [low, high] with low <= high, got {gw.tolist()}")
            elif len(r.problems) == n and w_ok and (gw[1] < w_range[0] or gw[0] > w_range[1]):
                r.problem("[goal]", f"field 'w_range': {gw.tolist()} is outside the level's w_range "
                                    f"{w_range.tolist()}, so the goal can never be reached")
        goal = GoalSpec(r.vector(goal_t, "center", "[goal]", 3), r.vector(goal_t, "size", "[goal]", 3, positive=True),
                        goal_w)

    phys = r.table(data, "physics", "[physics]")
    r.unknown(phys, {"gravity", "inverse_cube_g"}, "[physics]")
    gravity = r.vector(phys, "gravity", "[physics]", 4, default=(0.0, -9.81, 0.0, 0.0))
    inverse_cube_g = r.number(phys, "inverse_cube_g", "[physics]", default=0.0, lo=0.0)

    boxes = _boxes(r, data, "top level", DEFAULT_COLOR)
    meshes = _meshes(r, data, "top level", DEFAULT_COLOR)

    worlds = []
    for i, wt in enumerate(r.array_of_tables(data, "world", "top level"), 1):
        where = f"[[world]] #{i}"
        r.unknown(wt, {"name", "w", "depth", "profile", "color", "box", "mesh"}, where)
        wname = r.string(wt, "name", where, default=f"world{i}")
        where = f"[[world]] #{i} '{wname}'"
        color = r.color(wt, where)
        world = WorldSpec(
            wname,
            r.number(wt, "w", where),
            r.number(wt, "depth", where, lo=0.0, lo_open=True),
            r.string(wt, "profile", where, default="round", choices=PROFILES),
            color,
            _boxes(r, wt, where, color),
            _meshes(r, wt, where, color),
        )
        if not wt.get("box") and not wt.get("mesh"):
            r.problem(where, "has no [[world.box]] or [[world.mesh]] entries")
        worlds.append(world)

    objects = []
    from ..core.shapes import SHAPES  # the shape registry; imported here to keep level parsing light

    for i, ot in enumerate(r.array_of_tables(data, "object", "top level"), 1):
        where = f"[[object]] #{i}"
        r.unknown(ot, {"name", "shape", "params", "asset", "depth", "position", "rotation", "scale", "color",
                       "spin", "solid", "body", "mass", "velocity"}, where)
        oname = r.string(ot, "name", where, default=f"object{i}")
        where = f"[[object]] #{i} '{oname}'"
        shape = asset = None
        if ("shape" in ot) == ("asset" in ot):
            r.problem(where, "expected exactly one of 'shape' (a 4D shape name) or 'asset' (a 3D mesh to lift)")
        elif "shape" in ot:
            shape = r.string(ot, "shape", where, choices=tuple(SHAPES))
            if shape != ot["shape"]:  # reported; do not check params against a stand-in shape
                shape = None
        else:
            asset = r.asset(ot, where)
        params = ot.get("params", {})
        if not isinstance(params, dict):
            r.problem(where, f"field 'params': expected a table of shape parameters, got {params!r}")
            params = {}
        elif shape in SHAPES:
            try:
                inspect.signature(SHAPES[shape]).bind(**params)
            except TypeError as e:
                accepted = ", ".join(inspect.signature(SHAPES[shape]).parameters)
                r.problem(where, f"field 'params': {e} (shape '{shape}' accepts: {accepted})")
            else:
                for k, v in params.items():
                    why = _param_problem(k, v)
                    if why:
                        r.problem(where, f"field 'params': {why}")
        objects.append(ObjectSpec(
            oname, shape, params, asset,
            r.number(ot, "depth", where, default=1.0, lo=0.0, lo_open=True),
            r.vector(ot, "position", where, 4),
            r.angles(ot, "rotation", where),
            r.scale(ot, "scale", where, 4),
            r.color(ot, where, (0.95, 0.55, 0.2, 1.0)),
            r.angles(ot, "spin", where),
            r.boolean(ot, "solid", where, True),
            r.string(ot, "body", where, default="none", choices=OBJECT_BODIES),
            r.number(ot, "mass", where, default=1.0, lo=0.0, lo_open=True),
            r.vector(ot, "velocity", where, 4, default=(0.0, 0.0, 0.0, 0.0)),
        ))

    energy = read_energy(r, data)
    radar = read_radar(r, data)
    crystals = read_crystals(r, data, tuple(w_range) if w_ok else None)

    if r.problems:
        raise LevelError(path, r.problems)
    return Level(
        path=path, name=name, description=description, w_range=(float(w_range[0]), float(w_range[1])),
        spawn=spawn, spawn_yaw_deg=spawn_yaw, goal=goal, gravity=gravity, inverse_cube_g=inverse_cube_g,
        boxes=boxes, meshes=meshes, worlds=worlds, objects=objects,
        source_hash=hashlib.sha256(raw).hexdigest(), hints=list(hints),
        crystals=crystals, energy=energy, radar=radar,
    )
