"""The 4D camera's controls: turning the slice, the frustum switch, the orbit, the return.

Runs only in levels with a ``[camera]`` table (``level.camera.enabled``); elsewhere the
rig rests on the plain slice and this system does nothing. See :mod:`..camera` for the
rig and its modes.

- Synced, ``turn = true``: the held turn buttons turn the slice in the xw, yw and zw
  planes at ``turn_speed``; the step presses start a 90-degree glide and the snap
  press a glide to the nearest 90-degree orientation (both at twice the speed, landing
  exactly on the axes with a :class:`~..events.SliceAligned`). The pivot is the eye.
  With ``[energy] slice_cost``, turning away from where the slice rested is paid per degree
  (:mod:`..slice_pay`): the bar limits the turn, and a step it cannot pay is refused
  (:class:`~..events.SliceTurnUnpaid`).
- ``frustum = true``: the ``switch_camera`` press detaches the 4D camera (if the bar
  holds any energy when the switch costs some), sets the focus point and spawns the
  two indicators (kinds ``camera_focus`` and ``camera_eye``, on the radar). While
  detached, ``frustum_cost`` energy per second is paid to the thousandth (the amount
  owed after n ticks is ``floor(cost * n / 60)``); the orbit buttons move the camera
  round the focus point; the w keys do nothing (the slice stays where the camera
  left it). The switch press again, or an empty bar, starts the glide back.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...core.mesh import TriMesh3
from ...world.geometry import box_trimesh
from .. import slice_pay
from ..camera import GLIDE_FACTOR, GLIDE_SHARE, TURN_PLANES, CameraRig
from ..entities import Placed
from ..events import CameraSwitched, SliceAligned, SliceTurnRefused, SliceTurnUnpaid
from ..frame import Drawable, SliceGauges
from ..motion import JUMP_DEG, jump_now
from ..system import System, encode

FOCUS_COLOR = (1.0, 0.85, 0.2, 1.0)
EYE_COLOR = (0.4, 0.9, 1.0, 1.0)
#: Size of the indicators, metres: big enough to see across a room, small enough
#: not to hide what the camera looks at.
INDICATOR_SIZE = 0.2
#: Metres of rounding allowed at the ends of the w range when a turn towards w is checked.
W_SLACK = 1e-9
#: Ticks the notice of a refused turn stays on screen.
REFUSED_NOTICE_TICKS = 90

#: The camera's indicator is not drawn closer than this to the player's eye (metres):
#: at the switch it is exactly there, and a box round the eye would fill the screen.
EYE_CLEARANCE = 0.6


def setup(game) -> CameraRig:
    """The rig (``game.camera``): the plain axis-aligned slice until a level lets the player turn it."""
    return CameraRig(fov_deg=game.level.camera.fov)


def state_bytes(game) -> bytes:
    return encode(game.camera)


def _pivot(game) -> np.ndarray:
    """The eye in slice space ``(u, s)``: what turning the slice turns about."""
    p = game.player
    return np.append(p.eye(), float(p.position[3]))


def _return_ticks(game) -> int:
    return max(1, round(game.level.camera.return_time / game.dt))


def _rates(game, spec, actions) -> tuple:
    """This tick's held turn rates in the xw, yw and zw planes, radians/s."""
    speed = np.radians(spec.turn_speed)
    rates = tuple(
        speed * (float(getattr(actions, f"turn_{pl}_pos")) - float(getattr(actions, f"turn_{pl}_neg")))
        for pl in TURN_PLANES
    )
    if actions.reduced_motion:  # jumps of JUMP_DEG instead of a smooth turn
        jumps = [jump_now(game, f"turn_{pl}", rate != 0.0) for pl, rate in zip(TURN_PLANES, rates)]
        rates = tuple(np.sign(r) * np.radians(JUMP_DEG) / game.dt if j else 0.0 for r, j in zip(rates, jumps))
    return rates


def _press(game, rig, actions) -> None:
    """Queue the step and snap presses; a step the bar cannot pay in full is refused."""
    for pl in TURN_PLANES:
        for sign, name in ((1, f"step_{pl}_pos"), (-1, f"step_{pl}_neg")):
            for _ in range(actions.pressed(name)):
                queued = rig.glide
                rig.step(pl, sign)
                need = slice_pay.owed_for(game, rig, rig.glide)
                if need > 0 and need > game.energy.milli:
                    rig.glide = queued
                    _unpaid(game, rig)
    if actions.pressed("snap_slice"):
        rig.snap()


def _move(game, rig, spec, actions, rates, pivot, room: float = np.inf) -> bool:
    """Turn the slice by this tick's held rates, or advance its glide, at most ``room`` radians
    farther from its rest; True when a glide lands."""
    if any(rates):
        k = min(1.0, room / (float(np.linalg.norm(rates)) * game.dt))
        if k > 0.0:
            rig.turn(tuple(r * k for r in rates), game.dt, pivot)
        return False
    speed = np.inf if actions.reduced_motion else np.radians(spec.turn_speed) * GLIDE_FACTOR  # reduced: lands now
    speed = min(speed, room / game.dt)
    return rig.advance_glide(speed, game.dt, pivot) if speed > 0.0 else False


def _unpaid(game, rig) -> None:
    """Tell the player (once per cut turn, not every tick it is held) that the bar is short."""
    if game.tick - rig.unpaid_tick > 1:
        game.emit(SliceTurnUnpaid(slice_pay.step_milli(game), game.energy.milli))
    rig.unpaid_tick = game.tick
    rig.unpaid_milli = slice_pay.step_milli(game)


def _turn(game, rig, spec, actions) -> None:
    pivot = _pivot(game)
    before = rig.pose()
    rates = _rates(game, spec, actions)
    if not any(rates):
        _press(game, rig, actions)
    glide = rig.glide
    landed = _move(game, rig, spec, actions, rates, pivot)
    if slice_pay.short(game, rig):  # the bar cannot pay for all of it: turn only as far as it can
        room = slice_pay.room_rad(game, rig, before[0])
        rig.restore(before)
        rig.glide = glide
        landed = _move(game, rig, spec, actions, rates, pivot, room)
        _unpaid(game, rig)
    if _leaves_the_w_range(game, rig, before[0], pivot):
        rig.restore(before)
        rig.glide = None if glide is None or _turns_towards_w(glide, before[0]) else glide
        if game.tick - rig.refused_tick > 1:  # the first tick of a refused turn, not every one held
            game.emit(SliceTurnRefused(float(rig.to_world(pivot)[3]), *game.level.w_range))
        rig.refused_tick = game.tick
        return
    slice_pay.pay(game, rig)
    if landed:
        game.player.position[3] += rig.fold_offset()
        slice_pay.landed(rig)
        game.emit(SliceAligned(tuple(round(a) for a in rig.angles_deg())))


def _turns_towards_w(rot: np.ndarray, before: np.ndarray) -> bool:
    """Does the slice with rotation ``rot`` face the world's w axis more than ``before`` did?"""
    return abs(rot[3, 3]) > abs(before[3, 3]) + 1e-12


def _leaves_the_w_range(game, rig, before: np.ndarray, pivot: np.ndarray) -> bool:
    """Would this tick's turn bring the slice towards the world's w while the eye stands at a
    world w outside the level's range? Turned, the player walks along w far beyond the range
    (the turned slice's "ahead"); turning back there would leave them in the plain slice at a
    w the level never allows, so the turn waits until they walk back into the range."""
    if not _turns_towards_w(rig.rotation, before):
        return False
    lo, hi = game.level.w_range
    w = float(rig.to_world(pivot)[3])
    return not lo - W_SLACK <= w <= hi + W_SLACK


def _indicators(game, rig) -> None:
    """Spawn or move the focus and eye indicators (their poses are their world positions)."""
    pose, _ = rig.frustum_pose(game.player.eye(), float(game.player.position[3]), _return_ticks(game))
    where = {"camera_focus": rig.focus, "camera_eye": pose[:4, 4]}
    for kind, at in where.items():
        m = np.eye(5)
        m[:4, 4] = at
        found = game.entities.of_kind(kind)
        if found:
            found[0].motion.move(m)
        else:
            game.entities.spawn(kind, kind, None, Placed(m), radar=kind)


def _drop_indicators(game) -> None:
    for kind in ("camera_focus", "camera_eye"):
        for e in game.entities.of_kind(kind):
            game.remove(e.id)


def _pay(game, rig, spec) -> bool:
    """Pay this tick's share of the frustum's cost; False when the bar is empty."""
    if game.energy is None or spec.frustum_cost_milli <= 0:
        return True
    rig.detached_ticks += 1
    per_second = round(1.0 / game.dt)  # ticks: 60
    owed = spec.frustum_cost_milli * rig.detached_ticks // per_second - rig.paid_milli
    if owed > 0:
        rig.paid_milli += game.energy.spend_up_to(game, owed, "frustum")
    return game.energy.milli > 0


def step(game, actions):
    spec = game.level.camera
    if not spec.enabled:
        return None
    rig = game.camera
    switch = actions.pressed("switch_camera") > 0
    if rig.mode == "synced":
        if spec.turn:
            _turn(game, rig, spec, actions)
        can_pay = game.energy is None or spec.frustum_cost_milli <= 0 or game.energy.milli > 0
        if switch and spec.frustum and can_pay:
            p = game.player
            rig.glide = None
            ahead = np.array([np.sin(p.yaw), 0.0, np.cos(p.yaw)])
            rig.detach(p.eye(), ahead, float(p.position[3]), spec.focus_distance)
            game.emit(CameraSwitched("frustum", "key"))
            _indicators(game, rig)
    elif rig.mode == "frustum":
        turn = float(actions.orbit_right) - float(actions.orbit_left)
        stride = np.radians(spec.orbit_speed) * game.dt
        if actions.reduced_motion:  # jumps of JUMP_DEG instead of a smooth orbit
            stride = np.radians(JUMP_DEG) if jump_now(game, "orbit", turn != 0.0) else 0.0
        if turn and stride:
            rig.orbit += turn * stride
            rig.version += 1
        paid_up = _pay(game, rig, spec)
        if switch or not paid_up:
            rig.start_return()
            if actions.reduced_motion:  # no glide back: the frustum view only fades out
                rig.return_ticks = int(np.ceil(GLIDE_SHARE * _return_ticks(game)))
            game.emit(CameraSwitched("returning", "key" if switch else "energy"))
        _indicators(game, rig)
    else:  # returning
        rig.return_ticks += 1
        rig.version += 1
        if rig.return_ticks >= _return_ticks(game):
            rig.mode = "synced"
            rig.orbit = 0.0
            game.emit(CameraSwitched("synced", "arrived"))
            _drop_indicators(game)
        else:
            _indicators(game, rig)
    if rig.detached and actions.w != 0.0:
        return replace(actions, w=0.0)  # the slice stays where the detached camera left it
    return None


def ghost_weight(game) -> float:
    """How strongly the ghosts along w show, 0 to 1: fully on the plain synced slice, not at all
    on a turned one or while the camera is detached, fading in as a return fades the frustum
    view out (so they do not pop in at the hand-over)."""
    rig = game.camera
    if not rig.aligned:
        return 0.0
    if rig.mode == "synced":
        return 1.0
    if rig.mode == "frustum":
        return 0.0
    return 1.0 - rig.return_fade(_return_ticks(game))


def frustum_view(game):
    """The detached 4D camera's pose ``(5, 5)`` and its projection's placement ``(4, 4)``, or None
    while synced."""
    rig = game.camera
    if not rig.detached:
        return None
    p = game.player
    return rig.frustum_pose(p.eye(), float(p.position[3]), _return_ticks(game))


def seen_touching(game, center: np.ndarray, radius: float, others: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Which of ``others (k, 4)`` (balls of ``radii (k,)``) the ball at ``center (4,)`` touches *as
    seen through the detached 4D camera*: their images in slice space overlap, each image
    scaled by ``focal / depth`` (so a ball near the camera's view grows: its collider stretches).
    All False while synced, and for anything behind the camera's near hyperplane."""
    view = frustum_view(game)
    if view is None or len(others) == 0:
        return np.zeros(len(others), dtype=bool)
    pose, place = view
    pts, scale = game.camera.project_points(np.vstack([center, others]), pose, place)
    gap = np.linalg.norm(pts[1:] - pts[0], axis=1)
    with np.errstate(invalid="ignore"):
        return (scale[0] > 0) & (scale[1:] > 0) & (gap <= radius * scale[0] + radii * scale[1:])


def _marker(key: str, at: np.ndarray, color, style: str) -> Drawable:
    mesh: TriMesh3 = box_trimesh((0.0, 0.0, 0.0), (INDICATOR_SIZE,) * 3, color)
    place = np.eye(4)
    place[:3, 3] = at
    return Drawable(key, 0, mesh, model=place, style=style)


def draw(game, frame, alpha) -> None:
    spec = game.level.camera
    if not spec.enabled:
        return
    rig = game.camera
    frame.hud.slice = SliceGauges(rig.angles_deg(), rig.mode, float(np.degrees(rig.orbit)))
    if game.tick - rig.refused_tick < REFUSED_NOTICE_TICKS and not frame.hud.message:
        lo, hi = game.level.w_range
        w = float(rig.to_world(_pivot(game))[3])
        frame.hud.message = f"Turn back only at w {lo:+.1f} to {hi:+.1f} (you: w {w:+.1f}). Walk back first"
    if game.tick - rig.unpaid_tick < REFUSED_NOTICE_TICKS and not frame.hud.message:
        have = game.energy.value if game.energy is not None else 0.0
        frame.hud.message = (
            f"A 90-degree turn of the slice costs {rig.unpaid_milli / 1000:g} energy (you have {have:g})."
            " Crystals refill the bar"
        )
    if not rig.detached:
        return
    eye = frame.camera
    pose, _ = rig.frustum_pose(eye.position, eye.w, _return_ticks(game))
    # The focus point shows where it is on screen (it never moves there); the camera's
    # indicator stands at its slice-space position, its w offset read on the radar.
    frame.drawables.append(_marker("camera:focus", rig.focus_u, FOCUS_COLOR, "glow"))
    eye = rig.to_slice(pose[:4, 4])[:3]
    if np.linalg.norm(eye - frame.camera.position) > EYE_CLEARANCE:  # not round the player's own eye
        # Edges only: the camera swings in front of what it looks at, and must not hide it.
        frame.drawables.append(_marker("camera:eye", eye, EYE_COLOR, "wire"))


SYSTEM = System("camera", setup, step, draw, state_bytes)
