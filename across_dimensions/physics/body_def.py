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
from typing import Any, NamedTuple

import numpy as np

from across_dimensions.core import transform

from .collide import BOX, SPHERE
from .mass import box_inertia, box_volume, hypersphere_inertia, hypersphere_volume
from .state import DYNAMIC, KINEMATIC, STATIC

KINDS = {"static": STATIC, "kinematic": KINEMATIC, "dynamic": DYNAMIC}
SHAPES = {"hypersphere": SPHERE, "sphere": SPHERE, "ball": SPHERE, "hypercube": BOX, "box": BOX, "tesseract": BOX}


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


class Resolved(NamedTuple):
    """A :class:`BodyDef` checked and turned into the values of its body slot (see :class:`~.state.Bodies`)."""

    kind: int
    shape: int
    half_extents: np.ndarray
    bound: float
    mass: float
    inv_mass: float
    inv_inertia: np.ndarray
    position: np.ndarray
    rotation: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray


def resolve(d: BodyDef) -> Resolved:
    """Check ``d`` and work out its body's values: shape codes, half extents, mass and inertia, pose.

    Raises
    ------
    ValueError
        Unknown shape or kind, a non-positive size, radius or mass.
    """
    shape, size, radius, kind = d.shape, d.size, d.radius, d.kind
    if shape not in SHAPES:
        raise ValueError(f"unknown shape {shape!r}; use 'hypersphere' or 'hypercube'")
    if kind not in KINDS:
        raise ValueError(f"unknown kind {kind!r}; use dynamic, kinematic or static")
    sh = SHAPES[shape]
    if sh == SPHERE:
        r = float(radius) if radius is not None else (0.5 * float(size) if size is not None else 0.5)
        if not r > 0:
            raise ValueError("radius must be positive")
        half = np.full(4, r)
        volume = hypersphere_volume(r)
    else:
        s = np.broadcast_to(np.asarray(1.0 if size is None else size, dtype=np.float64), (4,))
        if not np.all(s > 0):
            raise ValueError("size must be positive")
        half = 0.5 * s
        volume = box_volume(half)
    m = float(d.mass) if d.mass is not None else float(d.density) * volume
    if not m > 0:
        raise ValueError("mass must be positive")
    inertia = hypersphere_inertia(m, half[0]) if sh == SPHERE else box_inertia(m, half)
    k = KINDS[kind]
    position = vec4(d.position, "position")
    rotation = rotation_matrix(d.rotation, d.angles)
    velocity = vec4(d.velocity, "velocity") if k != STATIC else 0.0
    angular_velocity = bivector(d.angular_velocity) if k != STATIC else 0.0
    return Resolved(
        k,
        sh,
        half,
        float(half[0] if sh == SPHERE else np.linalg.norm(half)),
        m,
        1.0 / m if k == DYNAMIC else 0.0,
        1.0 / inertia if k == DYNAMIC else np.zeros(6),
        position,
        rotation,
        np.broadcast_to(np.asarray(velocity, dtype=np.float64), (4,)).copy(),
        np.broadcast_to(np.asarray(angular_velocity, dtype=np.float64), (6,)).copy(),
    )


def rotation_matrix(rotation=None, angles: Mapping[str, float] | None = None) -> np.ndarray:
    if rotation is None:
        return transform.angles_to_rotation(angles or {})
    if isinstance(rotation, Mapping):
        return transform.angles_to_rotation(rotation)
    r = np.asarray(rotation, dtype=np.float64)
    if r.shape == (5, 5):
        r = r[:4, :4]
    if r.shape != (4, 4):
        raise ValueError(f"rotation must be (4, 4), got {r.shape}")
    if transform.orthonormality_error(r) > 1e-6 or np.linalg.det(r) < 0:
        raise ValueError("rotation is not a proper rotation matrix")
    return transform.orthonormalize(r)


def bivector(value) -> np.ndarray:
    if value is None:
        return np.zeros(6)
    if isinstance(value, Mapping):
        out = np.zeros(6)
        for plane, rate in value.items():
            if plane not in transform.PLANES:
                raise ValueError(f"unknown plane {plane!r}; use one of {', '.join(transform.PLANES)}")
            out[transform.PLANES.index(plane)] = float(rate)
        return out
    out = np.asarray(value, dtype=np.float64).reshape(6)
    return out.copy()


def vec4(value, name: str) -> np.ndarray:
    out = np.asarray(value if value is not None else np.zeros(4), dtype=np.float64).reshape(-1)
    if out.shape != (4,):
        raise ValueError(f"{name} must have 4 components (x, y, z, w), got {out.shape[0]}")
    return out.copy()
