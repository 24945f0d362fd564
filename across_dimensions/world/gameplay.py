"""Level tables of the game's systems (level format 2): crystals, energy, radar.

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

from .fields import Field
from .limits import COORD, CRYSTAL_SIZE, ENERGY, MAX_NAME_CHARS, RADAR_RANGE, RADAR_W_SCALE, RESPAWN, SPIN, Range

CRYSTAL_SHAPES = ("16-cell", "24-cell", "5-cell", "tesseract", "600-cell")
CRYSTAL_COLOR = (0.35, 1.0, 0.85, 1.0)
CRYSTAL_SPIN = {"xw": 50.0, "yw": 35.0, "zw": 65.0}  # degrees/s: turning in the three w planes
MILLI = 1000  # energy is counted in thousandths (see game.energy)

ENERGY_TABLE = {
    "start": Field("number", default=0.0, range=ENERGY, sign="nonnegative"),
    "max": Field("number", default=100.0, range=ENERGY, sign="positive"),
    "w_cost": Field("number", default=0.0, range=ENERGY, sign="nonnegative"),
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
#: The tables format 2 adds, by top-level key.
MODELS = {
    "energy": ENERGY_TABLE,
    "radar": RADAR_TABLE,
    "crystal": CRYSTAL_TABLE,
    "ghosts": GHOSTS_TABLE,
    "seek": SEEK_TABLE,
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

    @property
    def w_cost_milli(self) -> int:
        return int(round(self.w_cost * MILLI))


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


def read_ghosts(r, data) -> GhostsSpec:
    """The ``[ghosts]`` table (defaults when absent)."""
    if "ghosts" not in data:
        return GhostsSpec()
    t = r.table(data, "ghosts", "[ghosts]")
    r.unknown(t, GHOSTS_TABLE, "[ghosts]")
    v = r.read(t, GHOSTS_TABLE, "[ghosts]")
    return GhostsSpec(v["enabled"], v["distance"])


def read_seek(r, data) -> SeekSpec:
    """The ``[seek]`` table (defaults when absent)."""
    if "seek" not in data:
        return SeekSpec()
    t = r.table(data, "seek", "[seek]")
    r.unknown(t, SEEK_TABLE, "[seek]")
    v = r.read(t, SEEK_TABLE, "[seek]")
    return SeekSpec(v["enabled"])


def read_energy(r, data) -> EnergySpec:
    """The ``[energy]`` table (``r`` is the level loader's reader)."""
    if "energy" not in data:
        return EnergySpec()
    t = r.table(data, "energy", "[energy]")
    r.unknown(t, ENERGY_TABLE, "[energy]")
    v = r.read(t, ENERGY_TABLE, "[energy]")
    if v["start"] > v["max"]:
        r.problem("[energy]", f"field 'start': {v['start']:g} is more than 'max' ({v['max']:g})")
    return EnergySpec(True, min(v["start"], v["max"]), v["max"], v["w_cost"])


def read_radar(r, data) -> RadarSpec | None:
    """The ``[radar]`` table, or None when the level has none (no radar on screen)."""
    if "radar" not in data:
        return None
    t = r.table(data, "radar", "[radar]")
    r.unknown(t, RADAR_TABLE, "[radar]")
    v = r.read(t, RADAR_TABLE, "[radar]")
    return RadarSpec(v["range"], v["w_scale"])


def read_crystals(r, data, w_range) -> list[CrystalSpec]:
    """The ``[[crystal]]`` tables; ``w_range`` is the level's, or None when it is broken."""
    out = []
    for i, t in enumerate(r.entries(data, "crystal", "top level", lambda k: f"[[crystal]] #{k}"), 1):
        where = f"[[crystal]] #{i}"
        r.unknown(t, CRYSTAL_TABLE, where)
        name = r.read(t, CRYSTAL_TABLE, where, keys=("name",), name=f"crystal{i}")["name"]
        where = f"[[crystal]] #{i} '{name}'"
        n = len(r.problems)
        v = r.read(t, CRYSTAL_TABLE, where, keys=[k for k in CRYSTAL_TABLE if k != "name"], spin=dict(CRYSTAL_SPIN))
        w = v["position"][3]
        if len(r.problems) == n and w_range is not None and not w_range[0] <= w <= w_range[1]:
            r.problem(
                where,
                f"field 'position': w = {w:g} is outside the level's w_range {list(w_range)}, "
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
