"""Level tables for the game's systems (level format 2): crystals, energy, radar.

Each table is one small model: a dataclass with the defaults a level gets when
it leaves the table out, and a ``read`` function that checks the table and
reports every problem through the level loader's reader (naming the file, the
entry and the field). :func:`across_dimensions.world.level.load_level` calls
them; format-1 levels have none of these tables and get the defaults (no
energy bar, moving along w is free; a radar with the default range).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

CRYSTAL_SHAPES = ("16-cell", "24-cell", "5-cell", "tesseract", "600-cell")
CRYSTAL_COLOR = (0.35, 1.0, 0.85, 1.0)
CRYSTAL_SPIN = {"xw": 50.0, "yw": 35.0, "zw": 65.0}  # degrees/s: turning in the three w planes
MILLI = 1000
MAX_ENERGY = 1e6
MAX_CRYSTALS = 1000


@dataclass
class CrystalSpec:
    """A ``[[crystal]]``: energy waiting at a 4D position.

    ``position (4,) float64``; ``size`` is the crystal's radius in metres.
    """

    name: str
    position: np.ndarray
    milli: int
    shape: str = "16-cell"
    size: float = 0.35
    color: tuple = CRYSTAL_COLOR
    spin_deg: dict = field(default_factory=lambda: dict(CRYSTAL_SPIN))
    respawn: float = 0.0  # seconds until it grows back after being taken; 0: never


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


def read_energy(r, data) -> EnergySpec:
    t = r.table(data, "energy", "[energy]")
    if "energy" not in data:
        return EnergySpec()
    r.unknown(t, {"start", "max", "w_cost"}, "[energy]")
    maximum = r.number(t, "max", "[energy]", default=100.0, lo=0.001, hi=MAX_ENERGY)
    start = r.number(t, "start", "[energy]", default=0.0, lo=0.0, hi=MAX_ENERGY)
    if start > maximum:
        r.problem("[energy]", f"field 'start': {start:g} is more than 'max' ({maximum:g})")
    w_cost = r.number(t, "w_cost", "[energy]", default=0.0, lo=0.0, hi=MAX_ENERGY)
    return EnergySpec(True, min(start, maximum), maximum, w_cost)


def read_radar(r, data) -> RadarSpec:
    t = r.table(data, "radar", "[radar]")
    r.unknown(t, {"range", "w_scale"}, "[radar]")
    return RadarSpec(r.number(t, "range", "[radar]", default=20.0, lo=0.0, hi=1e4, lo_open=True),
                     r.number(t, "w_scale", "[radar]", default=0.5, lo=0.0, hi=100.0, lo_open=True))


def read_crystals(r, data, w_range) -> list[CrystalSpec]:
    out = []
    tables = r.array_of_tables(data, "crystal", "top level")
    if len(tables) > MAX_CRYSTALS:
        r.problem("top level", f"{len(tables)} [[crystal]] entries; a level may have at most {MAX_CRYSTALS}")
        return out
    for i, t in enumerate(tables, 1):
        where = f"[[crystal]] #{i}"
        r.unknown(t, {"name", "position", "energy", "shape", "size", "color", "spin", "respawn"}, where)
        name = r.string(t, "name", where, default=f"crystal{i}")
        where = f"[[crystal]] #{i} '{name}'"
        n = len(r.problems)
        position = r.vector(t, "position", where, 4)
        if len(r.problems) == n and w_range is not None and not w_range[0] <= position[3] <= w_range[1]:
            r.problem(where, f"field 'position': w = {position[3]:g} is outside the level's w_range "
                             f"{list(w_range)}, so the crystal can never be reached")
        energy = r.number(t, "energy", where, default=10.0, lo=0.0, hi=MAX_ENERGY, lo_open=True)
        shape = r.string(t, "shape", where, default="16-cell", choices=CRYSTAL_SHAPES)
        size = r.number(t, "size", where, default=0.35, lo=0.05, hi=5.0)
        spin = r.angles(t, "spin", where) if "spin" in t else dict(CRYSTAL_SPIN)
        respawn = r.number(t, "respawn", where, default=0.0, lo=0.0, hi=3600.0)
        out.append(CrystalSpec(name, position, int(round(energy * MILLI)), shape, size, r.color(t, where, CRYSTAL_COLOR),
                               spin, respawn))
    return out
