"""4D rigid-body physics: hyperspheres and hypercubes, the 3D world, player queries.

Depends on numpy, numba and :mod:`across_dimensions.core` only.

>>> from across_dimensions.physics import PhysicsWorld
>>> world = PhysicsWorld(gravity=(0, -9.81, 0, 0), inverse_cube_G=0.0)
"""

from ._cache import drop_stale_kernels

# Before any kernel is loaded from the on-disk cache (see _cache for why).
drop_stale_kernels()

from .events import ContactEvent  # noqa: E402
from .world import PhysicsWorld  # noqa: E402

__all__ = ["ContactEvent", "PhysicsWorld"]
