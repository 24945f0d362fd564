"""Enemies each tick, after the bullets: the blast's pull, bullet hits, the state machine,
their shots at the player, hidden crystals and the defeat burst.

See :mod:`..enemies` for the kinds, the animation and the states. Everything
here is deterministic: the only randomness is ``game.rng`` (drift targets and
the pause between shots), which the state hash covers.
"""

from __future__ import annotations

import math

import numpy as np

from ...world.gameplay import CrystalSpec
from .. import enemies as en
from .. import health as hp
from ..entities import Placed
from ..events import EnemyDefeated, EnemyHit, LootReleased
from ..player import HALF_WIDTH, HEIGHT
from ..system import System, encode
from . import crystals

ARMOUR_MESSAGE_TICKS = 90


# ------------------------------------------------------------------ setup
def setup(game) -> en.Hive | None:
    """The level's enemies, spawned; None when it has none."""
    specs = game.level.enemies
    if not specs:
        return None
    shot_mesh, shot_reach = en.small_mesh("16-cell", en.SHOT_COLOR)
    hive = en.Hive(shot_mesh=shot_mesh, shot_reach=shot_reach)
    spawn_w = float(game.level.spawn[3])
    for i, spec in enumerate(specs):
        body = en.build_body(spec, hive.bodies)
        keys = spec.keys if spec.keys else en.default_keys(spec.kind)
        side = 1 if spec.position[3] >= spawn_w else -1
        foe = en.Foe(spec, body, keys, i, spec.position.astype(np.float64).copy(), side, spec.health)
        foe.track = en.Track(keys)
        foe.phase = 0.9 * i
        foe.drift = spec.position.astype(np.float64).copy()
        model = en.body_model(body, keys, foe.centre, game.time + foe.phase)
        e = game.entities.spawn(
            "enemy", spec.name, body.mesh, Placed(model), radar="enemy", data=foe, radius=en.body_reach(body, keys)
        )
        hive.foes.append(e.id)
        foe.eid = e.id
        if spec.weak_spot is not None:
            mesh, r = en.small_mesh("5-cell", en.WEAK_COLOR)
            s = en.WEAK_RADIUS / r
            w = game.entities.spawn(
                "weak_spot",
                f"{spec.name} weak spot",
                mesh,
                Placed(_small_pose(foe.weak_point(), s)),
                radar="target",
                style="glow",
                radius=en.WEAK_RADIUS,
            )
            w.data = s
            foe.weak = w.id
        if spec.loot_milli > 0:
            mesh, r = en.small_mesh("16-cell", en.LOOT_COLOR)
            s = en.LOOT_SIZE / r
            at = _small_pose(foe.loot_point(), s)
            lo = game.entities.spawn("loot", f"{spec.name} loot", mesh, Placed(at), style="glow", radius=en.LOOT_SIZE)
            lo.data = s
            foe.loot = lo.id
    return hive


def state_bytes(game) -> bytes:
    """The hive; the enemies and their shots are entities (their data is hashed with them)."""
    return encode(game.states.enemies)


def _small_pose(at, s: float) -> np.ndarray:
    m = np.diag([s, s, s, s, 1.0])
    m[:4, 4] = at
    return m


def foes(game) -> list:
    """The live enemy entities (dying ones included), in the level's order."""
    hive = game.states.enemies
    if hive is None:
        return []
    return [e for e in (game.entities.get(i) for i in hive.foes) if e is not None]


# ------------------------------------------------------------------ movement
#: Half the side of an enemy's core, metres: the box round its centre kept out of the 3D world.
CORE = 0.3


def _boxes(game, ws: np.ndarray) -> np.ndarray:
    """The 3D world's boxes at each of ``ws (m,)``, ``(m, k, 2, 3)`` (NaN where absent): one
    set for every w when the level has no extended worlds."""
    if not game.scene.worlds:
        boxes = game.colliders_at(float(ws[0]))
        return np.broadcast_to(boxes, (len(ws), *boxes.shape))
    return np.stack([game.colliders_at(float(w)) for w in ws])


def _move_all(game, moves: list) -> None:
    """Every enemy of ``moves`` (``(foe, target (4,), speed, w_speed)``) towards its target,
    all at once: x, y, z at ``speed``, w at ``w_speed``; one axis at a time, so it slides
    along a wall instead of sticking, never into the 3D world."""
    if not moves:
        return
    dt = game.dt
    c = np.array([foe.centre for foe, *_ in moves], np.float64)
    target = np.array([t for _, t, _, _ in moves], np.float64)
    speed = np.array([sp for *_, sp, _ in moves]) * dt
    w_speed = np.array([ws for *_, ws in moves]) * dt
    d = target[:, :3] - c[:, :3]
    n = np.sqrt((d * d).sum(axis=1))  # rounded as np.linalg.norm rounds each row: squares, summed in order
    far = n > speed
    step = d.copy()
    step[far] = d[far] * (speed[far] / n[far])[:, None]
    boxes = _boxes(game, c[:, 3])
    for axis in range(3):
        trial = c.copy()
        trial[:, axis] += step[:, axis]
        lo, hi = trial[:, None, :3] - CORE, trial[:, None, :3] + CORE
        blocked = np.any(np.all((lo < boxes[:, :, 1]) & (hi > boxes[:, :, 0]), axis=2), axis=1)
        ok = (step[:, axis] != 0.0) & ~blocked
        c[ok] = trial[ok]
    c[:, 3] += np.clip(target[:, 3] - c[:, 3], -w_speed, w_speed)
    for (foe, *_), centre in zip(moves, c):
        foe.centre = centre


def _set_state(game, foe: en.Foe, state: str) -> None:
    foe.state, foe.since = state, game.tick


def _seconds(game, s: float) -> int:
    return max(1, int(round(s / game.dt)))


def _hide_w(game, foe: en.Foe) -> float:
    """The w it keeps while hidden: its post's, unless that is too near the player's slice."""
    pw = float(game.player.position[3])
    home = float(foe.spec.position[3])
    if abs(home - pw) >= en.HIDE_W:
        return home
    return pw + foe.side * en.HIDE_W


def _leave(game, foe: en.Foe) -> None:
    foe.leave_at = -1
    _set_state(game, foe, "fleeing")


def _think(game, foe: en.Foe, moves: list) -> None:
    """One tick of the state machine: transitions first, then the motion it asks for, added to
    ``moves`` (see :func:`_move_all`)."""
    p = game.player.position
    px, pz, pw = float(p[0]), float(p[2]), float(p[3])
    spec = foe.spec
    home = spec.position
    to_player = _length(px - float(foe.centre[0]), pz - float(foe.centre[2]))
    player_from_post = _length(px - float(home[0]), pz - float(home[2]))
    s = foe.state

    if s == "hidden":
        if player_from_post <= spec.sight and game.tick >= foe.back_at:
            _set_state(game, foe, "approaching")
        else:
            if game.tick >= foe.next_drift:
                foe.drift = home + game.rng.uniform(-1.0, 1.0, 4) * en.DRIFT
                foe.next_drift = game.tick + _seconds(game, en.DRIFT_EVERY)
            target = foe.drift.copy()
            target[3] = _hide_w(game, foe) + (foe.drift[3] - home[3])
            moves.append((foe, target, spec.speed * 0.4, en.W_SPEED))
            return
    if foe.state == "approaching":
        if player_from_post > spec.sight * 1.5:
            _leave(game, foe)
        elif abs(foe.centre[3] - pw) <= en.IN_SLICE and to_player <= spec.reach:
            _set_state(game, foe, "attacking")
            foe.shots_left = en.BURST
            foe.next_shot = game.tick + _seconds(game, en.WINDUP)
        else:
            moves.append((foe, _post_target(foe, p), spec.speed, en.W_SPEED))
            return
    if foe.state == "attacking":
        if to_player < en.FLEE_NEAR or (foe.leave_at >= 0 and game.tick >= foe.leave_at):
            _leave(game, foe)
        elif to_player > spec.reach * 1.25:
            _set_state(game, foe, "approaching")
        else:
            if foe.shots_left > 0 and game.tick >= foe.next_shot and abs(foe.centre[3] - pw) <= en.IN_SLICE:
                _fire(game, foe)
                foe.shots_left -= 1
                pause = en.RECOVER + float(game.rng.uniform(0.0, en.RECOVER_JITTER))
                if foe.shots_left == 0:
                    foe.leave_at = game.tick + _seconds(game, pause)
                else:
                    foe.next_shot = game.tick + _seconds(game, pause + en.WINDUP)
            elif foe.shots_left > 0 and abs(foe.centre[3] - pw) > en.IN_SLICE:
                # The player stepped out of the slice: follow, and wind up again once there.
                foe.next_shot = max(foe.next_shot, game.tick + _seconds(game, en.WINDUP))
            target = foe.centre.copy()
            target[3] = pw
            moves.append((foe, target, spec.speed, en.W_SPEED))
            return
    if foe.state == "fleeing":
        if abs(foe.centre[3] - pw) >= en.HIDE_W:
            _set_state(game, foe, "hidden")
            foe.back_at = game.tick + _seconds(game, float(game.rng.uniform(en.RETURN_MIN, en.RETURN_MAX)))
            foe.next_drift = game.tick
        else:
            target = np.append(home[:3], pw + foe.side * en.HIDE_W * 1.2)
            moves.append((foe, target, spec.speed, en.FLEE_W_SPEED))
        return
    if foe.state == "dragged":
        w0, w1, start, end = foe.pull
        k = min(max((game.tick + 1 - start) / max(end - start, 1), 0.0), 1.0)
        k = k * k * (3.0 - 2.0 * k)
        foe.centre[3] = w0 + (w1 - w0) * k
        if game.tick + 1 >= end:
            foe.pull = None
            _set_state(game, foe, "stunned")
        return
    if foe.state == "stunned" and game.tick - foe.since >= _seconds(game, en.STUN):
        _set_state(game, foe, "attacking")
        foe.shots_left = en.BURST
        foe.next_shot = game.tick + _seconds(game, en.WINDUP)


def _length(x: float, z: float) -> float:
    """``|(x, z)|``, as ``np.linalg.norm`` of the pair rounds it (two products, one sum, one
    root) without its cost: the enemies' state machine asks for a few per enemy and tick."""
    return math.sqrt(x * x + z * z)


def _post_target(foe: en.Foe, player_pos) -> np.ndarray:
    """Where it attacks from: its reach's standoff from the player, on the player's side of
    its post (so it comes towards a player far away and backs off from one too near), on a
    leash from the post, at the post's height and the player's w.

    In plain floats, each operation the one numpy did on the pairs, so the same bits."""
    home = foe.spec.position
    hx, hz, px, pz = float(home[0]), float(home[2]), float(player_pos[0]), float(player_pos[2])
    dx, dz = hx - px, hz - pz
    n = _length(dx, dz)
    ux, uz = (dx / n, dz / n) if n > 1e-9 else (0.0, 1.0)
    stand = float(foe.spec.reach)
    x, z = px + ux * stand * en.STANDOFF, pz + uz * stand * en.STANDOFF
    ox, oz = x - hx, z - hz
    k = _length(ox, oz)
    if k > en.LEASH:
        x, z = hx + ox * (en.LEASH / k), hz + oz * (en.LEASH / k)
    return np.array([x, float(home[1]), z, float(player_pos[3])])


# ------------------------------------------------------------------ shots
def _fire(game, foe: en.Foe) -> None:
    hive = game.states.enemies
    eid = foe.eid
    chest = game.player.position[:3] + np.array([0.0, en.CHEST, 0.0])
    d = chest - foe.centre[:3]
    n = float(np.linalg.norm(d))
    v = d / n * en.SHOT_SPEED if n > 1e-9 else np.array([0.0, 0.0, -en.SHOT_SPEED])
    origin = foe.centre.copy()
    origin[:3] += (v / en.SHOT_SPEED) * min(0.5 * foe.spec.size, max(n - 0.5, 0.0))  # from its skin, not its heart
    s = en.SHOT_RADIUS / hive.shot_reach
    e = game.entities.spawn(
        "enemy_shot",
        "shot",
        hive.shot_mesh,
        Placed(_small_pose(origin, s)),
        style="glow",
        data=en.Shot(origin, np.append(v, 0.0), game.tick, foe.spec.damage, eid),
        radius=en.SHOT_RADIUS,
    )
    hive.shots.append(e.id)


def _fly_shots(game, hive: en.Hive) -> None:
    p = game.player.position
    lo = p[:3] - np.array([HALF_WIDTH, 0.0, HALF_WIDTH]) - en.SHOT_RADIUS
    hi = p[:3] + np.array([HALF_WIDTH, HEIGHT, HALF_WIDTH]) + en.SHOT_RADIUS
    life = _seconds(game, en.SHOT_LIFETIME)
    for sid in list(hive.shots):
        e = game.entities.get(sid)
        shot = e.data
        age = game.tick + 1 - shot.born
        at = shot.at(age, game.dt)
        e.motion.move(_small_pose(at, e.motion.pose[0, 0]))
        gone = age >= life
        if np.all((at[:3] >= lo) & (at[:3] <= hi)) and abs(at[3] - p[3]) <= en.SHOT_W:
            source = game.entities.get(shot.source)
            origin = source.data.centre if source is not None else shot.origin
            if hp.damage(game, shot.damage, origin[[0, 2]], shot.source):
                player_died(game)  # every shot is gone, this one too
                return
            gone = True
        elif _point_in_world(game, at) or _through_solid(game, shot.at(age - 1, game.dt), at):
            gone = True
        if gone:
            hive.shots.remove(sid)
            game.remove(sid)


def _through_solid(game, start, end) -> bool:
    """Does the shot's path this tick cross a solid 4D object or a mesh part (a gate, an arch)?

    The physics' static colliders hold their true shapes (boxes, convex cells, boundary
    tets); the 3D world's boxes are :func:`_point_in_world`'s.
    """
    phys = game.physics
    d = np.asarray(end, np.float64) - start
    n = float(np.linalg.norm(d))
    if phys is None or n == 0.0:
        return False
    hit = phys.raycast(start, d, n, include_world=True)
    return hit is not None and hit[0] == "world"


def _point_in_world(game, at) -> bool:
    boxes = game.colliders_at(float(at[3]))
    if len(boxes) == 0:
        return False
    return bool(np.any(np.all((at[:3] > boxes[:, 0]) & (at[:3] < boxes[:, 1]), axis=1)))


# ------------------------------------------------------------------ hits
def _bullet_hits(game, hive: en.Hive) -> None:
    ars = game.states.weapons
    if ars is None or not ars.bullets:
        return
    live = [e for e in foes(game) if e.data.alive]
    for bid in list(ars.bullets):
        b = game.entities.get(bid)
        bp = b.center(game)
        for e in live:
            foe = e.data
            weak = foe.weak_point()
            # A bullet at the weak spot's w is in the weak spot's slice, not the armour's: it flies on.
            at_weak_w = weak is not None and abs(bp[3] - weak[3]) <= en.WEAK_W + b.radius
            hit_weak = at_weak_w and np.linalg.norm(bp[:3] - weak[:3]) <= en.WEAK_RADIUS + b.radius
            hit_body = (
                not at_weak_w
                and np.linalg.norm(bp[:3] - foe.centre[:3]) <= foe.spec.size + b.radius
                and abs(bp[3] - foe.centre[3]) <= foe.body.w_half + b.radius
            )
            if not (hit_weak or hit_body):
                continue
            damage = 1 if (hit_weak or weak is None) else 0
            ars.hit_tick = game.tick
            if damage == 0:
                hive.armour_tick = game.tick
            game.emit(EnemyHit(e.id, bid, damage, bool(hit_weak)))
            ars.bullets.remove(bid)
            game.remove(bid)
            if damage:
                _hurt(game, e, damage)
            break


def _hurt(game, e, damage: int) -> None:
    foe = e.data
    foe.health -= damage
    foe.hurt_tick = game.tick
    if foe.health <= 0:
        _defeat(game, e)
    elif foe.health * 2 <= foe.spec.health and foe.state in ("approaching", "attacking", "stunned"):
        _leave(game, foe)


def _defeat(game, e) -> None:
    foe = e.data
    _set_state(game, foe, "dying")
    foe.pull = None
    game.states.enemies.defeated += 1
    game.states.enemies.armour_tick = -(10**9)  # its armour is no longer the news
    opened = ""
    door = game.entities.named(foe.spec.opens) if foe.spec.opens else None
    if door is not None and door.kind in ("object", "body"):
        game.remove(door.id)
        opened = foe.spec.opens
    if foe.weak is not None:
        game.remove(foe.weak)
        foe.weak = None
    game.emit(EnemyDefeated(e.id, foe.spec.name, opened))
    _release(game, e, "defeated")


def _release(game, e, reason: str) -> None:
    """Turn the crystal hidden in the enemy into a crystal the player can take (once)."""
    foe = e.data
    if foe.loot is None:
        return
    at = foe.loot_point()
    game.remove(foe.loot)
    foe.loot = None
    lo, hi = game.level.w_range
    pw = float(game.player.position[3])
    # Where the player can reach it: at their w when a pull shook it out, else where it fell, within the range.
    w = pw if reason in ("forced", "camera") else min(max(float(at[3]), lo), hi)
    spec = CrystalSpec(f"{foe.spec.name} loot", np.array([at[0], at[1], at[2], w]), foe.spec.loot_milli)
    c = crystals.spawn(game, spec)
    game.emit(LootReleased(e.id, c.id, reason))


# ------------------------------------------------------------------ blast
def _blasts(game) -> None:
    """The blast drags every enemy within its radius into the player's slice."""
    blasts = [ev for ev in game.events if ev.kind == "blast"]
    if not blasts:
        return
    ars = game.states.weapons
    spec = ars.current if ars.current.kind == "blast" else next(s for s in ars.specs if s.kind == "blast")
    centre = game.player.center()
    end = game.tick + max(1, round(spec.duration / game.dt))
    for e in foes(game):
        foe = e.data
        if foe.alive and np.linalg.norm(foe.centre[:3] - centre) <= spec.radius:
            _drag(game, foe, float(blasts[-1].w), end)


def _drag(game, foe: en.Foe, w: float, end: int, by: str = "blast") -> None:
    """Pull the enemy from its w to ``w``, arriving at tick ``end``, then stunned; ``by`` is what
    pulls it (``"blast"`` or ``"camera"``), the cause its crystal comes out with."""
    foe.pull = (float(foe.centre[3]), float(w), game.tick, end)
    foe.pulled_by = by
    foe.shots_left = 0
    _set_state(game, foe, "dragged")


def hold(game, w: float, ticks: int) -> None:
    """Drag every live enemy to ``w`` and keep it there, in the slice and animated, for ``ticks``
    ticks, as a blast without end would (benchmarks, tests)."""
    for e in foes(game):
        if e.data.alive:
            _drag(game, e.data, w, game.tick + ticks)


#: The frustum camera's hold: switching to it drags every enemy in front of the player within
#: this many metres (the 4D camera sees them whole) to the player's w, over this many seconds.
FRUSTUM_HOLD_RANGE = 12.0
FRUSTUM_HOLD_TIME = 0.8


def _frustum_holds(game) -> None:
    """The switch to the frustum camera forces the enemies it looks at into the player's slice,
    as the blast does.

    The rule for loot the camera frees (the paper: crystals hidden in an enemy are looted "by
    forcing that enemy to perform particular movements or by controlling the 4D camera"): the
    switch to the frustum view holds every live enemy whose centre is ahead of the player (in
    x, z, within 90 degrees of the view's heading) and within :data:`FRUSTUM_HOLD_RANGE` of the
    eye, and drags it to the player's w over :data:`FRUSTUM_HOLD_TIME`. When that pull carries
    the crystal inside it across the player's slice (its w within the crystal's size of the
    player's, or passing it), the crystal comes out at the player's w with the cause
    ``"camera"`` (:class:`~..events.LootReleased`); a blast's pull frees it as ``"forced"``.
    An enemy behind the player, or farther, keeps its crystal."""
    if not any(ev.kind == "camera_switched" and ev.mode == "frustum" for ev in game.events):
        return
    p = game.player
    eye, pw = p.eye(), float(p.position[3])
    ahead = np.array([np.sin(p.yaw), np.cos(p.yaw)])  # the view's heading in x, z (yaw 0: +z)
    end = game.tick + max(1, round(FRUSTUM_HOLD_TIME / game.dt))
    for e in foes(game):
        foe = e.data
        rel = foe.centre[:3] - eye
        if foe.alive and np.linalg.norm(rel) <= FRUSTUM_HOLD_RANGE and rel[[0, 2]] @ ahead > 0.0:
            _drag(game, foe, pw, end, by="camera")


def _forced_loot(game, e, w_before: float) -> None:
    """A dragged enemy's crystal comes out when the pull carries its w across the player's slice."""
    foe = e.data
    if foe.loot is None or foe.state != "dragged":
        return
    pw = float(game.player.position[3])
    off = foe.loot_point()[3] - foe.centre[3]
    before, now = w_before + off - pw, foe.centre[3] + off - pw
    if abs(now) <= en.LOOT_SIZE or before * now < 0:
        _release(game, e, "camera" if foe.pulled_by == "camera" else "forced")


# ------------------------------------------------------------------ step and draw
def player_died(game) -> None:
    """The player died: shots vanish and every enemy in or near the slice backs off."""
    hive = game.states.enemies
    if hive is None:
        return
    for sid in hive.shots:
        game.remove(sid)
    hive.shots = []
    for e in foes(game):
        if e.data.state in ("approaching", "attacking", "dragged", "stunned"):
            e.data.pull = None
            _leave(game, e.data)


def _pose(game, posed: list) -> None:
    """Every enemy of ``posed`` at the next tick's animation pose, in one pass, and its markers."""
    if not posed:
        return
    t = game.time + game.dt
    burst = _seconds(game, en.DEFEAT_TIME)
    grows = [1.0 + 1.5 * (game.tick + 1 - e.data.since) / burst if e.data.state == "dying" else 1.0 for e in posed]
    models = en.body_models([e.data for e in posed], [t + e.data.phase for e in posed], grows)
    for e, model in zip(posed, models):
        e.motion.move(model)
        foe = e.data
        for eid, at in ((foe.weak, foe.weak_point), (foe.loot, foe.loot_point)):
            if eid is not None:
                m = game.entities.get(eid)
                m.motion.move(_small_pose(at(), m.data))


def _look(game, e) -> None:
    """Its style this tick: glowing after a hit, flickering while winding up a shot, bursting when defeated."""
    foe = e.data
    style = "solid"
    if foe.state == "dying" or game.tick - foe.hurt_tick < _seconds(game, en.HIT_FLASH):
        style = "glow"
    elif foe.state == "attacking" and foe.shots_left > 0:
        left = foe.next_shot - game.tick
        if 0 <= left < _seconds(game, en.WINDUP) and (left // 5) % 2 == 0:
            style = "glow"
    e.style = style


def step(game, actions) -> None:
    hive = game.states.enemies
    if hive is None:
        return
    _blasts(game)
    _frustum_holds(game)
    _bullet_hits(game, hive)
    posed, moves = [], []
    for e in foes(game):
        foe = e.data
        if foe.state == "dying":
            if game.tick - foe.since >= _seconds(game, en.DEFEAT_TIME):
                game.remove(e.id)
                hive.foes.remove(e.id)
                continue
        else:
            w_before = float(foe.centre[3])
            _think(game, foe, moves)
            _forced_loot(game, e, w_before)  # only a dragged enemy's: it never moves below
        posed.append(e)
        _look(game, e)
    _move_all(game, moves)  # no enemy's move reads another's: all of them at once
    _pose(game, posed)  # nothing above reads a pose
    _fly_shots(game, hive)


def draw(game, frame, alpha) -> None:
    hive = game.states.enemies
    if hive is None:
        return
    if game.tick - hive.armour_tick < ARMOUR_MESSAGE_TICKS and not frame.hud.message:
        frame.hud.message = "Armoured! Hit its weak spot: it hides at another w"


SYSTEM = System("enemies", setup, step, draw, state_bytes)
