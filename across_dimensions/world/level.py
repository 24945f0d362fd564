"""Level files: TOML data describing a 3D world with 4D content along w.

The format is documented with a complete example in ``levels/README.md``.
:func:`load_level` checks the whole file and raises :class:`LevelError` listing
every problem at once, each naming the file, the entry, the field and what was
expected. Level files are data only: nothing in them is executed, and asset
paths are confined to the assets folder.

The schema is declared once, as one model per TOML table (:data:`MODELS`): a
table maps each field name to a :class:`Field` saying what kind of value it
holds, its default and its accepted range (the ranges and the limits on how
much a level may ask for live in :mod:`.limits`). :class:`TableReader` reads any
table against its model; the per-table functions below only add what crosses
fields (a spawn inside the w range, exactly one of shape or asset, ...).
Adding a field is one line in a model; adding a table is a model and a small
function that builds its spec.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import beacons, design, enemy_tables, gameplay, limits, secrets
from .fields import Field
from .hints import HintSpec, hint_name_problems, read_hints
from .level_reader import DEFAULT_COLOR, LevelError, TableReader, hint_problem, parse_level
from .limits import (
    ANGLE,
    COORD,
    GRAVITY_MAX,
    INVERSE_CUBE_G,
    MAX_NAME_CHARS,
    MAX_TEXT_CHARS,
    ROLLING_RESISTANCE,
    SCALE,
    SIZE,
    Range,
)
from .object_table import OBJECT, ObjectSpec, read_object
from .resources import FLAT_FORMAT

PROFILES = ("prism", "round", "taper")
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
    "secret": secrets.SECRET_TABLE,
}
FORMATS = (1, 2)  # format 2 adds the tables of gameplay.MODELS
#: Top-level keys written ``[[key]]`` (arrays of tables); the others are ``[key]`` tables.
ARRAY_TABLES = ("box", "mesh", "world", "object", *gameplay.ARRAY_TABLES, "beacon", "secret")


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
    hints: list[HintSpec] = field(default_factory=list)
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
    enemies: list[enemy_tables.EnemySpec] = field(default_factory=list)
    checkpoints: list[enemy_tables.CheckpointSpec] = field(default_factory=list)
    health: enemy_tables.HealthSpec | None = None  # None: the player cannot be hurt
    camera: gameplay.CameraSpec = field(default_factory=gameplay.CameraSpec)
    needs: tuple[str, ...] = ()  # [design]: the mechanics the level is built to demand (world.design)
    beacons: list[beacons.BeaconSpec] = field(default_factory=list)  # [[beacon]]: key objects brought back
    secrets: tuple[secrets.SecretSpec, ...] = ()  # [[secret]]: hidden places the level counts

    @property
    def bodies(self) -> int:
        """How many objects are rigid bodies."""
        return sum(o.body != "none" for o in self.objects)

    def frame_cost_ms(self) -> float:
        """Estimated milliseconds per frame while moving along w (see :func:`limits.tick_cost_ms`)."""
        drawables = len(self.worlds) + len(self.objects)
        return limits.tick_cost_ms(drawables, self.tets, self.bodies, len(self.enemies), len(self.crystals))


# ====================================================================== tables
def _entry_label(where: str, kind: str):
    """How the k-th ``kind`` entry under ``where`` is named in messages."""
    if where == "top level":
        return lambda k: f"[[{kind}]] #{k}"
    return lambda k: f"{where} > {kind} #{k}"


def _boxes(r: TableReader, data, where, color) -> list[BoxSpec]:
    out = []
    label = _entry_label(where, "box")
    for i, b in enumerate(r.entries(data, "box", where, label), 1):
        w = label(i)
        r.unknown(b, BOX, w)
        v = r.read(b, BOX, w, color=color)
        out.append(BoxSpec(v["center"], v["size"], v["color"]))
    return out


def _meshes(r: TableReader, data, where, color) -> list[MeshSpec]:
    out = []
    label = _entry_label(where, "mesh")
    for i, m in enumerate(r.entries(data, "mesh", where, label), 1):
        w = label(i)
        r.unknown(m, MESH, w)
        v = r.read(m, MESH, w, color=color)
        if v["asset"] is not None:
            out.append(MeshSpec(v["asset"], v["position"], v["scale"], v["yaw"], v["color"]))
    return out


def _level_table(r: TableReader, data, path: Path) -> tuple[dict, bool]:
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
    v["hints"] = read_hints(r, meta, hint_problem)
    return v, w_ok


def _spawn_table(r: TableReader, data, w_range, w_ok) -> tuple[np.ndarray, float]:
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


def _goal_table(r: TableReader, data, w_range, w_ok) -> GoalSpec:
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


def _world_table(r: TableReader, wt: dict, i: int) -> WorldSpec:
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


def _content_tables(r: TableReader, data: dict) -> dict:
    """The level's 3D and 4D content: ``boxes``, ``meshes``, ``worlds`` and ``objects``."""
    top = "top level"
    return {
        "boxes": _boxes(r, data, top, DEFAULT_COLOR),
        "meshes": _meshes(r, data, top, DEFAULT_COLOR),
        "worlds": [
            _world_table(r, t, i) for i, t in enumerate(r.entries(data, "world", top, _entry_label(top, "world")), 1)
        ],
        "objects": [
            read_object(r, t, i) for i, t in enumerate(r.entries(data, "object", top, _entry_label(top, "object")), 1)
        ],
    }


def _system_tables(r: TableReader, data: dict, w_range, objects: list[ObjectSpec]) -> dict:
    """The tables of the game's systems (format 2, :mod:`.gameplay`), ``[design]``,
    ``[[beacon]]`` and ``[[secret]]``, by the
    :class:`Level` field each fills; ``w_range`` is None when the level's own is broken."""
    names = {o.name for o in objects}
    out = {
        "energy": gameplay.read_energy(r, data),
        "radar": gameplay.read_radar(r, data),
        "crystals": gameplay.read_crystals(r, data, w_range),
        "weapons": gameplay.read_weapons(r, data),
        "targets": gameplay.read_targets(r, data, names),
        "manipulables": gameplay.read_manipulables(r, data, objects),
        "ghosts": gameplay.read_ghosts(r, data),
        "seek": gameplay.read_seek(r, data),
    }
    animations = enemy_tables.read_animations(r, data)
    out["enemies"] = enemy_tables.read_enemies(r, data, animations, names)
    out["checkpoints"] = enemy_tables.read_checkpoints(r, data, w_range)
    out["health"] = enemy_tables.read_health(r, data, bool(out["enemies"]))
    out["camera"] = gameplay.read_camera(r, data)
    for o in objects:
        if o.walkable_in_frustum and not out["camera"].frustum:
            # Its image is met only while the frustum view holds: without one it is never walked on.
            r.problem(f"[[object]] '{o.name}'", "field 'walkable_in_frustum': needs [camera] with frustum = true")
    out["needs"] = design.read_design(r, data)
    out["beacons"] = beacons.read_beacons(r, data, objects)
    out["secrets"] = secrets.read_secrets(r, data, w_range)
    return out


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
    data, raw = parse_level(path, source)
    if isinstance(data.get("level"), dict) and data["level"].get("format") == FLAT_FORMAT:
        what = f'format = "{FLAT_FORMAT}" is a Flatland prologue level, not a 4D one (world/flat_level.py reads it)'
        raise LevelError(path, [f"{path}: [level]: {what}"])
    r = TableReader(path)
    r.unknown(data, MODELS, "top level")
    meta, w_ok = _level_table(r, data, path)
    w_range = meta["w_range"]
    spawn, spawn_yaw = _spawn_table(r, data, w_range, w_ok)
    goal = _goal_table(r, data, w_range, w_ok)

    phys_t = r.table(data, "physics", "[physics]")
    r.unknown(phys_t, PHYSICS, "[physics]")
    phys = r.read(phys_t, PHYSICS, "[physics]")
    content = _content_tables(r, data)
    systems = _system_tables(r, data, w_range if w_ok else None, content["objects"])
    found = [*content["objects"], *systems["crystals"], *systems["targets"], *systems["enemies"]]
    r.problems += hint_name_problems(path, meta["hints"], {x.name for x in found})
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
        rolling_resistance=phys["rolling_resistance"],
        source_hash=hashlib.sha256(raw).hexdigest(),
        hints=meta["hints"],
        tets=r.tets,
        **content,
        **systems,
    )
    from .placement import placement_problems  # where things are, once every entry is read

    problems = placement_problems(level)
    if problems:
        raise LevelError(path, problems)
    return level
