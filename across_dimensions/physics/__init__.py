"""4D rigid-body physics: hyperspheres and 4D boxes, the 3D world, player queries.

Depends on numpy, numba and :mod:`across_dimensions.core` only; no wall clock
and no global random state, so a replay of the same calls is bit-identical.

>>> from across_dimensions.physics import BodyDef, PhysicsWorld, WorldDef
>>> world = PhysicsWorld(WorldDef(gravity=(0, -9.81, 0, 0), inverse_cube_G=0.0))
>>> world.set_static_boxes([((0, 0.5, 3), (1, 0.5, 1))])   # 3D boxes, all of w
>>> ball = world.add_body(BodyDef("hypersphere", radius=0.3, position=(0, 2, 0, 0.2)))
>>> cube = world.add_body(BodyDef("hypercube", size=0.8, position=(1, 1, 0, 0),
...                               angles={"xw": 0.4}, restitution=0.2, friction=0.6))
>>> world.step(1 / 60)                                    # fixed ticks inside
1
>>> model = world.body_pose(cube)                         # (5, 5) model matrix

Game-facing API of :class:`PhysicsWorld`:

* bodies: ``add_body``, ``remove_body``, ``body_pose``, ``body_position``,
  ``body_rotation``, ``body_velocity``, ``body_mass``, ``body_inertia``, ``body_kind``,
  ``set_velocity``, ``set_pose``, ``push``, ``wake``, ``is_sleeping``,
  ``body_ids``;
* static world: ground ``y <= 0`` (``ground=True``), ``set_static_boxes``,
  ``add_half_space`` (slopes, walls in w), ``set_static_solids`` (4D boxes),
  ``set_static_convex`` (convex polytopes) and ``set_static_tets`` (the
  boundary tets of any other solid, see :mod:`.tet_mesh`): the level's solid objects;
* time: ``step(dt)`` runs whole ticks of ``tick_dt`` (default 1/60 s, four
  substeps each); ``tick()`` runs exactly one;
* queries: ``push_box_out`` (the player's collider), ``raycast``, ``events``
  (:class:`ContactEvent`), ``debug_draw`` (see :mod:`.debug_draw`);
* determinism: ``state_bytes``, ``state_hash``;
* settings: a :class:`WorldDef` when the world is made (every tuning value,
  with Box2D-like defaults); ``gravity``, ``inverse_cube_G`` and ``allow_sleep``
  may change per level afterwards.

Modules: :mod:`.bivector` (rotation maths on bivectors), :mod:`.mass`
(hypervolumes and inertia), :mod:`.state` (the named bundles a tick works on),
:mod:`.pipeline` (one compiled tick) and its stages in order: :mod:`.broadphase`,
:mod:`.narrowphase` (shape pairs in :mod:`.collide` and :mod:`.tet_mesh`, kept box
manifolds in :mod:`.reuse`), :mod:`.prepare` (contact preparation), :mod:`.solver`
(contact impulses, with :mod:`.scalars`), :mod:`.integration` and :mod:`.islands`
(waking and sleeping); :mod:`.queries` (ray casts, box push-out), :mod:`.body_def`,
:mod:`.world_def`, :mod:`.events`, :mod:`.debug_draw`, :mod:`.world` (with
:mod:`.world_bodies` and :mod:`.world_static`), :mod:`.bench`.
"""

from ._cache import drop_stale_kernels

# Before any kernel is loaded from the on-disk cache (see _cache for why).
drop_stale_kernels()

from .body_def import BodyDef  # noqa: E402
from .debug_draw import DebugDrawer, DebugDrawOptions  # noqa: E402
from .events import ContactEvent  # noqa: E402
from .world import PhysicsWorld  # noqa: E402
from .world_def import WorldDef  # noqa: E402

__all__ = ["BodyDef", "ContactEvent", "DebugDrawer", "DebugDrawOptions", "PhysicsWorld", "WorldDef"]
