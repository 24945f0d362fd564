"""Ghosts: what lies just off the slice, drawn translucent so the player sees along w.

Every 4D entity and every extended world is also sliced at ``w + k d`` and
``w - k d`` (``k = 1`` or ``1, 2``; ``d`` is the level's ``[ghosts] distance``
times the player's setting) and drawn with the renderer's ``"ghost"`` style:
translucent, hidden by solid geometry, never hiding anything. The two sides
differ in tint *and* pattern (ana, +w: warm stripes; kata, -w: cool dots), so
they never rely on colour alone. A ghost fades with its distance along w, and
while the player moves along w the side it moves towards grows stronger (a
preview of what is about to appear) and the other side fainter.

Draw only: ghosts have their own section-cache keys (``ghost+1:...``), so the
walker's colliders (``tick:`` keys), the radar and every ray cast never see
them; nothing here changes the simulation or its state hash.

The player's choices (on or off, distance, strength, layers) are a
:class:`GhostView`, the game's view option ``game.ghost_view`` (the defaults until
the window sets the player's own).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import section_collision
from ..frame import Drawable
from ..occlusion import hidden_rows
from ..player import W_SPEED, overlapping, player_box
from ..system import System
from . import camera

#: Ana (+w) ghosts: warm, striped. Tint is linear RGB and how far the colour is pulled to it.
ANA_TINT = (1.0, 0.4, 0.08, 0.75)
#: Kata (-w) ghosts: cool, dotted.
KATA_TINT = (0.1, 0.5, 1.0, 0.75)
ANA_PATTERN = "stripes"
KATA_PATTERN = "dots"
#: While moving along w at full speed, the side moved towards is this much more
#: opaque (x2) and the other side this much less (x0.5): the preview of issue 18.
PREVIEW_GAIN = 1.0
PREVIEW_DIM = 0.5
#: Opacity of the nearest layer at rest, times the renderer's ghost alpha (0.35): a
#: ghost must read against a bright floor, and still never look solid (under 0.6).
BASE_OPACITY = 2.0
#: A ghost of something solid that would stand where the player stands (a wall that
#: would block a step along w) is drawn this much stronger: the warning comes first.
BLOCK_GAIN = 1.6
#: Metres beyond an entity's reach within which the player's feet may be for its ghost
#: to block: the player's height (the box reaches 1.75 m above the feet).
BLOCK_REACH = 2.0
#: Most layers per side: beyond two the ghosts of one object pile up into a blur.
MAX_LAYERS = 2
#: Keys of the ghost sections in ``game.sections``.
PREFIX = "ghost"
#: A ghost layer may sit this far past the level's w range and still be drawn:
#: round-off in ``w + k d`` must not hide the last layer at the range's end.
RANGE_SLACK = 1e-9


@dataclass
class GhostView:
    """The player's ghost settings.

    Parameters
    ----------
    enabled : bool
        Ghosts drawn at all (a key toggles it).
    distance : float
        Factor on the level's ghost distance (1: the level's own).
    strength : float
        Factor on the ghosts' opacity (1: the default look).
    layers : int
        Ghost layers on each side, 1 or 2.
    """

    enabled: bool = True
    distance: float = 1.0
    strength: float = 1.0
    layers: int = 1


@dataclass(frozen=True)
class Layer:
    """One ghost layer: the slice at ``w`` (``side`` +1 ana, -1 kata; ``k``-th from the player)."""

    side: int
    k: int
    w: float
    opacity: float

    @property
    def tag(self) -> str:
        return f"{PREFIX}{'+' if self.side > 0 else '-'}{self.k}"

    @property
    def tint(self) -> tuple:
        return ANA_TINT if self.side > 0 else KATA_TINT

    @property
    def pattern(self) -> str:
        return ANA_PATTERN if self.side > 0 else KATA_PATTERN


def fade(k: int, layers: int) -> float:
    """Opacity factor of the ``k``-th layer of ``layers``: fainter the farther along w."""
    return 1.0 - k / (layers + 1.0) + 0.5 / (layers + 1.0)


def layers_of(game, w: float) -> list[Layer]:
    """The ghost layers to draw this frame about the slice at ``w`` (the frame's eye), nearest
    first, ana before kata; empty when off."""
    view, spec = game.ghost_view, game.level.ghosts
    if not (view.enabled and spec.enabled) or view.strength <= 0.0:
        return []
    weight = camera.ghost_weight(game)  # ghosts lie along the world's w: the plain slice's own
    if weight <= 0.0:
        return []
    d = spec.distance * view.distance
    n = int(min(max(view.layers, 1), MAX_LAYERS))
    lo, hi = game.level.w_range
    # Moving along w (held key or seek): lean in [-1, 1], + towards ana.
    lean = float(np.clip(game.player.velocity[3] / W_SPEED, -1.0, 1.0))
    out = []
    for k in range(1, n + 1):
        for side in (1, -1):
            wg = w + side * k * d
            if not lo - RANGE_SLACK <= wg <= hi + RANGE_SLACK:
                continue  # beyond the level's w range: nowhere the player can go
            towards = max(0.0, side * lean)
            away = max(0.0, -side * lean)
            emphasis = (1.0 + PREVIEW_GAIN * towards) * (1.0 - PREVIEW_DIM * away)
            out.append(Layer(side, k, wg, BASE_OPACITY * view.strength * fade(k, n) * emphasis * weight))
    return out


def _w_caps(mesh) -> tuple[float, float] | None:
    """``(w_lo, w_hi)`` when the mesh is a prism along w (every vertex on one of two w
    planes: a tesseract, a lifted 3D asset), else None. Cached on the mesh."""
    caps = mesh._cache.get("ghost_w_caps", False)
    if caps is False:
        w = np.unique(mesh.vertices[:, 3])
        caps = (float(w[0]), float(w[1])) if len(w) == 2 else None
        mesh._cache["ghost_w_caps"] = caps
    return caps


def same_as_slice(mesh, model: np.ndarray, w: float, wg: float) -> bool:
    """Is the section at ``wg`` the very section at ``w``? True for a prism along w that
    nothing turns out of w, when both lie strictly between its caps: every slice of it
    there is the same solid, so its ghost would only veil it (the Hive's gate).

    Parameters
    ----------
    mesh : TetMesh4
    model : (5, 5) float64
        Object to world.
    w, wg : float
        The slice's w and the ghost layer's.
    """
    caps = _w_caps(mesh)
    if caps is None or np.any(model[3, :3] != 0.0) or np.any(model[:3, 3] != 0.0):
        return False
    lo, hi = sorted(model[3, 3] * c + model[3, 4] for c in caps)
    return lo < min(w, wg) and max(w, wg) < hi


def slice_spans(caps: np.ndarray, models: np.ndarray) -> np.ndarray:
    """Where each thing is a prism along w that nothing turns out of w, the span ``(lo, hi)``
    of w between its caps, NaN elsewhere: ``(n, 2) float64``. :func:`same_as_slice` of thing
    ``i`` is ``lo < min(w, wg) and max(w, wg) < hi``, with the same arithmetic.

    Parameters
    ----------
    caps : (n, 2) float64
        Each mesh's :func:`_w_caps`, NaN where it has none.
    models : (n, 5, 5) float64
    """
    fixed = ~(models[:, 3, :3] != 0.0).any(axis=1) & ~(models[:, :3, 3] != 0.0).any(axis=1)
    a = models[:, 3, 3, None] * caps + models[:, 3, 4, None]
    spans = np.sort(a, axis=1)
    spans[~fixed] = np.nan
    return spans


def _caps(mesh) -> tuple[float, float]:
    caps = _w_caps(mesh)
    return (np.nan, np.nan) if caps is None else caps


def _holds_player(tri, lo, hi) -> bool:
    """Is the player's box ``(lo, hi)`` inside the solid this section bounds, or cut by its
    surface? (The walker's own test for a step along w: standing against a wall is not.)"""
    return section_collision.box_blocked(lo, hi, tri.vertices[tri.faces].astype(np.float64))


def _solid(table, feet) -> tuple[np.ndarray, np.ndarray]:
    """``(n,) bool`` twice: is each entity solid (or a body), and could its section stand where
    the player stands (a cheap test on its reach)?"""
    solid = table.column("ghost_solid", lambda e: e.solid or e.kind == "body").astype(bool)
    near = np.all(np.abs(table.centers[:, :3] - feet[:3]) <= (table.radii + BLOCK_REACH)[:, None], axis=1)
    return solid, solid & near


def draw(game, frame, alpha) -> None:
    used: set[str] = set()
    table = game.entity_models
    table.update(game)
    models = table.models(game, alpha)
    feet = game.player.position
    lo, hi = player_box(feet)
    solids, may_block = _solid(table, feet)
    planes = game.entity_sections.view_planes(frame.camera)
    blocked: list[int] = []
    w = frame.camera.w
    layers = layers_of(game, w)
    if layers:
        hidden = hidden_rows(game, frame, models, alpha)
        spans = slice_spans(table.column("ghost_w_caps", lambda e: _caps(e.mesh)).reshape(-1, 2), models)
    game.entity_sections.begin_ghosts({layer.tag for layer in layers})
    for layer in layers:
        tag = layer.tag
        # Solid things are drawn one by one (the ghost of one that would block the player is
        # stronger); the rest of the entities are cut together, one batch per layer. A ghost
        # that would be the section itself, drawn over it, is left out.
        near = np.abs(table.centers[:, 3] - layer.w) <= table.radii
        same = (spans[:, 0] < min(w, layer.w)) & (max(w, layer.w) < spans[:, 1])
        shown = np.flatnonzero(near & ~same)
        things = []
        for i in shown[solids[shown]]:
            e = table.entities[i]
            things.append((f"{tag}:{e.id}", f"{tag}:entity:{e.id}", e.mesh, models[i], bool(may_block[i])))
        batched = shown[~solids[shown] & ~hidden[shown]]  # what a box hides: no ghost to draw
        game.entity_sections.ghost_layer(frame, layer, [table.entities[i] for i in batched], models[batched], planes)
        worlds = enumerate(game.scene.worlds)
        things += [(f"{tag}:world:{i}", f"{tag}:world:{i}", wd.mesh, np.eye(5), True) for i, wd in worlds]
        for key, draw_key, mesh, model, solid in things:
            if same_as_slice(mesh, model, w, layer.w):
                continue
            tri, rev = game.sections.section(key, mesh, model, layer.w)
            used.add(key)
            if tri.is_empty:
                continue
            opacity = layer.opacity
            if solid and overlapping(lo, hi, game.sections.bounds(key)[None]).any() and _holds_player(tri, lo, hi):
                opacity *= BLOCK_GAIN  # it would block a step to this w: say so first
                if layer.side not in blocked:
                    blocked.append(layer.side)
            # Only the outer faces: one film, not two (half the cost on a software rasterizer).
            # A ghost around the player is then invisible from inside; the w gauge says it.
            look = {"tint": layer.tint, "pattern": layer.pattern, "opacity": opacity, "outside_only": True}
            frame.drawables.append(Drawable(draw_key, rev, tri, style="ghost", **look))
    frame.hud.w_blocked = tuple(blocked)
    game.sections.keep(PREFIX, used)  # layers or entities that went away


SYSTEM = System("ghosts", draw=draw)
