"""What the probe's bots can do, each a generator of per-tick actions (see :mod:`.pilot`):
take a crystal, pick a weapon up, shoot a switch (from where the bullet's w swing reaches it), blast, cast the
field, shoot through the frustum camera, turn a manipulable object, push a body, fight an
enemy, turn the slice, and walk to the goal with a walker's tricks when the way is blocked.

Each reads targets from the game (:mod:`.read`) and respects :class:`.pilot.Allow`.
"""

from __future__ import annotations

import math

import numpy as np

from ..game.actions import Actions
from ..world.pickups import KEY_OF
from . import read
from .pilot import (
    JUMP_CLEAR,
    Ctx,
    aim_at,
    box_at,
    distance_xz,
    drive,
    goto,
    idle,
    look,
    move_w,
    turn_to,
    wait,
    wrap,
    yaw_to,
)

#: Where the bot stands to shoot: never closer than this to what it shoots at (m).
MIN_SHOT = 1.0


# ------------------------------------------------------------------ weapons
def weapon_slot(ctx: Ctx, kind: str) -> int | None:
    """The slot of the owned weapon of ``kind`` the strategy may use, or None."""
    if kind not in ctx.allow.weapons:
        return None
    return next((k for k, s in enumerate(read.weapons(ctx.game)) if s.kind == kind and read.owned(ctx.game, k)), None)


def fetch(ctx: Ctx, kind: str):
    """Walk into the pickup of ``kind`` (at its w, when the strategy moves along w), if the
    strategy may use that weapon and one lies in the level. Returns whether it is owned."""
    game = ctx.game
    for _ in range(2):
        if kind not in ctx.allow.weapons or weapon_slot(ctx, kind) is not None:
            break
        lying = read.pickups(game, kind)
        if not lying:
            break
        w = float(lying[0].center[3]) if ctx.allow.w else None
        yield from goto(ctx, lying[0].center[[0, 2]], w, tol=0.3, ticks=1200)
    return weapon_slot(ctx, kind) is not None


def select(ctx: Ctx, k: int):
    """Take weapon ``k`` in hand (the number key of its kind)."""
    game = ctx.game
    press = KEY_OF[read.weapons(game)[k].kind]
    for _ in range(12):
        if read.slot(game) == k:
            return True
        yield Actions(presses=((press, 1),))
    return read.slot(game) == k


def use(ctx: Ctx, kind: str, yaw: float | None = None, pitch: float = 0.0):
    """Use the weapon of ``kind`` once (fetching it first from its pickup), facing ``yaw, pitch``
    (default: as now). Returns True when it fired."""
    game = ctx.game
    yield from fetch(ctx, kind)
    k = weapon_slot(ctx, kind)
    if k is None:
        return False
    yield from select(ctx, k)
    yield from turn_to(ctx, read.view(game)[0] if yaw is None else yaw, pitch)
    for _ in range(180):
        if read.weapon_ready(game):
            break
        yield idle(game)
    before = read.count(game, "weapon_refused")
    yield Actions(presses=(("fire", 1),))
    return read.count(game, "weapon_refused") == before


def gun(ctx: Ctx):
    """The gun the strategy may use, or None."""
    k = weapon_slot(ctx, "gun")
    return None if k is None else read.weapons(ctx.game)[k]


def swing_distance(spec, dw: float, tolerance: float) -> float | None:
    """How far ahead a bullet of ``spec`` is ``dw`` along w from where it was fired (within
    ``tolerance``), the nearest such distance from :data:`MIN_SHOT` on; None if never."""
    d = np.arange(MIN_SHOT, spec.speed * spec.lifetime, 0.05)
    if len(d) == 0:
        return None
    miss = np.abs(spec.amplitude * np.sin(2 * np.pi * d / (spec.speed * spec.period)) - dw)
    good = np.flatnonzero(miss <= 0.5 * tolerance)
    if len(good):
        return float(d[good[0]])  # the nearest spot where the swing is well within reach
    best = int(np.argmin(miss))
    return float(d[best]) if miss[best] <= tolerance else None


def swing_miss(spec, d: float, dw: float) -> float:
    """How far along w a bullet ``d`` metres out is from ``dw`` off the w it was fired at."""
    return abs(spec.amplitude * math.sin(2 * math.pi * d / (spec.speed * spec.period)) - dw)


def shot_spot(ctx: Ctx, spec, aim4, tolerance: float):
    """Where to stand (``(x, z)``, w) to hit ``aim4``: at the w nearest it the strategy may
    reach, as far from it as the bullet needs to swing there. None if no spot works."""
    game = ctx.game
    lo, hi = read.w_range(game)
    w0 = float(np.clip(aim4[3], lo, hi)) if ctx.allow.w else float(read.feet(game)[3])
    d = swing_distance(spec, aim4[3] - w0, tolerance * 0.8)
    if d is None:
        return None
    p = read.feet(game)
    away = np.array([p[0] - aim4[0], p[2] - aim4[2]])
    n = np.linalg.norm(away)
    away = away / n if n > 1e-6 else np.array([0.0, -1.0])
    return np.array([aim4[0], aim4[2]]) + away * d, w0


def fire_at(ctx: Ctx, point3, done, tries: int = 3, wait_ticks: int = 150):
    """Shoot the gun at ``point3`` until ``done()`` or ``tries`` shots; returns ``done()``."""
    game = ctx.game
    for _ in range(tries):
        if done():
            return True
        yaw, pitch = aim_at(game, point3)
        if not (yield from use(ctx, "gun", yaw, pitch)):
            return done()
        for _ in range(wait_ticks):
            if done() or read.live_bullets(game) == 0:
                break
            yield idle(game)
    return done()


# ------------------------------------------------------------------ switches
def _target(game, name: str):
    return next((t for t in read.targets(game, hit=None) if t.name == name), None)


def _hit(game, name: str) -> bool:
    t = _target(game, name)
    return t is None or t.id not in {x.id for x in read.targets(game)}


def reachable(ctx: Ctx, spec, t) -> bool:
    """Can a bullet from some w the strategy may stand at come within hitting range of ``t``?"""
    lo, hi = read.w_range(ctx.game)
    w = float(np.clip(t.center[3], lo, hi)) if ctx.allow.w else float(read.feet(ctx.game)[3])
    return abs(t.center[3] - w) <= spec.amplitude + spec.size + t.radius


def hit_target(ctx: Ctx, name: str, step=None):
    """Throw the switch ``name``: the field first if it is disguised, the blast if no bullet
    reaches it, the frustum camera if the route shot it so; then aim and fire."""
    game, allow = ctx.game, ctx.allow
    yield from fetch(ctx, "gun")
    t, spec = _target(game, name), gun(ctx)
    if t is None or _hit(game, name) or spec is None or not allow.aim:
        return
    if read.target_spec(game, t.id).disguised:
        if weapon_slot(ctx, "field") is None:
            return  # without the field the bot does not know the crate is a switch
        yield from goto(ctx, t.center[[0, 2]] + np.array([0.0, -3.0]), ticks=600)
        yield from use(ctx, "field")
    if step is not None and step.info.get("mode") == "frustum":
        yield from frustum_shot(ctx, name, step)
        return
    if not reachable(ctx, spec, t) and weapon_slot(ctx, "blast") is not None:
        yield from goto(ctx, t.center[[0, 2]] + _toward_player(game, t.center, 2.5), ticks=900)
        yield from use(ctx, "blast")
        yield from wait(ctx, 45)
        t = _target(game, name)
    if not reachable(ctx, spec, t):
        return
    spot = _route_spot(ctx, spec, t, step) or shot_spot(ctx, spec, t.center, spec.size + t.radius)
    if spot is None:
        return
    xz, w0 = spot
    yield from goto(ctx, xz, w0, tol=0.25, ticks=1200)
    yield from fire_at(ctx, _target(game, name).center[:3], lambda: _hit(game, name))


def _route_spot(ctx: Ctx, spec, t, step):
    """Where the route fired from, when a bullet from there (at the w the strategy may
    take) still reaches the switch; else None."""
    if step is None or step.at is None:
        return None
    w0 = float(step.at[3]) if ctx.allow.w else float(read.feet(ctx.game)[3])
    d = float(np.hypot(*(t.center[[0, 2]] - step.at[[0, 2]])))
    if swing_miss(spec, d, t.center[3] - w0) > 0.8 * (spec.size + t.radius):
        return None
    return step.at[[0, 2]], w0


def _toward_player(game, c4, d: float) -> np.ndarray:
    p = read.feet(game)
    v = np.array([p[0] - c4[0], p[2] - c4[2]])
    n = np.linalg.norm(v)
    return v / n * d if n > 1e-6 else np.array([0.0, -d])


def frustum_shot(ctx: Ctx, name: str, step=None):
    """Hit a switch through the frustum camera: from the route's spot with its orbit, or,
    without the orbit, standing at the switch's own x, z; then back to the plain view."""
    game, mode = ctx.game, ctx.allow.frustum
    t = _target(game, name)
    if mode == "none" or t is None:
        return
    orbit = 0.0
    if mode == "fixed" or step is None:
        yield from goto(ctx, t.center[[0, 2]], tol=0.2, ticks=900)
    else:
        yield from goto(ctx, step.at[[0, 2]], tol=0.2, ticks=900)
        yield from turn_to(ctx, step.yaw, 0.0)
        orbit = step.info.get("orbit", 0.0)
    yield Actions(presses=(("switch_camera", 1),))
    speed = max(game.level.camera.orbit_speed, 1e-6)
    for _ in range(int(abs(orbit) / speed * 60)):
        yield Actions(orbit_right=orbit > 0, orbit_left=orbit < 0)
    for _ in range(4):
        if _hit(game, name) or read.camera_mode(game) != "frustum":
            break
        img = read.image_of(game, _target(game, name).center)
        if img is None or np.linalg.norm(img - read.eye(game)) < 1.0:
            yaw, pitch = read.view(game)[0], 0.0
        else:
            yaw, pitch = aim_at(game, img)
        yield from use(ctx, "gun", yaw, pitch)
        yield from wait(ctx, 40)
    if read.camera_mode(game) == "frustum":
        yield Actions(presses=(("switch_camera", 1),))
    yield from wait(ctx, 70)


def _switch_from(ctx: Ctx, step):
    """Stand where the route switched the frustum camera on, face as it did, and switch."""
    yield from goto(ctx, step.at[[0, 2]], tol=0.05, ticks=900)
    yield from turn_to(ctx, step.yaw, step.pitch)
    yield Actions(presses=(("switch_camera", 1),))


def orbit_to(ctx: Ctx, deg: float, ticks: int = 1200):
    """Hold the orbit keys until the detached camera stands within one tick's stride of ``deg``."""
    game = ctx.game
    stride = game.level.camera.orbit_speed / 60.0
    for _ in range(ticks):
        gap = deg - read.orbit_deg(game)
        if abs(gap) <= stride / 2 or read.camera_mode(game) != "frustum":
            return
        yield Actions(orbit_right=gap > 0, orbit_left=gap < 0)


def camera_loot(ctx: Ctx, step):
    """Free an enemy's crystal as the route did (the frustum switch from the route's spot, which
    holds the enemy in the slice), switch back and take it."""
    game = ctx.game
    before = read.count(game, "loot_released")
    yield from _switch_from(ctx, step)
    for _ in range(120):
        if read.count(game, "loot_released") > before or read.camera_mode(game) != "frustum":
            break
        yield idle(game)
    if read.camera_mode(game) == "frustum":
        yield Actions(presses=(("switch_camera", 1),))
    for c in [c for c in read.crystals(game) if c.name == f"{step.name} loot"]:
        yield from collect(ctx, c)


def frustum_walk(ctx: Ctx, step):
    """Walk on a frustum image as the route did: switch from its spot, orbit as it had (not with
    the orbit forbidden), then walk to the goal while the view holds."""
    yield from _switch_from(ctx, step)
    if ctx.allow.frustum == "orbit":
        yield from orbit_to(ctx, step.info.get("orbit", 0.0))
    yield from walk_to_goal(ctx)


# ------------------------------------------------------------------ crystals
def collect(ctx: Ctx, thing):
    """Walk into a crystal (at its w, when the strategy moves along w)."""
    w = float(thing.center[3]) if ctx.allow.w else None
    yield from goto(ctx, thing.center[[0, 2]], w, tol=0.3, ticks=900)


def gather(ctx: Ctx, seen: set):
    """Take the crystals the strategy may know of, nearest first (``seen``: names at the start
    that lay in the starting slice)."""
    game = ctx.game
    if ctx.allow.crystals == "none" or read.energy(game) is None:
        return
    tried: set = set()
    while True:
        left = [c for c in read.crystals(game) if c.name not in tried]
        if ctx.allow.crystals == "visible":
            left = [c for c in left if c.name in seen]
        if not ctx.allow.w:
            left = [c for c in left if abs(c.center[3] - read.feet(game)[3]) <= c.radius]
        if not left:
            return
        c = min(left, key=lambda c: distance_xz(game, c.center[[0, 2]]) + abs(c.center[3] - read.feet(game)[3]))
        tried.add(c.name)
        yield from collect(ctx, c)


# ------------------------------------------------------------------ manipulation
def turn_handle(ctx: Ctx, name: str, plane: str, angle: float):
    """Grab the manipulable ``name`` and turn it in ``plane`` to ``angle`` (degrees)."""
    game = ctx.game
    h = next((h for h in read.handles(game) if h.name == name), None)
    if h is None or plane not in h.angles:
        return
    target = h.center[[0, 2]]
    while distance_xz(game, target) > h.reach - 1.5:
        if not (yield from goto(ctx, target, tol=h.reach - 1.5, ticks=600)):
            break
    yaw, pitch = aim_at(game, h.center[:3])
    yield from turn_to(ctx, yaw, pitch)
    axis, sign = read.TURN_AXES[list(h.angles).index(plane)][0], 1.0
    for _ in range(60 * 20):
        h = next(x for x in read.handles(game) if x.name == name)
        gap = angle - h.angles[plane]
        if read.held(game) == h.id and abs(gap) <= (h.step or 1.0) * 0.5:
            break
        sign = 1.0 if gap > 0 else -1.0
        push = {axis: sign} if read.held(game) == h.id else {}
        yield Actions(manipulate=True, **push)
    yield from wait(ctx, 60)  # let go: it settles on the next step


# ------------------------------------------------------------------ bodies
def push_body(ctx: Ctx, name: str, dest_xz, ticks: int = 1800):
    """Push the body ``name`` to ``dest_xz``: get behind it, walk it there, step round to
    get behind again when it drifts off the line."""
    game = ctx.game
    end = game.tick + ticks
    while game.tick < end:
        b = read.body_named(game, name)
        if b is None:
            return False
        to = np.asarray(dest_xz, float) - b.center[[0, 2]]
        dist = np.linalg.norm(to)
        if dist < 0.3:
            return True
        d = to / dist
        half = b.radius / 2
        w = _body_w(ctx, b)
        behind = b.center[[0, 2]] - d * (half + 0.55)
        p = read.feet(game)[[0, 2]]
        if np.dot(p - b.center[[0, 2]], d) > -half:  # on the wrong side: round it
            side = np.array([-d[1], d[0]])
            side = side if np.dot(p - b.center[[0, 2]], side) >= 0 else -side
            yield from goto(ctx, b.center[[0, 2]] + side * (half + 0.9) - d * (half + 0.6), w, ticks=300)
        if distance_xz(game, behind) > 0.3:
            yield from goto(ctx, behind, w, tol=0.2, ticks=300)
        for _ in range(60):
            yield drive(game, np.asarray(dest_xz, float), w, jump=False, allow_w=ctx.allow.w)
            b2 = read.body_named(game, name)
            if b2 is None or np.linalg.norm(np.asarray(dest_xz) - b2.center[[0, 2]]) < 0.3:
                break
    return False


def _body_w(ctx: Ctx, b) -> float | None:
    """The w to push the body at: its own, when it lies off the slice and the strategy may
    find it there (the radar shows its pin) and move along w; else None (stay)."""
    here = float(read.feet(ctx.game)[3])
    if abs(b.center[3] - here) <= 0.1 or not (ctx.allow.w and ctx.allow.radar):
        return None
    return float(b.center[3])


# ------------------------------------------------------------------ enemies
def fight(ctx: Ctx, name: str, ticks: int = 3600):
    """Beat the enemy ``name``: wait for it at a distance while it hides, and once it is in
    the slice stand where the bullet's swing reaches the w of its weak spot (or its body),
    face it and fire whenever the gun is ready and the swing from here reaches it."""
    game = ctx.game
    spec = gun(ctx)
    if spec is None or not ctx.allow.enemies:
        return
    lo, hi = read.w_range(game)
    end = game.tick + ticks
    while game.tick < end and not read.won(game):
        foe = next((f for f in read.foes(game) if f.name == name), None)
        if foe is None:
            return
        me = read.feet(game)
        weak = foe.weak_spot is not None
        aim_w = foe.center[3] + (foe.weak_spot[3] if weak else 0.0)
        tol = (read.WEAK_W if weak else 0.5) + spec.size
        w_stand = float(np.clip(aim_w - 0.7 * spec.amplitude, lo, hi)) if ctx.allow.w else float(me[3])
        want = swing_distance(spec, aim_w - w_stand, tol) or spec.speed * spec.period / 4
        spot = foe.center[[0, 2]] + _toward_player(game, foe.center, want)
        if distance_xz(game, spot) > 0.8 or abs(me[3] - w_stand) > 0.05:
            yield drive(game, spot, w_stand, allow_w=ctx.allow.w)
            continue
        yaw, pitch = aim_at(game, foe.center[:3])
        d_now = float(np.hypot(*(foe.center[[0, 2]] - me[[0, 2]])))
        reaches = swing_miss(spec, d_now, aim_w - me[3]) <= 0.8 * tol
        fire = reaches and read.weapon_ready(game) and abs(wrap(yaw - read.view(game)[0])) < 0.05
        dy, dp = look(game, yaw, pitch)
        yield Actions(yaw=dy, pitch=dp, presses=(("fire", 1),) if fire else ())


# ------------------------------------------------------------------ the slice
def turn_slice(ctx: Ctx, step, back_after: float | None = None):
    """Turn the slice as the route did at its spot; with ``back_after``, walk that far towards
    the goal and turn it back (half way across, say)."""
    game = ctx.game
    if ctx.allow.slice_turn == "none":
        return
    yield from goto(ctx, step.at[[0, 2]], tol=0.3, ticks=900)
    yield from turn_to(ctx, step.yaw, 0.0)
    yield Actions(presses=((step.name, step.info.get("presses", 1)),))
    yield from wait(ctx, 90)
    if back_after is None:
        return
    centre, _, _ = read.goal(game)
    start = read.feet(game)[[0, 2]]
    while distance_xz(game, start) < back_after and not read.won(game):
        yield drive(game, centre[[0, 2]])
    undo = step.name.replace("_pos", "_tmp").replace("_neg", "_pos").replace("_tmp", "_neg")
    yield Actions(presses=((undo, step.info.get("presses", 1)),))
    yield from wait(ctx, 90)


# ------------------------------------------------------------------ the goal
def goal_w(ctx: Ctx) -> float | None:
    """The w the bot heads for at the goal: the middle of its w range when the strategy may
    know it (the radar shows what marks it) and move there."""
    _, _, wr = read.goal(ctx.game)
    if wr is None or not (ctx.allow.w and ctx.allow.radar):
        return None
    return 0.5 * (wr[0] + wr[1])


def walk_to_goal(ctx: Ctx, tricks: bool = True, ticks: int = 3600):
    """Walk to the goal, jumping where the ground asks for it. With ``tricks``, a walker
    stopped short tries, in turn: firing straight ahead, sweeping along w, and stepping
    aside along the obstacle."""
    game = ctx.game
    centre, _, _ = read.goal(game)
    xz, w = centre[[0, 2]], goal_w(ctx)
    end = min(game.tick + ticks, ctx.give_up or 10**9)
    attempt = 0
    while game.tick < end and not read.won(game) and attempt < 9:
        if (yield from goto(ctx, xz, w, tol=0.2, ticks=end - game.tick)):
            yield from wait(ctx, 5)  # inside the goal box: done next tick
            if read.won(game) or w is not None:
                return read.won(game)
        if not tricks:
            return read.won(game)
        attempt += 1
        yield from unstick(ctx, attempt)
    return read.won(game)


def unstick(ctx: Ctx, attempt: int):
    """One try at getting past what stops a walker (see :func:`walk_to_goal`), in turn:
    fire straight ahead, move along w, step aside to the right, back off four metres and fire
    ahead, move along w again, step aside to the left."""
    game = ctx.game
    centre, _, _ = read.goal(game)
    heading = yaw_to(game, centre[[0, 2]])
    trick = (attempt - 1) % 6
    armed = weapon_slot(ctx, "gun") is not None
    if trick in (0, 3) and armed:
        if trick == 3:
            p = read.feet(game)
            yield from goto(ctx, p[[0, 2]] - 4.0 * np.array([math.sin(heading), math.cos(heading)]), ticks=240)
            heading = yaw_to(game, centre[[0, 2]])
        for _ in range(2):
            yield from use(ctx, "gun", heading, 0.0)
        yield from wait(ctx, 30)
    elif trick in (1, 4) and ctx.allow.w:
        lo, hi = read.w_range(game)
        here = float(read.feet(game)[3])
        near, far = sorted((lo, hi), key=lambda v: abs(v - here))
        yield from move_w(ctx, (near, far, float(game.level.spawn[3]))[(attempt // 6) % 3])
    else:
        yield from sidestep(ctx, 1 if trick < 3 else -1)


def clear_towards(game, heading: float, d: float = 0.8) -> bool:
    """Is the way ``d`` metres ahead along ``heading`` open to a walker (or a jumper)?"""
    pos = read.feet(game)
    w = float(pos[3])
    lo, hi = box_at(pos, d * math.sin(heading), d * math.cos(heading), 0.36)
    if not read.blocked_box(game, lo, hi, w):
        return True
    lo, hi = box_at(pos, d * math.sin(heading), d * math.cos(heading), JUMP_CLEAR)
    return not read.blocked_box(game, lo, hi, w)


def sidestep(ctx: Ctx, side: int, ticks: int = 300):
    """Walk along an obstacle (to the right for ``side = 1``) until the way to the goal opens,
    then a step past it."""
    game = ctx.game
    centre, _, _ = read.goal(game)
    for _ in range(ticks):
        to_goal = yaw_to(game, centre[[0, 2]])
        if clear_towards(game, to_goal):
            break
        p = read.feet(game)
        along = to_goal + side * math.pi / 2
        yield drive(game, p[[0, 2]] + 2.0 * np.array([math.sin(along), math.cos(along)]))
    for _ in range(25):
        yield drive(game, centre[[0, 2]])
