"""Debug drawing: the physics world describes itself to a drawer it knows nothing about.

In the style of Box2D's ``b2DebugDraw`` and pymunk's ``SpaceDebugDrawOptions``:
:func:`debug_draw` walks the world and calls the methods of any object with the
:class:`DebugDrawer` methods; what the drawer does with them (GL lines in the
game, see :mod:`across_dimensions.render.debug_draw`; a list in a test) is its
own business. :class:`DebugDrawOptions` says what to report and in which colours.

What is reported is the **3D section at one w** (the slice the player sees), so
the overlay lines up with the rendered world:

* a hypersphere of radius ``r`` whose centre is ``dw`` away from the slice is
  the sphere of radius ``sqrt(r^2 - dw^2)`` (:meth:`DebugDrawer.draw_sphere`);
* a 4D box is the convex polytope where the slice cuts it, given as its edges
  (:meth:`DebugDrawer.draw_section`): each edge is where the slice crosses one
  of the box's 24 square faces;
* bodies the slice misses are not reported;
* the static 3D world boxes (they span all of w) and query boxes such as the
  player's collider are axis-aligned boxes (:meth:`DebugDrawer.draw_box`);
  half-spaces (the ground, walls in w) are unbounded and not reported;
* contact points of the last tick within ``contact_slab`` of the slice, with
  their normals (xyz parts; the normal is not renormalised, so a short normal
  says the push is mostly along w) (:meth:`DebugDrawer.draw_contact`).

Colours are RGBA tuples in [0, 1]; a body's colour says its state: dynamic and
awake, asleep (whole islands sleep together, so a sleeping island shows as one
colour), kinematic, or static.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from itertools import combinations, product
from typing import TYPE_CHECKING, Protocol

import numpy as np

from .collide import SPHERE
from .state import DYNAMIC, KINEMATIC

if TYPE_CHECKING:  # pragma: no cover
    from .world import PhysicsWorld

Color = tuple[float, float, float, float]


class DebugDrawer(Protocol):
    """What :func:`debug_draw` calls. All coordinates are world xyz, metres."""

    def draw_sphere(self, body_id: int, center: np.ndarray, radius: float, color: Color) -> None:
        """The section of hypersphere ``body_id``: centre ``(3,) float64``."""

    def draw_section(self, body_id: int, edges: np.ndarray, color: Color) -> None:
        """The section of box ``body_id`` as edges ``(k, 2, 3) float64`` (segment end points)."""

    def draw_contact(self, point: np.ndarray, normal: np.ndarray, color: Color) -> None:
        """A contact point ``(3,)`` and the xyz part of its normal ``(3,)`` (from body a to b)."""

    def draw_box(self, center: np.ndarray, half_extents: np.ndarray, color: Color) -> None:
        """An axis-aligned box: centre and half extents ``(3,) float64``."""


@dataclass
class DebugDrawOptions:
    """What :func:`debug_draw` reports, and in which colours (RGBA in [0, 1]).

    Attributes
    ----------
    shapes, contacts, boxes : bool
        Report bodies and world boxes, contact points, query boxes (the player).
    contact_slab : float
        Contacts whose point is at most this far (metres, along w) from the
        slice are reported.
    """

    shapes: bool = True
    contacts: bool = True
    boxes: bool = True
    contact_slab: float = 0.5
    dynamic_color: Color = (0.25, 0.9, 0.35, 1.0)
    sleeping_color: Color = (0.35, 0.5, 1.0, 1.0)
    kinematic_color: Color = (1.0, 0.8, 0.2, 1.0)
    static_color: Color = (0.65, 0.65, 0.65, 1.0)
    contact_color: Color = (1.0, 0.2, 0.2, 1.0)
    # Half transparent: in first person the camera sits inside the player's box.
    box_color: Color = (1.0, 1.0, 1.0, 0.5)


# The 24 square faces of a 4D box: two free axes (p, q) and signs for the other
# two. Each row lists the face's four corners in order around it, as indices
# into the 16 corners (bit k of the index set = + along axis k).
def _square_faces() -> np.ndarray:
    rows = []
    for p, q in combinations(range(4), 2):
        fixed = [a for a in range(4) if a not in (p, q)]
        for s0, s1 in product((0, 1), repeat=2):
            base = (s0 << fixed[0]) | (s1 << fixed[1])
            rows.append([base, base | (1 << p), base | (1 << p) | (1 << q), base | (1 << q)])
    return np.array(rows, dtype=np.int64)


_SQUARES = _square_faces()  # (24, 4)
_CORNER_SIGNS = np.array([[1.0 if (c >> k) & 1 else -1.0 for k in range(4)] for c in range(16)])  # (16, 4)


def box_section_edges(position, rotation, half_extents, w: float, tol: float = 1e-9) -> np.ndarray:
    """Edges of the 3D section of a 4D box by the hyperplane at ``w``.

    Parameters
    ----------
    position : (4,) array_like
    rotation : (4, 4) array_like
        Body to world (columns are the box axes).
    half_extents : (4,) array_like
    w : float
    tol : float
        Corners within this distance of the slice count as on it.

    Returns
    -------
    (k, 2, 3) float64
        Segment end points; ``k = 0`` when the slice misses the box.
    """
    pos = np.asarray(position, dtype=np.float64)
    corners = pos + (_CORNER_SIGNS * np.asarray(half_extents, dtype=np.float64)) @ np.asarray(rotation).T
    f = corners[:, 3] - w
    f[np.abs(f) <= tol] = 0.0
    if f.min() > 0.0 or f.max() < 0.0:
        return np.zeros((0, 2, 3))
    edges = []
    for sq in _SQUARES:
        fs = f[sq]
        if not (fs == 0.0).all():
            pts = []
            for k in range(4):
                i, j = sq[k], sq[(k + 1) % 4]
                if f[i] == 0.0:
                    pts.append(corners[i, :3])
                elif f[i] * f[j] < 0.0:
                    t = f[i] / (f[i] - f[j])
                    pts.append(corners[i, :3] + t * (corners[j, :3] - corners[i, :3]))
            if len(pts) == 2 and not np.array_equal(pts[0], pts[1]):
                edges.append(pts)
            continue
        # A square lying in the slice: its four sides are section edges (each
        # is also found on the neighbouring squares: keep one copy).
        for k in range(4):
            edges.append([corners[sq[k], :3], corners[sq[(k + 1) % 4], :3]])
    if not edges:
        return np.zeros((0, 2, 3))
    out = np.array(edges, dtype=np.float64)
    # Drop duplicates (a side shared by two squares in the slice), in either direction.
    seen: set[tuple] = set()
    keep = []
    for e in out:
        a, b = tuple(np.round(e[0], 9)), tuple(np.round(e[1], 9))
        k = (a, b) if a <= b else (b, a)
        if k not in seen:
            seen.add(k)
            keep.append(e)
    return np.array(keep)


def debug_draw(
    world: PhysicsWorld, drawer: DebugDrawer, w: float, options: DebugDrawOptions | None = None, boxes: Iterable = ()
) -> None:
    """Report the world's colliders, contacts and ``boxes`` in the slice at ``w`` to ``drawer``.

    Bodies are reported in id order, then world boxes, then contacts (in the
    order the solver holds them), then ``boxes``. Nothing in the world changes.

    Parameters
    ----------
    world : PhysicsWorld
    drawer : DebugDrawer
    w : float
        The slice.
    options : DebugDrawOptions, optional
    boxes : iterable of (center (4,), half_extents (4,))
        Query boxes to show, such as the player's collider; reported when
        the slice passes through them (their xyz part).
    """
    opt = options or DebugDrawOptions()
    b = world.bodies
    w = float(w)
    if opt.shapes:
        for i in range(b.count):
            if not b.alive[i]:
                continue
            if b.kind[i] == DYNAMIC:
                color = opt.dynamic_color if b.awake[i] else opt.sleeping_color
            elif b.kind[i] == KINEMATIC:
                color = opt.kinematic_color
            else:
                color = opt.static_color
            pos = b.position[i]
            if b.shape[i] == SPHERE:
                r = float(b.half_extents[i, 0])
                dw = float(pos[3]) - w
                if abs(dw) < r:
                    drawer.draw_sphere(i, pos[:3].copy(), float(np.sqrt(r * r - dw * dw)), color)
            elif abs(float(pos[3]) - w) <= b.bound[i]:
                edges = box_section_edges(pos, b.rotation[i], b.half_extents[i], w)
                if edges.shape[0]:
                    drawer.draw_section(i, edges, color)
        for row in world.static.boxes:
            drawer.draw_box(row[:3].copy(), row[3:].copy(), opt.static_color)
    if opt.contacts:
        c = world.contacts
        for k in range(world.last_contact_count):
            p = c.point[k]
            if abs(float(p[3]) - w) <= opt.contact_slab:
                drawer.draw_contact(p[:3].copy(), c.normal[k, :3].copy(), opt.contact_color)
    if opt.boxes:
        for center, half in boxes:
            center = np.asarray(center, dtype=np.float64).reshape(4)
            half = np.asarray(half, dtype=np.float64).reshape(4)
            if abs(center[3] - w) <= half[3]:
                drawer.draw_box(center[:3].copy(), half[:3].copy(), opt.box_color)
