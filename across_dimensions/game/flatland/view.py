"""What a prologue frame shows, as plain data: the side view, the z bar, the hint, the turn to 3D.

:func:`flat_frame` reads a :class:`~.sim.FlatGame` (never changes it) and says what to draw: the
sections the being meets, in its plane's coordinates; the being, interpolated between ticks; the
z bar (the one-axis radar: the level's z range, the being's plane on it, a pin for each thing of
interest at its own z); and, once the level is complete, how far the view has turned to show the
3D world the being lived in (:attr:`FlatFrame.reveal`) and the line that ties it to the 4D game.
``render/flatland.py`` draws it; tests read it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...core.flat_section import Solid3
from ...core.flat_solids import box_solid
from ..player import HALF_WIDTH, HEIGHT

#: Seconds the view takes to turn from the flat side view to the 3D world, after the goal.
REVEAL_SECONDS = 6.0
#: The line shown as the 3D world comes into view, and at the start of Arrival.
CLOSING_LINE = "You are the flat being now, and w is your z."
#: Half the view's height in metres: the side view shows 12 m from top to bottom.
VIEW_HALF_HEIGHT = 6.0
#: How far (m) the view keeps above the being's feet: ground below, jumps above.
VIEW_ABOVE_FEET = 2.0


@dataclass
class Piece:
    """A convex piece of a solid's section, ``points (k, 2) float64`` counter-clockwise.

    ``cue`` is where the plane cuts a solid that ends along z within the level's z range,
    ``(z0 - z of its middle) / half its z extent`` (0 through the middle, +-1 at its ends): the
    analogue of the 4D game's w cue, drawn as bands. None for what goes on along all of z.
    """

    key: str
    points: np.ndarray
    color: tuple
    kind: str  # "solid", "crate"
    cue: float | None = None


@dataclass
class Circle:
    """A 3D ball's section: ``side`` is where the plane cuts it, ``(z0 - z of its centre) / radius``
    (0 through the middle, towards +-1 at its ends), the analogue of the 4D game's w cue."""

    key: str
    center: tuple[float, float]
    radius: float
    color: tuple
    kind: str  # "ball", "item"
    side: float


@dataclass
class Pin:
    """A thing on the z bar: its own ``z``, ``dx`` metres right of the being, and whether the plane
    cuts it now (``in_plane``)."""

    key: str
    kind: str  # "item", "ball"
    z: float
    dx: float
    in_plane: bool
    color: tuple


@dataclass
class Solid:
    """A 3D solid for the turn to 3D."""

    key: str
    solid: Solid3
    color: tuple


@dataclass
class Ball3:
    """A 3D ball for the turn to 3D."""

    key: str
    center: np.ndarray
    radius: float
    color: tuple


@dataclass
class FlatFrame:
    """One frame of the prologue."""

    center: tuple[float, float]  # the view's centre in the plane, metres
    half_height: float
    z: float
    z_range: tuple[float, float]
    being: tuple[float, float]  # feet (x, y), interpolated
    being_size: tuple[float, float]
    facing: float  # +1 right, -1 left
    goal: tuple[tuple[float, float], tuple[float, float]]  # centre, size
    pieces: list[Piece] = field(default_factory=list)
    outlines: list[Piece] = field(default_factory=list)  # the sections' closed outlines (the pieces' are inner)
    circles: list[Circle] = field(default_factory=list)
    pins: list[Pin] = field(default_factory=list)
    z_blocked: bool = False
    hint: str = ""
    hint_label: str = ""
    message: str = ""
    time: float = 0.0
    reveal: float = 0.0  # 0: the flat side view; 1: the view turned to the 3D world
    solids3: list[Solid] = field(default_factory=list)
    balls3: list[Ball3] = field(default_factory=list)
    line: str = ""  # the closing line, once the view turns


def flat_frame(game, alpha: float = 1.0, hint: str = "", hint_label: str = "", message: str = "") -> FlatFrame:
    """What to draw of ``game`` (a :class:`~.sim.FlatGame`), ``alpha`` of the way from its last tick.

    ``hint`` and ``hint_label`` are the hint on screen with the player's keys filled in (the window's
    job: the simulation knows actions, not keys).
    """
    lvl, world = game.level, game.world
    feet = game.prev_position[:2] + alpha * (game.position[:2] - game.prev_position[:2])
    z = float(game.z)
    frame = FlatFrame(
        center=(float(feet[0]), float(max(feet[1] + VIEW_ABOVE_FEET, lvl.goal_center[1] + 1.0))),
        half_height=VIEW_HALF_HEIGHT,
        z=z,
        z_range=lvl.z_range,
        being=(float(feet[0]), float(feet[1])),
        being_size=(2 * HALF_WIDTH, HEIGHT),
        facing=game.facing,
        goal=(tuple(map(float, lvl.goal_center)), tuple(map(float, lvl.goal_size))),
        z_blocked=bool(game.z_blocked),
        hint=hint,
        hint_label=hint_label,
        message=message,
        time=game.time,
    )
    for spec, pieces, outlines in zip(lvl.solids, world.pieces(z), world.outlines(z)):
        lo, hi = spec.solid.z_extent()
        cue = None if lo <= lvl.z_range[0] and hi >= lvl.z_range[1] else (z - (lo + hi) / 2) / ((hi - lo) / 2)
        frame.pieces += [Piece(spec.name, p, spec.color, "solid", cue) for p in pieces]
        frame.outlines += [Piece(spec.name, o, spec.color, "solid", cue) for o in outlines]
    for i, (body, shape) in enumerate(game.space.crates):
        if world.crate_present(i, z):
            corners = np.array([tuple(body.local_to_world(v)) for v in shape.get_vertices()])
            frame.pieces.append(Piece(lvl.crates[i].name, corners, lvl.crates[i].color, "crate"))
            frame.outlines.append(frame.pieces[-1])
    for i, b in enumerate(lvl.balls):
        r, bz = world.ball_radius(i, z), float(world.ball_z[i])
        if r > 0.0:
            frame.circles.append(Circle(b.name, (b.center[0], b.center[1]), r, b.color, "ball", (z - bz) / b.radius))
        frame.pins.append(Pin(b.name, "ball", bz, float(b.center[0] - feet[0]), r > 0.0, b.color))
    for i, item in enumerate(lvl.items):
        if item.name in world.taken:
            continue
        r, c = world.item_radius(i, z), item.position
        if r > 0.0:
            frame.circles.append(Circle(item.name, (c[0], c[1]), r, item.color, "item", (z - c[2]) / item.radius))
        frame.pins.append(Pin(item.name, "item", float(c[2]), float(c[0] - feet[0]), r > 0.0, item.color))
    frame.pins = [p for p in frame.pins if abs(p.dx) <= lvl.radar_range]
    if game.completed_tick is not None:
        seconds = (game.tick - game.completed_tick) * game.dt
        frame.reveal = float(min(1.0, max(0.0, seconds / REVEAL_SECONDS)))
        frame.line = CLOSING_LINE
        frame.solids3 = [Solid(s.name, s.solid, s.color) for s in lvl.solids if s.name not in world.gone]
        for (body, _), c in zip(game.space.crates, lvl.crates):
            frame.solids3.append(Solid(c.name, box_solid((*body.position, c.center[2]), c.size), c.color))
        for i, b in enumerate(lvl.balls):
            frame.balls3.append(Ball3(b.name, np.r_[b.center[:2], world.ball_z[i]], b.radius, b.color))
    return frame
