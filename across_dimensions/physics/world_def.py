"""What a new world is made of: :class:`WorldDef`, the argument of :class:`PhysicsWorld`.

As Box2D's ``b2WorldDef``: a frozen record with a default for every setting,
so a caller names only what differs and one definition can make many worlds.

>>> from across_dimensions.physics import PhysicsWorld, WorldDef
>>> world = PhysicsWorld(WorldDef(gravity=(0, -9.81, 0, 0), ground=False))
>>> moon = PhysicsWorld(WorldDef(gravity=(0, -1.62, 0, 0)))
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np


@dataclass(frozen=True)
class WorldDef:
    """The settings of a :class:`~across_dimensions.physics.PhysicsWorld`, with their defaults.

    Attributes
    ----------
    gravity : (4,) sequence of float
        Acceleration, m/s^2. Default ``-9.81`` along y and nothing along w.
    inverse_cube_G : float
        When non-zero, every pair of bodies attracts with ``G m1 m2 / r^3``
        (Gauss's law in four dimensions). Sleeping is disabled then, because
        attraction never lets a body rest.
    ground : bool
        Add the ground half-space ``y <= 0``.
    tick_dt : float
        Fixed tick, seconds: contacts are found once per tick.
    substeps : int
        Solver substeps per tick (the integration step is ``tick_dt / substeps``).
    iterations, relax_iterations : int
        Solver sweeps per substep with and without the push-out of overlaps.
    allow_sleep : bool
    max_ticks : int
        Most ticks one :meth:`~.PhysicsWorld.step` may run (caps the catch-up
        after a hitch; the surplus time is dropped).
    world_friction, world_restitution : float
        Material of the static world.
    sleep_time : float
        Seconds a group of touching bodies must stay calm before it sleeps.
    sleep_linear, sleep_angular : float
        m/s and rad/s: a body slower and spinning slower than these is calm.
    softening : float
        Length added in quadrature to distances in the inverse-cube law, so
        that touching bodies do not feel a near-infinite pull.
    margin : float
        m, the speculative contact distance at rest.
    contact_hertz, damping_ratio, max_push : float
        Stiffness, damping and top speed (m/s) of the push-out of overlaps.
    restitution_threshold : float
        m/s: slower approaches do not bounce.
    linear_damping, angular_damping : float
        1/s, drag on every dynamic body's motion and spin.
    spin_friction : float
        Contact-patch radius of a hypersphere as a fraction of its radius: it
        brakes spinning in the planes of the contact (which point friction
        cannot), so balls do not twirl in place forever. 0 turns it off.
    rolling_resistance : float
        Hypersphere rolling resistance: the braking torque is at most this
        times the normal force times the radius. 0 (the default) rolls on
        ideally, as the physics tests expect; a level may want about 0.02 so
        balls come to rest and sleep.
    reuse_distance, reuse_angle : float
        A box pair's contact manifold is reused while the pair moves less than
        this (m) and turns less than this (rad) since it was found (see
        :mod:`.reuse`); an angle of 0 finds every manifold every tick.
    """

    gravity: tuple[float, float, float, float] = (0.0, -9.81, 0.0, 0.0)
    inverse_cube_G: float = 0.0
    ground: bool = True
    tick_dt: float = 1.0 / 60.0
    substeps: int = 4
    iterations: int = 1
    relax_iterations: int = 1
    allow_sleep: bool = True
    max_ticks: int = 4
    world_friction: float = 0.6
    world_restitution: float = 0.0
    sleep_time: float = 0.5
    sleep_linear: float = 0.05
    sleep_angular: float = 0.1
    softening: float = 0.05
    margin: float = 0.02
    contact_hertz: float = 30.0
    damping_ratio: float = 10.0
    max_push: float = 3.0
    restitution_threshold: float = 0.5
    linear_damping: float = 0.0
    angular_damping: float = 0.0
    spin_friction: float = 0.1
    rolling_resistance: float = 0.0
    reuse_distance: float = 1e-3
    reuse_angle: float = float(np.radians(2.0))

    def __post_init__(self):
        if not self.tick_dt > 0 or int(self.substeps) < 1:
            raise ValueError("tick_dt must be positive and substeps at least 1")

    def write_params(self, params: np.ndarray) -> None:
        """Fill the ``(1,)`` record array ``params`` (:data:`.state.PARAMS_DTYPE`) from this
        definition; ``gravity``, ``inverse_cube_G`` and ``allow_sleep`` are the world's own
        settings (it wakes its bodies when they change) and are left out."""
        own = ("gravity", "inverse_cube_G", "allow_sleep")
        for f in fields(self):
            if f.name in params.dtype.names and f.name not in own:
                params[f.name] = float(getattr(self, f.name))
