"""The game simulation: one fixed tick at a time, no window, no clock.

``Game.step(actions)`` advances everything by ``1 / TICK_RATE`` seconds by
running the systems of :mod:`across_dimensions.game.systems` in order;
``Game.frame(alpha)`` asks the same systems what to draw, interpolated
``alpha`` of the way from the previous tick to this one. The simulation never
reads the wall clock and draws randomness only from its own seeded generator,
so the same level, seed and actions always give the same states (replays rely
on it).

What lives in the level (4D objects, rigid bodies, crystals, ...) is an entity
in ``game.entities`` (:mod:`.entities`); what happened in the last tick is in
``game.events`` (:mod:`.events`); each system's own state is in ``game.states``
(:mod:`.system`).
"""

from __future__ import annotations

import hashlib
from collections import Counter
from dataclasses import dataclass

import numpy as np

from ..world.level import Level
from ..world.scene import Scene, SectionCache, build_physics, build_scene
from . import health
from .actions import Actions
from .camera import CameraRig
from .energy import EnergyBar
from .entities import EntityStore, EntityTable, Rigid, Scripted, reach
from .entity_models import EntityModels
from .entity_sections import EntitySections
from .events import Event
from .frame import Camera3, Frame, Hud
from .frustum_walk import image_triangles, images_hold, walkable
from .player import HALF_WIDTH, HEIGHT, Player
from .player_bodies import bodies_block
from .projection import items, project
from .section_collision import MeshParts, triangles_of
from .system import States, encode
from .systems import SYSTEMS
from .systems.ghosts import GhostView

TICK_RATE = 60
DT = 1.0 / TICK_RATE
#: Metres around the player's feet within which solid 4D objects are sliced for
#: collision: the player's height plus more than a tick's travel at any speed the
#: walker reaches (a fall at 30 m/s moves 0.5 m a tick).
COLLIDE_MARGIN = 3.0


@dataclass(frozen=True)
class RadarView:
    """How the player likes the radar (their settings): shown or not, and factors on the
    level's range and pin heights. A view choice: it changes no simulation state."""

    shown: bool = True
    range_scale: float = 1.0
    height_scale: float = 1.0


class Game:
    """A level being played.

    Parameters
    ----------
    level : Level
    seed : int
        Seeds the world's random generator (``self.rng``).
    scene : Scene, optional
        Pre-built geometry (building lifts assets, which can take a while).

    Attributes
    ----------
    entities : EntityStore
    events : list of Event
        What happened in the last tick, in order.
    event_counts : collections.Counter
        Events of each kind since the start.
    states : States
        Each system's state under its name (``states.weapons``, ``states.seek``, ...; see
        :mod:`.system`), set up once when the game is made.
    radar_view, ghost_view, show_ghosts
        The player's view options (radar, ghosts along w, manipulation's previews): drawing
        only, never part of the simulation's state; the window sets them from the settings.
    """

    dt = DT

    def __init__(self, level: Level, seed: int = 0, scene: Scene | None = None):
        self.level = level
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.scene = scene if scene is not None else build_scene(level)
        self.sections = SectionCache()
        self.meshes = MeshParts(self.scene)  # [[mesh]] and [[world.mesh]] collide by their surfaces
        self.entity_sections = EntitySections()  # what the frame draws of the entities, batched
        self.entity_models = EntityModels()  # the drawn entities' models, made in one pass
        self.physics, body_of = build_physics(self.scene, DT)
        self.entities = EntityStore()
        self._table_key: tuple | None = None
        self._table: EntityTable | None = None
        self._moving: list[int] = []  # rows of the table whose centre can change from tick to tick
        self._colliders_key: tuple | None = None
        self._colliders: dict[float, np.ndarray] = {}
        self._sections: dict[float, list] = {}
        self._triangles: dict[str, tuple] = {}  # section key -> (TriMesh3, its (t, 3, 3) triangles)
        self._images: dict[int, tuple] = {}  # walkable entity -> (camera pose, model, image triangles)
        self.pose_version = 0  # bumped by systems that move solid objects within a tick (manipulation)
        self.entity_of_body: dict[int, int] = {}
        for i, obj in enumerate(self.scene.objects):
            if i in body_of:
                e = self.entities.spawn(
                    "body",
                    obj.name,
                    obj.mesh,
                    Rigid(body_of[i], obj.scale),
                    radar="body",
                    radius=reach(obj.mesh, obj.scale),
                )
                self.entity_of_body[body_of[i]] = e.id
            else:
                self.entities.spawn(
                    "object",
                    obj.name,
                    obj.mesh,
                    Scripted(obj),
                    solid=obj.solid,
                    radar="object",
                    radius=reach(obj.mesh, obj.scale),
                )
        self.radar_settings = level.radar
        self.radar_view = RadarView()
        self.ghost_view = GhostView()
        self.show_ghosts = True
        self.events: list[Event] = []
        self.event_counts: Counter = Counter()
        self.cause_counts: Counter = Counter()  # "kind:cause" -> count (Event.causes)
        self.tick = 0
        self.outcome: str | None = None  # "complete" once the goal is reached
        self.completed_tick: int | None = None
        self.player = self._spawned()
        self.respawns = 0
        self.states = States(s.name for s in SYSTEMS)
        for system in SYSTEMS:  # in order: entities the systems spawn get their ids in this order
            if system.setup is not None:
                setattr(self.states, system.name, system.setup(self))
        self.reset_interpolation()

    @property
    def energy(self) -> EnergyBar | None:
        """The energy bar (the energy system's state); None when the level has no energy rules
        (moving along w is free)."""
        return self.states.energy

    @energy.setter
    def energy(self, bar: EnergyBar | None) -> None:
        self.states.energy = bar

    @property
    def camera(self) -> CameraRig:
        """The 4D camera (the camera system's state): the plain axis-aligned slice until a level
        lets the player turn it."""
        return self.states.camera

    def reset_interpolation(self) -> None:
        """Draw the next frames from where the player stands now, without blending from the
        last tick (after the player was placed rather than moved: a respawn, the editor's
        camera, a benchmark's viewpoint)."""
        p = self.player
        self._prev_eye = self._eye4()
        self._prev_view = (p.yaw, p.pitch)

    def place_player(self, position, yaw: float | None = None, pitch: float | None = None) -> None:
        """Stand the player at ``position (4,)`` (feet), at rest, turned to ``yaw`` and ``pitch``
        (radians) when given, and draw from there without blending from where it was (a
        benchmark's viewpoint, a test's setup)."""
        p = self.player
        p.position = np.array(position, dtype=np.float64).reshape(4)
        p.velocity = np.zeros(4)
        if yaw is not None:
            p.yaw = float(yaw)
        if pitch is not None:
            p.pitch = float(pitch)
        self.reset_interpolation()

    def solids_moved(self) -> None:
        """Solid objects moved within this tick (an object turned by the player, a tool): the
        walker's colliders and sections of the tick are worked out again."""
        self.pose_version += 1

    def _eye4(self) -> np.ndarray:
        return np.append(self.player.eye(), float(self.player.position[3]))

    # ---------------------------------------------------------------- stepping
    @property
    def time(self) -> float:
        """Simulated seconds since the start."""
        return self.tick * DT

    def emit(self, event: Event) -> None:
        """Record an event of this tick (systems call this)."""
        self.events.append(event)
        self.event_counts[event.kind] += 1
        if event.causes is not None:  # for the replay summary only: nothing in play reads it
            self.cause_counts[f"{event.kind}:{getattr(event, event.causes)}"] += 1

    def remove(self, entity_id: int) -> None:
        """Remove an entity and free what it holds (its rigid body, its cached sections)."""
        e = self.entities.remove(entity_id)
        if e is None:
            return
        if isinstance(e.motion, Rigid):
            self.physics.remove_body(e.motion.body)
            del self.entity_of_body[e.motion.body]
        self.sections.forget(f"tick:{e.id}")
        self.sections.forget(f"draw:{e.id}")

    def entity_table(self) -> EntityTable:
        """The live entities with their centres and reaches as arrays; built once per tick."""
        key = (self.tick, self.entities.version)
        if self._table_key != key:
            if self._table is None or self._table_key[1] != key[1]:  # entities came or went
                ents = list(self.entities)
                centers = np.array([e.center(self) for e in ents], dtype=np.float64).reshape(-1, 4)
                self._table = EntityTable(ents, centers, np.array([e.radius for e in ents], dtype=np.float64))
                self._moving = [i for i, e in enumerate(ents) if not isinstance(e.motion, Scripted)]
            else:  # a scripted entity turns about its origin: only the others' centres move
                for i in self._moving:
                    self._table.centers[i] = self._table.entities[i].center(self)
            self._table_key = key
        return self._table

    def colliders_at(self, w: float) -> np.ndarray:
        """Boxes ``(k, 2, 3)`` solid in the slice at ``w``: the 3D world and the
        extended worlds' parts. The rows are the same things at every w; a thing
        absent at ``w`` is NaN, and so are the meshes' rows: meshes and solid 4D
        objects collide by their true surfaces and sections instead
        (:meth:`sections_at`).

        Nothing moves within a tick, so the answer for a w is kept until the
        tick (or the set of entities) changes: the walker asks for the slice it
        is in and the one it steps to several times a tick.
        """
        self._fresh_colliders()
        boxes = self._colliders.get(w)
        if boxes is None:
            worlds = self.scene.world_boxes_at(w)
            if not self.camera.aligned:  # a turned slice cuts the worlds slantwise: by their sections
                worlds = np.full_like(worlds, np.nan)
            boxes = np.concatenate([self.scene.static_boxes, worlds])
            if len(self.meshes):
                boxes[self.meshes.rows] = np.nan  # meshes collide by their surfaces (sections_at)
            self._colliders[w] = boxes
        return boxes

    def slice_of(self, w: float):
        """The slice at offset ``w`` as the section cache takes it: ``w`` itself on the plain
        axis-aligned slice, the turned slice's pose otherwise (see :mod:`.camera`)."""
        return self.camera.slice_of(w)

    def sections_at(self, w: float) -> list:
        """The triangles of each solid 4D object's section at ``w``: one
        ``(t, 3, 3) float64`` array per solid entity, in spawn order, empty where
        the object is absent from the slice or beyond the player's reach; then
        the surfaces of the ``[[mesh]]`` and ``[[world.mesh]]`` parts near the
        player (:class:`.section_collision.MeshParts`).

        Sections are recomputed only when an object's pose or the slice changed
        (``game.sections`` compares both), and the list for a w is kept for the
        tick.
        """
        self._fresh_colliders()
        found = self._sections.get(w)
        if found is None:
            found = self._sections[w] = self._sections_now(w)
        return found

    def _fresh_colliders(self) -> None:
        key = (self.tick, self.entities.version, self.pose_version, self.camera.version)
        if self._colliders_key != key:
            self._colliders_key, self._colliders, self._sections = key, {}, {}

    def _sections_now(self, w: float) -> list:
        out = []
        feet = self.player.position
        cam = self.camera
        images = images_hold(self)
        for e in self.entities:
            if walkable(e):  # a slot always, so lists for two w's line up
                if images:  # the frustum view holds: its image, wherever it lies
                    out.append(self.image_triangles(e))
                    continue
                if not e.solid:
                    out.append(np.zeros((0, 3, 3)))
                    continue
            elif not e.solid:
                continue
            key = f"tick:{e.id}"
            # Only what the player can touch this tick needs its section: within its
            # reach of the player's box in space, and of the slice in w.
            c = cam.to_slice(e.center(self))  # slice space (the entity's own centre while aligned)
            near = np.all(np.abs(c[:3] - feet[:3]) <= e.radius + COLLIDE_MARGIN)
            if near and abs(float(c[3]) - w) <= e.radius:
                tri, _ = self.sections.section(key, e.mesh, e.model(self), cam.slice_of(w))
                cached = self._triangles.get(key)
                if cached is None or cached[0] is not tri:  # a new section: its triangles once
                    cached = self._triangles[key] = (tri, triangles_of(tri))
                out.append(cached[1])
            else:
                self.sections.forget(key)
                self._triangles.pop(key, None)
                out.append(np.zeros((0, 3, 3)))
        if not cam.aligned:
            # The extended worlds' boxes stand for their sections only on the plain slice;
            # a turned slice collides with their true sections instead.
            for i, world in enumerate(self.scene.worlds):
                key = f"tick:world:{i}"
                tri, _ = self.sections.section(key, world.mesh, np.eye(5), cam.slice_of(w))
                cached = self._triangles.get(key)
                if cached is None or cached[0] is not tri:
                    cached = self._triangles[key] = (tri, triangles_of(tri))
                out.append(cached[1])
        out += self.meshes.triangles_at(w, feet, COLLIDE_MARGIN)  # after the entities
        return out

    def image_triangles(self, e) -> np.ndarray:
        """The frustum image ``(t, 3, 3) float64`` of a ``walkable_in_frustum`` entity ``e``, in
        slice space (cached on the camera's pose and the object's model)."""
        return image_triangles(self, e, self._images)

    def bodies_block_w(self, position, w: float) -> bool:
        """Would stepping to ``w`` put the player inside a rigid body?"""
        return bodies_block(self.physics, position, w, HALF_WIDTH, HEIGHT)

    def step(self, actions: Actions) -> None:
        """Advance one tick: every system's ``step``, in order."""
        self.reset_interpolation()
        self.events = []
        for system in SYSTEMS:
            if system.step is not None:
                changed = system.step(self, actions)
                if changed is not None:  # a system took some of the input (see systems/__init__.py)
                    actions = changed
        self.tick += 1

    def _spawned(self) -> Player:
        return Player(self.level.spawn.astype(np.float64).copy(), yaw=float(np.radians(self.level.spawn_yaw_deg)))

    def respawn(self) -> None:
        """Back to the last checkpoint reached, or the spawn point (after falling out of the level)."""
        if self.checkpoint is not None:
            health.restart_at(self, self.checkpoint)
        else:
            self.player = self._spawned()
            self.reset_interpolation()
        self.respawns += 1

    def state_array(self) -> np.ndarray:
        """The player and the counters that evolve, as one ``float64`` array."""
        energy = [self.energy.milli] if self.energy is not None else []
        return np.concatenate([[self.tick], self.player.state_array(), [self.respawns], energy])

    @property
    def checkpoint(self) -> int | None:
        """Index of the last checkpoint the player reached, or None (the level's start)."""
        h = self.states.health
        return h.checkpoint if h is not None and h.checkpoint >= 0 else None

    def restart_at_checkpoint(self, index: int) -> None:
        """Continue a saved game: the player starts at checkpoint ``index`` (see :func:`.health.restart_at`)."""
        health.restart_at(self, index)

    def state_hash(self) -> str:
        """A short hash of the whole simulation state; equal states give equal hashes.

        Covers the tick, the player, the counters, every entity (id, kind, look, motion and
        data), the random generator's state, and every system's state through its
        ``state_bytes`` (the physics world's among them), so a replay that drifts is caught
        at the tick it drifts.
        """
        counts = sorted(self.event_counts.items())
        core = (self.tick, self.player, self.respawns, self.outcome, self.completed_tick, counts)
        h = hashlib.sha256(encode(core + (self.entities.next_id,)))
        for e in self.entities:
            h.update(encode(e))
        h.update(repr(self.rng.bit_generator.state).encode())
        for system in SYSTEMS:
            absent = not system.hashed_when_absent and getattr(self.states, system.name) is None
            if system.state_bytes is not None and not absent:
                h.update(encode(system.name) + system.state_bytes(self))
        return h.hexdigest()[:16]

    # ------------------------------------------------------------------ frame
    def frame(self, alpha: float = 1.0, fov_y_deg: float = 75.0, pip: bool = False) -> Frame:
        """What to draw, the camera ``alpha`` of the way from the last tick: every system's ``draw``.

        With ``pip``, ``frame.pip`` also holds the 4D content in the projection the camera is
        not in (the picture-in-picture); without it nothing of that is computed."""
        p = self.player
        now = self._eye4()
        eye = now - (1.0 - alpha) * (now - self._prev_eye)  # exactly the eye now at alpha 1
        dyaw = (p.yaw - self._prev_view[0] + np.pi) % (2 * np.pi) - np.pi
        yaw = self._prev_view[0] + alpha * dyaw
        pitch = self._prev_view[1] + alpha * (p.pitch - self._prev_view[1])
        lo, hi = self.level.w_range
        w = float(eye[3])
        frame = Frame(Camera3(eye[:3], yaw, pitch, fov_y_deg=fov_y_deg, w=w), hud=Hud(w=w, w_min=lo, w_max=hi))
        for system in SYSTEMS:
            if system.draw is not None:
                system.draw(self, frame, alpha)
        self.entity_sections.flush()  # the entity batches' kernels, left for last
        if pip:
            frame.pip = project(self, self.camera, items(self, alpha), eye, other=True)
        return frame


__all__ = ["Game", "RadarView", "TICK_RATE", "DT"]
