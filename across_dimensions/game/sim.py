"""The game simulation: one fixed tick at a time, no window, no clock.

``Game.step(actions)`` advances everything by ``1 / TICK_RATE`` seconds;
``Game.frame(alpha)`` describes what to draw, interpolated ``alpha`` of the way
from the previous tick to this one. The simulation never reads the wall clock
and draws randomness only from its own seeded generator, so the same level,
seed and actions always give the same states (replays rely on it).
"""

from __future__ import annotations

import hashlib

import numpy as np

from ..core.transform import scaling
from ..world.level import Level
from ..world.scene import Scene, SectionCache, build_physics, build_scene
from .actions import Actions
from .frame import Camera3, Drawable, Frame, Hud
from .player import HALF_WIDTH, HEIGHT, Player, move_axis, step_player
from .player_bodies import bodies_block, player_collide

TICK_RATE = 60
DT = 1.0 / TICK_RATE
FALL_LIMIT = -30.0  # below this y the player has fallen out of the level
PUSH = 0.5  # share of the player's velocity into a body given to it per tick of contact


class Game:
    """A level being played.

    Parameters
    ----------
    level : Level
    seed : int
        Seeds the world's random generator (``self.rng``).
    scene : Scene, optional
        Pre-built geometry (building lifts assets, which can take a while).
    """

    def __init__(self, level: Level, seed: int = 0, scene: Scene | None = None):
        self.level = level
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.scene = scene if scene is not None else build_scene(level)
        self.sections = SectionCache()
        self.physics, self.body_of = build_physics(self.scene, DT)
        self.events: list = []  # contact events of the last tick (physics.ContactEvent)
        self.tick = 0
        self.outcome: str | None = None  # "complete" once the goal is reached
        self.completed_tick: int | None = None
        self.player = self._spawned()
        self.respawns = 0
        self._prev_eye = self.player.eye()
        self._prev_view = (self.player.yaw, self.player.pitch)

    # ---------------------------------------------------------------- stepping
    @property
    def time(self) -> float:
        """Simulated seconds since the start."""
        return self.tick * DT

    def object_model(self, index: int, alpha: float | None = None) -> np.ndarray:
        """Object-to-world ``(5, 5)`` of object ``index``: its rigid body's pose,
        or its level pose turned by its spin; ``alpha`` of the way from the
        previous tick when given (for drawing)."""
        obj = self.scene.objects[index]
        body = self.body_of.get(index)
        if body is None:
            return obj.model_at(self.time if alpha is None else self.time - (1.0 - alpha) * DT)
        return self.physics.body_pose(body, alpha) @ scaling(obj.scale)

    def colliders_at(self, w: float) -> np.ndarray:
        """Boxes ``(k, 2, 3)`` solid in the slice at ``w``: the 3D world, the
        extended worlds and the bounds of solid 4D objects' sections. The rows
        are the same things at every w; a thing absent at ``w`` is NaN."""
        parts = [self.scene.static_boxes, self.scene.world_boxes_at(w)]
        for i, obj in enumerate(self.scene.objects):
            if not obj.solid or i in self.body_of:  # rigid bodies collide through physics
                continue
            key = f"object:{i}"
            self.sections.section(key, obj.mesh, self.object_model(i), w)
            parts.append(self.sections.bounds(key)[None])
        return np.concatenate(parts)

    def step(self, actions: Actions) -> None:
        """Advance one tick."""
        p = self.player
        self._prev_eye = p.eye()
        self._prev_view = (p.yaw, p.pitch)
        step_player(p, actions, DT, float(self.level.gravity[1]), self.level.w_range, self.colliders_at,
                    self._bodies_block if self.physics else None)
        if self.physics is not None:
            self._touch_bodies()
            self.physics.tick()
            self.events = self.physics.events
        if p.position[1] < FALL_LIMIT:
            self.respawn()
        self.tick += 1
        if self.outcome is None and self.in_goal():
            self.outcome = "complete"
            self.completed_tick = self.tick

    def _bodies_block(self, position, w: float) -> bool:
        """Would stepping to ``w`` put the player inside a rigid body?"""
        return bodies_block(self.physics, position, w, HALF_WIDTH, HEIGHT)

    def _touch_bodies(self) -> None:
        """Bodies in the player's slice block the player, and the player pushes them."""
        p = self.player
        corr, touched = player_collide(self.physics, p.position, HALF_WIDTH, HEIGHT)
        n = np.linalg.norm(corr)
        if n == 0.0:
            return
        # Apply the push-out as a move, so the static world still stops it: a
        # body never shoves the player through a floor or a wall.
        boxes = self.colliders_at(float(p.position[3]))
        for axis in (0, 2, 1):
            p.position, _ = move_axis(p.position, axis, float(corr[axis]), boxes)
        normal = corr / n
        into = float(p.velocity[:3] @ normal)
        if into < 0.0:  # stop moving into the body, pass the motion on to it
            p.velocity[:3] -= into * normal
            for b in touched:
                mass = self.physics.body_mass(b)
                self.physics.push(b, np.append(into * normal * mass * PUSH, 0.0))  # away from the player
        if normal[1] > 0.7:  # standing on a body
            p.on_ground = True
            p.velocity[1] = max(p.velocity[1], 0.0)

    def _spawned(self) -> Player:
        return Player(self.level.spawn.astype(np.float64).copy(), yaw=float(np.radians(self.level.spawn_yaw_deg)))

    def respawn(self) -> None:
        """Back to the spawn point (after falling out of the level)."""
        self.player = self._spawned()
        self.respawns += 1

    def in_goal(self) -> bool:
        g = self.level.goal
        c = self.player.center()
        if np.any(np.abs(c - g.center) > g.size / 2):
            return False
        return g.w_range is None or g.w_range[0] <= self.player.position[3] <= g.w_range[1]

    def state_array(self) -> np.ndarray:
        """Everything that evolves, as one ``float64`` array (for hashing)."""
        return np.concatenate([[self.tick], self.player.state_array(), [self.respawns]])

    def state_hash(self) -> str:
        """A short hash of the simulation state; equal states give equal hashes."""
        h = hashlib.sha256(self.state_array().astype(np.float64).tobytes())
        if self.physics is not None:
            h.update(self.physics.state_bytes())
        return h.hexdigest()[:16]

    # ------------------------------------------------------------------ frame
    def frame(self, alpha: float = 1.0, fov_y_deg: float = 75.0) -> Frame:
        """What to draw, the camera ``alpha`` of the way from the last tick."""
        p = self.player
        eye = self._prev_eye + alpha * (p.eye() - self._prev_eye)
        dyaw = (p.yaw - self._prev_view[0] + np.pi) % (2 * np.pi) - np.pi
        yaw = self._prev_view[0] + alpha * dyaw
        pitch = self._prev_view[1] + alpha * (p.pitch - self._prev_view[1])
        camera = Camera3(eye, yaw, pitch, fov_y_deg=fov_y_deg)
        w = float(p.position[3])
        drawables = [Drawable("static", 0, self.scene.static_mesh), Drawable("floor", 0, self.scene.floor_mesh, style="floor")]
        for i, world in enumerate(self.scene.worlds):
            tri, rev = self.sections.section(f"world:{i}", world.mesh, np.eye(5), w)
            drawables.append(Drawable(f"world:{i}", rev, tri))
        for i, obj in enumerate(self.scene.objects):
            tri, rev = self.sections.section(f"object:{i}", obj.mesh, self.object_model(i, alpha), w)
            drawables.append(Drawable(f"object:{i}", rev, tri))
        lo, hi = self.level.w_range
        message = "Level complete" if self.outcome == "complete" else ""
        return Frame(camera, drawables, Hud(w=w, w_min=lo, w_max=hi, message=message))


__all__ = ["Game", "TICK_RATE", "DT"]
