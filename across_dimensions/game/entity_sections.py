"""The entities' cross-sections for drawing: one batch per style, one kernel call each.

Every entity with a mesh whose reach spans the player's slice is sliced by a
:class:`~across_dimensions.core.section_batch.SectionBatch` of its style (all
but ``"wire"`` outlines, which stay one drawable each) into
one shared vertex array, which the frame carries as one
:class:`~across_dimensions.game.frame.TriangleBatch` (one draw call per style,
whatever the number of entities). Entities whose bounding sphere is outside a
generous view frustum are not sliced at all.

The triangles are exactly those :func:`core.section.cross_section` gives for
each entity, less those of a changing entity that clearly face away from the
eye: the batches are drawn with inner faces skipped, so the renderer would skip
them too (tests compare the frames pixel by pixel).

The ghost layers' batches take turns: each is cut again every other frame, ana layers on one,
kata layers on the next, unless the player moved along w or the things in it changed; in between
it shows what it cut a frame before. Animated things (enemies) cut again for their ghosts were
two thirds of their frame's slicing, and a translucent, patterned ghost a frame behind the solid
it shadows (a few centimetres at a walk, at 60 Hz) does not show.

The batches' kernels run last, back to back (:meth:`EntitySections.flush`, which
``Game.frame`` calls after every system's draw and :meth:`~EntitySections.has_section`
before it answers): Python right after a large kernel call runs with cold caches, so
the frame's Python goes first.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..core.mesh import TetMesh4
from ..core.section_batch import SectionBatch, pool_part
from ..core.transform import translation
from .frame import WIDEST_VIEW, Drawable, Frame, TriangleBatch

#: Styles whose vertex colour alpha carries the thing's w offset (the renderer's w cue:
#: opaque, so alpha is free): see :func:`w_offset`.
W_CUED = ("solid", "glow")
#: Column of the colour's alpha in a batch row (position 3, normal 3, colour 4).
ALPHA = 9


def w_offset(mesh, model: np.ndarray, camera: np.ndarray) -> float:
    """Where the slice cuts a thing along the slice's normal: 0 mid-way through its extent
    that way, -1 or 1 at its ends (the renderer's w cue; + when the thing lies ana). A batch
    writes the same into its rows' alpha itself (``SectionBatch.update(..., w_cue=True)``).

    ``camera`` is the slice's camera-to-world pose ``(5, 5)`` (its ``w = 0`` hyperplane is the
    slice). The extent is the posed mesh's, so a turning thing's changes."""
    row = np.linalg.solve(np.asarray(camera, np.float64), np.asarray(model, np.float64))[3]  # camera space
    ws = mesh.vertices @ row[:4].astype(np.float32) + np.float32(row[4])
    lo, hi = float(ws.min()), float(ws.max())
    half = 0.5 * (hi - lo)
    return 0.5 * (lo + hi) / half if half > 0.0 else 0.0


def kept_meshes(state) -> list[TetMesh4]:
    """The meshes a system's state (a dataclass, or None) holds in its fields, directly or as a
    dict's values: those its entities spawned later are drawn with."""
    if state is None or not dataclasses.is_dataclass(state):
        return []
    out = []
    for f in dataclasses.fields(state):
        value = getattr(state, f.name)
        values = value.values() if isinstance(value, dict) else (value,)
        out += [v for v in values if isinstance(v, TetMesh4)]
    return out


def view_planes(camera, aspect: float = WIDEST_VIEW) -> np.ndarray:
    """The six planes ``(6, 4) float64`` of ``camera``'s view at ``aspect`` (inside: ``n . x + d >= 0``)."""
    m = camera.projection_matrix(aspect) @ camera.view_matrix()
    return np.array([m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2], m[3] - m[2]])


class EntitySections:
    """Per-style section batches of a game's entities, kept from frame to frame.

    Entities that neither moved nor left the view keep their triangles in the
    batch (neither re-sliced nor re-uploaded).
    """

    def __init__(self):
        self.batches: dict[str, SectionBatch] = {}
        self.ghost_batches: dict[str, SectionBatch] = {}  # per ghost layer (its tag)
        self._ghost_frame = 0  # frames the ghost layers were asked for (see begin_ghosts)
        self._ghost_cut: dict[str, tuple] = {}  # tag -> (w, ids) of its batch's last cut
        self._sliced: dict[int, bool] = {}  # entity id -> its section is non-empty (or, culled by view: reaches w)
        self._planes: tuple = (None, None)  # (camera key, its view planes)
        self._names: dict = {}  # member name prefix -> (ids, their names)
        # What flush slices and adds: (frame, batch, key, look, noted: has_section answers for its entities)
        self._pending: list = []

    @staticmethod
    def prepare(entities, states=()) -> None:
        """Make what the batches need of every mesh an entity may be drawn with now (at a
        level's start) rather than on the frame that first cuts it: 20-30 ms for an enemy's
        body or the gun's first bullet (a 120-cell), a dropped frame.

        Parameters
        ----------
        entities : iterable of Entity
            Those of the level now.
        states : iterable of (str, object), optional
            The systems' states (``game.states``): the meshes they keep to spawn later (the
            arsenal's bullet, the hive's shots; see :func:`kept_meshes`) are made ready too.
        """
        meshes = {id(e.mesh): e.mesh for e in entities if e.mesh is not None}
        for _, state in states:
            meshes.update((id(m), m) for m in kept_meshes(state))
        for mesh in meshes.values():
            pool_part(mesh)

    def draw(self, frame: Frame, entities, models, camera: np.ndarray, sections) -> None:
        """Slice ``entities`` (placed by ``models``) by the slice whose camera-to-world pose is
        ``camera`` (``(5, 5)``; ``translation((0, 0, 0, w))`` for the plain slice at ``w``): one
        batch per style, added to ``frame`` by :meth:`flush`.

        ``"wire"`` entities (outlines) are drawn one drawable each, sliced through
        ``sections`` (a :class:`~across_dimensions.world.scene.SectionCache`): the
        renderer derives their edges per mesh.
        """
        planes = self.view_planes(frame.camera)
        by_style: dict[str, list] = {}
        for i, e in enumerate(entities):
            by_style.setdefault(e.style, []).append(i)
        wires = [(entities[i], models[i]) for i in by_style.pop("wire", [])]
        for style in [s for s in self.batches if s not in by_style]:
            del self.batches[style]  # nothing of this style left: free its arrays
        self._sliced = {}
        sections.keep("draw:", {f"draw:{e.id}" for e, _ in wires})
        for e, m in wires:
            tri, rev = sections.section(f"draw:{e.id}", e.mesh, m, camera)
            frame.drawables.append(Drawable(f"entity:{e.id}", rev, tri, style="wire"))
            self._sliced[e.id] = not tri.is_empty
        for style, rows in by_style.items():
            batch = self.batches.get(style)
            if batch is None:
                batch = self.batches[style] = SectionBatch()
            ids = [entities[i].id for i in rows]
            meshes, eye = [entities[i].mesh for i in rows], frame.camera.position
            batch.update(ids, meshes, models[rows], camera, planes, w_cue=style in W_CUED, eye=eye, defer=True)
            look = {"style": style, "members": self._members("entity:", ids), "w_cue": style in W_CUED}
            self._pending.append((frame, batch, f"entities:{style}", look, True))

    def flush(self) -> None:
        """Slice what :meth:`draw` and :meth:`ghost_layer` left, batch after batch, and add their
        triangle batches to their frames in the order they were asked for."""
        pending, self._pending = self._pending, []
        for _, batch, _, _, _ in pending:
            batch.finish()
        for frame, batch, key, look, noted in pending:
            if noted:
                self._note_sliced(batch)
            frame.batches.append(
                TriangleBatch(key, batch.revision, batch.vertices, changed_from=batch.changed_from,
                              outside_only=True, **look)
            )  # fmt: skip

    def _note_sliced(self, batch: SectionBatch) -> None:
        """Record which of the batch's entities have a section (all at once: per-entity Python is
        what the batch avoids)."""
        keys = batch.instances()[0]
        self._sliced.update(zip(keys, (batch.cut_counts > 0).tolist()))
        self._sliced.update(dict.fromkeys(batch.view_culled, True))

    def note_reaching(self, entities, models: np.ndarray, w: float) -> None:
        """Entities in the view left out of this frame's slicing though their reach spans the
        slice (hidden behind a box; posed by ``models (k, 5, 5)``, the slice at ``w``
        axis-aligned): :meth:`has_section` says whether the slice passes strictly between their
        lowest and highest vertex along w (for a connected surface, whether it has a section,
        as the radar needs)."""
        for e, m in zip(entities, models):
            ws = e.mesh.vertices @ m[3, :4] + m[3, 4]
            self._sliced[e.id] = bool(ws.min() < w < ws.max())

    def view_planes(self, camera) -> np.ndarray:
        """:func:`view_planes` of ``camera``, made once for the systems that draw one frame."""
        key = (tuple(np.asarray(camera.position, np.float64).tolist()), camera.yaw, camera.pitch,
               camera.fov_y_deg, camera.near, camera.far)  # fmt: skip
        if self._planes[0] != key:
            self._planes = (key, view_planes(camera))
        return self._planes[1]

    def ghost_layer(self, frame: Frame, layer, entities, models, planes: np.ndarray) -> None:
        """Slice ``entities`` (placed by ``models (k, 5, 5)``) by the plain slice at ``layer.w``
        into one ghost batch in the layer's tint, pattern and opacity (a
        :class:`~.systems.ghosts.Layer`), added to ``frame`` by :meth:`flush`; ``planes`` are the
        view's (:func:`view_planes`).

        On a frame that is not the layer's turn (see the module docstring) the batch keeps what it
        cut on the frame before, when that was at the same w and of the same entities."""
        tag = layer.tag
        batch = self.ghost_batches.get(tag)
        if batch is None:
            batch = self.ghost_batches[tag] = SectionBatch()
        ids = [e.id for e in entities]
        if not self._ghost_waits(tag, layer, ids):
            pose = translation((0.0, 0.0, 0.0, layer.w))
            batch.update(ids, [e.mesh for e in entities], models, pose, planes, eye=frame.camera.position, defer=True)
            self._ghost_cut[tag] = (layer.w, ids)
        look = {"style": "ghost", "tint": layer.tint, "pattern": layer.pattern, "opacity": layer.opacity}
        look["members"] = self._members(f"{tag}:entity:", ids)
        self._pending.append((frame, batch, f"{tag}:entities", look, False))

    def _ghost_waits(self, tag: str, layer, ids: list) -> bool:
        """May the layer's batch show its last cut this frame? Only off its turn (ana layers
        and kata layers in alternate frames: never more than a frame behind), and only a cut
        at the same w, of the same entities."""
        turn = (self._ghost_frame + (layer.side < 0)) % 2 == 0
        return not turn and self._ghost_cut.get(tag) == (layer.w, ids)

    def _members(self, prefix: str, ids: list) -> tuple:
        """``prefix + id`` of each of ``ids``, made again only when the ids change."""
        last = self._names.get(prefix)
        if last is None or last[0] != ids:
            last = self._names[prefix] = (ids, tuple(f"{prefix}{i}" for i in ids))
        return last[1]

    def begin_ghosts(self, tags) -> None:
        """Begin a frame's ghost layers (the ghosts system calls it once a frame, before
        :meth:`ghost_layer`): count the frame, for the layers' turns, and free the batches of
        layers not drawn in it."""
        self._ghost_frame += 1
        for tag in [t for t in self.ghost_batches if t not in tags]:
            del self.ghost_batches[tag]
            self._ghost_cut.pop(tag, None)

    def has_section(self, entity_id: int) -> bool:
        """Was the entity's section non-empty in the last frame drawn?

        For an entity outside the view (not sliced), whether its bounding sphere reaches the slice.
        """
        self.flush()
        return self._sliced.get(entity_id, False)
