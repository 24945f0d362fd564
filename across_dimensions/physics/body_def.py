"""What a new body is made of: :class:`BodyDef`, the argument of :meth:`PhysicsWorld.add_body`.

As Box2D's ``b2BodyDef``: a plain record with a default for everything, so a
caller names only what differs and one definition can make many bodies.

>>> from across_dimensions.physics import BodyDef
>>> ball = BodyDef("hypersphere", radius=0.3, position=(0, 2, 0, 0.2))
>>> crate = BodyDef("hypercube", size=0.8, angles={"xw": 0.4}, friction=0.6)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any


@dataclass
class BodyDef:
    """A rigid body to add to a :class:`~across_dimensions.physics.PhysicsWorld`.

    Attributes
    ----------
    shape : {"hypersphere", "hypercube"}
        ``"sphere"`` and ``"ball"`` are accepted for "hypersphere", ``"box"``
        and ``"tesseract"`` for "hypercube".
    size : float or (4,) array_like, optional
        Hypercube: edge length, or the four edge lengths of a box (its
        inertia is then anisotropic). Hypersphere: diameter, if ``radius``
        is not given. Default 1.
    radius : float, optional
        Hypersphere radius.
    position : (4,) array_like
        Centre, metres.
    rotation : (4, 4) array_like or mapping of plane to angle, optional
    angles : mapping of plane name to radians, optional
        Alternative to ``rotation`` (see :func:`~across_dimensions.core.transform.angles_to_rotation`).
    velocity : (4,) array_like, optional
        m/s.
    angular_velocity : (6,) array_like or mapping of plane to rad/s, optional
        Bivector in ``xy xz yz xw yw zw`` order.
    mass : float, optional
        Overrides ``density * hypervolume``.
    density : float
        kg per m^4.
    kind : {"dynamic", "kinematic", "static"}
        Kinematic bodies move with the velocity you set and push others
        without being pushed; static ones never move.
    restitution : float
        Bounciness in [0, 1]; a pair uses the larger of its two values.
    friction : float
        Coulomb coefficient; a pair uses the geometric mean.
    """

    shape: str = "hypersphere"
    size: Any = None
    radius: float | None = None
    position: Any = (0.0, 0.0, 0.0, 0.0)
    rotation: Any = None
    angles: Mapping[str, float] | None = None
    velocity: Any = None
    angular_velocity: Any = None
    mass: float | None = None
    density: float = 1.0
    kind: str = "dynamic"
    restitution: float = 0.1
    friction: float = 0.5
