"""Level tables of the game's systems (level format 2): crystals, energy, radar, weapons, targets,
manipulables, ghosts, seek and the camera (the enemies' tables are in :mod:`.enemy_tables`).

Each table is a model of :class:`~.fields.Field` s (read and checked by the
level loader like every other table, and exported to the JSON Schema) and a
spec dataclass with the defaults a level gets when it leaves the table out.
A level without ``[energy]`` has no energy bar (moving along w is free); one
without ``[radar]`` has no radar: the first level looks like an ordinary 3D game,
and the 4D tools appear as the campaign introduces them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.transform import PLANES as PLANE_ORDER
from . import enemy_tables
from .fields import Field
from .limits import (
    AMMO,
    ANGLE,
    BULLET_CAP,
    COORD,
    CRYSTAL_SIZE,
    ENERGY,
    MASS,
    MAX_NAME_CHARS,
    MILLI,
    RADAR_RANGE,
    RADAR_W_SCALE,
    RESPAWN,
    SPIN,
    TARGET_SIZE,
    WEAPON_REACH,
    WEAPON_SPEED,
    WEAPON_TIME,
    Range,
)

CRYSTAL_SHAPES = ("16-cell", "24-cell", "5-cell", "tesseract", "600-cell")
CRYSTAL_COLOR = (0.35, 1.0, 0.85, 1.0)
CRYSTAL_SPIN = {"xw": 50.0, "yw": 35.0, "zw": 65.0}  # degrees/s: turning in the three w planes
MANIP_STEP = Range(0.1, 360.0, "degrees")  # a snapping step; zero is refused (no step: leave it out)
MANIP_SPEED = Range(1.0, 720.0, "degrees/s")
MANIP_REACH = Range(0.5, 100.0, "m")

ENERGY_TABLE = {
    "start": Field("number", default=0.0, range=ENERGY, sign="nonnegative"),
    "max": Field("number", default=100.0, range=ENERGY, sign="positive"),
    "w_cost": Field("number", default=0.0, range=ENERGY, sign="nonnegative"),
    "slice_cost": Field("number", default=0.0, range=ENERGY, sign="nonnegative"),
}
RADAR_TABLE = {
    "range": Field("number", default=20.0, range=RADAR_RANGE, sign="positive"),
    "w_scale": Field("number", default=0.5, range=RADAR_W_SCALE, sign="positive"),
}
CRYSTAL_TABLE = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "position": Field("vector", 4, range=COORD),
    "energy": Field("number", default=10.0, range=ENERGY, sign="positive"),
    "shape": Field("string", default="16-cell", choices=CRYSTAL_SHAPES),
    "size": Field("number", default=0.35, range=CRYSTAL_SIZE, sign="positive"),
    "color": Field("color", default=CRYSTAL_COLOR),
    "spin": Field("angles", default=None, range=SPIN),
    "respawn": Field("number", default=0.0, range=RESPAWN, sign="nonnegative"),
}
WEAPON_KINDS = ("gun", "blast", "field")
#: Every field a ``[[weapon]]`` (how a weapon behaves in the level; the player finds weapons in
#: ``[[pickup]]`` s) may have; which apply to which kind is :data:`WEAPON_FIELDS`.
WEAPON_TABLE = {
    "kind": Field("string", choices=WEAPON_KINDS),
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "cost": Field("number", default=None, range=ENERGY, sign="nonnegative"),
    "cooldown": Field("number", default=None, range=WEAPON_TIME, sign="nonnegative"),
    "speed": Field("number", default=None, range=WEAPON_SPEED, sign="positive"),
    "amplitude": Field("number", default=None, range=WEAPON_REACH, sign="nonnegative"),
    "period": Field("number", default=None, range=WEAPON_TIME, sign="positive"),
    "size": Field("number", default=None, range=WEAPON_REACH, sign="positive"),
    "mass": Field("number", default=None, range=MASS, sign="positive"),
    "lifetime": Field("number", default=None, range=WEAPON_TIME, sign="positive"),
    "max_live": Field("number", default=None, range=BULLET_CAP, sign="positive"),
    "radius": Field("number", default=None, range=WEAPON_REACH, sign="positive"),
    "duration": Field("number", default=None, range=WEAPON_TIME, sign="positive"),
    "ammo": Field("number", default=None, range=AMMO, sign="nonnegative"),
    "max_ammo": Field("number", default=None, range=AMMO, sign="positive"),
    "refill": Field("number", default=None, range=AMMO, sign="nonnegative"),
}
#: Each kind's fields and their defaults (a field of another kind is a problem, not ignored).
WEAPON_FIELDS = {
    "gun": {
        "name": "120-cell gun",
        "cost": 1.0,
        "cooldown": 0.35,
        "speed": 12.0,
        "amplitude": 1.0,
        "period": 2.0,
        "size": 0.15,
        "mass": 0.5,
        "lifetime": 6.0,
        "max_live": 8.0,
        "ammo": -1.0,
        "max_ammo": 30.0,
        "refill": 5.0,
    },
    "blast": {"name": "w-pull blast", "cost": 5.0, "cooldown": 1.5, "radius": 6.0, "duration": 0.6},
    "field": {"name": "wire field", "cost": 3.0, "cooldown": 1.0, "radius": 8.0, "duration": 5.0},
}
TARGET_SHAPES = CRYSTAL_SHAPES + ("120-cell",)
TARGET_COLOR = (1.0, 0.35, 0.3, 1.0)
TARGET_TABLE = {
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "position": Field("vector", 4, range=COORD),
    "size": Field("number", default=0.4, range=TARGET_SIZE, sign="positive"),
    "shape": Field("string", default="5-cell", choices=TARGET_SHAPES),
    "color": Field("color", default=TARGET_COLOR),
    "rotation": Field("angles", default=None, range=ANGLE),
    "spin": Field("angles", default=None, range=SPIN),
    "opens": Field("text", default="", range=Range(0, MAX_NAME_CHARS)),
    "disguised": Field("bool", default=False),
    "anchored": Field("bool", default=False),
}
MANIPULABLE_TABLE = {
    "object": Field("text", range=Range(0, MAX_NAME_CHARS)),
    "min": Field("angles", default=None, range=ANGLE),
    "max": Field("angles", default=None, range=ANGLE),
    "step": Field("number", default=None, range=MANIP_STEP, sign="positive"),
    "speed": Field("number", default=60.0, range=MANIP_SPEED, sign="positive"),
    "cost": Field("number", default=0.0, range=ENERGY, sign="nonnegative"),
    "reach": Field("number", default=6.0, range=MANIP_REACH, sign="positive"),
    "slide": Field("vector", 2, default=None, range=COORD, names="ab"),
}
#: How far off the slice a level may set its ghosts: past a few units a ghost no
#: longer says "just off the slice", and below 2 cm it coincides with the section.
GHOST_DISTANCE = Range(0.02, 5.0, "units of w")
GHOSTS_TABLE = {
    "enabled": Field("bool", default=True),
    "distance": Field("number", default=0.3, range=GHOST_DISTANCE, sign="positive"),
}
SEEK_TABLE = {
    "enabled": Field("bool", default=True),
}
#: The 4D camera: how fast the slice turns and the orbit moves, the frustum camera's field of view.
TURN_SPEED = Range(1.0, 720.0, "degrees/s")
CAMERA_FOV = Range(10.0, 150.0, "degrees")
FOCUS_DISTANCE = Range(0.5, 100.0, "m")
RETURN_TIME = Range(0.1, 10.0, "s")
CAMERA_TABLE = {
    "turn": Field("bool", default=True),
    "turn_speed": Field("number", default=60.0, range=TURN_SPEED, sign="positive"),
    "frustum": Field("bool", default=False),
    "frustum_cost": Field("number", default=1.0, range=ENERGY, sign="nonnegative"),
    "fov": Field("number", default=60.0, range=CAMERA_FOV, sign="positive"),
    "focus_distance": Field("number", default=4.0, range=FOCUS_DISTANCE, sign="positive"),
    "orbit_speed": Field("number", default=45.0, range=TURN_SPEED, sign="positive"),
    "return_time": Field("number", default=1.0, range=RETURN_TIME, sign="positive"),
}
#: Which of the tables below are arrays of tables (``[[crystal]]``); the others are single tables.
ARRAY_TABLES = ("crystal", "weapon", "target", "manipulable", "enemy", "animation", "checkpoint")
#: The tables format 2 adds, by top-level key.
MODELS = {
    "energy": ENERGY_TABLE,
    "radar": RADAR_TABLE,
    "crystal": CRYSTAL_TABLE,
    "weapon": WEAPON_TABLE,
    "target": TARGET_TABLE,
    "manipulable": MANIPULABLE_TABLE,
    "ghosts": GHOSTS_TABLE,
    "seek": SEEK_TABLE,
    "camera": CAMERA_TABLE,
    **enemy_tables.MODELS,
}


@dataclass
class CrystalSpec:
    """A ``[[crystal]]``: energy waiting at a 4D position.

    ``position (4,) float64``; ``size`` is the crystal's radius in metres;
    ``milli`` its energy in thousandths; ``respawn`` the seconds until it grows
    back after being taken (0: never).
    """

    name: str
    position: np.ndarray
    milli: int
    shape: str = "16-cell"
    size: float = 0.35
    color: tuple = CRYSTAL_COLOR
    spin_deg: dict = field(default_factory=lambda: dict(CRYSTAL_SPIN))
    respawn: float = 0.0


@dataclass
class EnergySpec:
    """``[energy]``: the bar's rules. ``enabled`` is False when the table is absent."""

    enabled: bool = False
    start: float = 0.0
    maximum: float = 100.0
    w_cost: float = 0.0  # energy per unit of w travelled
    slice_cost: float = 0.0  # energy per degree the slice turns away from where it rested

    @property
    def w_cost_milli(self) -> int:
        return int(round(self.w_cost * MILLI))

    @property
    def slice_cost_milli(self) -> int:
        """Energy per degree of slice turn, thousandths."""
        return int(round(self.slice_cost * MILLI))


@dataclass
class RadarSpec:
    """``[radar]``: metres to the disc's rim, and disc radii per unit of w offset."""

    range: float = 20.0
    w_scale: float = 0.5


@dataclass
class GhostsSpec:
    """``[ghosts]``: whether the level shows ghosts of what lies just off the slice, and how
    far off (units of w; the player's settings may scale it). On when the table is absent."""

    enabled: bool = True
    distance: float = 0.3


@dataclass
class SeekSpec:
    """``[seek]``: whether the seek key works in this level. On when the table is absent."""

    enabled: bool = True


@dataclass
class CameraSpec:
    """``[camera]``: what the player may do with the 4D camera. Absent: nothing (the slice
    stays axis-aligned, no frustum projection).

    ``turn``: the slice may be turned in the xw, yw and zw planes at ``turn_speed`` degrees/s
    (90-degree steps and the snap glide at twice that). ``frustum``: the switch key detaches
    the 4D camera into frustum projection, paid ``frustum_cost`` energy per second while
    detached; ``fov`` is its field of view (degrees), ``focus_distance`` how far ahead of the
    eye the orbit's focus point is set (metres), ``orbit_speed`` degrees/s, ``return_time`` the
    glide back in seconds.
    """

    enabled: bool = False
    turn: bool = False
    turn_speed: float = 60.0
    frustum: bool = False
    frustum_cost: float = 1.0
    fov: float = 60.0
    focus_distance: float = 4.0
    orbit_speed: float = 45.0
    return_time: float = 1.0

    @property
    def frustum_cost_milli(self) -> int:
        """Energy per second while detached, thousandths."""
        return int(round(self.frustum_cost * MILLI))


def read_camera(r, data) -> CameraSpec:
    """The ``[camera]`` table (``CameraSpec()``, nothing enabled, when absent)."""
    v = r.values(data, "camera", CAMERA_TABLE)
    if v is None:
        return CameraSpec()
    return CameraSpec(True, **{k: v[k] for k in CAMERA_TABLE})


def read_ghosts(r, data) -> GhostsSpec:
    """The ``[ghosts]`` table (defaults when absent)."""
    v = r.values(data, "ghosts", GHOSTS_TABLE)
    return GhostsSpec() if v is None else GhostsSpec(v["enabled"], v["distance"])


def read_seek(r, data) -> SeekSpec:
    """The ``[seek]`` table (defaults when absent)."""
    v = r.values(data, "seek", SEEK_TABLE)
    return SeekSpec() if v is None else SeekSpec(v["enabled"])


def read_energy(r, data) -> EnergySpec:
    """The ``[energy]`` table (``r`` is the level loader's reader); absent: no energy bar."""
    v = r.values(data, "energy", ENERGY_TABLE)
    if v is None:
        return EnergySpec()
    if v["start"] > v["max"]:
        r.problem("[energy]", f"field 'start': {v['start']:g} is more than 'max' ({v['max']:g})")
    return EnergySpec(True, min(v["start"], v["max"]), v["max"], v["w_cost"], v["slice_cost"])


def read_radar(r, data) -> RadarSpec | None:
    """The ``[radar]`` table, or None when the level has none (no radar on screen)."""
    v = r.values(data, "radar", RADAR_TABLE)
    return None if v is None else RadarSpec(v["range"], v["w_scale"])


def read_crystals(r, data, w_range) -> list[CrystalSpec]:
    """The ``[[crystal]]`` tables; ``w_range`` is the level's, or None when it is broken."""
    out = []
    for i, t in enumerate(r.entries(data, "crystal", "top level", lambda k: f"[[crystal]] #{k}"), 1):
        where = f"[[crystal]] #{i}"
        r.unknown(t, CRYSTAL_TABLE, where)
        name = r.read(t, CRYSTAL_TABLE, where, keys=("name",), name=f"crystal{i}")["name"]
        where = f"[[crystal]] #{i} '{name}'"
        n = len(r.problems)
        v = r.read(t, CRYSTAL_TABLE, where, keys=("position",))  # first, so its w is judged whatever else is wrong
        w = v["position"][3]
        position_ok = len(r.problems) == n
        v |= r.read(t, CRYSTAL_TABLE, where, keys=[k for k in CRYSTAL_TABLE if k not in ("name", "position")],
                    spin=dict(CRYSTAL_SPIN))  # fmt: skip
        if position_ok and w_range is not None and not w_range[0] <= w <= w_range[1]:
            r.problem(
                where,
                f"field 'position': w = {w:g} is outside the level's w_range [{w_range[0]:g}, {w_range[1]:g}], "
                "so the crystal can never be reached",
            )
        out.append(
            CrystalSpec(
                name,
                v["position"],
                int(round(v["energy"] * MILLI)),
                v["shape"],
                v["size"],
                v["color"],
                v["spin"] if "spin" in t else dict(CRYSTAL_SPIN),
                v["respawn"],
            )
        )
    return out


@dataclass
class WeaponSpec:
    """A weapon as a level has it: a ``[[weapon]]`` table's tuning, or the defaults of its kind.

    Times in seconds, lengths in metres; ``cost_milli`` is the energy one use
    costs, in thousandths. Fields that do not apply to ``kind`` keep their
    defaults and are unused.

    Attributes
    ----------
    kind : {"gun", "blast", "field"}
    speed, amplitude, period, size, mass, lifetime, max_live
        The gun's bullet: muzzle speed, the amplitude and period of its w
        oscillation, its radius and mass, how long it lives, how many may fly.
    radius, duration
        The blast's and the field's reach, and how long they act.
    ammo, max_ammo, refill
        A gun with ``ammo >= 0`` fires rounds instead of paying energy: it starts
        with ``ammo``, holds at most ``max_ammo`` and every crystal collected adds
        ``refill``. ``ammo = -1`` (the default) pays ``cost`` from the energy bar.
    """

    kind: str
    name: str
    cost_milli: int
    cooldown: float
    speed: float = 12.0
    amplitude: float = 1.0
    period: float = 2.0
    size: float = 0.15
    mass: float = 0.5
    lifetime: float = 6.0
    max_live: int = 8
    radius: float = 6.0
    duration: float = 0.6
    ammo: int = -1
    max_ammo: int = 30
    refill: int = 5


@dataclass
class TargetSpec:
    """A ``[[target]]``: a 4D switch that reacts to a bullet.

    ``position (4,) float64`` may lie at a w the player cannot reach; ``size``
    is its radius (drawn and hit); hitting it removes the ``[[object]]`` named
    ``opens`` (a door), if any. A ``disguised`` target is drawn like ordinary
    scenery and stays off the radar; an ``anchored`` one is fixed at its w: the
    blast does not move it (a switch meant for another tool, with the blast in hand).
    """

    name: str
    position: np.ndarray
    size: float = 0.4
    shape: str = "5-cell"
    color: tuple = TARGET_COLOR
    rotation_deg: dict = field(default_factory=dict)
    spin_deg: dict = field(default_factory=dict)
    opens: str = ""
    disguised: bool = False
    anchored: bool = False


def read_weapons(r, data) -> list[tuple[int, WeaponSpec]]:
    """The ``[[weapon]]`` tables that read well, with their numbers from 1, in order: how each
    weapon behaves in the level (they give none: see :mod:`.pickups`)."""
    out = []
    for i, t in enumerate(r.entries(data, "weapon", "top level", lambda k: f"[[weapon]] #{k}"), 1):
        where = f"[[weapon]] #{i}"
        r.unknown(t, WEAPON_TABLE, where)
        n = len(r.problems)
        kind = r.read(t, WEAPON_TABLE, where, keys=("kind",))["kind"]
        if len(r.problems) != n:
            continue  # no defaults to read the rest by
        defaults = WEAPON_FIELDS[kind]
        for k in t:
            if k in WEAPON_TABLE and k != "kind" and k not in defaults:
                r.problem(where, f"field '{k}' does not apply to a {kind} (its fields: {', '.join(defaults)})")
        v = r.read(t, WEAPON_TABLE, where, keys=list(defaults), **defaults)
        counts = {}
        for k in ("max_live", "ammo", "max_ammo", "refill"):
            if k in v:
                if v[k] != int(v[k]) and k in t:
                    r.problem(where, f"field '{k}': expected a whole number, got {v[k]:g}")
                counts[k] = int(v[k])
        if "ammo" in t and "max_ammo" in v and v["ammo"] > v["max_ammo"]:
            r.problem(where, f"field 'ammo': {v['ammo']:g} is more than 'max_ammo' ({v['max_ammo']:g})")
        extra = {k: v[k] for k in defaults if k not in ("name", "cost", "cooldown") and k not in counts}
        out.append((i, WeaponSpec(kind, v["name"], int(round(v["cost"] * MILLI)), v["cooldown"], **counts, **extra)))
    return out


def read_targets(r, data, object_names) -> list[TargetSpec]:
    """The ``[[target]]`` tables; ``opens`` must name one of ``object_names``."""
    out = []
    for i, t in enumerate(r.entries(data, "target", "top level", lambda k: f"[[target]] #{k}"), 1):
        where = f"[[target]] #{i}"
        r.unknown(t, TARGET_TABLE, where)
        name = r.read(t, TARGET_TABLE, where, keys=("name",), name=f"target{i}")["name"]
        where = f"[[target]] #{i} '{name}'"
        v = r.read(t, TARGET_TABLE, where, keys=[k for k in TARGET_TABLE if k != "name"])
        if v["opens"] and v["opens"] not in object_names:
            r.problem(where, f"field 'opens': no [[object]] is named {v['opens']!r}")
        out.append(
            TargetSpec(
                name,
                v["position"],
                v["size"],
                v["shape"],
                v["color"],
                v["rotation"],
                v["spin"],
                v["opens"],
                v["disguised"],
                v["anchored"],
            )
        )
    return out


@dataclass
class ManipulableSpec:
    """A ``[[manipulable]]``: a 4D object the player may turn with the manipulation tool.

    ``planes`` maps each plane the object may turn in to its limits
    ``(low, high)`` in degrees, as offsets from the object's ``rotation``
    (``low <= 0 <= high``); ``step`` the snapping step in degrees (None: turn
    freely); ``speed`` degrees per second; ``cost_milli`` energy per degree in
    thousandths; ``reach`` how far (metres) the player may aim at it from.
    """

    object: str
    planes: dict
    step: float | None = None
    speed: float = 60.0
    cost_milli: int = 0
    reach: float = 6.0
    slide: tuple | None = None  # (low, high) metres it may move along w from its position; None: it may not


def read_manipulables(r, data, objects) -> list[ManipulableSpec]:
    """The ``[[manipulable]]`` tables; ``objects`` are the level's :class:`ObjectSpec` s.

    A plane is allowed when it appears in ``min`` or ``max`` (a missing side is
    0: ``max = { xw = 90 }`` turns from 0 to 90 degrees). Each table must name a
    solid 4D object that is not a rigid body and does not spin, once.
    """
    out = []
    by_name = {o.name: o for o in objects}
    if "manipulable" in data:
        tables = r.array_of_tables(data, "manipulable", "top level")[: len(objects) + 1]
    else:
        tables = []
    seen = set()
    for i, t in enumerate(tables, 1):
        where = f"[[manipulable]] #{i}"
        r.unknown(t, MANIPULABLE_TABLE, where)
        name = r.read(t, MANIPULABLE_TABLE, where, keys=("object",))["object"]
        if name:
            where = f"[[manipulable]] #{i} '{name}'"
        v = r.read(t, MANIPULABLE_TABLE, where, keys=[k for k in MANIPULABLE_TABLE if k != "object"])
        o = by_name.get(name)
        if "object" in t and name and o is None:
            r.problem(where, f"field 'object': no [[object]] is named '{name}'")
        elif o is not None:
            if o.body != "none":
                r.problem(where, f"field 'object': '{name}' is a rigid body; only objects with body = \"none\" turn")
            if any(x != 0.0 for x in o.spin_deg.values()):
                r.problem(where, f"field 'object': '{name}' has a spin; a manipulable object must not spin")
            if name in seen:
                r.problem(where, f"field 'object': '{name}' is already manipulable (one table per object)")
            seen.add(name)
        planes = {}
        for plane in sorted(set(v["min"]) | set(v["max"]), key=PLANE_ORDER.index):
            lo, hi = v["min"].get(plane, 0.0), v["max"].get(plane, 0.0)
            if lo > 0.0 or hi < 0.0 or lo >= hi:
                r.problem(
                    where,
                    f"plane '{plane}': limits min = {lo:g}, max = {hi:g} are inverted or empty "
                    "(expected min <= 0 <= max and min < max, in degrees from the object's rotation)",
                )
            planes[plane] = (lo, hi)
        slide = None
        if v["slide"] is not None:
            lo, hi = (float(x) for x in v["slide"])
            if lo > 0.0 or hi < 0.0 or lo >= hi:
                r.problem(
                    where,
                    f"field 'slide': [{lo:g}, {hi:g}] is inverted or empty "
                    "(expected [low, high] metres with low <= 0 <= high and low < high)",
                )
            elif len(planes) > 2:
                r.problem(where, "field 'slide': an object with three planes has no keys left to slide it")
            slide = (lo, hi)
        if not planes and slide is None and "min" not in t and "max" not in t:
            r.problem(where, "nothing to do: give 'max' and/or 'min', e.g. max = { xw = 90 }, or 'slide'")
        out.append(
            ManipulableSpec(name, planes, v["step"], v["speed"], int(round(v["cost"] * MILLI)), v["reach"], slide)
        )
    return out
