"""What a level may ask for: how many things, which values, and how much work.

Everything a level file can request is bounded here, in one place, so that
whatever ``check-level`` accepts loads in bounded time and memory and plays
with finite numbers. ``levels/README.md`` ("Limits and ranges") documents the
same figures; ``tests/test_level_limits.py`` checks that the two agree.

- **Counts** (:data:`MAX_COUNTS`): boxes, meshes, worlds, 4D objects, rigid
  bodies, hints. The loader stops reading a kind at its limit, so a file with
  a million boxes costs no more to check than one with a thousand and one.
- **Ranges** (:class:`Range` constants): every number of the format has one,
  used by the field tables of :mod:`.level`.
- **Work**: tetrahedra per object and in total are estimated from the shape
  and its parameters (:func:`shape_tets`) with the closed forms of
  ``core/shapes.py``, without building anything; :func:`tick_cost_ms` turns
  the level's content into an estimated cost per frame, and ``check-level``
  warns when it exceeds one 60 Hz frame.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass

from ..core.fileio import MiB

__all__ = [
    "FRAME_MS",
    "MAX_COUNTS",
    "MAX_LEVEL_BYTES",
    "MAX_OBJECT_TETS",
    "MAX_TOTAL_TETS",
    "Range",
    "asset_object_tets",
    "shape_tets",
    "tick_cost_ms",
    "world_tets",
]

#: Largest level file read. A level with every count at its limit is about
#: 200 KiB, comments aside. Parsing is the cost of checking a big file: here
#: (2 busy cores) 1 MiB of TOML took 3-5 s to parse, so half that keeps
#: check-level at a second or two on anything it is handed, and a file of a
#: million boxes (tens of MiB) is refused before it is read.
MAX_LEVEL_BYTES = MiB // 2

#: Most entries of each kind in one level: table name -> (limit, what it counts).
#: Boxes and meshes count those inside worlds too.
MAX_COUNTS = {
    "box": (1000, "boxes ([[box]] and [[world.box]])"),
    "mesh": (64, "meshes ([[mesh]] and [[world.mesh]])"),
    "world": (32, "worlds"),
    "object": (256, "4D objects"),
    "body": (200, "rigid bodies (objects with a body)"),
    "crystal": (1000, "crystals"),
    "hints": (20, "hints"),
    "weapon": (9, "weapons (number keys 1 to 9 select them)"),
    "target": (200, "targets"),
    "enemy": (64, "enemies"),
    "animation": (512, "animation keyframes ([[animation]])"),
    "checkpoint": (64, "checkpoints"),
    "secret": (32, "secrets"),
}

MAX_NAME_CHARS = 100  # level, world and object names
MAX_TEXT_CHARS = 1000  # description and each hint

#: Tetrahedra one 4D object may have (a 128 x 128 duoprism has 98,304; a
#: hypersphere with subdivisions = 2 has 76,800, with 3 it has 307,200: too many
#: for a level, though ``shape`` builds it).
MAX_OBJECT_TETS = 200_000
#: Tetrahedra of all the level's 4D content (objects and extended worlds). Moving
#: along w re-slices solid content up to three times a tick (the walker's slice,
#: the slice it steps to, the picture): about 60 ms per million in the worst case
#: (below), so this keeps the heaviest level near 25 ms, and check-level warns.
MAX_TOTAL_TETS = 400_000


@dataclass(frozen=True)
class Range:
    """A closed interval ``[lo, hi]`` of accepted values, with its unit for messages."""

    lo: float
    hi: float
    unit: str = ""

    def __contains__(self, v) -> bool:
        return self.lo <= v <= self.hi

    def text(self) -> str:
        """``"from -10000 to 10000 m"``."""
        return f"from {self.lo:g} to {self.hi:g}{' ' + self.unit if self.unit else ''}"


# The ranges of the level format. Why these: coordinates within 10 km keep
# float32 vertices exact to a millimetre; sizes from 1 mm to 10 km stay well
# inside float range even when multiplied (size x scale x shape radius); the
# dynamic figures (gravity, speeds, spin, mass ratios) are those at which the
# physics tick of 1/60 s with 4 substeps stays stable.
COORD = Range(-1e4, 1e4, "m")  # positions, centres, world w, w ranges
SIZE = Range(1e-3, 1e4, "m")  # box sizes, depths, shape radii and sizes
SCALE = Range(1e-3, 1e4)  # mesh and object scale factors
ANGLE = Range(-3600.0, 3600.0, "degrees")  # yaw, rotation (ten turns either way)
SPIN = Range(-720.0, 720.0, "degrees/s")  # two turns a second
SPEED = Range(-50.0, 50.0, "m/s")  # each component of an initial velocity
MASS = Range(1e-3, 1e4, "kg")
GRAVITY_MAX = 100.0  # m/s^2, the magnitude of [physics] gravity (about 10 g)
INVERSE_CUBE_G = Range(0.0, 10.0)
ROLLING_RESISTANCE = Range(0.0, 1.0)
COLOR = Range(0.0, 1.0)
ENERGY = Range(0.0, 1e6)  # energy amounts: bar maximum, start, crystal energy, cost per unit of w
MILLI = 1000  # energy is counted in thousandths, exactly (see game.energy)
RADAR_RANGE = Range(1.0, 1e3, "m")
RADAR_W_SCALE = Range(0.01, 100.0)  # disc radii per unit of w
CRYSTAL_SIZE = Range(0.05, 5.0, "m")
RESPAWN = Range(0.0, 3600.0, "s")
WEAPON_SPEED = Range(0.1, 200.0, "m/s")  # a bullet's muzzle speed
WEAPON_TIME = Range(0.0, 600.0, "s")  # cooldowns, periods, lifetimes, durations
WEAPON_REACH = Range(0.01, 1000.0, "m")  # bullet radius and amplitude, blast and field radius
BULLET_CAP = Range(1.0, 64.0)  # live bullets at once
TARGET_SIZE = Range(0.05, 10.0, "m")
AMMO = Range(0.0, 1e4)  # rounds a gun holds or a crystal gives
ENEMY_HEALTH = Range(1.0, 1e4)  # hits an enemy takes (zero is refused: it would be dead on arrival)
ENEMY_SIZE = Range(0.1, 10.0, "m")  # an enemy body's reach from its centre
ENEMY_SPEED = Range(0.0, 50.0, "m/s")
ENEMY_DAMAGE = Range(0.0, 1e4)  # health points one enemy shot takes
KEY_TIME = Range(0.0, 600.0, "s")  # an animation keyframe's time
PLAYER_HEALTH = Range(1.0, 1e4)

# Rigid bodies: the envelope in which the physics step stays finite, found by
# stepping random scenes for 600 ticks (4 bodies each: random shapes, sizes,
# masses from 1e-3 to 1e4 kg, velocities, spins, gravity of 100 m/s^2 in a
# random direction, inverse-cube pull 0 or 10, 1 mm thin floors and walls).
# With spins of 3600 degrees/s, speeds of 100 m/s or bodies 10 times longer
# than wide, 2-25 % of the scenes blew up (NaN or past 1e6 m). Inside this
# envelope 3 of 200 still went NaN, every time after bodies had fallen
# through a thin floor and kept speeding up; with the walls world/scene.py
# puts around every level, none of 200 did (tests/test_level_limits.py plays
# 40 such random levels).
BODY_SIZE = Range(0.01, 100.0, "m")  # the collider's extent along each axis
BODY_ASPECT = 4.0  # longest extent / shortest

#: Shapes with two lengths: they may differ by at most this factor. Beyond it
#: the builders' tolerances see slivers (a duoprism 3 x 128 with r1 / r2 = 100
#: has degenerate tetrahedra), so a level that checks would fail to play.
MAX_SHAPE_ASPECT = 10.0
SHAPE_LENGTH_PAIRS = {"duoprism": ("r1", "r2"), "cubinder": ("radius", "height"), "spherinder": ("radius", "height")}


def shape_aspect_problem(shape: str, params: dict) -> str | None:
    """Why two lengths of ``shape`` are too different to build, or None."""
    pair = SHAPE_LENGTH_PAIRS.get(shape)
    if pair is None:
        return None
    p = {**_defaults(shape), **params}
    a, b = float(p[pair[0]]), float(p[pair[1]])
    if max(a, b) > MAX_SHAPE_ASPECT * min(a, b):
        return (
            f"'{pair[0]}' and '{pair[1]}' may differ by a factor of at most {MAX_SHAPE_ASPECT:g}, got {a:g} and {b:g}"
        )
    return None


# ------------------------------------------------------------------ bodies
_LENGTHS = ("radius", "size", "r1", "r2", "height")
#: Which length parameter stretches each axis (x, y, z, w) of a shape.
_AXIS_LENGTH = {
    "duoprism": ("r1", "r1", "r2", "r2"),
    "cubinder": ("radius", "height", "radius", "height"),
    "spherinder": ("radius", "radius", "radius", "height"),
    "tesseract": ("size",) * 4,
}
_unit_vertices_cache: dict = {}


def shape_vertices(shape: str, params: dict):
    """Vertices ``(n, 4) float64`` of ``shape`` with these (checked) parameters.

    Built once per shape and whole-number parameters with unit lengths (and at
    most one subdivision: more only adds points on the same sphere), then
    stretched per axis, so measuring a body costs next to nothing.
    """
    import numpy as np

    from ..core.shapes import make_shape

    p = {**_defaults(shape), **params}
    whole = {k: v for k, v in p.items() if k in ("p", "q", "segments", "subdivisions")}
    if "subdivisions" in whole:
        whole["subdivisions"] = min(int(whole["subdivisions"]), 1)
    key = (shape, tuple(sorted(whole.items())))
    if key not in _unit_vertices_cache:
        units = {k: 1.0 for k in p if k in _LENGTHS}
        _unit_vertices_cache[key] = make_shape(shape, **whole, **units).vertices.astype(np.float64)
    axes = _AXIS_LENGTH.get(shape, ("radius",) * 4)
    return _unit_vertices_cache[key] * np.array([float(p[a]) for a in axes])


def body_extent(vertices, scale, body: str):
    """Extent ``(4,) float64`` of the collider world/scene.py gives an object.

    ``vertices (n, 4)`` in the object's frame, ``scale (4,)``; a
    ``hypersphere`` body is a ball around the origin through the farthest
    vertex, a ``hypercube`` the scaled bounding box.
    """
    import numpy as np

    v = np.asarray(vertices, dtype=np.float64)
    scale = np.asarray(scale, dtype=np.float64)
    if body == "hypersphere":
        return np.full(4, 2.0 * float(np.linalg.norm(v, axis=1).max()) * float(scale.max()))
    return np.ptp(v, axis=0) * scale


def body_problem(extent) -> str | None:
    """Why a collider of this extent is outside the physics envelope, or None."""
    lo, hi = float(min(extent)), float(max(extent))
    tol = 1 + 1e-6  # shape vertices are float32: a body of exactly the limit must pass
    if lo * tol < BODY_SIZE.lo or hi > BODY_SIZE.hi * tol or hi > BODY_ASPECT * lo * tol:
        shown = ", ".join(f"{x:.3g}" for x in extent)
        return (
            f"as a rigid body it measures [{shown}] m along x, y, z, w; a body must measure "
            f"{BODY_SIZE.text()} along each axis, the longest at most {BODY_ASPECT:g} times the shortest"
        )
    return None


# ------------------------------------------------------------------ tetrahedra
# Closed forms of the tetrahedra core/shapes.py builds (tests/test_level_limits.py
# compares them with the built meshes). Parameters missing from ``params`` take
# the builder's defaults.
_FIXED_TETS = {
    "5-cell": 5,
    "simplex": 5,
    "tesseract": 48,
    "16-cell": 16,
    "24-cell": 96,
    "120-cell": 3240,
    "600-cell": 600,
}


def _defaults(shape: str) -> dict:
    from ..core.shapes import SHAPES

    return {
        k: p.default
        for k, p in inspect.signature(SHAPES[shape]).parameters.items()
        if p.default is not inspect.Parameter.empty
    }


def shape_tets(shape: str, params: dict) -> int:
    """Tetrahedra of ``shapes.make_shape(shape, **params)``, without building it.

    ``params`` must already be checked (whole numbers in range).
    """
    if shape in _FIXED_TETS:
        return _FIXED_TETS[shape]
    p = {**_defaults(shape), **params}
    if shape == "hypersphere":  # the 600-cell, each tet split in 8 per subdivision
        return 600 * 8 ** int(p["subdivisions"])
    if shape == "spherinder":  # an icosphere ball (20 * 4^s faces) times a segment
        return 100 * 4 ** int(p["subdivisions"]) - 10
    if shape == "duoprism":  # q p-gonal prisms and p q-gonal prisms, each coned from a corner
        a, b = int(p["p"]), int(p["q"])
        return 6 * a * b - 6 * a - 6 * b
    if shape == "duocylinder":
        k = int(p["segments"])
        return 6 * k * k - 12 * k
    if shape == "cubinder":
        return 18 * int(p["segments"]) - 24
    raise KeyError(shape)


#: Tetrahedra assumed for one 3D asset filled with tetrahedra (the shipped
#: ones fill with 500 to 2,700; asset files themselves are bounded by the bake
#: step). A level is checked without baking, so this is an estimate.
ASSET_SOLID_TETS = 3000
#: Lifting a 3D tetrahedron to a prism over one w layer gives 3 4D ones.
_TETS_PER_LAYER = 3
#: A box of an extended world as world/scene.py builds it (WORLD_LAYERS = 9;
#: a test checks the figure).
WORLD_BOX_TETS = 240


def asset_object_tets() -> int:
    """Estimated tetrahedra of a lifted-asset [[object]] (a prism: one layer)."""
    return ASSET_SOLID_TETS * _TETS_PER_LAYER


def world_tets(n_boxes: int, n_meshes: int, layers: int = 9) -> int:
    """Estimated tetrahedra of an extended world with these parts."""
    return n_boxes * WORLD_BOX_TETS + n_meshes * ASSET_SOLID_TETS * _TETS_PER_LAYER * (layers - 1)


# ------------------------------------------------------------------ frame cost
# Cost per frame on a typical 2-core machine with Mesa's software rasterizer,
# at 1280x720, while the player moves along w (every section is recomputed,
# uploaded and drawn: the worst steady case). Calibrated on this project's
# machine: generated levels (a 40 x 40 m floor and N spinning objects in a
# grid) of 1-200 tesseracts, 100-200 120-cells, 100-200 hypersphere bodies and
# 8 duoprisms 128x128, each timed as the median over 240 ticks of Game.step +
# Game.frame + Renderer.draw into a 1280x720 offscreen framebuffer (EGL,
# llvmpipe) + ctx.finish(), holding w_ana / w_kata. The machine was shared (load ~7 on 2 cores) and
# `across-dimensions bench` showed its physics median at 11 ms wall against
# 3.2 ms CPU, so the measured times were divided by 3, the same factor:
#   base (player, 3D world, floor, fill):  ~5 ms      (16 ms measured)
#   per 4D object or world drawn:          ~0.06 ms   (200 tesseracts: 48 ms)
#   per million tetrahedra re-sliced:      ~60 ms     (10 solid duoprisms 128x128 that the
#                                                      slice cuts everywhere, 0.98 M: 120 ms per
#                                                      tick for the walker alone, measured again
#                                                      with the load at ~3; the slicer's worst case
#                                                      is ~32 M tets/s and a tick slices solids twice)
#   per rigid body (solver, contacts):     ~0.016 ms  (bench: 200 bodies 3.2 ms)
#   per enemy:                             ~0.35 ms   (its state machine, its body re-sliced every tick
#                                                      as its animation turns it, and three drawables:
#                                                      the section and its two ghosts. Game.step +
#                                                      Game.frame in CPU time, the lowest median of three
#                                                      alternated runs of 240 ticks: 64 tree-shaped
#                                                      enemies 10.9 ms, 64 swarms 8.4 ms, an empty floor
#                                                      0.20 ms, so 0.17 ms each, plus 3 x 0.06 ms drawn)
#   per crystal:                           ~0.003 ms  (1000 crystals 3.1 ms CPU against 0.20 ms; they
#                                                      are drawn in one batch per style)
# It is a rough guide (triangle count and overdraw of translucent ghosts are
# not modelled), used only to warn.
FRAME_MS = 1000.0 / 60.0
BASE_MS = 5.0
PER_DRAWABLE_MS = 0.06
PER_MILLION_TETS_MS = 60.0
PER_BODY_MS = 0.016
PER_ENEMY_MS = 0.35
PER_CRYSTAL_MS = 0.003


def tick_cost_ms(drawables: int, tets: int, bodies: int, enemies: int = 0, crystals: int = 0) -> float:
    """Estimated milliseconds per frame for a level with this content."""
    return (
        BASE_MS
        + PER_DRAWABLE_MS * drawables
        + PER_MILLION_TETS_MS * tets / 1e6
        + PER_BODY_MS * bodies
        + PER_ENEMY_MS * enemies
        + PER_CRYSTAL_MS * crystals
    )


def fmt_count(n: int) -> str:
    """``1234567`` -> ``"1,234,567"``."""
    return f"{n:,}"
