"""A level turned into geometry: what exists at every w, the extended worlds,
the 4D objects, and the boxes that are solid in the slice at a given w.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core import lift, shapes
from ..core.mesh import TetMesh4, TriMesh3, concatenate
from ..core.section import cross_section
from ..core.transform import pose, translation
from .geometry import box_trimesh, face_runs, merge_trimeshes, placement_matrix, surface_trimesh
from .level import Level, MeshSpec

WORLD_LAYERS = 9  # w-layers of an extended world; more makes the shrinking smoother


@dataclass
class ExtendedWorld:
    """A 3D world extended along w.

    ``centers``/``halves`` ``(b, 3) float64`` are its solid parts' bounds at
    full size; at a w the parts are scaled about their centres by the profile,
    exactly as in its 4D mesh (both use the same layer table).
    """

    name: str
    mesh: TetMesh4
    centers: np.ndarray
    halves: np.ndarray
    layers_w: np.ndarray
    layer_scales: np.ndarray

    def scale_at(self, w: float) -> float:
        """Size of the world's parts in the slice at ``w`` (0 where absent)."""
        if w <= self.layers_w[0] or w >= self.layers_w[-1]:
            return 0.0
        return float(np.interp(w, self.layers_w, self.layer_scales))

    def boxes_at(self, w: float) -> np.ndarray:
        """Bounds ``(b, 2, 3)`` of each part at ``w``; NaN where absent, so every
        w gives the same rows and comparisons with an absent part are false."""
        s = self.scale_at(w)
        h = self.halves * (s if s > 0.0 else np.nan)
        return np.stack([self.centers - h, self.centers + h], axis=1)


@dataclass
class Object4:
    """A 4D object of the level: its mesh and the pose it starts in."""

    name: str
    mesh: TetMesh4
    position: np.ndarray
    rotation_deg: dict
    scale: np.ndarray
    spin_deg: dict
    solid: bool
    body: str
    mass: float
    velocity: np.ndarray
    walkable_in_frustum: bool = False  # while the frustum view holds, the walker meets its image

    @classmethod
    def prop(cls, name: str, mesh: TetMesh4, position, scale, rotation_deg=None, spin_deg=None) -> Object4:
        """A 4D thing the game places itself (a crystal, a target): posed and spinning like a
        level object, never solid and never a rigid body. ``scale`` is a number or ``(4,)``."""
        return cls(
            name,
            mesh,
            np.array(position, dtype=np.float64),
            dict(rotation_deg or {}),
            np.broadcast_to(np.asarray(scale, dtype=np.float64), (4,)).copy(),
            dict(spin_deg or {}),
            solid=False,
            body="none",
            mass=1.0,
            velocity=np.zeros(4),
        )

    def model_at(self, t: float, position=None, extra_rotation=None) -> np.ndarray:
        """Object-to-world ``(5, 5)`` at time ``t`` seconds (spin included)."""
        angles = {
            p: np.radians(self.rotation_deg.get(p, 0.0) + self.spin_deg.get(p, 0.0) * t)
            for p in set(self.rotation_deg) | set(self.spin_deg)
        }
        m = pose(self.position if position is None else position, angles, self.scale)
        if extra_rotation is not None:
            m[:4, :4] = extra_rotation @ m[:4, :4]
        return m

    @property
    def animated(self) -> bool:
        return any(v != 0.0 for v in self.spin_deg.values())


@dataclass
class Scene:
    """Geometry built from a :class:`Level`."""

    level: Level
    static_mesh: TriMesh3
    static_boxes: np.ndarray
    floor_mesh: TriMesh3 = field(default_factory=TriMesh3.empty)
    worlds: list[ExtendedWorld] = field(default_factory=list)
    objects: list[Object4] = field(default_factory=list)
    #: The ``[[mesh]]`` surfaces; ``static_mesh`` and ``floor_mesh`` hold only boxes. All three
    #: are closed, wound counter-clockwise seen from outside (an asset still open after repair
    #: is refused: ``bake.load_surface``; placements never mirror, their scales are positive).
    open_mesh: TriMesh3 = field(default_factory=TriMesh3.empty)
    #: Where each box of ``static_mesh`` and ``floor_mesh`` and each surface of ``open_mesh``
    #: starts among the mesh's faces, then their count (``Drawable.parts``): ``(k + 1,) int64``.
    static_parts: np.ndarray | None = None
    floor_parts: np.ndarray | None = None
    open_parts: np.ndarray | None = None

    def world_boxes_at(self, w: float) -> np.ndarray:
        """Boxes ``(k, 2, 3)`` of the extended worlds in the slice at ``w`` (NaN where absent)."""
        parts = [wd.boxes_at(w) for wd in self.worlds]
        return np.concatenate(parts) if parts else np.zeros((0, 2, 3))


def _mesh_surface(spec: MeshSpec):
    from .bake import load_surface  # trimesh is imported only when a level uses assets

    v, f = load_surface(spec.asset)
    return v, f, placement_matrix(spec.position, spec.scale, spec.yaw_deg)


def _aabb_of(v) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = v.min(axis=0), v.max(axis=0)
    return 0.5 * (lo + hi), 0.5 * (hi - lo)


def build_scene(level: Level) -> Scene:
    """Build all geometry of ``level`` (lifted assets come from the bake cache)."""
    tris: list[TriMesh3] = []
    floors: list[TriMesh3] = []
    surfaces: list[TriMesh3] = []
    boxes = []
    for b in level.boxes:
        # Wide, flat boxes are floors: drawn with a metre grid, which tells the
        # player how fast they move and how far things are.
        is_floor = b.size[1] <= 1.0 and b.size[0] * b.size[2] >= 16.0
        (floors if is_floor else tris).append(box_trimesh(b.center, b.size, b.color))
        boxes.append([b.center - b.size / 2, b.center + b.size / 2])
    for m in level.meshes:
        v, f, model = _mesh_surface(m)
        t = surface_trimesh(v, f, m.color, model)
        surfaces.append(t)
        boxes.append([t.vertices.min(axis=0), t.vertices.max(axis=0)])
    static_boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 2, 3)

    worlds = [_build_world(w) for w in level.worlds]
    meshes: dict = {}  # objects of the same shape and colour share one mesh (drawn as instances of it)
    objects = [_build_object(o, meshes) for o in level.objects]
    return Scene(
        level,
        merge_trimeshes(tris),
        static_boxes,
        merge_trimeshes(floors),
        worlds,
        objects,
        merge_trimeshes(surfaces),
        face_runs(tris),
        face_runs(floors),
        face_runs(surfaces),
    )


def _build_world(spec) -> ExtendedWorld:
    layers_w = lift.profile_layers(spec.w, spec.depth, spec.profile, WORLD_LAYERS)
    scales = lift.profile_scales(layers_w, spec.w, spec.depth / 2, spec.profile)
    parts, centers, halves = [], [], []
    for b in spec.boxes:
        v3, t3 = lift.box_solid(b.center, b.size)
        parts.append(lift.extrude(v3, t3, layers_w, scales, center=b.center, colors=b.color))
        centers.append(b.center)
        halves.append(b.size / 2)
    for m in spec.meshes:
        from .bake import bake_solid  # pytetwild runs only on a cache miss

        v3, t3 = bake_solid(m.asset)
        model = placement_matrix(m.position, m.scale, m.yaw_deg)
        v3 = v3 @ model[:3, :3].T + model[:3, 3]
        c, h = _aabb_of(v3)
        parts.append(lift.extrude(v3, t3, layers_w, scales, center=c, colors=m.color))
        centers.append(c)
        halves.append(h)
    return ExtendedWorld(
        spec.name,
        concatenate(parts, name=spec.name),
        np.asarray(centers),
        np.asarray(halves),
        layers_w,
        np.asarray(scales, dtype=np.float64),
    )


def _build_object(spec, meshes: dict) -> Object4:
    key = (spec.shape, repr(sorted(spec.params.items())), str(spec.asset), spec.depth, repr(spec.color))
    mesh = meshes.get(key)
    if mesh is None:
        if spec.shape is not None:
            mesh = shapes.make_shape(spec.shape, **spec.params)
        else:
            from .bake import lift_asset

            mesh = lift_asset(spec.asset, spec.depth)
        mesh = meshes[key] = mesh.with_color(spec.color)
    return Object4(
        spec.name,
        mesh,
        spec.position.copy(),
        dict(spec.rotation_deg),
        spec.scale.copy(),
        dict(spec.spin_deg),
        spec.solid,
        spec.body,
        spec.mass,
        spec.velocity.copy(),
        spec.walkable_in_frustum,
    )


BOUNDS_MARGIN = 20.0  # metres between everything in a level and the walls that keep bodies in


def level_bounds(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """Bounds ``(lo (3,), hi (3,)) float64`` of everything in the level: boxes,
    meshes, worlds' parts, 4D objects (a ball through their farthest point),
    the spawn point and the goal."""
    level = scene.level
    los = [level.spawn[:3], level.goal.center - level.goal.size / 2]
    his = [level.spawn[:3] + [0.0, 2.0, 0.0], level.goal.center + level.goal.size / 2]
    if len(scene.static_boxes):
        los.append(scene.static_boxes[:, 0].min(axis=0))
        his.append(scene.static_boxes[:, 1].max(axis=0))
    for wd in scene.worlds:
        if len(wd.centers):
            los.append((wd.centers - wd.halves).min(axis=0))
            his.append((wd.centers + wd.halves).max(axis=0))
    for o in scene.objects:
        r = float(np.linalg.norm(o.mesh.vertices, axis=1).max() * o.scale.max()) if len(o.mesh.vertices) else 0.0
        los.append(o.position[:3] - r)
        his.append(o.position[:3] + r)
    return np.min(los, axis=0).astype(np.float64), np.max(his, axis=0).astype(np.float64)


#: Metres past the physics' walls in w (the level's w range, widened for a gun's bullets)
#: that the prisms of ``[[mesh]]`` parts reach: their caps are never met.
PRISM_SLACK = 1.0


def physics_w_walls(level: Level) -> tuple[float, float]:
    """Where the physics' walls in w stand: the level's ``w_range``, widened by how far a
    gun's bullets swing along w (that is how they hit targets out of the player's reach)."""
    guns = [wp for wp in getattr(level, "weapons", ()) if wp.kind == "gun"]
    beyond = max((wp.amplitude + 2.0 * wp.size for wp in guns), default=0.0)
    lo, hi = level.w_range
    return lo - beyond, hi + beyond


def prism_tets(triangles: np.ndarray, w0: float, w1: float) -> np.ndarray:
    """The side of a 3D solid extruded along w: three tets per surface triangle.

    Parameters
    ----------
    triangles : (t, 3, 3) float64
        The solid's closed surface (either winding: it is made outward here, by the sign
        of the enclosed volume).
    w0, w1 : float
        The prism's extent in w (its caps are left out: nothing reaches them).

    Returns
    -------
    (3 t', 4, 4) float64
        Tets ordered so that ``core.mesh.cross4`` of their edges from corner 0 points out
        of the solid (``(n, 0)`` for the outward normal ``n`` of their triangle), as
        :meth:`..physics.PhysicsWorld.set_static_tets` takes them; degenerate triangles
        are dropped.
    """
    from ..core.mesh import cross4

    tri = np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    if np.einsum("ij,ij->", tri[:, 0], n) < 0.0:  # 6x the enclosed volume: negative when wound inward
        n = -n
    area = np.linalg.norm(n, axis=1)
    keep = area > 1e-12 * max(float(area.max(initial=0.0)), 1e-300)
    tri, n = tri[keep], n[keep]
    low = np.concatenate([tri, np.full((len(tri), 3, 1), float(w0))], axis=2)
    high = np.concatenate([tri, np.full((len(tri), 3, 1), float(w1))], axis=2)
    corners = np.concatenate([low, high], axis=1)  # a0 b0 c0 a1 b1 c1
    tets = corners[:, [[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]]]  # (t, 3, 4, 4)
    normal = np.concatenate([n, np.zeros((len(n), 1))], axis=1)[:, None, :]
    edges = tets[..., 1:, :] - tets[..., :1, :]
    out = cross4(edges[..., 0, :], edges[..., 1, :], edges[..., 2, :])
    flip = np.einsum("ijk,ijk->ij", out, np.broadcast_to(normal, out.shape)) < 0.0
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    return np.ascontiguousarray(tets.reshape(-1, 4, 4))


def static_tet_meshes(scene: Scene) -> list[np.ndarray]:
    """The 3D meshes and the extended worlds as the rigid bodies meet them: by their true
    shapes, as boundary tets (cached on the scene, so the same arrays are handed over each tick).

    A ``[[mesh]]`` part is the same at every w: the side of its solid extruded over the
    physics' w span (:func:`prism_tets`). An extended world is its own 4D mesh, whose
    sections are what the player sees and walks on.

    Returns
    -------
    list of (T, 4, 4) float64
    """
    cached = scene.__dict__.get("_static_tets")
    if cached is None:
        lo, hi = physics_w_walls(scene.level)
        cached = []
        for m in scene.level.meshes:
            v, f, model = _mesh_surface(m)
            v = np.asarray(v, dtype=np.float64) @ model[:3, :3].T + model[:3, 3]
            cached.append(prism_tets(v[np.asarray(f, dtype=np.int64)], lo - PRISM_SLACK, hi + PRISM_SLACK))
        for wd in scene.worlds:
            cached.append(np.ascontiguousarray(wd.mesh.vertices.astype(np.float64)[wd.mesh.tets.astype(np.int64)]))
        scene.__dict__["_static_tets"] = cached
    return cached


def build_physics(scene: Scene, tick_dt: float):
    """The rigid-body world of a scene, or ``(None, {})`` when nothing in it moves
    (a level with a gun always has one: bullets are bodies).

    Bodies collide with the level's boxes (present at every w, as boxes
    extending over all w), with its ``[[mesh]]`` parts and extended worlds by
    their true shapes (:func:`static_tet_meshes`), with walls in w at both ends of the level's
    ``w_range`` and walls in x, y and z ``BOUNDS_MARGIN`` beyond everything
    in the level (:func:`level_bounds`), and with each other. A body
    object's collider is its mesh's bounding box (``hypercube``) or bounding
    hypersphere, scaled; its ``spin`` becomes its initial angular velocity.

    Returns
    -------
    physics : PhysicsWorld or None
    body_of : dict of int to int
        Object index to body id.
    """
    movers = [i for i, o in enumerate(scene.objects) if o.body != "none"]
    guns = [wp for wp in getattr(scene.level, "weapons", ()) if wp.kind == "gun"]
    if not movers and not guns:
        return None, {}
    from ..core.transform import PLANES
    from ..physics import BodyDef, PhysicsWorld, WorldDef

    level = scene.level
    world = PhysicsWorld(
        WorldDef(
            gravity=level.gravity,
            inverse_cube_G=level.inverse_cube_g,
            ground=False,
            tick_dt=tick_dt,
            rolling_resistance=level.rolling_resistance,
        )
    )
    # Walls at both ends of the level's w range: the player cannot leave it, so
    # a body that rolled out along w would never be seen again (and, rolling
    # on forever, never sleep). A body's whole extent stays inside.
    # A gun's bullets swing along w beyond where the player can go (that is how
    # they hit targets out of reach), so with a gun the walls stand that much further out.
    lo, hi = physics_w_walls(level)
    world.add_half_space((0.0, 0.0, 0.0, -1.0), -hi)  # solid where w >= hi
    world.add_half_space((0.0, 0.0, 0.0, 1.0), lo)  # solid where w <= lo
    # And an invisible box BOUNDS_MARGIN beyond everything in the level: a body
    # that falls off an edge, or through a thin floor at speed, lands on its
    # floor (a half-space: solid all the way down, so nothing tunnels through
    # it) instead of falling and speeding up for ever. Random stress scenes at
    # the level format's limits blew up (NaN) without it, none with it.
    lo3, hi3 = level_bounds(scene)
    for axis in range(3):
        n = np.zeros(4)
        n[axis] = 1.0
        world.add_half_space(n, lo3[axis] - BOUNDS_MARGIN)  # solid below the lowest point
        world.add_half_space(-n, -(hi3[axis] + BOUNDS_MARGIN))  # solid above the highest
    # The level's boxes are exact as boxes; its [[mesh]] parts (the rows after them) and its
    # extended worlds are met by their true shapes, as tets.
    boxes = scene.static_boxes[: len(level.boxes)]
    world.set_static_boxes([(0.5 * (lo + hi), 0.5 * (hi - lo)) for lo, hi in boxes])
    world.set_static_tets(static_tet_meshes(scene))
    body_of = {}
    for i in movers:
        o = scene.objects[i]
        v = o.mesh.vertices.astype(np.float64)
        common = dict(
            position=o.position,
            angles={p: np.radians(a) for p, a in o.rotation_deg.items()},
            velocity=o.velocity,
            mass=o.mass,
            angular_velocity=[np.radians(o.spin_deg.get(p, 0.0)) for p in PLANES],
        )
        if o.body == "hypersphere":
            radius = float(np.linalg.norm(v, axis=1).max() * o.scale.max())
            body_of[i] = world.add_body(BodyDef("hypersphere", radius=radius, **common))
        else:
            body_of[i] = world.add_body(BodyDef("hypercube", size=np.ptp(v, axis=0) * o.scale, **common))
    return world, body_of


def _same_slice(a, b) -> bool:
    """Are two slices (each a w or a (5, 5) pose) the same?"""
    if np.ndim(a) == 0 and np.ndim(b) == 0:
        return a == b
    return np.ndim(a) == np.ndim(b) and np.array_equal(a, b)


class SectionCache:
    """Cross-sections recomputed only when the object or the hyperplane moved.

    Each key keeps its last inputs, result, bounds and a revision that bumps
    whenever the result is recomputed, which is what the renderer uploads by.
    """

    def __init__(self):
        self._entries: dict[str, tuple] = {}
        self.computed = 0

    def section(self, key: str, mesh: TetMesh4, model: np.ndarray, w) -> tuple[TriMesh3, int]:
        """Section of ``mesh`` placed by ``model`` at the slice ``w``; world xyz frame.

        ``w`` is the slice's w (a number), or the ``(5, 5)`` pose of a turned slice
        (``game.camera.slice_of``); the section is then in the slice's own xyz frame.
        """
        entry = self._entries.get(key)
        if entry is not None and _same_slice(entry[0], w) and np.array_equal(entry[1], model):
            return entry[2], entry[3]
        turned = np.ndim(w) != 0
        tri = cross_section(mesh, np.asarray(w, dtype=np.float64) if turned else translation((0.0, 0.0, 0.0, w)), model)
        rev = 0 if entry is None else entry[3] + 1
        self._entries[key] = (np.array(w, copy=True) if turned else w, np.array(model, copy=True), tri, rev, None)
        self.computed += 1
        return tri, rev

    def forget(self, key: str) -> None:
        """Drop a key's entry (its entity is gone)."""
        self._entries.pop(key, None)

    def keep(self, prefix: str, keys: set) -> None:
        """Drop every entry whose key starts with ``prefix`` and is not in ``keys``."""
        for k in [k for k in self._entries if k.startswith(prefix) and k not in keys]:
            del self._entries[k]

    def has_section(self, key: str) -> bool:
        """Is there a non-empty section cached for ``key``?"""
        entry = self._entries.get(key)
        return entry is not None and not entry[2].is_empty

    def bounds(self, key: str) -> np.ndarray:
        """Bounds ``(2, 3) float64`` of the last section for ``key``; NaN if it is empty.

        Computed once per section (the walker asks for them several times a tick).
        """
        entry = self._entries.get(key)
        if entry is None or entry[2].is_empty:
            return np.full((2, 3), np.nan)
        if entry[4] is None:
            v = entry[2].vertices
            entry = entry[:4] + (np.stack([v.min(axis=0), v.max(axis=0)]).astype(np.float64),)
            self._entries[key] = entry
        return entry[4]
