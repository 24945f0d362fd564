"""4D rigid-body physics: hyperspheres and hypercubes, the 3D world, player queries.

Depends on numpy, numba and :mod:`across_dimensions.core` only.

>>> from across_dimensions.physics import PhysicsWorld
>>> world = PhysicsWorld(gravity=(0, -9.81, 0, 0), inverse_cube_G=0.0)
"""

from .events import ContactEvent
from .world import PhysicsWorld

__all__ = ["ContactEvent", "PhysicsWorld"]
