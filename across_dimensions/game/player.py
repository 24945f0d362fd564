"""The first-person walking controller.

The player is an axis-aligned box (``2 * HALF_WIDTH`` wide, ``HEIGHT`` tall,
feet at ``position[1]``) living in the 3D slice at ``w = position[3]``. It
collides with axis-aligned boxes (the 3D world's boxes, the extended worlds'
parts) and with the true cross-section of solid 4D objects at the player's w:
the section's triangles, swept exactly (:mod:`.section_collision`), so a turned
slab is a ramp and an arch's doorway is open.

Why not pymunk (which the design suggested for the walker's collisions in the
ground plane): a walker here needs the third axis too (jumping onto ledges,
stepping up, ceilings), its obstacles change every time the player moves along
w, and against boxes an axis-by-axis sweep is exact, cheap and deterministic,
which replays rely on. Rebuilding a 2D pymunk space per w step would cost more
and still leave y to this code; so the project does not depend on pymunk.

Motion is resolved one axis at a time (x, z, then y): a move that would enter
a box, anywhere along the way, stops flush against it, so nothing tunnels
however fast the player falls. Moving along w
changes which 4D walls exist; a w step that would put the player inside one is
refused (you cannot phase into a wall).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from . import section_collision
from .actions import Actions

HALF_WIDTH = 0.3
HEIGHT = 1.75
EYE_HEIGHT = 1.6
WALK_SPEED = 4.5  # m/s
GROUND_ACCEL = 40.0  # m/s^2 towards the wanted velocity on the ground
AIR_ACCEL = 8.0
JUMP_SPEED = 5.2  # m/s: a 1.4 m jump under 9.81 m/s^2
W_SPEED = 1.2  # w units/s
W_ACCEL = 8.0
#: Seek (a glide along w to a chosen w): top speed, acceleration, and an ease-out
#: that slows it in proportion to the gap left (per second), never below
#: SEEK_MIN_SPEED so it always arrives.
SEEK_SPEED = 2.4  # w units/s: twice walking, a glide rather than a crawl
SEEK_ACCEL = 16.0
SEEK_EASE = 5.0
SEEK_MIN_SPEED = 0.25
MAX_PITCH = np.radians(89.0)
STEP_HEIGHT = 0.35  # ledges up to this high are climbed without jumping
SKIN = 1e-4  # gap kept to surfaces so resting contact is not overlap


@dataclass
class Player:
    """Player state; all arrays float64.

    Parameters
    ----------
    position : (4,) float64
        Feet position x, y, z, w.
    velocity : (4,) float64
    yaw, pitch : float
        Radians.
    on_ground : bool
    """

    position: np.ndarray
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(4))
    yaw: float = 0.0
    pitch: float = 0.0
    on_ground: bool = False

    def eye(self) -> np.ndarray:
        """Eye position ``(3,) float64``."""
        p = self.position
        return np.array([p[0], p[1] + EYE_HEIGHT, p[2]])

    def center(self) -> np.ndarray:
        """Centre of the player's box ``(3,) float64``."""
        p = self.position
        return np.array([p[0], p[1] + HEIGHT / 2, p[2]])

    def state_array(self) -> np.ndarray:
        return np.concatenate([self.position, self.velocity, [self.yaw, self.pitch, float(self.on_ground)]])


def player_box(position) -> tuple[np.ndarray, np.ndarray]:
    """The player's bounds ``(lo (3,), hi (3,))`` at a feet position."""
    x, y, z = position[0], position[1], position[2]
    return np.array([x - HALF_WIDTH, y, z - HALF_WIDTH]), np.array([x + HALF_WIDTH, y + HEIGHT, z + HALF_WIDTH])


def overlapping(lo, hi, boxes: np.ndarray) -> np.ndarray:
    """Which of ``boxes (k, 2, 3)`` overlap the box ``[lo, hi]`` (open intervals;
    a NaN box, absent from this slice, overlaps nothing)."""
    if len(boxes) == 0:
        return np.zeros(0, bool)
    return np.all((lo < boxes[:, 1]) & (hi > boxes[:, 0]), axis=1)


def move_axis(pos: np.ndarray, axis: int, delta: float, boxes: np.ndarray, tris=None) -> tuple[np.ndarray, bool]:
    """Move along one axis, stopping flush at the first box or section triangle entered.

    ``tris`` is ``(t, 3, 3) float64`` or a :class:`.section_collision.Soup`
    (triangles of solid 4D objects' sections) or None.
    """
    if delta == 0.0:
        return pos, False
    new, hit = _move_boxes(pos, axis, delta, boxes)
    if tris is not None and len(tris):
        lo0, hi0 = player_box(pos)
        s = section_collision.first_hit(lo0, hi0, axis, delta, tris)
        if s is not None:
            # Stop SKIN short of the contact, never behind the start.
            along = s * abs(delta) - SKIN
            stop = pos[axis] + np.copysign(max(along, 0.0), delta)
            if (delta > 0 and stop < new[axis]) or (delta < 0 and stop > new[axis]):
                new = pos.copy()
                new[axis] = stop
            hit = True
    return new, hit


def _move_boxes(pos: np.ndarray, axis: int, delta: float, boxes: np.ndarray) -> tuple[np.ndarray, bool]:
    lo0, hi0 = player_box(pos)
    before = overlapping(lo0, hi0, boxes)
    new = pos.copy()
    new[axis] += delta
    # Test the box swept over the whole move, not just where it ends: a fast
    # fall (strong gravity, a long drop) must not skip over a thin floor.
    lo1, hi1 = player_box(new)
    hit = overlapping(np.minimum(lo0, lo1), np.maximum(hi0, hi1), boxes) & ~before
    if not hit.any():
        return new, False
    lo_off = 0.0 if axis == 1 else -HALF_WIDTH
    hi_off = HEIGHT if axis == 1 else HALF_WIDTH
    if delta > 0:
        new[axis] = boxes[hit, 0, axis].min() - hi_off - SKIN
    else:
        new[axis] = boxes[hit, 1, axis].max() - lo_off + SKIN
    # Never move backwards because of a box we were already touching.
    new[axis] = min(new[axis], pos[axis] + delta) if delta > 0 else max(new[axis], pos[axis] + delta)
    if (delta > 0 and new[axis] < pos[axis]) or (delta < 0 and new[axis] > pos[axis]):
        new[axis] = pos[axis]
    return new, True


def _move_horizontal(pos, dx: float, dz: float, boxes, on_ground: bool, tris=None) -> np.ndarray:
    """Walk in x then z; when blocked on the ground, also try stepping up a ledge (or a ramp's slope)."""
    flat, hit_x = move_axis(pos, 0, dx, boxes, tris)
    flat, hit_z = move_axis(flat, 2, dz, boxes, tris)
    if not (on_ground and (hit_x or hit_z)):
        return flat
    up, _ = move_axis(pos, 1, STEP_HEIGHT, boxes, tris)
    stepped, _ = move_axis(up, 0, dx, boxes, tris)
    stepped, _ = move_axis(stepped, 2, dz, boxes, tris)
    stepped, _ = move_axis(stepped, 1, pos[1] - up[1], boxes, tris)  # back down onto the ledge
    moved = lambda p: (p[0] - pos[0]) ** 2 + (p[2] - pos[2]) ** 2  # noqa: E731
    return stepped if moved(stepped) > moved(flat) + 1e-12 else flat


def _enters_section(lo, hi, now: list, then: list) -> bool:
    """Would the box ``(lo, hi)`` be in a solid's section at the new w that it is not in now?

    ``now`` and ``then`` list the same objects' sections (one ``(t, 3, 3)`` each)
    at the current and the new w; an object already touching the box is not
    counted (the player may leave it, as with boxes).
    """
    for a, b in zip(now, then):
        if section_collision.box_blocked(lo, hi, b) and not section_collision.box_blocked(lo, hi, a):
            return True
    return False


def _seek_w(pos: np.ndarray, v: np.ndarray, dt: float, goal: float, jump: bool) -> float:
    """Where a seek puts the player along w this tick; sets ``v[3]`` (0 once it arrives)."""
    gap = float(goal) - float(pos[3])
    if not jump and gap != 0.0:
        want = np.copysign(min(SEEK_SPEED, SEEK_EASE * abs(gap) + SEEK_MIN_SPEED), gap)
        v[3] += float(np.clip(want - v[3], -SEEK_ACCEL * dt, SEEK_ACCEL * dt))
        if v[3] * gap <= 0.0 or abs(v[3]) * dt < abs(gap):
            return float(pos[3] + v[3] * dt)
    # Arrived (or jumping): exactly the goal, with no w speed left to overshoot it.
    v[3] = 0.0
    return float(goal)


@dataclass(frozen=True)
class Surroundings:
    """What the walker moves through, by w.

    Parameters
    ----------
    w_range : (float, float)
        Allowed w interval.
    colliders_at : callable
        ``colliders_at(w) -> (k, 2, 3) float64`` boxes solid in the slice at w.
    blocked_w : callable, optional
        ``blocked_w(position, w) -> bool``: something other than those boxes
        (a rigid body) would overlap the player moved to ``w``.
    sections_at : callable, optional
        ``sections_at(w) -> list of (t, 3, 3) float64``: the closed triangle
        surfaces of solid 4D objects' sections in the slice at w, one array per
        object (see :mod:`.section_collision`). None: boxes only.
    """

    w_range: tuple[float, float]
    colliders_at: Callable
    blocked_w: Callable | None = None
    sections_at: Callable | None = None


def step_player(
    player: Player,
    actions: Actions,
    dt: float,
    gravity_y: float,
    around: Surroundings,
    w_budget: float | tuple[float, float] = np.inf,
    w_goal: tuple[float, bool] | None = None,
) -> str | None:
    """Advance the player one tick.

    Parameters
    ----------
    player : Player
        Updated in place.
    actions : Actions
    dt : float
        Tick length, seconds.
    gravity_y : float
        Vertical gravity (negative is down).
    around : Surroundings
        The boxes, solids and bodies in the way.
    w_budget : float or (float, float)
        The farthest the player may move along w this tick (what the energy
        bar can pay for): one distance either way, or ``(down, up)``, how far
        towards -w and towards +w; unlimited by default.
    w_goal : (float, bool), optional
        Seek: glide towards this w (or, when the flag is true, jump to it in one
        tick) instead of following ``actions.w``. The move lands exactly on the
        goal and stops there; range, energy, walls and bodies cut it exactly as
        they cut a held w key.

    Returns
    -------
    str or None
        Why the player's w motion was cut short this tick: ``"range"`` (the end
        of the level's w range), ``"energy"`` (the budget), ``"wall"`` (a wall
        would appear around the player) or ``"body"`` (a rigid body is there);
        None when it moved freely.
    """
    player.yaw = float((player.yaw + actions.yaw + np.pi) % (2 * np.pi) - np.pi)
    player.pitch = float(np.clip(player.pitch + actions.pitch, -MAX_PITCH, MAX_PITCH))
    _steer(player, actions, dt, gravity_y)
    pos, v = player.position, player.velocity
    w_target = _w_target(pos, v, actions, dt, w_goal)
    w_new, cut = _clip_w(pos, w_target, around.w_range, w_budget)
    if w_new != pos[3]:
        blocked = _w_blocked(pos, w_new, around)
        if blocked is not None:
            w_new, cut = float(pos[3]), blocked
    if w_new != w_target:  # stopped by the range's end, the energy or a wall appearing
        v[3] = 0.0
    pos[3] = w_new
    _move_in_slice(player, dt, around.colliders_at(pos[3]), around.sections_at)
    return cut


def _steer(player: Player, actions: Actions, dt: float, gravity_y: float) -> None:
    """Walking: steer the horizontal velocity towards the wanted one; jumping and falling."""
    fwd = np.array([np.sin(player.yaw), np.cos(player.yaw)])
    right = np.array([np.cos(player.yaw), -np.sin(player.yaw)])
    wish = actions.forward * fwd + actions.right * right
    n = np.linalg.norm(wish)
    if n > 1.0:
        wish /= n
    want = wish * WALK_SPEED
    v = player.velocity
    accel = GROUND_ACCEL if player.on_ground else AIR_ACCEL
    dv = want - v[[0, 2]]
    dv_len = np.linalg.norm(dv)
    if dv_len > accel * dt:
        dv *= accel * dt / dv_len
    v[0] += dv[0]
    v[2] += dv[1]
    if actions.jump and player.on_ground:
        v[1] = JUMP_SPEED
    v[1] += gravity_y * dt


def _w_target(pos: np.ndarray, v: np.ndarray, actions: Actions, dt: float, w_goal) -> float:
    """Where the player would be along w after this tick, nothing in the way; sets ``v[3]``."""
    if w_goal is not None:
        return _seek_w(pos, v, dt, *w_goal)
    # Smooth acceleration to the wanted speed.
    dw = np.clip(actions.w * W_SPEED - v[3], -W_ACCEL * dt, W_ACCEL * dt)
    v[3] += dw
    return pos[3] + v[3] * dt


def _clip_w(pos: np.ndarray, w_target: float, w_range, w_budget) -> tuple[float, str | None]:
    """``w_target`` kept inside the level's w range and the energy budget, and which cut it."""
    w_new = float(np.clip(w_target, *w_range))
    cut = "range" if w_new != w_target else None
    down, up = w_budget if isinstance(w_budget, tuple) else (w_budget, w_budget)
    limit = up if w_new > pos[3] else down
    if abs(w_new - pos[3]) > limit:
        w_new = float(pos[3] + np.copysign(limit, w_new - pos[3]))
        cut = "energy"
    return w_new, cut


def _w_blocked(pos: np.ndarray, w_new: float, around: Surroundings) -> str | None:
    """``"wall"`` when a box or a solid's section would appear around the player at ``w_new``,
    ``"body"`` when a rigid body is there, else None."""
    lo, hi = player_box(pos)
    boxes_at, sections_at = around.colliders_at, around.sections_at
    if (overlapping(lo, hi, boxes_at(w_new)) & ~overlapping(lo, hi, boxes_at(pos[3]))).any():
        return "wall"
    if sections_at is not None and _enters_section(lo, hi, sections_at(pos[3]), sections_at(w_new)):
        return "wall"
    if around.blocked_w is not None and around.blocked_w(pos, w_new):
        return "body"
    return None


def _move_in_slice(player: Player, dt: float, boxes: np.ndarray, sections_at) -> None:
    """Move the player by its velocity in the slice at its w, against ``boxes (k, 2, 3)`` and the
    solids' sections; velocity along an axis it was stopped on is gone."""
    pos, v = player.position, player.velocity
    tris = None
    if sections_at is not None:
        found = [t for t in sections_at(pos[3]) if len(t)]
        tris = section_collision.Soup(np.concatenate(found)) if found else None  # prepared once for every move
    pos_new = _move_horizontal(pos, v[0] * dt, v[2] * dt, boxes, player.on_ground, tris)
    pos_new, hit_y = move_axis(pos_new, 1, v[1] * dt, boxes, tris)
    for axis in (0, 2):
        if abs(pos_new[axis] - (pos[axis] + v[axis] * dt)) > 1e-9:
            v[axis] = 0.0
    player.on_ground = bool(hit_y and v[1] <= 0)
    if hit_y:
        v[1] = 0.0
    player.position = pos_new
