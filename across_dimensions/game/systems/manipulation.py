"""Manipulation: the player turns 4D objects in their w planes, guided by ghost previews.

A level marks objects ``[[manipulable]]`` (``world.gameplay.ManipulableSpec``)
with the planes they may turn in and the limits of each. The player aims at one
(the crosshair's ray meets its section within the table's ``reach``) and holds
the ``manipulate`` action: the object is grabbed and glows, and while it is held
the walking keys turn it instead of moving the player:

- the first allowed plane (in ``xy xz yz xw yw zw`` order) with
  ``move_forward`` / ``move_back`` (+ / -),
- the second with ``strafe_right`` / ``strafe_left``,
- the third with ``w_ana`` / ``w_kata``; with fewer than three planes those keys
  still move the player along w, so the ghosts can be watched changing with w.

An object whose table has ``slide = [low, high]`` may also move along w (by
``low`` to ``high`` metres, at :data:`SLIDE_SPEED`, paid like the player's own
moves along w, ``[energy] w_cost``): the slide takes the key pair after its
planes (``"w"`` in :attr:`Manipulable.planes`).

The HUD shows these keys next to the object on screen, one plane a line, with
the player's own bindings (``{action}`` placeholders the window fills in, as
for hints; see :class:`..frame.ScreenLabel`). Turning is smooth at the
table's ``speed``; with a ``step``, a turn that is let go of carries on to the
next multiple of the step in its direction (snapping), so the object always
settles on a step. Turning back undoes a turn. Every degree turned, snapping
included, costs ``cost`` energy, paid through the one energy account: the
total paid is always ``ceil(cost_milli * turned_millidegrees / 1000)``
thousandths, and a turn stops where the bar runs dry. A turn that would put the
object's section around the player is refused (nothing appears inside you, as
for steps along w).

Angles are kept as whole millidegrees, so a replay turns exactly the same on
every run; the object's pose (in the state hash through its
:class:`~..entities.Placed` motion) is rebuilt from them each tick, and the
grab, the angles and the energy paid are in the state hash too
(:func:`state_bytes`).

Rigid bodies: in a level with physics, each manipulable object also gets a
kinematic hypercube collider (its scaled bounds, exact for a tesseract slab),
driven each tick so that the physics step ends at the object's new pose with
the turn's velocity: a body resting on it is carried along or slides off, and
contacts push it out rather than let the object turn through it.

Ghosts (:func:`draw`): while an object is held, one translucent preview per
allowed plane and direction floats above it, showing the section the object
would have after the next step (or :data:`PREVIEW_DEG` without a step), as a
miniature at most :data:`GHOST_SIZE` across, cut by
the same hyperplane as the object itself, so they change live as the player
moves along w. They are drawables only: they never collide and are no entity.
``game.show_ghosts`` (a view option the window sets from the settings) switches them off.

Events: ``manipulation_started`` (grabbed), ``manipulated`` (a turn in a plane
settled: plane and angle), ``manipulation_ended`` (let go).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ...core.transform import PLANES, pose
from ...world.gameplay import ManipulableSpec
from .. import section_collision
from ..entities import Placed, Scripted
from ..events import Manipulated, ManipulationEnded, ManipulationStarted
from ..frame import Drawable, ScreenLabel
from ..motion import JUMP_DEG, JUMP_SECONDS, jump_now
from ..player import player_box
from ..system import System, encode, fixed

PREVIEW_DEG = 15.0  # what a ghost previews in a plane without a snapping step
GHOST_GAP = 0.6  # metres between the object's section and the row of ghosts above it
GHOST_SIZE = 1.2  # metres: a ghost larger than this is shown shrunk to fit (a miniature beside the object)
GHOST_SPACING = 0.4  # metres between ghosts in the row
#: Walking axes that turn the first, second and third allowed plane (Actions field, + key, - key).
AXES = (("forward", "move_forward", "move_back"), ("right", "strafe_right", "strafe_left"), ("w", "w_ana", "w_kata"))
#: Metres around an object's section that still count as aiming at it: a crosshair
#: a hand's width off a thin beam should still grab it.
AIM_MARGIN = 0.25
DEAD_ZONE = 0.5
SLIDE_UNIT = 1_000_000  # a slide along w is kept in whole micrometres (exact, like angles in millidegrees)
SLIDE_SPEED = 1.0  # metres per second along w
SLIDE_PREVIEW = 0.25  # metres a slide's ghost previews  # an axis must be pushed past this to turn (keys give 0 or 1)


@dataclass
class Manipulable:
    """A manipulable object's state (``Entity.data``).

    ``offsets`` are millidegrees from the level's rotation per allowed plane;
    ``direction`` the sign of each plane's last turn (where a snap goes);
    ``turned`` all millidegrees turned so far and ``paid`` the thousandths of
    energy paid for them.
    """

    spec: ManipulableSpec = fixed()
    position: np.ndarray = fixed()
    rotation_deg: dict = fixed()
    scale: np.ndarray = fixed()
    offsets: dict[str, int] = field(default_factory=dict)
    direction: dict[str, int] = field(default_factory=dict)
    moving: dict[str, bool] = field(default_factory=dict)
    turned: int = 0
    paid: int = 0
    was_moving: bool = False
    #: Its kinematic collider in the physics world, when the level has one.
    body: int | None = fixed(default=None)
    box_center: np.ndarray = fixed(default_factory=lambda: np.zeros(4))  # mesh bounds' centre, object frame
    box_size: np.ndarray = fixed(default_factory=lambda: np.ones(4))  # mesh bounds' size, scaled

    slid: int = 0  # micrometres slid along w so far, and the thousandths of energy paid for them
    slide_paid: int = 0

    @property
    def planes(self) -> list[str]:
        """The allowed planes in ``xy xz yz xw yw zw`` order, then ``"w"`` when it may slide along w."""
        return [p for p in PLANES if p in self.spec.planes] + (["w"] if self.spec.slide is not None else [])

    def limits(self, plane: str) -> tuple[int, int]:
        """Limits of a plane in millidegrees, or of the slide (``"w"``) in micrometres."""
        if plane == "w":
            lo, hi = self.spec.slide
            return int(round(lo * SLIDE_UNIT)), int(round(hi * SLIDE_UNIT))
        lo, hi = self.spec.planes[plane]
        return int(round(lo * 1000)), int(round(hi * 1000))

    def model(self, offsets: dict | None = None) -> np.ndarray:
        """Object-to-world ``(5, 5) float64`` with ``offsets`` (millidegrees; default: the current ones)."""
        offsets = self.offsets if offsets is None else offsets
        planes = (set(self.rotation_deg) | set(offsets)) - {"w"}
        angles = {p: np.radians(self.rotation_deg.get(p, 0.0) + offsets.get(p, 0) / 1000.0) for p in planes}
        position = self.position.copy()
        position[3] += offsets.get("w", 0) / SLIDE_UNIT
        return pose(position, angles, self.scale)

    def angle_deg(self, plane: str) -> float:
        """The object's rotation in ``plane`` now, degrees (for ``"w"``: its w, metres)."""
        if plane == "w":
            return float(self.position[3] + self.offsets.get("w", 0) / SLIDE_UNIT)
        return self.rotation_deg.get(plane, 0.0) + self.offsets.get(plane, 0) / 1000.0


@dataclass
class Tool:
    """The manipulation tool (``game.states.manipulation``): what is aimed at and what is held (entity ids)."""

    aimed: int | None = None
    held: int | None = None


def setup(game) -> Tool:
    """The tool; makes the level's manipulable objects placed by this system."""
    for spec in game.level.manipulables:
        e = game.entities.named(spec.object)
        obj = e.motion.obj if e is not None and isinstance(e.motion, Scripted) else None
        if obj is None:
            continue
        data = Manipulable(
            spec,
            np.array(obj.position, dtype=np.float64),
            dict(obj.rotation_deg),
            np.array(obj.scale, dtype=np.float64),
            offsets={p: 0 for p in [*PLANES, "w"] if p in spec.planes or (p == "w" and spec.slide is not None)},
        )
        data.direction = dict.fromkeys(data.offsets, 0)
        data.moving = dict.fromkeys(data.offsets, False)
        e.kind = "manipulable"
        e.data = data
        e.motion = Placed(data.model())
        if game.physics is not None:
            _add_collider(game, e)
    return Tool()


def _add_collider(game, e) -> None:
    """Give a box-shaped object (a tesseract slab) a kinematic hypercube in the physics world,
    exactly its shape, so rigid bodies rest on it and are carried or tipped off when it turns.
    Any other shape is met by its boundary tets, which move with it and carry the bodies too
    (:func:`..player_bodies.tet_colliders`)."""
    from ...physics import BodyDef
    from ..player_bodies import shape_kind

    d = e.data
    if shape_kind(e.mesh) != "box":
        return
    v = e.mesh.vertices.astype(np.float64)
    lo, hi = v.min(axis=0), v.max(axis=0)
    d.box_center = 0.5 * (lo + hi) * d.scale
    d.box_size = np.maximum((hi - lo) * d.scale, 1e-3)
    m = d.model()
    rot = _rotation(m)
    d.body = game.physics.add_body(
        BodyDef("hypercube", size=d.box_size, kind="kinematic", position=m[:4, 4] + rot @ d.box_center, rotation=rot)
    )
    game.entity_of_body[d.body] = e.id


def _rotation(model: np.ndarray) -> np.ndarray:
    """The rotation ``(4, 4)`` of a pose ``T R S`` (scale divided out of the columns)."""
    a = model[:4, :4]
    return a / np.linalg.norm(a, axis=0)


def _drive_collider(game, d: Manipulable, before: np.ndarray, after: np.ndarray) -> None:
    """Put the kinematic collider at ``before`` moving so that this tick's physics step ends at ``after``.

    The angular velocity is the rotation ``after @ before.T`` spread over the tick
    (its antisymmetric part, exact to third order in the tick's angle; the next tick
    sets the pose again, so nothing accumulates).
    """
    r0, r1 = _rotation(before), _rotation(after)
    c0 = before[:4, 4] + r0 @ d.box_center
    c1 = after[:4, 4] + r1 @ d.box_center
    delta = r1 @ r0.T
    omega = 0.5 * (delta - delta.T) / game.dt  # omega[j, i]: rate of turning axis i towards j
    bivector = [omega[j, i] for i, j in ((0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3))]
    game.physics.set_pose(d.body, position=c0, rotation=r0)
    game.physics.set_velocity(d.body, (c1 - c0) / game.dt, bivector)


def state_bytes(game) -> bytes:
    """The tool; the objects' angles and what they cost are their entities' data."""
    return encode(game.states.manipulation)


def aimed_at(game) -> int | None:
    """The manipulable entity the crosshair's ray meets first within its reach, or None."""
    p = game.player
    eye = p.eye()
    cp = np.cos(p.pitch)
    ray = np.array([np.sin(p.yaw) * cp, np.sin(p.pitch), np.cos(p.yaw) * cp])
    w = float(p.position[3])
    best, best_t = None, np.inf
    for e in game.entities.of_kind("manipulable"):
        if not e.reaches_slice(game, w):
            continue
        key = f"tick:{e.id}"
        game.sections.section(key, e.mesh, e.model(game), w)
        b = game.sections.bounds(key) + np.array([[-AIM_MARGIN], [AIM_MARGIN]])
        if np.isnan(b).any():
            continue
        # Slab test of the ray against the section's bounds.
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (b[0] - eye) / ray
            t2 = (b[1] - eye) / ray
        lo = np.where(ray == 0.0, np.where((eye >= b[0]) & (eye <= b[1]), -np.inf, np.inf), np.minimum(t1, t2))
        hi = np.where(ray == 0.0, np.where((eye >= b[0]) & (eye <= b[1]), np.inf, -np.inf), np.maximum(t1, t2))
        near, far = max(lo.max(), 0.0), hi.min()
        if near <= far and near <= e.data.spec.reach and near < best_t:
            best, best_t = e.id, near
    return best


def _rate(game, d: Manipulable, plane: str) -> tuple[int, int, int, int]:
    """``(cost, per, done, paid)``: thousandths of energy per ``per`` units (millidegrees, or
    micrometres for a slide), the units moved so far and the thousandths paid for them."""
    if plane == "w":  # sliding along w costs what moving the player along w does
        cost = game.level.energy.w_cost_milli if game.energy is not None else 0
        return cost, SLIDE_UNIT, d.slid, d.slide_paid
    return d.spec.cost_milli, 1000, d.turned, d.paid


def _affordable(game, d: Manipulable, plane: str, units: int) -> int:
    """How many of ``units`` the bar can pay for (all when moving is free)."""
    cost, per, done, paid = _rate(game, d, plane)
    if cost <= 0 or game.energy is None:
        return units
    # Largest m with ceil(cost * (done + m) / per) - paid <= bar.
    m = ((game.energy.milli + paid) * per) // cost - done
    return int(max(0, min(units, m)))


def _pay(game, d: Manipulable, plane: str, units: int) -> None:
    cost, per, done, paid = _rate(game, d, plane)
    done += units
    due = -((-cost * done) // per) - paid if cost > 0 and game.energy is not None else 0  # ceil, exact integers
    if due > 0:
        paid += game.energy.spend_up_to(game, due, "manipulate")
    if plane == "w":
        d.slid, d.slide_paid = done, paid
    else:
        d.turned, d.paid = done, paid


def _turn(game, e, plane: str, want: int) -> int:
    """Turn ``e`` by up to ``want`` millidegrees in ``plane`` (limits, energy, the player); returns the turn."""
    d = e.data
    lo, hi = d.limits(plane)
    cur = d.offsets[plane]
    target = min(max(cur + want, lo), hi)
    amount = _affordable(game, d, plane, abs(target - cur))
    if amount == 0:
        return 0
    new = cur + int(np.copysign(amount, target - cur))
    offsets = dict(d.offsets)
    offsets[plane] = new
    if _swallows_player(game, e, offsets):
        return 0
    d.offsets = offsets
    _pay(game, d, plane, amount)
    return new - cur


def _swallows_player(game, e, offsets: dict) -> bool:
    """Would the object with ``offsets`` be around or through the player where it is not now?"""
    p = game.player
    w = float(p.position[3])
    if not e.solid or not e.reaches_slice(game, w):
        return False
    lo, hi = player_box(p.position)
    now, _ = game.sections.section(f"tick:{e.id}", e.mesh, e.model(game), w)
    then, _ = game.sections.section(f"try:{e.id}", e.mesh, e.data.model(offsets), w)
    before = section_collision.triangles_of(now)
    after = section_collision.triangles_of(then)
    return section_collision.box_blocked(lo, hi, after) and not section_collision.box_blocked(lo, hi, before)


def set_offset(game, e, plane: str, milli: int) -> None:
    """Put the manipulable entity ``e`` at ``milli`` millidegrees from the level's rotation in
    ``plane`` at once, as a tool does (no energy, no limits, no check of the player)."""
    d = e.data
    d.offsets = {**d.offsets, plane: int(milli)}
    e.motion.move(d.model())
    game.solids_moved()


def _snap_target(d: Manipulable, plane: str) -> int | None:
    """Where an unheld plane settles: the next step multiple in its last direction (None: already there)."""
    if d.spec.step is None or plane == "w":
        return None
    step = int(round(d.spec.step * 1000))
    cur = d.offsets[plane]
    if cur % step == 0:
        return None
    target = (cur // step + (1 if d.direction[plane] >= 0 else 0)) * step
    lo, hi = d.limits(plane)
    return min(max(target, lo), hi)


def _jump(game, e, d: Manipulable, plane: str, pushed: bool) -> int:
    """Under reduce motion, how far ``plane`` may turn this tick (millidegrees, or slide units):
    a whole jump on the ticks :func:`..motion.jump_now` says, else nothing; a plane left
    between steps (by the bar running dry) settles at once."""
    if plane == "w":
        jump = int(round(SLIDE_SPEED * JUMP_SECONDS * SLIDE_UNIT))
    else:
        jump = int(round((d.spec.step or JUMP_DEG) * 1000))
    if jump_now(game, f"manipulate:{e.id}:{plane}", pushed):
        return jump
    return 0 if pushed else jump


def step(game, actions):
    """Grab, turn, snap and let go; returns the actions the later systems see (walking keys taken while held)."""
    tool = game.states.manipulation
    if not game.entities.of_kind("manipulable"):
        return None
    held = game.entities.get(tool.held) if tool.held is not None else None
    if held is not None and not actions.manipulate:
        game.emit(ManipulationEnded(held.id))
        tool.held, held = None, None
    tool.aimed = aimed_at(game) if held is None else held.id
    if held is None and actions.manipulate and tool.aimed is not None:
        held = game.entities.get(tool.aimed)
        tool.held = held.id
        game.emit(ManipulationStarted(held.id))

    out = None
    changed = False
    for e in game.entities.of_kind("manipulable"):
        d = e.data
        for i, plane in enumerate(d.planes):
            push = 0.0
            if e is held and i < len(AXES):
                push = getattr(actions, AXES[i][0])
            rate = int(round((SLIDE_SPEED * SLIDE_UNIT if plane == "w" else d.spec.speed * 1000) * game.dt))
            if actions.reduced_motion:  # jumps (a step, or JUMP_DEG) instead of a smooth turn
                rate = _jump(game, e, d, plane, abs(push) > DEAD_ZONE)
            turned = 0
            if abs(push) > DEAD_ZONE:
                d.direction[plane] = 1 if push > 0 else -1
                turned = _turn(game, e, plane, rate * d.direction[plane])
            else:
                target = _snap_target(d, plane)
                if target is not None:
                    turned = _turn(game, e, plane, int(np.clip(target - d.offsets[plane], -rate, rate)))
            if turned:
                changed = True
            elif d.moving[plane]:
                game.emit(Manipulated(e.id, plane, d.angle_deg(plane), d.offsets[plane] / 1000.0))
            d.moving[plane] = turned != 0
        before = e.motion.pose
        after = d.model()
        e.motion.move(after)
        if d.body is not None and (not np.array_equal(before, after) or d.was_moving):
            _drive_collider(game, d, before, after)  # also once after a turn, to stop it
        if d.body is not None:
            d.was_moving = not np.array_equal(before, after)
        e.style = "glow" if e.id in (tool.aimed, tool.held) else "solid"
    if changed:
        game.solids_moved()  # the walker's sections of this tick are stale
    if held is not None:
        n = len(held.data.planes)
        taken = {"forward": 0.0, "right": 0.0, "jump": False}
        if n >= 3:
            taken["w"] = 0.0
        out = replace(actions, **taken)
    return out


def _label(d: Manipulable, sep: str = "   ") -> str:
    """The keys of each allowed plane (``{action}`` placeholders) and where it stands, joined by ``sep``."""
    parts = []
    for i, plane in enumerate(d.planes[: len(AXES)]):
        _, plus, minus = AXES[i]
        if plane == "w":
            parts.append(f"[{{{plus}}}] [{{{minus}}}] slide along w (w = {d.angle_deg(plane):+.2f})")
        else:
            parts.append(f"[{{{plus}}}] [{{{minus}}}] turn {plane} ({d.angle_deg(plane):.0f} deg)")
    return sep.join(parts)


def _key_label(game, frame, held, d: Manipulable) -> None:
    """The keys, one plane a line, on screen just right of the held object's section; on
    the message line instead when the section is not in front of the player."""
    b = game.sections.bounds(f"tick:{held.id}")
    label = None
    if not np.isnan(b).any():
        corners = np.array([[b[i, 0], b[j, 1], b[k, 2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
        label = ScreenLabel.beside(_label(d, "\n"), frame.camera, corners)
    if label is None:
        frame.hud.message = _label(d) + "   let go of {manipulate} to release"
    else:
        frame.hud.labels.append(label)
        frame.hud.message = "let go of {manipulate} to release"


def ghost_offsets(d: Manipulable) -> list[tuple[str, int, dict]]:
    """The previews: ``(plane, direction, offsets)`` for the next step each way in each allowed plane
    (directions already at their limit have none)."""
    out = []
    for plane in d.planes:
        lo, hi = d.limits(plane)
        cur = d.offsets[plane]
        snapping = d.spec.step is not None and plane != "w"
        if plane == "w":
            step = int(round(SLIDE_PREVIEW * SLIDE_UNIT))
        else:
            step = int(round((d.spec.step or PREVIEW_DEG) * 1000))
        for sign in (1, -1):
            if sign > 0:
                nxt = (cur // step + 1) * step if snapping else cur + step
            else:
                nxt = -((-cur) // step + 1) * step if snapping else cur - step
            nxt = min(max(nxt, lo), hi)
            if nxt != cur:
                out.append((plane, sign, {**d.offsets, plane: nxt}))
    return out


def draw(game, frame, alpha) -> None:
    tool = game.states.manipulation
    if not game.entities.of_kind("manipulable"):
        return
    held = game.entities.get(tool.held) if tool.held is not None else None
    if held is None:
        aimed = game.entities.get(tool.aimed) if tool.aimed is not None else None
        if aimed is not None:
            frame.hud.message = f"Hold {{manipulate}} to turn the {aimed.name}"
        game.sections.keep("ghost:", set())
        return
    d = held.data
    _key_label(game, frame, held, d)
    if not game.show_ghosts:
        game.sections.keep("ghost:", set())
        return
    w = frame.camera.w
    top = game.sections.bounds(f"tick:{held.id}")
    centre = held.center(game)[:3]
    base_y = (top[1, 1] if not np.isnan(top).any() else centre[1]) + GHOST_GAP
    p = game.player
    right = np.array([np.cos(p.yaw), 0.0, -np.sin(p.yaw)])  # the player's right, in the ground plane
    items = []
    for plane, sign, offsets in ghost_offsets(d):
        key = f"ghost:{held.id}:{plane}{'+' if sign > 0 else '-'}"
        tri, rev = game.sections.section(key, held.mesh, d.model(offsets), w)
        b = game.sections.bounds(key)
        if len(tri.faces) == 0 or np.isnan(b).any():
            continue
        items.append((key, tri, rev, b))
    game.sections.keep("ghost:", {k for k, *_ in items})
    x = -(len(items) - 1) / 2 * (GHOST_SIZE + GHOST_SPACING)
    for key, tri, rev, b in items:
        mid = 0.5 * (b[0] + b[1])
        # A miniature: shrunk (never grown) to fit GHOST_SIZE, centred on its slot in a
        # row along the player's right, floating GHOST_GAP above the object.
        scale = min(1.0, GHOST_SIZE / max(float((b[1] - b[0]).max()), 1e-6))
        target = centre + right * x
        target[1] = base_y + GHOST_SIZE / 2
        frame.drawables.append(Drawable(key, rev, tri, model=ghost_model(mid, target, scale), style="ghost"))
        x += GHOST_SIZE + GHOST_SPACING


def ghost_model(mid, target, scale: float) -> np.ndarray:
    """``(4, 4) float64`` that shrinks a ghost by ``scale`` about ``mid (3,)`` and moves it to ``target (3,)``."""
    m = np.eye(4)
    m[:3, :3] *= scale
    m[:3, 3] = np.asarray(target, dtype=np.float64) - scale * np.asarray(mid, dtype=np.float64)
    return m


SYSTEM = System("manipulation", setup, step, draw, state_bytes)
