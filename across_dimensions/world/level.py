"""Level files: TOML data describing a 3D world with 4D content along w.

The format is documented with a complete example in ``levels/README.md``.
:func:`load_level` checks the whole file and raises :class:`LevelError` listing
every problem at once, each naming the file, the entry, the field and what was
expected. Level files are data only: nothing in them is executed, and asset
paths are confined to the assets folder.

The schema is declared once, as one model per TOML table (:data:`MODELS`): a
table maps each field name to a :class:`Field` saying what kind of value it
holds, its default and its accepted range (the ranges and the limits on how
much a level may ask for live in :mod:`.limits`). :class:`_Reader` reads any
table against its model; the per-table functions below only add what crosses
fields (a spawn inside the w range, exactly one of shape or asset, ...).
Adding a field is one line in a model; adding a table is a model and a small
function that builds its spec.
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

from ..core import fileio
from ..core.errors import InputError
from ..core.shapes import SHAPE_PARAM_RULES
from ..core.transform import PLANES
from . import beacons, design, gameplay, limits, resources
from .fields import REQUIRED, Field
from .limits import (
    ANGLE,
    COLOR,
    COORD,
    GRAVITY_MAX,
    INVERSE_CUBE_G,
    MASS,
    MAX_COUNTS,
    MAX_NAME_CHARS,
    MAX_TEXT_CHARS,
    ROLLING_RESISTANCE,
    SCALE,
    SIZE,
    SPEED,
    SPIN,
    Range,
)
from .resources import FLAT_FORMAT

PROFILES = ("prism", "round", "taper")
OBJECT_BODIES = ("none", "hypersphere", "hypercube")
DEFAULT_COLOR = (0.7, 0.7, 0.72, 1.0)
OBJECT_COLOR = (0.95, 0.55, 0.2, 1.0)
MESH_SUFFIXES = (".obj", ".glb", ".gltf", ".stl")  # what world/bake.py reads
_INT64 = (-(2**63), 2**63 - 1)  # TOML integers are 64-bit; tomllib accepts any size


def _is_number(x) -> bool:
    """A finite int or float, not a bool."""
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _big_ints(value):
    """Dotted paths of integers outside TOML's 64-bit range (iterative: nesting depth is the file's)."""
    stack = [("", value)]
    while stack:
        where, v = stack.pop()
        if isinstance(v, dict):
            stack.extend((f"{where}.{k}" if where else k, x) for k, x in reversed(list(v.items())))
        elif isinstance(v, list):
            stack.extend((f"{where}[{i}]", x) for i, x in reversed(list(enumerate(v))))
        elif isinstance(v, int) and not isinstance(v, bool) and not _INT64[0] <= v <= _INT64[1]:
            yield where


# ====================================================================== models
BOX = {
    "center": Field("vector", 3, range=COORD),
    "size": Field("vector", 3, range=SIZE, sign="positive"),
    "color": Field("color", default=None),
}
MESH = {
    "asset": Field("asset"),
    "position": Field("vector", 3, default=(0.0, 0.0, 0.0), range=COORD),
    "scale": Field("scale", 3, default=1.0, range=SCALE, sign="positive"),
    "yaw": Field("number", default=0.0, range=ANGLE),
    "color": Field("color", default=None),
}
LEVEL = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "description": Field("text", default="", range=Range(0, MAX_TEXT_CHARS)),
    "format": Field("number", default=1),
    "w_range": Field("vector", 2, default=(-1.0, 1.0), range=COORD, names="ab"),
    "hints": Field("hints", default=()),
}
SPAWN = {
    "position": Field("vector", 4, range=COORD),
    "yaw": Field("number", default=0.0, range=ANGLE),
}
GOAL = {
    "center": Field("vector", 3, range=COORD),
    "size": Field("vector", 3, range=SIZE, sign="positive"),
    "w_range": Field("vector", 2, default=None, range=COORD, names="ab"),
}
PHYSICS = {
    "gravity": Field("vector", 4, default=(0.0, -9.81, 0.0, 0.0), length=GRAVITY_MAX),
    "inverse_cube_g": Field("number", default=0.0, range=INVERSE_CUBE_G, sign="nonnegative"),
    "rolling_resistance": Field("number", default=0.0, range=ROLLING_RESISTANCE, sign="nonnegative"),
}
WORLD = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "color": Field("color", default=None),
    "w": Field("number", range=COORD),
    "depth": Field("number", range=SIZE, sign="positive"),
    "profile": Field("string", default="round", choices=PROFILES),
    "box": Field("tables", default=()),
    "mesh": Field("tables", default=()),
}
OBJECT = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "shape": Field("string", default=None),
    "asset": Field("asset", default=None),
    "params": Field("params", default=None),
    "depth": Field("number", default=1.0, range=SIZE, sign="positive"),
    "position": Field("vector", 4, range=COORD),
    "rotation": Field("angles", default=None, range=ANGLE),
    "scale": Field("scale", 4, default=1.0, range=SCALE, sign="positive"),
    "color": Field("color", default=OBJECT_COLOR),
    "spin": Field("angles", default=None, range=SPIN),
    "solid": Field("bool", default=True),
    "body": Field("string", default="none", choices=OBJECT_BODIES),
    "mass": Field("number", default=1.0, range=MASS, sign="positive"),
    "velocity": Field("vector", 4, default=(0.0, 0.0, 0.0, 0.0), range=SPEED),
}
#: The format, one model per table (top-level keys; ``world.box`` and
#: ``world.mesh`` use ``box`` and ``mesh``).
MODELS = {
    "level": LEVEL,
    "spawn": SPAWN,
    "goal": GOAL,
    "physics": PHYSICS,
    "box": BOX,
    "mesh": MESH,
    "world": WORLD,
    "object": OBJECT,
    **gameplay.MODELS,
    "design": design.DESIGN_TABLE,
    "beacon": beacons.BEACON_TABLE,
}
FORMATS = (1, 2)  # format 2 adds the tables of gameplay.MODELS
#: Top-level keys written ``[[key]]`` (arrays of tables); the others are ``[key]`` tables.
ARRAY_TABLES = ("box", "mesh", "world", "object", *gameplay.ARRAY_TABLES, "beacon")

# Shape parameters: how each is checked (the builders in core/shapes.py take these names).
# One table of rules for the core's builders and for levels (core.shapes.SHAPE_PARAM_RULES);
# lengths are in metres here.
_PARAM_RULES = {
    name: (kind, Range(lo, hi, "m" if kind == "positive" else ""))
    for name, (kind, (lo, hi)) in SHAPE_PARAM_RULES.items()
}


def _param_problem(name, value) -> str | None:
    if name == "color":
        return "set the colour with the object's 'color' field, not in 'params'"
    kind, rng = _PARAM_RULES.get(name, (None, None))
    if kind == "positive":
        if not (_is_number(value) and value > 0):
            return f"'{name}' must be a positive number, got {value!r}"
        if value not in rng:
            return f"'{name}' must be a number {rng.text()}, got {value!r}"
    if kind == "whole" and not (isinstance(value, int) and not isinstance(value, bool) and value in rng):
        return f"'{name}' must be a whole number from {rng.lo:g} to {rng.hi:g}, got {value!r}"
    return None


def _hint_problem(hint: str) -> str | None:
    """Why the window cannot show ``hint`` ({action} placeholders, {{ }} for braces)."""
    if len(hint) > MAX_TEXT_CHARS:
        return f"expected at most {MAX_TEXT_CHARS} characters, got {len(hint)}"
    try:
        parts = list(string.Formatter().parse(hint))
    except ValueError as e:
        return f"{e} (write {{{{ and }}}} for a brace)"
    for _, name, spec, conv in parts:
        if name is not None and (not name.isidentifier() or spec or conv):
            shown = f"{{{name}{'!' + conv if conv else ''}{':' + spec if spec else ''}}}"
            return f"'{shown}' is not an {{action}} placeholder"
    return None


class LevelError(InputError):
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
    crystals: list[gameplay.CrystalSpec] = field(default_factory=list)
    energy: gameplay.EnergySpec = field(default_factory=gameplay.EnergySpec)
    radar: gameplay.RadarSpec | None = None
    ghosts: gameplay.GhostsSpec = field(default_factory=gameplay.GhostsSpec)
    seek: gameplay.SeekSpec = field(default_factory=gameplay.SeekSpec)
    rolling_resistance: float = 0.0
    tets: int = 0  # estimated tetrahedra of the 4D content (objects and worlds)
    weapons: list[gameplay.WeaponSpec] = field(default_factory=list)
    targets: list[gameplay.TargetSpec] = field(default_factory=list)
    manipulables: list[gameplay.ManipulableSpec] = field(default_factory=list)
    enemies: list[gameplay.EnemySpec] = field(default_factory=list)
    checkpoints: list[gameplay.CheckpointSpec] = field(default_factory=list)
    health: gameplay.HealthSpec | None = None  # None: the player cannot be hurt
    camera: gameplay.CameraSpec = field(default_factory=gameplay.CameraSpec)
    needs: tuple[str, ...] = ()  # [design]: the mechanics the level is built to demand (world.design)
    beacons: list[beacons.BeaconSpec] = field(default_factory=list)  # [[beacon]]: key objects brought back

    @property
    def bodies(self) -> int:
        """How many objects are rigid bodies."""
        return sum(o.body != "none" for o in self.objects)

    def frame_cost_ms(self) -> float:
        """Estimated milliseconds per frame while moving along w (see :func:`limits.tick_cost_ms`)."""
        drawables = len(self.worlds) + len(self.objects)
        return limits.tick_cost_ms(drawables, self.tets, self.bodies, len(self.enemies), len(self.crystals))


class _Reader:
    """Reads tables against their models, collecting problems instead of raising."""

    def __init__(self, path: Path):
        self.path = path
        self.problems: list[str] = []
        self.counts = dict.fromkeys(MAX_COUNTS, 0)
        self.tets = 0  # estimated tetrahedra of the 4D content read so far
        self._tets_reported = False

    def problem(self, where: str, msg: str) -> None:
        self.problems.append(f"{self.path}: {where}: {msg}")

    # ------------------------------------------------------------ tables
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

    def entries(self, data, key, where, label) -> list[dict]:
        """The ``[[key]]`` tables of ``data``, cut at the level's limit for that kind.

        ``label(k)`` names the k-th entry (from 1) for messages. Entries past the
        limit are not read at all, so an enormous file costs no more than one
        just over the limit.
        """
        items = self.array_of_tables(data, key, where)
        limit, what = MAX_COUNTS[key]
        room = limit - self.counts[key]
        if len(items) > room:
            if room >= 0:  # one line per kind: later tables of that kind are just not read
                self.problem(
                    label(room + 1),
                    f"a level may have at most {limit} {what}; this one and those after it are not read",
                )
            items = items[: max(room, 0)]
            room = -1
        self.counts[key] = limit + 1 if room < 0 else self.counts[key] + len(items)
        return items

    def add_tets(self, n: int, where: str) -> None:
        """Count an entry's estimated tetrahedra against the level's total."""
        self.tets += n
        if self.tets > limits.MAX_TOTAL_TETS and not self._tets_reported:
            self._tets_reported = True
            self.problem(
                where,
                f"with this entry the level's 4D content reaches about {self.tets:,} tetrahedra; "
                f"a level may have at most {limits.MAX_TOTAL_TETS:,}",
            )

    def unknown(self, data: dict, allowed, where) -> None:
        for k in data:
            if k not in allowed:
                self.problem(where, f"unknown field '{k}' (expected one of: {', '.join(sorted(allowed))})")

    def read(self, data: dict, model: dict, where: str, keys=None, **defaults) -> dict:
        """Read the fields ``keys`` (default: all but nested tables) of ``data`` by ``model``.

        ``defaults`` override the model's defaults (a colour inherited from a world).
        Returns field name -> value (numbers as float, vectors as float64 arrays).
        """
        out = {}
        for key in keys if keys is not None else model:
            f = model[key]
            if f.kind in ("tables", "params", "hints", "words"):
                continue
            out[key] = getattr(self, f"_{f.kind}")(data, key, where, f, defaults.get(key, f.default))
        return out

    # ------------------------------------------------------------ field kinds
    @staticmethod
    def _fallback(f: Field, default, n: int | None = None):
        """A stand-in for a bad value, so later checks can run (the level is refused anyway)."""
        if n is None:
            if _is_number(default):
                return float(default)
            return float(min(max(0.0, f.range.lo), f.range.hi)) if f.range else 0.0
        return np.ones(n) if f.sign == "positive" else np.zeros(n)

    def _number(self, data, key, where, f: Field, default):
        if key not in data:
            if default is REQUIRED:
                self.problem(where, f"missing field '{key}' (a number)")
                return self._fallback(f, None)
            return default if default is None else float(default)
        v = data[key]
        if not _is_number(v):
            self.problem(where, f"field '{key}': expected a number, got {v!r}")
        elif f.sign == "positive" and v <= 0:
            self.problem(where, f"field '{key}': expected a number > 0, got {v!r}")
        elif f.sign == "nonnegative" and v < 0:
            self.problem(where, f"field '{key}': expected a number >= 0, got {v!r}")
        elif f.range is not None and v not in f.range:
            self.problem(where, f"field '{key}': expected a number {f.range.text()}, got {v!r}")
        else:
            return float(v)
        return self._fallback(f, default)

    def _vector(self, data, key, where, f: Field, default):
        n, names = f.n, f.names
        if key not in data:
            if default is REQUIRED:
                self.problem(where, f"missing field '{key}' (a list of {n} numbers {list(names[:n])})")
                return np.zeros(n)
            return None if default is None else np.asarray(default, dtype=np.float64)
        v = data[key]
        ok = isinstance(v, list) and len(v) == n and all(_is_number(x) for x in v)
        if ok and f.sign == "positive" and any(x <= 0 for x in v):
            self.problem(where, f"field '{key}': expected {n} positive numbers, got {v!r}")
        elif not ok:
            self.problem(where, f"field '{key}': expected a list of {n} numbers {list(names[:n])}, got {v!r}")
        elif f.range is not None and any(x not in f.range for x in v):
            self.problem(where, f"field '{key}': expected {n} numbers {f.range.text()}, got {v!r}")
        elif f.length is not None and math.hypot(*v) > f.length:
            self.problem(
                where,
                f"field '{key}': expected a length of at most {f.length:g}, got {v!r} (length {math.hypot(*v):.4g})",
            )
        else:
            return np.asarray(v, dtype=np.float64)
        return self._fallback(f, default, n)

    def _scale(self, data, key, where, f: Field, default):
        v = data.get(key, default)
        n = f.n
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            if not _is_number(v) or v <= 0:
                self.problem(where, f"field '{key}': expected a positive number or {n} positive numbers, got {v!r}")
                return np.ones(n)
            if f.range is not None and v not in f.range:
                self.problem(where, f"field '{key}': expected a number or {n} numbers {f.range.text()}, got {v!r}")
                return np.ones(n)
            return np.full(n, float(v))
        return self._vector(data, key, where, f, REQUIRED)

    def _string(self, data, key, where, f: Field, default):
        if key not in data:
            if default is REQUIRED:
                self.problem(where, f"missing field '{key}' (a string)")
                return ""
            return default
        v = data[key]
        choices = f.choices
        default = None if default is REQUIRED else default
        if not isinstance(v, str):
            self.problem(where, f"field '{key}': expected a string, got {v!r}")
            return default or ""
        if choices and v not in choices:
            self.problem(where, f"field '{key}': expected one of {', '.join(choices)}, got {v!r}")
            return default or choices[0]
        return v

    def _text(self, data, key, where, f: Field, default):
        v = self._string(data, key, where, f, default)
        if isinstance(v, str) and len(v) > f.range.hi:
            self.problem(where, f"field '{key}': expected at most {f.range.hi:g} characters, got {len(v)}")
            return v[: int(f.range.hi)]
        return v

    def _bool(self, data, key, where, f: Field, default):
        v = data.get(key, default)
        if not isinstance(v, bool):
            self.problem(where, f"field '{key}': expected true or false, got {v!r}")
            return default
        return v

    def _color(self, data, key, where, f: Field, default):
        default = DEFAULT_COLOR if default is None else default
        if key not in data:
            return tuple(default)
        v = data[key]
        if (
            isinstance(v, list)
            and len(v) in (3, 4)
            and all(isinstance(x, (int, float)) and not isinstance(x, bool) and x in COLOR for x in v)
        ):
            return tuple(float(x) for x in v) + ((1.0,) if len(v) == 3 else ())
        self.problem(where, f"field '{key}': expected 3 or 4 numbers between 0 and 1 (RGB[A]), got {v!r}")
        return tuple(default)

    def _angles(self, data, key, where, f: Field, default) -> dict:
        v = data.get(key, {})
        if not isinstance(v, dict):
            self.problem(
                where, f"field '{key}': expected a table of plane = degrees with planes {', '.join(PLANES)}, got {v!r}"
            )
            return {}
        out = {}
        for plane, deg in v.items():
            if plane not in PLANES:
                self.problem(
                    where, f"field '{key}': unknown rotation plane '{plane}' (expected one of {', '.join(PLANES)})"
                )
            elif not _is_number(deg):
                self.problem(where, f"field '{key}.{plane}': expected degrees as a number, got {deg!r}")
            elif f.range is not None and deg not in f.range:
                self.problem(where, f"field '{key}.{plane}': expected a number {f.range.text()}, got {deg!r}")
            else:
                out[plane] = float(deg)
        return out

    def _asset(self, data, key, where, f: Field, default) -> Path | None:
        if key not in data and default is not REQUIRED:
            return default
        rel = self._string(data, key, where, f, REQUIRED)
        if not rel:
            if isinstance(data.get(key), str):
                self.problem(
                    where,
                    f"field '{key}': expected a path inside the assets folder such as "
                    f'"meshes/crate.obj", got an empty string',
                )
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


# ====================================================================== tables
def _entry_label(where: str, kind: str):
    """How the k-th ``kind`` entry under ``where`` is named in messages."""
    if where == "top level":
        return lambda k: f"[[{kind}]] #{k}"
    return lambda k: f"{where} > {kind} #{k}"


def _boxes(r: _Reader, data, where, color) -> list[BoxSpec]:
    out = []
    label = _entry_label(where, "box")
    for i, b in enumerate(r.entries(data, "box", where, label), 1):
        w = label(i)
        r.unknown(b, BOX, w)
        v = r.read(b, BOX, w, color=color)
        out.append(BoxSpec(v["center"], v["size"], v["color"]))
    return out


def _meshes(r: _Reader, data, where, color) -> list[MeshSpec]:
    out = []
    label = _entry_label(where, "mesh")
    for i, m in enumerate(r.entries(data, "mesh", where, label), 1):
        w = label(i)
        r.unknown(m, MESH, w)
        v = r.read(m, MESH, w, color=color)
        if v["asset"] is not None:
            out.append(MeshSpec(v["asset"], v["position"], v["scale"], v["yaw"], v["color"]))
    return out


def _level_table(r: _Reader, data, path: Path) -> tuple[dict, bool]:
    meta = r.table(data, "level", "[level]", required=True)
    r.unknown(meta, LEVEL, "[level]")
    v = r.read(meta, LEVEL, "[level]", keys=("name", "description", "format"), name=path.stem)
    if v["format"] not in FORMATS:
        r.problem("[level]", f"field 'format': this game reads formats 1 and 2, the file says {v['format']:g}")
    elif v["format"] == 1:
        for table in gameplay.MODELS:
            if table in data:
                r.problem("top level", f"'{table}' needs format 2 (set format = 2 in [level])")
    n = len(r.problems)
    w_range = r.read(meta, LEVEL, "[level]", keys=("w_range",))["w_range"]
    w_ok = len(r.problems) == n
    if w_ok and w_range[0] > w_range[1]:  # low == high: a 3D level (no moving along w, no w gauge)
        r.problem("[level]", f"field 'w_range': expected [low, high] with low <= high, got {w_range.tolist()}")
        w_ok = False
    v["w_range"] = w_range
    hints = meta.get("hints", [])
    if not (isinstance(hints, list) and all(isinstance(h, str) for h in hints)):
        r.problem("[level]", "field 'hints': expected a list of strings")
        hints = []
    limit, what = MAX_COUNTS["hints"]
    if len(hints) > limit:
        r.problem("[level]", f"field 'hints': a level may have at most {limit} {what}, got {len(hints)}")
        hints = hints[:limit]
    for i, h in enumerate(hints, 1):
        why = _hint_problem(h)
        if why:
            r.problem("[level]", f"field 'hints': hint #{i}: {why}")
    v["hints"] = list(hints)
    return v, w_ok


def _spawn_table(r: _Reader, data, w_range, w_ok) -> tuple[np.ndarray, float]:
    n = len(r.problems)
    spawn_t = r.table(data, "spawn", "[spawn]", required=True)
    if len(r.problems) != n:  # a missing [spawn] is one problem, not one per field
        return np.zeros(4), 0.0
    r.unknown(spawn_t, SPAWN, "[spawn]")
    n = len(r.problems)
    spawn = r.read(spawn_t, SPAWN, "[spawn]", keys=("position",))["position"]
    if len(r.problems) == n and w_ok and not w_range[0] <= spawn[3] <= w_range[1]:
        r.problem("[spawn]", f"field 'position': w = {spawn[3]:g} is outside the level's w_range {w_range.tolist()}")
    return spawn, r.read(spawn_t, SPAWN, "[spawn]", keys=("yaw",))["yaw"]


def _goal_table(r: _Reader, data, w_range, w_ok) -> GoalSpec:
    n = len(r.problems)
    goal_t = r.table(data, "goal", "[goal]", required=True)
    if len(r.problems) != n:
        return GoalSpec(np.zeros(3), np.ones(3), None)
    r.unknown(goal_t, GOAL, "[goal]")
    n = len(r.problems)
    gw = r.read(goal_t, GOAL, "[goal]", keys=("w_range",))["w_range"]
    goal_w = None
    if gw is not None:
        goal_w = (float(gw[0]), float(gw[1]))
        if len(r.problems) == n and gw[0] > gw[1]:
            r.problem("[goal]", f"field 'w_range': expected [low, high] with low <= high, got {gw.tolist()}")
        elif len(r.problems) == n and w_ok and (gw[1] < w_range[0] or gw[0] > w_range[1]):
            r.problem(
                "[goal]",
                f"field 'w_range': {gw.tolist()} is outside the level's w_range "
                f"{w_range.tolist()}, so the goal can never be reached",
            )
    v = r.read(goal_t, GOAL, "[goal]", keys=("center", "size"))
    return GoalSpec(v["center"], v["size"], goal_w)


def _world_table(r: _Reader, wt: dict, i: int) -> WorldSpec:
    where = f"[[world]] #{i}"
    r.unknown(wt, WORLD, where)
    name = r.read(wt, WORLD, where, keys=("name",), name=f"world{i}")["name"]
    where = f"[[world]] #{i} '{name}'"
    v = r.read(wt, WORLD, where, keys=("color", "w", "depth", "profile"))
    world = WorldSpec(
        name,
        v["w"],
        v["depth"],
        v["profile"],
        v["color"],
        _boxes(r, wt, where, v["color"]),
        _meshes(r, wt, where, v["color"]),
    )
    if not wt.get("box") and not wt.get("mesh"):
        r.problem(where, "has no [[world.box]] or [[world.mesh]] entries")
    r.add_tets(limits.world_tets(len(world.boxes), len(world.meshes)), where)
    return world


def _object_table(r: _Reader, ot: dict, i: int) -> ObjectSpec:
    from ..core.shapes import (
        SHAPES,  # the shape registry; imported here to keep level parsing light
    )

    where = f"[[object]] #{i}"
    r.unknown(ot, OBJECT, where)
    name = r.read(ot, OBJECT, where, keys=("name",), name=f"object{i}")["name"]
    where = f"[[object]] #{i} '{name}'"
    shape = asset = None
    if ("shape" in ot) == ("asset" in ot):
        r.problem(where, "expected exactly one of 'shape' (a 4D shape name) or 'asset' (a 3D mesh to lift)")
    elif "shape" in ot:
        shape = r._string(ot, "shape", where, Field("string", choices=tuple(SHAPES)), REQUIRED)
        if shape != ot["shape"]:  # reported; do not check params against a stand-in shape
            shape = None
    else:
        asset = r._asset(ot, "asset", where, OBJECT["asset"], REQUIRED)
    params = ot.get("params", {})
    params_ok = False
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
            n = len(r.problems)
            for k, val in params.items():
                why = _param_problem(k, val)
                if why:
                    r.problem(where, f"field 'params': {why}")
            params_ok = len(r.problems) == n
    tets = 0
    why = limits.shape_aspect_problem(shape, params) if params_ok else None
    if why:
        r.problem(where, f"field 'params': {why}")
    if params_ok:
        tets = limits.shape_tets(shape, params)
        if tets > limits.MAX_OBJECT_TETS:
            r.problem(
                where,
                f"field 'params': shape '{shape}' with these parameters has {tets:,} tetrahedra; "
                f"an object may have at most {limits.MAX_OBJECT_TETS:,}",
            )
    elif asset is not None:
        tets = limits.asset_object_tets()
    r.add_tets(tets, where)
    v = r.read(
        ot,
        OBJECT,
        where,
        keys=("depth", "position", "rotation", "scale", "color", "spin", "solid", "body", "mass", "velocity"),
    )
    if v["body"] != "none":
        r.counts["body"] += 1
        limit, what = MAX_COUNTS["body"]
        if r.counts["body"] == limit + 1:
            r.problem(where, f"field 'body': a level may have at most {limit} {what}")
        n = len(r.problems)
        vertices = None
        if params_ok:
            vertices = limits.shape_vertices(shape, params)
        elif asset is not None and len(r.problems) == n:
            vertices = _asset_vertices(asset, v["depth"])
        if vertices is not None:
            why = limits.body_problem(limits.body_extent(vertices, v["scale"], v["body"]))
            if why:
                r.problem(where, f"field 'scale': {why}")
    return ObjectSpec(
        name,
        shape,
        params,
        asset,
        v["depth"],
        v["position"],
        v["rotation"],
        v["scale"],
        v["color"],
        v["spin"],
        v["solid"],
        v["body"],
        v["mass"],
        v["velocity"],
    )


def _asset_vertices(asset: Path, depth: float):
    """Vertices ``(2n, 4)`` of the asset lifted to a prism ``depth`` deep, or None if it
    cannot be read (that is reported when the level is played and the asset baked)."""
    from .bake import (
        load_surface,  # trimesh is imported only for a body made from an asset
    )

    try:
        v3, _ = load_surface(asset)
    except (ValueError, OSError):
        return None
    half = np.full((len(v3), 1), depth / 2)
    return np.concatenate([np.hstack([v3, -half]), np.hstack([v3, half])])


def _parse(path: Path, source: bytes | None = None) -> tuple[dict, bytes]:
    """Read ``path`` (bounded), or take ``source`` as its text, and parse it as TOML,
    or raise LevelError with one line."""
    if source is not None and len(source) > limits.MAX_LEVEL_BYTES:
        raise LevelError(path, [f"{path}: a level is at most {limits.MAX_LEVEL_BYTES:,} bytes, got {len(source):,}"])
    try:
        raw = source if source is not None else fileio.read_bytes(path, limit=limits.MAX_LEVEL_BYTES, what="level")
    except fileio.FileProblem as e:
        raise LevelError(path, [str(e)]) from None
    try:
        data = tomllib.loads(raw.decode("utf-8-sig"))  # -sig: skip a byte-order mark
    except UnicodeDecodeError:
        raise LevelError(path, [f"{path}: not a text file (expected UTF-8 TOML)"]) from None
    except (tomllib.TOMLDecodeError, ValueError) as e:  # ValueError: an integer over 4300 digits
        raise LevelError(path, [f"{path}: not valid TOML: {e}"]) from None
    except RecursionError:
        raise LevelError(path, [f"{path}: not valid TOML: arrays or tables nested too deeply"]) from None
    big = list(_big_ints(data))
    if big:
        raise LevelError(
            path,
            [
                f"{path}: {b}: integer out of range (TOML integers are 64-bit; write a float like 1e30 for huge values)"
                for b in big[:20]
            ],
        )
    return data, raw


def load_level(path, source: bytes | None = None) -> Level:
    """Read and check a level file (or ``source``, the text it would have: the editor
    checks an unsaved level with the very messages a saved one would get).

    The file is read through the bounded reader (at most
    :data:`limits.MAX_LEVEL_BYTES`), every field is checked against its model
    and range, and the counts and estimated tetrahedra against the limits of
    :mod:`.limits`.

    Raises
    ------
    LevelError
        Listing every problem, each naming the file, entry and field.
    """
    path = Path(path)
    data, raw = _parse(path, source)
    if isinstance(data.get("level"), dict) and data["level"].get("format") == FLAT_FORMAT:
        what = f'format = "{FLAT_FORMAT}" is a Flatland prologue level, not a 4D one (world/flat_level.py reads it)'
        raise LevelError(path, [f"{path}: [level]: {what}"])
    r = _Reader(path)
    r.unknown(data, MODELS, "top level")
    meta, w_ok = _level_table(r, data, path)
    w_range = meta["w_range"]
    spawn, spawn_yaw = _spawn_table(r, data, w_range, w_ok)
    goal = _goal_table(r, data, w_range, w_ok)

    phys_t = r.table(data, "physics", "[physics]")
    r.unknown(phys_t, PHYSICS, "[physics]")
    phys = r.read(phys_t, PHYSICS, "[physics]")

    boxes = _boxes(r, data, "top level", DEFAULT_COLOR)
    meshes = _meshes(r, data, "top level", DEFAULT_COLOR)
    worlds = [
        _world_table(r, wt, i)
        for i, wt in enumerate(r.entries(data, "world", "top level", _entry_label("top level", "world")), 1)
    ]
    objects = [
        _object_table(r, ot, i)
        for i, ot in enumerate(r.entries(data, "object", "top level", _entry_label("top level", "object")), 1)
    ]

    energy = gameplay.read_energy(r, data)
    radar = gameplay.read_radar(r, data)
    crystals = gameplay.read_crystals(r, data, w_range if w_ok else None)
    weapons = gameplay.read_weapons(r, data)
    targets = gameplay.read_targets(r, data, {o.name for o in objects})
    manipulables = gameplay.read_manipulables(r, data, objects)
    ghosts = gameplay.read_ghosts(r, data)
    seek = gameplay.read_seek(r, data)
    animations = gameplay.read_animations(r, data)
    enemies = gameplay.read_enemies(r, data, animations, {o.name for o in objects})
    checkpoints = gameplay.read_checkpoints(r, data, w_range if w_ok else None)
    health = gameplay.read_health(r, data, bool(enemies))
    camera = gameplay.read_camera(r, data)
    needs = design.read_design(r, data)
    resets = beacons.read_beacons(r, data, objects)

    if r.problems:
        raise LevelError(path, r.problems)
    level = Level(
        path=path,
        name=meta["name"],
        description=meta["description"],
        w_range=(float(w_range[0]), float(w_range[1])),
        spawn=spawn,
        spawn_yaw_deg=spawn_yaw,
        goal=goal,
        gravity=phys["gravity"],
        inverse_cube_g=phys["inverse_cube_g"],
        boxes=boxes,
        meshes=meshes,
        worlds=worlds,
        objects=objects,
        source_hash=hashlib.sha256(raw).hexdigest(),
        hints=meta["hints"],
        rolling_resistance=phys["rolling_resistance"],
        tets=r.tets,
        crystals=crystals,
        energy=energy,
        radar=radar,
        weapons=weapons,
        targets=targets,
        manipulables=manipulables,
        ghosts=ghosts,
        seek=seek,
        enemies=enemies,
        checkpoints=checkpoints,
        health=health,
        camera=camera,
        needs=needs,
        beacons=resets,
    )
    from .placement import placement_problems  # where things are, once every entry is read

    problems = placement_problems(level)
    if problems:
        raise LevelError(path, problems)
    return level
