"""Which 4D things the level's boxes hide from the eye, so they are neither sliced nor drawn.

On a software rasterizer every triangle costs its set-up even when the depth test then hides
all of it: the enemies of an arena behind a closed gate (their sections, the depth pre-pass's
copy of them and two ghost layers, some 30,000 triangles) cost a third of the frame seen from
the next room. A thing is hidden when one box lies between the eye and all of it.

The occluders are the boxes solid in the slice (:meth:`.sim.Game.colliders_at`: the 3D
world's boxes and the extended worlds' parts at the slice's w) and the solid 4D objects whose
section is a box (an axis-aligned tesseract such as a door, while the slice cuts it). A box the
eye stands in, or next to, hides nothing: boxes are drawn outside only, and the near plane
may open the face in front of the eye.

The test is conservative. Each thing is its bounding ball (its reach round its centre: any
section of it, at any w, lies inside), taken as the ball's bounding box ``T``. ``T`` is hidden
by a convex box ``B`` that it does not touch when the segment from the eye to each of ``T``'s
eight corners crosses ``B``: the directions that meet ``B`` form a convex cone holding those
of all of ``T``, and every separating plane of the two leaves the eye on ``B``'s side (else a
segment from the eye to ``T`` could not reach ``B``), so ``B`` is met before ``T``.

The same boxes tell where the sky cannot show (:func:`open_rectangles`, which the renderer asks
of the frame's :func:`sky_boxes`): the view is cut into cells, and a cell that one box covers
gets no sky. On llvmpipe the sky's depth test costs about half of a whole sky on every pixel it
covers, even where the scene hides it: a wall seen from close by, or the walls of a room, would
cost a millisecond or more for no pixel.
"""

from __future__ import annotations

import numpy as np

from ..physics.sightlines import segments_cross_boxes, segments_cross_their_boxes
from .frame import WIDEST_VIEW

#: A box whose bounds, grown by this (m), hold the eye hides nothing (its faces are culled from
#: inside, and the near plane may cut the one in front of the eye).
EYE_MARGIN = 0.3
#: Occluders are shrunk by this (m) before the test: rounding never hides a visible edge.
SHRINK = 0.01
#: Added to each thing's reach (m): its model is the frame's (between two ticks), its centre
#: the tick's.
MOTION_MARGIN = 0.25
#: Meshes with fewer vertices are not tested (a crystal, a bullet: cheaper to draw than to test
#: when there are hundreds); an enemy has a thousand.
MIN_VERTICES = 64
#: Things at least this big (reach, m) reaching into a box are cut into pieces outside it.
BIG = 1.0
#: A thing reaching into boxes is cut into at most this many pieces outside them (more, and
#: it is taken as seen: a crate among crates is not worth the loop).
MAX_PIECES = 8
#: Offsets of a box's eight corners from its centre, in units of its half sizes.
_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], np.float64)
#: Rows of cells :func:`open_rectangles` cuts the view into by default (square cells: 60 pixels
#: at 720 lines).
SKY_ROWS = 12


def hidden(eye, centers, radii, boxes) -> np.ndarray:
    """Is each ball wholly hidden from ``eye`` by ``boxes``?

    Parameters
    ----------
    eye : (3,) array_like
    centers : (n, 3) array_like
    radii : (n,) array_like
    boxes : (k, 2, 3) array_like
        Lower and upper corners; rows with NaN are ignored.

    Returns
    -------
    (n,) bool
    """
    eye = np.asarray(eye, np.float64)
    return _hidden(eye, centers, radii, _occluders(eye, np.asarray(boxes, np.float64).reshape(-1, 2, 3)))


def _hidden(eye: np.ndarray, centers, radii, b: np.ndarray) -> np.ndarray:
    """:func:`hidden` by occluders ``b (k, 2, 3)`` already chosen and shrunk (:func:`_occluders`)."""
    c = np.asarray(centers, np.float64).reshape(-1, 3)
    r = np.asarray(radii, np.float64).reshape(-1, 1)
    if not len(c) or not len(b):
        return np.zeros(len(c), bool)
    # A box that hides any part of a thing, whole or a piece outside other boxes, is crossed
    # by the segment to its middle (its direction lies in the cone of the corners'): on most
    # frames no pair is, and that one test is all.
    ahead, anyone = _ahead(eye, c, b)
    if not anyone:
        return np.zeros(len(c), bool)
    whole = np.stack([c - r, c + r], axis=1)
    out = _behind(eye, whole, b, ahead)
    # A thing reaching into an occluder (an enemy pressed against a gate): what lies inside a
    # box is hidden by its faces, so only the rest must be behind one.
    # Tried only for a big one (an enemy, not a crate or a crystal: little to draw) reaching
    # into a box that the segment to its middle crosses (a gate it is pressed against, not the
    # floor under it): the few cases worth a Python loop.
    rows = np.flatnonzero(~out & (r[:, 0] >= BIG))
    if not rows.size:
        return out
    touching = np.all((whole[rows, None, 0] < b[None, :, 1]) & (whole[rows, None, 1] > b[None, :, 0]), axis=2)
    tried = (touching & ahead[rows]).any(axis=1)
    rows, touching = rows[tried], touching[tried]
    pieces = [_outside(whole[i], b[t]) for i, t in zip(rows, touching)]
    if rows.size:
        behind = np.split(_behind(eye, np.concatenate(pieces), b), np.cumsum([len(p) for p in pieces])[:-1])
        out[rows] = [len(p) <= MAX_PIECES and bool(h.all()) for p, h in zip(pieces, behind)]
    return out


def _behind(eye: np.ndarray, things: np.ndarray, b: np.ndarray, ahead: np.ndarray | None = None) -> np.ndarray:
    """``(n,) bool``: is each box of ``things (n, 2, 3)`` apart from one of the occluders
    ``b (k, 2, 3)`` and behind it (the segment from ``eye`` to each of its corners crosses it)?
    ``ahead (n, k) bool``, when given, says which segments to the things' middles cross which
    occluders (:func:`_hidden` has it already)."""
    n = len(things)
    if not n:
        return np.zeros(0, bool)
    lo, hi = b[None, :, 0], b[None, :, 1]  # (1, k, 3)
    # Touching counts as apart: a piece left by subtracting an occluder shares a face with it.
    apart = np.any((things[:, None, 1] <= lo) | (things[:, None, 0] >= hi), axis=2)  # (n, k)
    mid, half = 0.5 * (things[:, 0] + things[:, 1]), 0.5 * (things[:, 1] - things[:, 0])
    # The segment to the middle crosses every box that hides the whole (it lies in the cone of
    # the corners'): the few such pairs are the only ones whose eight corners are tried.
    if ahead is None:
        ahead = _ahead(eye, mid, b)[0]
    i, j = np.nonzero(apart & ahead)
    corners = (mid[i, None] + half[i, None] * _CORNERS[None]).reshape(-1, 3)  # (p * 8, 3)
    all8 = _crossed(eye, corners, np.repeat(b[j], 8, axis=0)).reshape(-1, 8).all(axis=1)
    out = np.zeros(n, bool)
    out[i[all8]] = True
    return out


def _crossed(eye: np.ndarray, ends: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """``(m,) bool``: does the segment from ``eye`` to each of ``ends (m, 3)`` cross the box
    beside it in ``boxes (m, 2, 3)``?"""
    out = np.empty(len(ends), bool)
    segments_cross_their_boxes(_c(eye), _c(ends), _c(boxes), out)
    return out


def _ahead(eye: np.ndarray, ends: np.ndarray, boxes: np.ndarray) -> tuple[np.ndarray, bool]:
    """``(m, k) bool``: does the segment from ``eye`` to each of ``ends (m, 3)`` cross each of
    ``boxes (k, 2, 3)``; and does any?"""
    out = np.empty((len(ends), len(boxes)), bool)
    return out, segments_cross_boxes(_c(eye), _c(ends), _c(boxes), out)


def _c(a) -> np.ndarray:
    """``a`` as a contiguous float64 array: the kernels' one signature (a view would compile another)."""
    return np.ascontiguousarray(a, np.float64)


def _outside(box: np.ndarray, b: np.ndarray) -> np.ndarray:
    """What of ``box (2, 3)`` lies outside the occluders ``b (k, 2, 3)`` it overlaps, as
    boxes ``(m, 2, 3)`` (each subtraction leaves at most six slabs; plain floats: a handful of
    tiny boxes, where numpy's per-call cost would be most of the work)."""
    pieces = [box.tolist()]
    for lo, hi in b.tolist():
        rest = []
        for p in pieces:
            if not all(lo[a] < p[1][a] and hi[a] > p[0][a] for a in range(3)):
                rest.append(p)
                continue
            core = [list(p[0]), list(p[1])]
            for a in range(3):  # peel the slabs below and above the occluder, axis by axis
                if core[0][a] < lo[a]:
                    s = [list(core[0]), list(core[1])]
                    s[1][a] = core[0][a] = lo[a]
                    rest.append(s)
                if core[1][a] > hi[a]:
                    s = [list(core[0]), list(core[1])]
                    s[0][a] = core[1][a] = hi[a]
                    rest.append(s)
            # what is left of ``core`` lies inside the occluder: hidden by its faces
        pieces = rest
        if len(pieces) > MAX_PIECES:
            break
    return np.array(pieces, np.float64).reshape(-1, 2, 3)


def _occluders(eye: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """The rows of ``boxes (k, 2, 3)`` that may hide something from ``eye``, shrunk by
    :data:`SHRINK`: no NaN, not holding the eye (with :data:`EYE_MARGIN`), not flat."""
    ok = ~np.isnan(boxes).any(axis=(1, 2))
    b = boxes[ok]
    near = np.all((b[:, 0] - EYE_MARGIN <= eye) & (eye <= b[:, 1] + EYE_MARGIN), axis=1)
    b = b[~near] + np.array([SHRINK, -SHRINK])[None, :, None]
    return b[np.all(b[:, 1] > b[:, 0], axis=1)]


#: Styles the renderer draws see-through (outlines, ghosts): an entity drawn so hides nothing.
SEE_THROUGH = ("wire", "ghost")


def box_sections(table, models: np.ndarray, w: float) -> np.ndarray:
    """Bounds ``(m, 2, 3)`` of the sections at ``w`` of the solid entities of ``table`` (a
    :class:`.entity_models.EntityModels`, posed by ``models (n, 5, 5)``) that are boxes drawn
    opaque: a mesh whose every vertex is a corner of its bounds, posed without a turn, cut
    inside its extent along w, in a style not :data:`SEE_THROUGH`."""
    boxy = table.column("occluder", lambda e: e.solid and _is_box(e.mesh)).astype(bool)
    # Drawn opaque now: a box the field weapon shows as a wireframe, or a ghost, hides nothing.
    rows = np.array([i for i in np.flatnonzero(boxy) if table.entities[i].style not in SEE_THROUGH], np.int64)
    if not len(rows):
        return np.zeros((0, 2, 3))
    m = models[rows]
    lin = m[:, :4, :4]
    unturned = np.all(np.abs(lin - lin * np.eye(4)) < 1e-9, axis=(1, 2))
    lo, hi = _mesh_bounds(table, rows)
    scale, move = np.diagonal(lin, axis1=1, axis2=2), m[:, :4, 4]
    a, b = lo * scale + move, hi * scale + move
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    cut = unturned & (lo[:, 3] < w) & (w < hi[:, 3])
    return np.stack([lo[cut, :3], hi[cut, :3]], axis=1)


def _mesh_bounds(table, rows) -> tuple[np.ndarray, np.ndarray]:
    """Each row's mesh bounds ``(m, 4)`` twice (lower, upper), in its own space."""
    lo = np.array([table.entities[i].mesh.vertices.min(axis=0) for i in rows], np.float64)
    hi = np.array([table.entities[i].mesh.vertices.max(axis=0) for i in rows], np.float64)
    return lo, hi


def _is_box(mesh) -> bool:
    """Does every vertex of ``mesh`` sit on a corner of its bounds (a tesseract, subdivided or
    not, has no other), and are all sixteen corners there? Its cuts are then boxes."""
    v = np.asarray(mesh.vertices, np.float64)
    lo, hi = v.min(axis=0), v.max(axis=0)
    tol = 1e-6 * max(1.0, float(np.abs(v).max()))
    at_lo, at_hi = np.abs(v - lo) <= tol, np.abs(v - hi) <= tol
    if not np.all(at_lo | at_hi) or np.any(hi - lo <= tol):
        return False
    return len(np.unique(at_hi.astype(np.int8), axis=0)) == 16


def hidden_rows(game, frame, models: np.ndarray, alpha: float) -> np.ndarray:
    """``(n,) bool`` over ``game.entity_models``'s entities (posed by ``models (n, 5, 5)``, the
    frame's ``alpha``): in the view, worth the test, and hidden from ``frame``'s eye by a box in
    its slice (what is outside the view the batches cull themselves; solid things, doors and
    walls, are the occluders; small meshes, crystals and bullets, cost less to draw than to
    test). None are while the slice is turned (the occluders are world boxes) or the camera is
    detached. Kept for the frame: the sections and the
    ghosts ask in turn."""
    table = game.entity_models
    n = len(table.entities)
    if not n or not game.camera.aligned or game.camera.detached:
        return np.zeros(n, bool)
    cam = frame.camera
    key = (game.tick, alpha, tuple(np.asarray(cam.position, np.float64).tolist()), cam.w, n)
    if table.hidden_memo[0] == key:
        return table.hidden_memo[1]
    # Only what is in the view: the rest is not cut anyway (the batches' own culling).
    planes = game.entity_sections.view_planes(cam)
    r = table.radii + MOTION_MARGIN
    c = table.centers[:, :3]
    worth = table.column("occludee", lambda e: not e.solid and len(e.mesh.vertices) >= MIN_VERTICES).astype(bool)
    seen = worth & np.all(
        c @ planes[:, :3].T + planes[:, 3] >= -r[:, None] * np.linalg.norm(planes[:, :3], axis=1), axis=1
    )
    out = np.zeros(n, bool)
    if seen.any():
        out[seen] = _hidden(
            np.asarray(cam.position, np.float64), c[seen], r[seen], _frame_occluders(game, frame, models, alpha)
        )
    table.hidden_memo = (key, out)
    return out


def _frame_occluders(game, frame, models: np.ndarray, alpha: float) -> np.ndarray:
    """The occluders of ``frame``'s eye (:func:`_occluders` of the boxes solid in its slice), kept
    for the frame: the sections, the ghosts and the sky ask in turn."""
    table, cam = game.entity_models, frame.camera
    eye = np.asarray(cam.position, np.float64)
    key = (game.tick, alpha, tuple(eye.tolist()), cam.w, len(table.entities))
    if table.occluder_memo[0] != key:
        boxes = np.concatenate([game.colliders_at(cam.w), box_sections(table, models, cam.w)])
        table.occluder_memo = (key, _occluders(eye, boxes))
    return table.occluder_memo[1]


_SKY_GRIDS: dict = {}  # (the tangent of half a field of view, rows) -> its cells (:func:`_sky_grid`)


def _sky_grid(t: float, rows: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The edges ``xs (cols + 1,)`` and ``ys (rows + 1,)`` of ``rows`` rows of square cells in
    the view's units, and their corners on the far plane in eye space, ``(x t, y t, 1)``,
    ``(m, 3)``: made once per field of view (``t``, the tangent of half of it) and rows."""
    grid = _SKY_GRIDS.get((t, rows))
    if grid is None:
        xs = np.linspace(-WIDEST_VIEW, WIDEST_VIEW, round(rows * WIDEST_VIEW) + 1)
        ys = np.linspace(-1.0, 1.0, rows + 1)
        gx, gy = np.meshgrid(xs * t, ys * t)
        grid = (xs, ys, np.stack([gx.ravel(), gy.ravel(), np.ones(gx.size)], axis=1))
        if len(_SKY_GRIDS) >= 8:  # a zoom sweeping the field of view: keep a few
            _SKY_GRIDS.clear()
        _SKY_GRIDS[(t, rows)] = grid
    return grid


def sky_boxes(game, frame, models: np.ndarray, alpha: float) -> np.ndarray | None:
    """The boxes that may hide the sky in ``frame``'s view, ``(k, 2, 3)`` (the boxes solid in its
    slice, as :func:`hidden_rows` takes them); None while the slice is turned or the camera
    detached (the occluders are world boxes)."""
    if not game.camera.aligned or game.camera.detached:
        return None
    return _frame_occluders(game, frame, models, alpha)


def open_rectangles(eye, axes, t: float, far: float, boxes: np.ndarray, rows: int = SKY_ROWS) -> np.ndarray | None:
    """Where the sky may show in a view: rectangles ``(k, 4) float64``, each ``x0, y0, x1, y1``
    in the view's own units (its height spans -1 to 1, its width -aspect to aspect for any
    window up to :data:`.frame.WIDEST_VIEW` wide); None for anywhere (no box is in
    the way).

    The view is cut into square cells, ``rows`` high, and a cell that one of the
    ``boxes`` covers is left out: the four rays through its corners, out to the far plane, all
    cross the box. The rays that meet a convex box from outside it form a convex cone, so
    every ray through the cell meets the box too, nearer than the far plane where the sky is
    drawn. Runs of open cells, along a row and down the rows where they recur, are one
    rectangle each; no rectangle at all when every cell is covered (a wall seen from close by).

    Parameters
    ----------
    eye : (3,) float64
    axes : (3, 3) float64
        The view's x, y and forward directions, rows (:meth:`.frame.Camera3.axes`).
    t : float
        The tangent of half the vertical field of view.
    far : float
        The far plane's distance.
    boxes : (k, 2, 3) float64
        Lower and upper corners, none holding the eye (:func:`_occluders`).
    rows : int
        Rows of cells: finer leaves out more of the sky's pixels, for more rays to test
        (``(rows + 1) (3 rows + 1)``: 481 for 12, 8 for 1, the whole view in three cells).
    """
    eye, axes = np.asarray(eye, np.float64), np.asarray(axes, np.float64)
    # A box wholly behind the eye covers nothing (about half of a level's walls in any view).
    mid, half = 0.5 * (boxes[:, 0] + boxes[:, 1]), 0.5 * (boxes[:, 1] - boxes[:, 0])
    boxes = boxes[(mid - eye) @ axes[2] + half @ np.abs(axes[2]) > 0.0]
    if not len(boxes):
        return None
    xs, ys, corners = _sky_grid(float(t), int(rows))
    crossed, anyone = _ahead(eye, eye + far * (corners @ axes), boxes)
    if not anyone:
        return None
    c = crossed.reshape(len(ys), len(xs), len(boxes))
    covered = (c[:-1, :-1] & c[:-1, 1:] & c[1:, :-1] & c[1:, 1:]).any(axis=2)  # (rows, cols)
    if not covered.any():
        return None
    # Runs of open cells along each row: where the row, padded with covered cells, steps up,
    # and where it steps down (row-major, like the starts: the n-th end closes the n-th run).
    padded = np.zeros((len(ys) - 1, len(xs) + 1), bool)
    padded[:, 1:-1] = ~covered
    r0, c0 = np.nonzero(padded[:, 1:] & ~padded[:, :-1])
    _, c1 = np.nonzero(padded[:, :-1] & ~padded[:, 1:])
    # A run the row below has too grows down into one rectangle (the open sky over a wall
    # is one): fewer edges across llvmpipe's tiles, each of which it rasterizes pixel by pixel.
    rects: dict = {}  # (first column, end column) -> [first row, end row] of the rectangle growing down
    done = []
    for r, a, b in zip(r0.tolist(), c0.tolist(), c1.tolist()):
        last = rects.get((a, b))
        if last is not None and last[1] == r:
            last[1] = r + 1
            continue
        if last is not None:
            done.append((a, b, *last))
        rects[(a, b)] = [r, r + 1]
    done += [(a, b, *span) for (a, b), span in rects.items()]
    i = np.array(done, np.int64).reshape(-1, 4)
    return np.stack([xs[i[:, 0]], ys[i[:, 2]], xs[i[:, 1]], ys[i[:, 3]]], axis=1)
