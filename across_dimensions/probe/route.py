"""The intended route: what the shipped replay of a level does, as a plan of steps.

The replay in ``levels/replays/`` is the designer's own play-through. Played headless once,
it says which switches were thrown and from where, which crystals were taken, which enemies
beaten, which objects turned to what angles, which bodies the player touched (and where each
was left), whether the slice was turned or the frustum camera used, and what each cost. The
probe's full bot follows these steps with its own hands (never the replay's inputs), and the
soft-lock proofs ask what the steps not yet done still need.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..game.replay import Replay, ReplayError
from ..game.replay_level import same_file
from ..game.sim import Game
from ..world.resources import levels_dir
from . import read


@dataclass
class Step:
    """One thing the route does.

    ``kind``: ``crystal``, ``pickup`` (its name is the weapon), ``target``, ``blast``,
    ``field``, ``manipulate``, ``body``, ``turn``, ``frustum``, ``enemy``, ``camera_loot`` (an
    enemy's crystal freed by the frustum switch: ``at``/``yaw`` are the switch's) or
    ``frustum_walk`` (the player stepped onto a ``walkable_in_frustum`` image: ``at``/``yaw`` the
    switch's, ``info["orbit"]`` the orbit then); ``name`` what it acts on; ``at`` the player's
    feet ``(4,)`` when it happened (None in a plan made from the level alone); ``yaw``/``pitch``
    the view then; ``info`` the rest (a target's door and how the shot got there, angles, a
    body's resting place, ...).
    """

    kind: str
    name: str
    tick: int
    at: np.ndarray | None
    yaw: float = 0.0
    pitch: float = 0.0
    info: dict = field(default_factory=dict)


@dataclass
class Route:
    """The shipped replay's plan: its steps in order, its length and the energy it spent."""

    steps: list
    ticks: int
    won: bool
    spent: dict  # energy paid per reason (w_move, gun, blast, field, manipulate, frustum)
    final_w: float

    def of_kind(self, kind: str) -> list:
        return [s for s in self.steps if s.kind == kind]

    def uses(self, kind: str) -> bool:
        return any(s.kind == kind for s in self.steps)


def replay_for(level_path: Path) -> Path | None:
    """The shipped replay beside a shipped level, if there is one."""
    p = Path(level_path)
    for folder in (p.parent / "replays", levels_dir() / "replays"):
        candidate = folder / f"{p.stem}.json"
        if candidate.is_file():
            return candidate
    return None


class _Recorder:
    """Turns a replay's ticks into :class:`Step` s (see :func:`load_route`)."""

    def __init__(self, game: Game):
        self.game = game
        self.steps: list[Step] = []
        self.shots: dict[int, tuple] = {}  # bullet id -> (feet, yaw, pitch, camera mode, orbit)
        self.names: dict[int, str] = {}
        self.touch: dict[int, np.ndarray] = {}  # body entity id -> where it was at the last touch
        self.first_touch: dict[int, int] = {}  # body entity id -> tick of the first touch
        self.spent: dict[str, float] = {}
        self.orbit = 0.0
        self.switch: tuple = (None, 0.0, 0.0)  # feet, yaw and pitch at the last frustum switch

    def before(self) -> None:
        self.names = read.names(self.game)

    def _step(self, kind, name, **info) -> None:
        g = self.game
        y, p = read.view(g)
        self.steps.append(Step(kind, name, g.tick, read.feet(g), y, p, info))

    def after(self, actions) -> None:
        g = self.game
        for ev in read.events(g):
            self._event(ev)
        for eid in read.touched_bodies(g):
            at = read.center_of(g, eid)
            if at is not None:
                self.touch[eid] = at
                self.first_touch.setdefault(eid, g.tick)
        for name, n in actions.presses:
            if name.startswith("step_") or name == "snap_slice":
                self._step("turn", name, presses=n)
        if read.camera_mode(g) == "frustum":
            self.orbit = read.orbit_deg(g)

    def _event(self, ev) -> None:
        g, k = self.game, ev.kind
        if k == "crystal_collected":
            self._step("crystal", self.names.get(ev.entity, ""))
        elif k == "shot_fired":
            y, p = read.view(g)
            self.shots[ev.entity] = (read.feet(g), y, p, read.camera_mode(g), self.orbit)
        elif k == "target_hit":
            feet, y, p, mode, orbit = self.shots.get(ev.bullet, (read.feet(g), 0.0, 0.0, "synced", 0.0))
            spec = next(t for t in g.level.targets if t.name == self.names.get(ev.entity))
            self.steps.append(
                Step("target", spec.name, g.tick, feet, y, p, {"opens": spec.opens, "mode": mode, "orbit": orbit})
            )
        elif k in ("blast", "field"):
            self._step(k, k)
        elif k == "weapon_acquired":
            self._step("pickup", ev.weapon)
        elif k == "camera_switched" and ev.mode == "frustum":
            self._step("frustum", "camera")
            self.switch = (read.feet(g), *read.view(g))
        elif k == "loot_released" and ev.reason == "camera":
            self.steps.append(Step("camera_loot", self.names.get(ev.entity, ""), g.tick, *self.switch))
        elif k == "entered_frustum_object":
            self.steps.append(Step("frustum_walk", ev.name, g.tick, *self.switch, {"orbit": self.orbit}))
        elif k == "enemy_defeated":
            self._step("enemy", ev.name, opens=ev.opened)
        elif k == "energy_spent":
            self.spent[ev.reason] = self.spent.get(ev.reason, 0.0) + ev.milli / 1000.0

    def finish(self) -> None:
        g = self.game
        for h in read.handles(g):
            turned = {p: a for p, a in h.angles.items() if a != 0.0}
            if turned:
                self._step("manipulate", h.name, angles=turned, center=h.center)
        for eid, where in self.touch.items():
            name = self.names.get(eid, "")
            start = next((o.position for o in g.level.objects if o.name == name), where)
            self._step("body", name, start=np.asarray(start, float), rest=where)
            self.steps[-1].tick = self.first_touch[eid]
        self.steps.sort(key=lambda s: s.tick)


def planned_route(level) -> Route:
    """A plan from the level alone, for a level without a replay: every switch that opens
    something, every enemy that does, each manipulable turned to the top of its first plane."""
    steps = [Step("pickup", p.weapon, 0, None) for p in level.pickups]
    steps += [Step("target", t.name, 0, None, info={"opens": t.opens}) for t in level.targets if t.opens]
    steps += [Step("enemy", e.name, 0, None, info={"opens": e.opens}) for e in level.enemies if e.opens]
    for m in level.manipulables:
        plane, (lo, hi) = next(iter(m.planes.items()))
        steps.append(Step("manipulate", m.object, 0, None, info={"angles": {plane: hi if hi else lo}}))
    return Route(steps, 0, False, {}, float(level.spawn[3]))


def load_route(level, replay_path: Path | None = None, scene=None) -> Route:
    """Play the level's shipped replay headless and return its plan; without a replay (or
    with one recorded on another version of the level), the plan of :func:`planned_route`."""
    path = replay_path if replay_path is not None else replay_for(level.path)
    if path is None:
        return planned_route(level)
    try:
        rep = Replay.load(path)
    except ReplayError:
        return planned_route(level)
    if not same_file(rep, level):  # the file and, for a level with assets, their bakes folded in
        return planned_route(level)
    if rep.arsenal is not None:  # the weapons the recording started with
        level = level.with_arsenal(rep.arsenal)
    game = Game(level, seed=rep.seed, scene=scene)
    rec = _Recorder(game)
    for a in rep.actions:
        rec.before()
        game.step(a)
        rec.after(a)
        if game.outcome == "complete":
            break
    rec.finish()
    return Route(rec.steps, game.tick, game.outcome == "complete", rec.spent, float(read.feet(game)[3]))
