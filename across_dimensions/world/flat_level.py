"""Prologue levels: a flat world that is the slice ``z = z0`` of a 3D one (``format = "flatland"``).

The prologue teaches the w step one dimension down: the player is a flat being in a side view
``(x, y)``, and the w keys move its plane along a z it cannot see. Its level file is TOML like
every level (``levels/README.md``, *The Flatland prologue*), recognised by ``format = "flatland"``
in ``[level]``, and read by the 4D loader's own reader (:class:`~.level_reader.TableReader`), so its
messages name the file, the table, the entry's index and the field the same way, and every
problem is reported at once (:class:`~.level.LevelError`).

The 3D content is built here, once, as closed triangle meshes (:mod:`..core.flat_solids`): boxes,
prisms of a profile (a wall that tapers along z), staircases; balls stay analytic spheres, and
crates are boxes the being pushes. What the flat being meets of them is their section at its z
(:mod:`..core.flat_section`), computed by the simulation (``game/flatland``).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.flat_section import Solid3, signed_area
from ..core.flat_solids import box_solid, prism_solid, staircase_profile
from .design import DESIGN_TABLE, read_design
from .fields import Field
from .level_reader import LevelError, TableReader, hint_problem, parse_level
from .limits import MAX_NAME_CHARS, MAX_TEXT_CHARS, Range
from .resources import FLAT_FORMAT as FORMAT

#: Coordinates of a flat world: a prologue room is tens of metres; pymunk's solver keeps its
#: precision for bodies within a kilometre of the origin.
FLAT_COORD = Range(-1000.0, 1000.0, "m")
FLAT_SIZE = Range(0.01, 200.0, "m")
FLAT_MASS = Range(0.1, 1000.0, "kg")
FLAT_SPEED = Range(0.0, 20.0, "m/s")
FLAT_GRAVITY = Range(-100.0, 0.0, "m/s^2")
STEPS = Range(1, 50)
#: Most entries of each kind in a prologue level.
MAX_ENTRIES = 64
MAX_PROFILE_POINTS = 64
#: What a hint's ``until.event`` may name: the events of the prologue's simulation.
EVENTS = ("item_taken", "door_opened", "z_blocked", "checkpoint", "fell", "complete")
ALONG = ("+x", "-x", "+z", "-z")
DEFAULT_COLOR = (0.45, 0.5, 0.6, 1.0)

BOX = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "center": Field("vector", 3, range=FLAT_COORD),
    "size": Field("vector", 3, range=FLAT_SIZE, sign="positive"),
    "color": Field("color", default=DEFAULT_COLOR),
}
PRISM = {
    "name": BOX["name"],
    "along": Field("string", choices=("x", "z")),
    "extent": Field("vector", 2, range=FLAT_COORD, names="ab"),
    "profile": Field("points"),
    "color": BOX["color"],
}
STAIRS = {
    "name": BOX["name"],
    "position": Field("vector", 3, range=FLAT_COORD),
    "steps": Field("number", range=STEPS, sign="positive"),
    "run": Field("number", range=FLAT_SIZE, sign="positive"),
    "rise": Field("number", range=FLAT_SIZE, sign="positive"),
    "width": Field("number", range=FLAT_SIZE, sign="positive"),
    "along": Field("string", default="+x", choices=ALONG),
    "color": BOX["color"],
}
BALL = {
    "name": BOX["name"],
    "center": Field("vector", 3, range=FLAT_COORD),
    "radius": Field("number", range=FLAT_SIZE, sign="positive"),
    "roll": Field("vector", 2, default=None, range=FLAT_COORD, names="ab"),
    "speed": Field("number", default=0.0, range=FLAT_SPEED, sign="nonnegative"),
    "color": Field("color", default=(1.0, 0.6, 0.25, 1.0)),
}
CRATE = {
    "name": BOX["name"],
    "center": Field("vector", 3, range=FLAT_COORD),
    "size": BOX["size"],
    "mass": Field("number", default=20.0, range=FLAT_MASS, sign="positive"),
    "color": Field("color", default=(0.75, 0.55, 0.3, 1.0)),
}
ITEM = {
    "name": BOX["name"],
    "position": Field("vector", 3, range=FLAT_COORD),
    "radius": Field("number", default=0.35, range=FLAT_SIZE, sign="positive"),
    "opens": Field("string", default=""),
    "color": Field("color", default=(0.35, 1.0, 0.85, 1.0)),
}
HINT = {"text": Field("text", range=Range(1, MAX_TEXT_CHARS)), "until": Field("until", default=None)}
UNTIL = {k: Field("number", default=None, range=FLAT_COORD) for k in ("x_min", "x_max", "z_min", "z_max")}
UNTIL["event"] = Field("string", default=None, choices=EVENTS)
CHECKPOINT = {"name": BOX["name"], "position": Field("vector", 3, range=FLAT_COORD)}
LEVEL = {
    "format": Field("string"),
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "description": Field("text", default="", range=Range(0, MAX_TEXT_CHARS)),
    "z_range": Field("vector", 2, default=(-1.0, 1.0), range=FLAT_COORD, names="ab"),
}
SPAWN = {"position": Field("vector", 3, range=FLAT_COORD)}
GOAL = {
    "center": Field("vector", 2, range=FLAT_COORD, names="xy"),
    "size": Field("vector", 2, range=FLAT_SIZE, sign="positive", names="xy"),
    "z_range": Field("vector", 2, default=None, range=FLAT_COORD, names="ab"),
}
PHYSICS = {
    "gravity": Field("number", default=-9.81, range=FLAT_GRAVITY),
    "fall_y": Field("number", default=-20.0, range=FLAT_COORD),
}
RADAR = {"range": Field("number", default=20.0, range=FLAT_SIZE, sign="positive")}
TABLES = {"level": LEVEL, "spawn": SPAWN, "goal": GOAL, "physics": PHYSICS, "radar": RADAR}
ARRAYS = {
    "box": BOX,
    "prism": PRISM,
    "stairs": STAIRS,
    "ball": BALL,
    "crate": CRATE,
    "item": ITEM,
    "hint": HINT,
    "checkpoint": CHECKPOINT,
}


@dataclass(frozen=True)
class SolidSpec:
    """A fixed 3D solid (a box, prism or staircase) as the mesh its sections are cut from."""

    name: str
    kind: str
    solid: Solid3
    color: tuple


@dataclass(frozen=True)
class BallSpec:
    """A 3D ball; with ``roll`` its centre rolls along z between the two values and back at ``speed``."""

    name: str
    center: np.ndarray
    radius: float
    roll: tuple[float, float] | None
    speed: float
    color: tuple


@dataclass(frozen=True)
class CrateSpec:
    """A box the being pushes: it moves in x and y, and exists for z within its own extent."""

    name: str
    center: np.ndarray
    size: np.ndarray
    mass: float
    color: tuple


@dataclass(frozen=True)
class ItemSpec:
    """A small 3D ball the being takes by touching its circle; ``opens`` names a solid it removes."""

    name: str
    position: np.ndarray
    radius: float
    opens: str
    color: tuple


@dataclass(frozen=True)
class HintSpec:
    """A hint and the level state that completes it (``until``: ``x_min``, ``x_max``, ``z_min``,
    ``z_max``, ``event``; all given must hold). Without ``until`` it stays for its reading time."""

    text: str
    until: dict


@dataclass
class FlatLevel:
    """A checked prologue level."""

    path: Path
    name: str
    description: str
    z_range: tuple[float, float]
    spawn: np.ndarray  # (3,) feet x, y and z
    goal_center: np.ndarray  # (2,)
    goal_size: np.ndarray  # (2,)
    goal_z: tuple[float, float] | None
    gravity: float
    fall_y: float
    radar_range: float
    source_hash: str
    solids: list[SolidSpec] = field(default_factory=list)
    balls: list[BallSpec] = field(default_factory=list)
    crates: list[CrateSpec] = field(default_factory=list)
    items: list[ItemSpec] = field(default_factory=list)
    hints: list[HintSpec] = field(default_factory=list)
    checkpoints: list[tuple[str, np.ndarray]] = field(default_factory=list)
    needs: tuple[str, ...] = ()  # [design]: the mechanics the prologue is built to demand (world.design)


class _FlatReader(TableReader):
    """The level reader, with the two field kinds only this format has."""

    def _points(self, data, key, where, f: Field, default):
        v = data.get(key)
        pairs = isinstance(v, list) and all(
            isinstance(p, list) and len(p) == 2 and all(_number(x) and x in FLAT_COORD for x in p) for p in v
        )
        if not pairs or not 3 <= len(v) <= MAX_PROFILE_POINTS:
            self.problem(
                where,
                f"field '{key}': expected 3 to {MAX_PROFILE_POINTS} points [a, y] {FLAT_COORD.text()}, got {v!r}",
            )
            return None
        p = np.asarray(v, np.float64)
        if abs(signed_area(p)) < 1e-6 or _self_crossing(p):
            self.problem(where, f"field '{key}': expected a simple polygon (no crossing edges, some area), got {v!r}")
            return None
        return p

    def _until(self, data, key, where, f: Field, default):
        v = data.get(key)
        if v is None:
            return {}
        if not isinstance(v, dict) or not v:
            self.problem(where, f"field '{key}': expected a table of {', '.join(UNTIL)}, got {v!r}")
            return {}
        self.unknown(v, UNTIL, f"{where} > until")
        got = self.read(v, UNTIL, f"{where} > until", keys=[k for k in UNTIL if k in v])
        return {k: x for k, x in got.items() if x is not None}


def _number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _self_crossing(p: np.ndarray) -> bool:
    """Whether two edges of the polygon that are not neighbours touch or cross."""
    n = len(p)

    def orient(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    for i in range(n):
        a, b = p[i], p[(i + 1) % n]
        for j in range(i + 2, n):
            if (j + 1) % n == i:
                continue
            c, d = p[j], p[(j + 1) % n]
            if orient(a, b, c) != orient(a, b, d) and orient(c, d, a) != orient(c, d, b):
                return True
    return False


def _entries(r: TableReader, data: dict, key: str) -> list[tuple[str, dict]]:
    """``[[key]]`` tables with their labels (``[[box]] #3``), the unknown fields of each reported."""
    items = r.array_of_tables(data, key, "top level")
    if len(items) > MAX_ENTRIES:
        r.problem(f"[[{key}]] #{MAX_ENTRIES + 1}", f"a prologue level may have at most {MAX_ENTRIES}; not read")
        items = items[:MAX_ENTRIES]
    out = []
    for i, t in enumerate(items, 1):
        name = t.get("name")
        where = f"[[{key}]] #{i}" + (f" {name!r}" if isinstance(name, str) and name else "")
        r.unknown(t, ARRAYS[key], where)
        out.append((where, t))
    return out


def _range_pair(r: TableReader, v, where: str, key: str) -> tuple[float, float] | None:
    if v is None:
        return None
    if v[0] >= v[1]:
        r.problem(where, f"field '{key}': expected [low, high] with low < high, got {v.tolist()}")
    return float(v[0]), float(v[1])


def _solids(r: TableReader, data: dict) -> list[SolidSpec]:
    out = []
    for where, t in _entries(r, data, "box"):
        v = r.read(t, BOX, where)
        out.append(SolidSpec(v["name"] or f"box{len(out) + 1}", "box", box_solid(v["center"], v["size"]), v["color"]))
    for where, t in _entries(r, data, "prism"):
        v = r.read(t, PRISM, where)
        extent = _range_pair(r, v["extent"], where, "extent")
        if v["profile"] is not None and extent is not None and extent[0] < extent[1]:
            out.append(SolidSpec(v["name"] or f"prism{len(out) + 1}", "prism", _prism(v, extent), v["color"]))
    for where, t in _entries(r, data, "stairs"):
        v = r.read(t, STAIRS, where)
        if v["steps"] != int(v["steps"]):
            r.problem(where, f"field 'steps': expected a whole number, got {v['steps']:g}")
            continue
        out.append(SolidSpec(v["name"] or f"stairs{len(out) + 1}", "stairs", _stairs(v), v["color"]))
    return out


def _prism(v: dict, extent) -> Solid3:
    """A prism from its level fields: ``profile`` points ``[a, y]``, ``a`` the horizontal axis across."""
    p = v["profile"] if signed_area(v["profile"]) > 0 else v["profile"][::-1]
    if v["along"] == "z":
        return prism_solid(p, *extent, axis="z")  # (x, y): the profile as the flat being sees it
    return prism_solid(p[::-1, ::-1], *extent, axis="x")  # (z, y) -> (y, z), turned back counter-clockwise


def _stairs(v: dict) -> Solid3:
    steps, run, rise, width = int(v["steps"]), v["run"], v["rise"], v["width"]
    x, y, z = v["position"]
    profile = staircase_profile(steps, run, rise)
    sign = 1.0 if v["along"][0] == "+" else -1.0
    if sign < 0:  # climbing towards -axis: the profile mirrored (and turned back counter-clockwise)
        profile = np.c_[-profile[::-1, 0], profile[::-1, 1]]
    if v["along"][1] == "x":
        return prism_solid(profile + (x, y), z - width / 2, z + width / 2, axis="z")
    return prism_solid((profile + (z, y))[::-1, ::-1], x - width / 2, x + width / 2, axis="x")


def _movers(r: TableReader, data: dict, lvl: dict) -> None:
    for where, t in _entries(r, data, "ball"):
        v = r.read(t, BALL, where)
        roll = _range_pair(r, v["roll"], where, "roll")
        if roll is not None and not roll[0] <= v["center"][2] <= roll[1]:
            r.problem(where, f"field 'center': z = {v['center'][2]:g} is outside its roll {list(roll)}")
        name = v["name"] or f"ball{len(lvl['balls']) + 1}"
        lvl["balls"].append(BallSpec(name, v["center"], v["radius"], roll, v["speed"], v["color"]))
    for where, t in _entries(r, data, "crate"):
        v = r.read(t, CRATE, where)
        name = v["name"] or f"crate{len(lvl['crates']) + 1}"
        lvl["crates"].append(CrateSpec(name, v["center"], v["size"], v["mass"], v["color"]))


def _items(r: TableReader, data: dict, solids: list[SolidSpec]) -> list[ItemSpec]:
    out, names = [], {s.name for s in solids}
    for where, t in _entries(r, data, "item"):
        v = r.read(t, ITEM, where)
        if v["opens"] and v["opens"] not in names:
            known = ", ".join(sorted(names)) or "none"
            r.problem(where, f"field 'opens': no box, prism or stairs named {v['opens']!r} (named: {known})")
        out.append(ItemSpec(v["name"] or f"item{len(out) + 1}", v["position"], v["radius"], v["opens"], v["color"]))
    return out


def _hints(r: TableReader, data: dict) -> list[HintSpec]:
    out = []
    for where, t in _entries(r, data, "hint"):
        v = r.read(t, HINT, where)
        why = hint_problem(v["text"])
        if why:
            r.problem(where, f"field 'text': {why}")
        out.append(HintSpec(v["text"], v["until"]))
    return out


def _in_range(r: TableReader, where: str, z: float, z_range, what: str) -> None:
    if z_range is not None and not z_range[0] <= z <= z_range[1]:
        r.problem(where, f"{what}: z = {z:g} is outside the level's z_range {list(z_range)}")


def load_flat_level(path, source: bytes | None = None) -> FlatLevel:
    """Read and check a prologue level (or ``source``, the text it would have).

    Raises
    ------
    LevelError
        Listing every problem, each naming the file, the table (with the entry's index for
        ``[[...]]`` tables) and the field.
    """
    path = Path(path)
    data, raw = parse_level(path, source)
    r = _FlatReader(path)
    r.unknown(data, {**TABLES, **ARRAYS, "design": DESIGN_TABLE}, "top level")
    t = {name: r.table(data, name, f"[{name}]", required=name in ("level", "spawn", "goal")) for name in TABLES}
    for name, model in TABLES.items():
        r.unknown(t[name], model, f"[{name}]")
    given = {name: isinstance(data.get(name), dict) for name in TABLES}  # missing ones are reported
    meta = r.read(t["level"], LEVEL, "[level]", name=path.stem) if given["level"] else {"format": FORMAT}
    meta.setdefault("z_range", np.array([-1.0, 1.0]))
    if given["level"] and meta["format"] != FORMAT:
        r.problem("[level]", f"field 'format': expected \"{FORMAT}\" for a prologue level, got {meta['format']!r}")
    z_range = _range_pair(r, meta["z_range"], "[level]", "z_range")
    spawn = r.read(t["spawn"], SPAWN, "[spawn]")["position"] if given["spawn"] else np.zeros(3)
    _in_range(r, "[spawn]", float(spawn[2]), z_range, "field 'position'")
    goal = r.read(t["goal"], GOAL, "[goal]") if given["goal"] else {"center": np.zeros(2), "size": np.ones(2)}
    goal_z = _range_pair(r, goal.get("z_range"), "[goal]", "z_range")
    physics, radar = r.read(t["physics"], PHYSICS, "[physics]"), r.read(t["radar"], RADAR, "[radar]")
    solids = _solids(r, data)
    lvl: dict = {"balls": [], "crates": []}
    _movers(r, data, lvl)
    items = _items(r, data, solids)
    hints = _hints(r, data)
    needs = read_design(r, data)
    checkpoints = []
    for where, ct in _entries(r, data, "checkpoint"):
        v = r.read(ct, CHECKPOINT, where)
        _in_range(r, where, float(v["position"][2]), z_range, "field 'position'")
        checkpoints.append((v["name"] or f"checkpoint{len(checkpoints) + 1}", v["position"]))
    names = [s.name for s in solids] + [b.name for b in lvl["balls"]] + [c.name for c in lvl["crates"]]
    for dup in sorted({n for n in names + [i.name for i in items] if (names + [i.name for i in items]).count(n) > 1}):
        r.problem("top level", f"the name {dup!r} is given to more than one entry; expected each name once")
    if r.problems:
        raise LevelError(path, r.problems)
    return FlatLevel(
        path=path,
        name=meta["name"],
        description=meta["description"],
        z_range=z_range,
        spawn=spawn,
        goal_center=goal["center"],
        goal_size=goal["size"],
        goal_z=goal_z,
        gravity=physics["gravity"],
        fall_y=physics["fall_y"],
        radar_range=radar["range"],
        source_hash=hashlib.sha256(raw).hexdigest(),
        solids=solids,
        balls=lvl["balls"],
        crates=lvl["crates"],
        items=items,
        hints=hints,
        checkpoints=checkpoints,
        needs=needs,
    )
