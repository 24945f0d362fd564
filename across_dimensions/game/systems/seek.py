"""Seek: one key moves the player along w to the w of the nearest thing of interest.

Things of interest are crystals, targets, enemies and rigid bodies within the
radar's range (or :data:`RANGE` metres without a radar), and the goal when it
only counts at some w. The first press picks the nearest one (4D distance from
the player) and glides there; a second press within :data:`CYCLE_SECONDS` (or
while still gliding) goes on to the next one in the same order, wrapping round.

The glide goes through the walker's own w motion (``step_player``'s
``w_goal``), so it is paid per unit of w exactly as a held w key is, and the
range, the energy bar, walls and bodies stop it exactly as they stop walking.
When it is stopped short the player stays at the nearest reachable w and the
HUD says why (a :class:`~..events.SeekBlocked` event). A held w key takes over
and ends the seek. ``seek_jump``, and ``seek`` with the player's "reduce motion"
setting on (:mod:`..motion`), land in one tick instead of gliding; when the
jump is refused it falls back to gliding, which stops at the nearest reachable w.

A level can turn seek off with ``[seek] enabled = false``.

The system's state is a :class:`Seek` (``game.states.seek``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..events import SeekArrived, SeekBlocked, SeekStarted
from ..system import System, encode

#: Entity kinds a seek may head for (radar pin kinds of things a player looks for).
KINDS = ("crystal", "target", "enemy", "body")
#: Metres within which things count when the level has no radar.
RANGE = 25.0
#: A second press within this many seconds of the last seek cycles to the next thing.
CYCLE_SECONDS = 3.0
#: Things already this close to the player's w are not worth seeking (a hair of w).
SAME_W = 1e-3
#: How long the HUD shows what seek did.
MESSAGE_SECONDS = 2.5
GOAL = "goal"
_WHY = {
    "wall": "a wall is in the way",
    "body": "a body is in the way",
    "energy": "not enough energy",
    "range": "the end of the level's w range",
}


@dataclass
class Seek:
    """What seek is doing (``game.states.seek``).

    Attributes
    ----------
    order : list
        Entity ids (and :data:`GOAL`) in the order presses visit them, nearest first.
    index : int
        Which of ``order`` is sought.
    active : bool
        Gliding (or jumping) now.
    jump : bool
        Land in one tick instead of gliding.
    last_tick : int
        Tick of the last press, for cycling.
    message : str
        Shown on the HUD until ``message_tick``.
    """

    order: list[int | str] = field(default_factory=list)
    index: int = -1
    active: bool = False
    jump: bool = False
    last_tick: int = -(10**9)
    message: str = ""
    message_tick: int = -1

    @property
    def sought(self):
        return self.order[self.index] if 0 <= self.index < len(self.order) else None


def setup(game) -> Seek:
    return Seek()


def state_bytes(game) -> bytes:
    return encode(game.states.seek)


def _target_w(game, thing) -> float | None:
    """The w a seek for ``thing`` heads for, inside the level's range; None if it is gone."""
    lo, hi = game.level.w_range
    if thing == GOAL:
        gw = game.level.goal.w_range
        if gw is None:
            return None
        w = float(np.clip(game.player.position[3], max(gw[0], lo), min(gw[1], hi)))
    else:
        e = game.entities.get(thing)
        if e is None:
            return None
        w = float(e.center(game)[3])
    return float(np.clip(w, lo, hi))


def candidates(game) -> list:
    """Things of interest in reach, nearest first (ties by id): entity ids, and :data:`GOAL`."""
    p = game.player.position
    reach = game.radar_settings.range if game.radar_settings is not None else RANGE
    table = game.entity_table()
    found = []
    for e, c in zip(table.entities, table.centers):
        if e.kind not in KINDS:
            continue
        dx, dz = c[0] - p[0], c[2] - p[2]
        if dx * dx + dz * dz > reach * reach:  # no hypot: glibc versions round it differently
            continue
        found.append((float(np.linalg.norm(c - p)), e.id, e.id))
    g = game.level.goal
    if g.w_range is not None:
        gc = np.array([g.center[0], g.center[1] - 1.0, g.center[2], np.clip(p[3], *g.w_range)])
        found.append((float(np.linalg.norm(gc - p)), 1 << 62, GOAL))
    return [thing for *_, thing in sorted(found, key=lambda f: (f[0], f[1]))]


def _say(game, s: Seek, text: str) -> None:
    s.message = text
    s.message_tick = game.tick + round(MESSAGE_SECONDS / game.dt)


#: How each kind of entity reads in a seek message (the level's names are ids: "stack-1").
NOUNS = {"body": "4D body", "target": "switch", "crystal": "crystal", "enemy": "enemy", "object": "4D object"}


def _name(game, thing) -> str:
    """What the player reads for ``thing``: ``"the tumbler (4D body)"``, ``"the goal"``."""
    if thing == GOAL:
        return "the goal"
    e = game.entities.get(thing)
    if e is None:
        return "something"
    noun = NOUNS.get(e.kind, e.kind.replace("_", " "))
    words = (e.name or "").replace("-", " ").replace("_", " ").strip()
    return f"the {words} ({noun})" if words else f"a {noun}"


def _press(game, s: Seek, jump: bool) -> None:
    if not game.level.seek.enabled:
        _say(game, s, "Seek is off in this level")
        return
    cycling = s.order and (s.active or game.tick - s.last_tick <= round(CYCLE_SECONDS / game.dt))
    s.last_tick = game.tick
    w = float(game.player.position[3])
    if cycling:
        # Next thing in the same order, skipping what has gone or needs no move.
        for step in range(1, len(s.order) + 1):
            i = (s.index + step) % len(s.order)
            t = _target_w(game, s.order[i])
            if t is not None and abs(t - w) > SAME_W:
                s.index = i
                break
        else:
            cycling = False
    if not cycling:
        s.order = [c for c in candidates(game) if (t := _target_w(game, c)) is not None and abs(t - w) > SAME_W]
        s.index = 0 if s.order else -1
    if not s.order:
        s.active = False
        _say(game, s, "Nothing to seek along w nearby")
        return
    s.active, s.jump = True, jump
    target = _target_w(game, s.sought)
    game.emit(SeekStarted(-1 if s.sought == GOAL else s.sought, target))
    _say(game, s, f"Seeking {_name(game, s.sought)} at w = {target:+.2f}")


def step(game, actions) -> None:
    """Before the player moves: presses start, cycle or end a seek."""
    s = game.states.seek
    presses = actions.pressed("seek") + actions.pressed("seek_jump")
    if actions.w != 0.0 and s.active:
        s.active = False  # the player's own w key takes over
    for _ in range(presses):
        _press(game, s, jump=actions.pressed("seek_jump") > 0 or actions.reduced_motion)


def w_goal(game) -> tuple[float, bool] | None:
    """``(w, jump)`` for ``step_player`` while a seek is under way, else None."""
    s = game.states.seek
    if not s.active:
        return None
    target = _target_w(game, s.sought)
    if target is None:  # taken or removed on the way
        s.active = False
        _say(game, s, "Seek target is gone")
        return None
    return target, s.jump


def moved(game, cut: str | None) -> None:
    """After the player moved: arrival, or a stop short (``cut`` says why)."""
    s = game.states.seek
    if not s.active:
        return
    w = float(game.player.position[3])
    target = _target_w(game, s.sought)
    if cut is not None:
        if s.jump and cut in ("wall", "body"):
            s.jump = False  # refused as a jump: glide, and stop at the nearest reachable w
            return
        s.active = False
        game.emit(SeekBlocked(cut, w))
        _say(game, s, f"Seek stopped at w = {w:+.2f}: {_WHY.get(cut, cut)}")
    elif target is not None and w == target:
        s.active = False
        game.emit(SeekArrived(-1 if s.sought == GOAL else s.sought, w))


def sought_id(game):
    """The entity id (or :data:`GOAL`) the radar highlights: the one sought now or just now."""
    s = game.states.seek
    if s.sought is None:
        return None
    if s.active or game.tick - s.last_tick <= round(CYCLE_SECONDS / game.dt):
        return s.sought
    return None


def draw(game, frame, alpha) -> None:
    s = game.states.seek
    if s.message and game.tick < s.message_tick and not frame.hud.message:
        frame.hud.message = s.message


SYSTEM = System("seek", setup, step, draw, state_bytes)
