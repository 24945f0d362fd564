"""Draws a :class:`~across_dimensions.game.frame.Frame` with moderngl.

The renderer only reads the frame: it never changes game state. It keeps one
set of GPU buffers per ``Drawable.key`` and re-uploads a mesh only when the
drawable's ``revision`` changes, so a static world costs no bus traffic and a
cross-section that changes every frame re-uses its buffers (they grow, never
shrink, while the key lives).

Styles
------
``"solid"``
    Opaque, lit: Lambert + hemisphere ambient + small Phong specular + rim,
    two-sided (the normal is flipped toward the eye).
``"floor"``
    Like solid, plus a procedural anti-aliased grid (1 m minor, 10 m major
    lines) on the world plane the surface faces. Added by the render package;
    the frame module documents only the other three.
``"ghost"``
    Translucent (alpha ~0.35 times the vertex alpha and the drawable's
    ``opacity``), lit like solid, drawn after all opaque geometry with depth
    writes off, drawables sorted back to front. A drawable's ``tint`` pulls its
    colour towards a hue and its ``pattern`` (:data:`GHOST_PATTERNS`) modulates
    the opacity in screen space, so the ghosts of the two sides of the slice
    differ in pattern as well as hue.
``"wire"``
    Unlit lines along the mesh's feature edges (edges between coplanar
    triangles, e.g. quad diagonals, are dropped), derived on upload.
``"glow"``
    Opaque and emissive, brightest at the silhouette, lightly fogged: things
    that are not scenery (crystals).

Looks
-----
:attr:`Renderer.look` is ``"scifi"`` (the game's look: panelled scenery, a sky dome
when ``Frame.sky`` is ``"dome"``, 4D cross-sections with a ``w_offset`` drawn as alien
matter banded by w) or ``"flat"`` (the plain look above); colours come from
:attr:`Renderer.palette` (see :mod:`.materials`).

There is no back-face culling: the view matrix contains a reflection (see
``CONVENTIONS.md``, "Axes and handedness"), so "front" winding flips; two-sided
lighting makes culling unnecessary for correctness.
"""

from __future__ import annotations

import time

import moderngl
import numpy as np

from ..game.frame import Drawable, Frame
from . import materials
from . import palette as w_cues
from .batch import DEPTH_FRAGMENT, DEPTH_VERTEX, BatchBuffers
from .context import RenderError, color_writes
from .gl_math import frustum_planes, mat4_bytes
from .hud import HudRenderer
from .mesh_cache import GpuMesh, MeshCache
from .near_first import faces_in_order, nearest_first
from .passes import PassProfile, RenderStats
from .programs import FrameUniforms, StylePrograms, set_uniform
from .radar import RadarRenderer
from .radar_yield import YIELD_ALPHA, interest_on_screen, radar_yields
from .sky import SkyRenderer, open_sky, open_triangles

STYLES = ("solid", "floor", "wire", "ghost", "glow")
#: Ghost patterns by name, as the shader's ``u_pattern`` codes.
GHOST_PATTERNS = {"": 0, "stripes": 1, "dots": 2}
_NO_TINT = (0.0, 0.0, 0.0, 0.0)


def flat_batch(tb) -> bool:
    """Whether a batch's vertices have no normals (see :class:`~..game.frame.TriangleBatch`): a
    frustum image's, the indexed kind, have none; a section's, three rows a triangle, have them."""
    return tb.faces is not None


#: A batch with more triangles than this is left out of the depth pre-pass (see
#: :meth:`Renderer._depth_prepass`): many small triangles draw faster without it, a
#: level's 4D things (hundreds) in front of its scenery faster with it.
PREPASS_MAX_TRIANGLES = 20_000


class _Cued:
    """A drawable with a w cue, as drawn: its program (``hyper`` for solids) and band scale."""

    __slots__ = ("key", "style", "w_offset", "band_scale", "tint", "pattern", "opacity", "outside_only")

    def __init__(self, d: Drawable, style: str, band_scale: float):
        self.key, self.style, self.w_offset, self.band_scale = d.key, style, d.w_offset, band_scale
        self.tint, self.pattern, self.opacity, self.outside_only = d.tint, d.pattern, d.opacity, d.outside_only


class Renderer:
    """Draws frames into whatever framebuffer is bound.

    Parameters
    ----------
    ctx : moderngl.Context
        From :func:`~across_dimensions.render.context.create_offscreen_context`
        or :func:`~across_dimensions.render.context.wrap_current_context`.
    fog_density : float
        Exponential-squared fog, per world unit: at distance ``d`` the fog
        fraction is ``1 - exp(-(d * fog_density)**2)`` (0.018: ~7% at 15 m,
        ~55% at 50 m, ~96% at 100 m).
    ghost_alpha : float
        Opacity of ``"ghost"`` drawables (times the vertex alpha).
    look : str
        ``"scifi"`` or ``"flat"`` (:data:`.materials.LOOKS`); may be changed between draws.

    Attributes
    ----------
    palette : dict
        Named colours of the sci-fi look (:func:`.materials.palette`); replace it to
        switch palettes (a colour-blind-safe one, a level's mood).
    stats : RenderStats
    hud : HudRenderer
    radar : RadarRenderer

    Notes
    -----
    Several views can be drawn in one frame (a split screen, a mirror): give each its own
    ``view`` name in :meth:`draw`. A mesh is released when no view's latest draw used its key, so
    one view never evicts another's meshes; a view not drawn for :attr:`VIEW_TTL` draws is
    forgotten (or call :meth:`forget_view`). Keys name one mesh across all views.
    """

    #: Draws (of any view) after which a view that was not drawn again stops holding its meshes.
    VIEW_TTL = 16

    def __init__(
        self, ctx: moderngl.Context, fog_density: float = 0.018, ghost_alpha: float = 0.35, look: str = "scifi"
    ):
        self.ctx = ctx
        self.fog_density = float(fog_density)
        self.ghost_alpha = float(ghost_alpha)
        self.stats = RenderStats()
        self.meshes = MeshCache(ctx, self.stats)
        self.palette = materials.palette()
        self.look = look
        self.programs = StylePrograms(ctx)
        self.programs.use(look, self.palette)
        self._sky: SkyRenderer | None = None
        self._view_mirrored = True  # set per frame from the camera (see draw)
        self._depth_prog: moderngl.Program | None = None
        #: Lay down the opaque drawables' depth before shading them (see :meth:`_depth_prepass`).
        self.depth_prepass = True
        self.hud = HudRenderer(ctx)
        self.radar = RadarRenderer(ctx)
        self.batches = BatchBuffers(ctx, self._programs)
        self._batch_views: dict[str, tuple[int, set[str]]] = {}  # view -> (draw number, batch keys)
        self._views: dict[str, tuple[int, set[str]]] = {}  # view -> (draw number, keys it used)
        #: When set, each pass is finished and charged to it (:mod:`.passes`; the benchmark's breakdown).
        self.profile: PassProfile | None = None

    def set_palette(self, name: str) -> None:
        """Switch the named colours: ``"default"``, ``"colour_blind"`` (ana and kata, crystals
        and trims told apart by lightness too, never by red and green alone) or
        ``"high_contrast"``; the overlays' w cues (:mod:`.palette`) follow."""
        self.palette = materials.palette("colorblind" if name in ("colour_blind", "colorblind") else name)
        w_cues.use("colour_blind" if name == "colorblind" else name)  # the overlays' w cues follow

    @property
    def _programs(self) -> dict[str, moderngl.Program]:
        """The style programs of the current look and palette (:attr:`StylePrograms.current`)."""
        return self.programs.current

    # ----------------------------------------------------------------- caching
    def cached_keys(self) -> list[str]:
        """Keys that currently hold GPU buffers."""
        return self.meshes.keys()

    def gpu_bytes(self) -> int:
        """Bytes of every vertex, index and edge buffer this renderer holds for meshes and batches."""
        return self.batches.bytes + self.meshes.bytes

    def release(self) -> None:
        """Free every GPU object this renderer made."""
        self.meshes.release()
        self.programs.release()
        if self._sky is not None:
            self._sky.release()
            self._sky = None
        if self._depth_prog is not None:
            self._depth_prog.release()
            self._depth_prog = None
        self.hud.release()
        self.radar.release()
        self.batches.release()

    def forget_meshes(self) -> None:
        """Release every cached mesh, so the next frame uploads what it draws anew.

        Call it when the world behind the drawables is replaced (a new level, a
        new game): its keys and revisions start again (``static``, revision 0),
        so a cached mesh of the old world would stand in for the new one.
        """
        self.meshes.release()
        self._views.clear()
        self.batches.sync([])
        self._batch_views.clear()

    def forget_view(self, view: str) -> None:
        """Stop holding the meshes only ``view`` used (they are released at the next draw)."""
        self._views.pop(view, None)

    # ----------------------------------------------------------------- drawing
    def draw(
        self, frame: Frame, viewport: tuple[int, int, int, int] | None = None, hud: bool = True, view: str = "main"
    ) -> None:
        """Draw ``frame`` into the currently bound framebuffer.

        Parameters
        ----------
        frame : Frame
            Read only.
        viewport : (x, y, w, h) ints, optional
            Pixels, OpenGL convention (origin bottom-left). Defaults to the
            whole bound framebuffer. Only this rectangle is cleared and drawn.
        hud : bool
            Also draw ``frame.hud`` on top, and ``frame.radar`` (when not None) in its corner.
        view : str
            Which view this is; meshes used by other views' latest draws stay cached.

        Raises
        ------
        RenderError
            No framebuffer is bound, a drawable has an unknown style, a
            duplicate key, or a malformed mesh.
        """
        fbo = self.ctx.fbo
        if fbo is None:
            raise RenderError("no framebuffer bound: call Offscreen.use() (or ctx.screen.use()) before Renderer.draw")
        if viewport is None:
            viewport = (0, 0, *fbo.size)
        viewport = tuple(int(x) for x in viewport)
        _, _, w, h = viewport
        if w <= 0 or h <= 0:
            return
        self.programs.use(self.look, self.palette)
        scifi = self.look == "scifi"
        st = self.stats
        st.frames += 1
        st.draw_calls = st.depth_calls = st.triangles = st.lines = st.upload_bytes = st.culled = 0

        self.ctx.viewport = viewport
        sky = tuple(float(x) for x in frame.sky_color)
        dome = scifi and frame.sky == "dome"
        # The dome is drawn only where no box may cover the view (game/occlusion.py), and not at
        # all when boxes cover all of it: there even its depth test costs on llvmpipe.
        sky_corners = open_triangles(open_sky(frame, w, h), w / h) if dome else None
        sky_drawn = dome and len(sky_corners) > 0
        self._clear(fbo, viewport, sky, sky_drawn)

        cam = frame.camera
        view_mat = cam.view_matrix()
        view_proj = cam.projection_matrix(w / h) @ view_mat
        eye = np.asarray(cam.position, np.float64)
        light = np.asarray(frame.light_dir, np.float64)
        light = light / max(np.linalg.norm(light), 1e-12)

        seen, opaque, wires, ghosts = self._bucket(frame, frustum_planes(view_proj), eye)
        self._keep_views_meshes(view, seen)
        self._sync_batches(frame, view)

        # Outer faces are counter-clockwise seen from outside; on screen they stay so unless
        # the view (the camera's is a mirror: x right, z forward) and a model mirror space.
        self._view_mirrored = bool(np.linalg.det(view_mat[:3, :3]) < 0.0)
        vp_bytes = mat4_bytes(view_proj)
        fog, alpha = self.fog_density, self.ghost_alpha
        uniforms = FrameUniforms(float(frame.time), vp_bytes, tuple(eye), tuple(light), sky, dome, fog, alpha)
        self.programs.set_frame_uniforms(uniforms)
        self._lap("setup")

        self._draw_opaque(frame, opaque, wires, vp_bytes, eye)
        if sky_drawn:
            # After the opaque scene: the sky shades only the pixels nothing covered.
            if self._sky is None:
                self._sky = SkyRenderer(self.ctx)
            st.draw_calls += self._sky.draw(view_proj, eye, light, self.palette, self._set, sky_corners)
            self._lap("sky")
        self._draw_ghosts(frame, ghosts, vp_bytes)
        self._lap("ghosts")
        if hud:
            self.draw_overlay(frame, viewport)

    def _clear(self, fbo, viewport: tuple, sky: tuple, sky_drawn: bool) -> None:
        """Clear ``viewport`` of ``fbo``: its depth to the far plane, its colour to ``sky``, unless
        the dome will be drawn (``sky_drawn``). The dome shades every pixel the scene leaves (all
        those still at the far depth), so the colour clear would write the whole view for nothing:
        on llvmpipe about 1.7 ms of CPU at 1280x720."""
        fbo.depth_mask = True  # glClear honours the depth mask
        if sky_drawn:
            color_writes(fbo, False)
        self.ctx.clear(sky[0], sky[1], sky[2], 1.0, depth=1.0, viewport=viewport)
        if sky_drawn:
            color_writes(fbo, True)

    def _bucket(self, frame: Frame, planes: np.ndarray, eye: np.ndarray) -> tuple[set, list, list, list]:
        """Upload what changed, cull what is outside the view's ``planes (6, 4)``, and bucket the
        rest by pass: the keys seen, then ``(distance², drawable, GpuMesh, model)`` lists of the
        opaque, wire and ghost drawables."""
        seen: set[str] = set()
        opaque, wires, ghosts = [], [], []
        for d in frame.drawables:
            if d.style not in STYLES:
                raise RenderError(f"drawable {d.key!r}: unknown style {d.style!r}; expected one of {', '.join(STYLES)}")
            if d.style == "ghost" and d.pattern not in GHOST_PATTERNS:
                raise RenderError(f"drawable {d.key!r}: unknown ghost pattern {d.pattern!r}; expected stripes or dots")
            if d.key in seen:
                raise RenderError(f"two drawables share the key {d.key!r}; keys must be unique within a frame")
            seen.add(d.key)
            gm = self.meshes.sync(d)
            if gm.n_indices == 0:
                continue
            model = np.asarray(d.model, np.float64)
            lin = model[:3, :3]
            center = lin @ gm.center + model[:3, 3]
            # Bounding sphere culling: llvmpipe pays for every triangle it sets
            # up, even off-screen ones. The radius scales by the largest axis stretch.
            radius = gm.radius * float(np.linalg.norm(lin, axis=0).max())
            if (planes[:, :3] @ center + planes[:, 3] < -radius).any():
                self.stats.culled += 1
                continue
            dist2 = float(np.sum((center - eye) ** 2))
            if d.w_offset is not None:
                # The w cue: which side of the slice and how far, and the drawable's size for band spacing.
                d = _Cued(d, "hyper" if d.style == "solid" else d.style, materials.band_scale(radius))
            bucket = ghosts if d.style == "ghost" else wires if d.style == "wire" else opaque
            bucket.append((dist2, d, gm, model))
        return seen, opaque, wires, ghosts

    def _keep_views_meshes(self, view: str, seen: set[str]) -> None:
        """Note the keys ``view`` drew; release the meshes whose key left every view."""
        st = self.stats
        self._views[view] = (st.frames, seen)
        for name in [v for v, (n, _) in self._views.items() if st.frames - n > self.VIEW_TTL]:
            del self._views[name]
        self.meshes.keep_only(set().union(*(keys for _, keys in self._views.values())))
        st.cached = len(self.meshes.meshes)

    def _sync_batches(self, frame: Frame, view: str) -> None:
        """Check the frame's batches and upload them, keeping those other views still draw."""
        st = self.stats
        for tb in frame.batches:
            if tb.style not in STYLES or tb.style == "wire":
                raise RenderError(
                    f"batch {tb.key!r}: style {tb.style!r} cannot be batched; expected solid, floor, ghost or glow"
                )
            if tb.style == "ghost" and tb.pattern not in GHOST_PATTERNS:
                raise RenderError(f"batch {tb.key!r}: unknown ghost pattern {tb.pattern!r}; expected stripes or dots")
        self._batch_views[view] = (st.frames, {tb.key for tb in frame.batches})
        for name in [v for v, (n, _) in self._batch_views.items() if st.frames - n > self.VIEW_TTL]:
            del self._batch_views[name]
        t0 = time.thread_time()
        self.batches.sync(frame.batches, keep=set().union(*(k for _, k in self._batch_views.values())))
        st.batch_sync_cpu_ms = 1e3 * (time.thread_time() - t0)
        st.upload_bytes += self.batches.upload_bytes

    def _draw_opaque(self, frame: Frame, opaque: list, wires: list, vp_bytes: bytes, eye: np.ndarray) -> None:
        """The opaque drawables (the scenery's pieces nearest first, then the rest front to
        back), the frame's solid batches and the wires."""
        ctx = self.ctx
        scifi = self.look == "scifi"
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE | moderngl.BLEND)
        ctx.depth_func = "<"
        # The scenery in pieces (Drawable.parts), in the frame's order, each drawn nearest piece
        # first: the depth test rejects what they hide before it is shaded, with no pre-pass
        # (see near_first.py). The rest front to back, for the same reason, as whole drawables.
        pieces = [o for o in opaque if o[2].parts is not None]
        for _, _d, gm, model in pieces:
            self._order_pieces(gm, model, eye)
        rest = sorted((o for o in opaque if o[2].parts is None), key=lambda o: o[0])
        solid_batches = [tb for tb in frame.batches if tb.style != "ghost"]
        # The 4D things (the rest and the batches) may stand in front of the scenery: their depth
        # laid down first keeps the walls they hide from being shaded. Without scenery there is
        # nothing to keep: batches alone are closed surfaces drawn outside only, with little to
        # hide from each other (a hundred 120-cells drew 10-30 % slower with a pre-pass).
        prepass = self.depth_prepass and bool(opaque) and bool(rest or solid_batches)
        if prepass:
            self._depth_prepass(rest, solid_batches, vp_bytes)
            self._lap("prepass")
        # Two pieces' faces in one plane (a box flush with a floor) go to the one drawn last, with
        # or without a pre-pass, as they did when the whole scenery was in it.
        ctx.depth_func = "<="
        for _, d, gm, model in pieces:
            self._draw_mesh(d.style, gm, model, moderngl.TRIANGLES, gm.n_indices, d)
            self._lap("scenery")
        ctx.depth_func = "<=" if prepass else "<"
        for _, d, gm, model in rest:
            self._draw_mesh(d.style, gm, model, moderngl.TRIANGLES, gm.n_indices, d)
            self._lap("matter" if isinstance(d, _Cued) else "scenery")
        for tb in solid_batches:
            self._draw_batch(tb, vp_bytes, scifi)
            if prepass:
                ctx.depth_func = "<="  # a batch with its own pre-pass sets "<" back after it
        self._lap("matter")
        if prepass:
            ctx.depth_func = "<"
        for _, _d, gm, model in wires:
            n = self.meshes.edges(gm)
            if n:
                self._draw_mesh("wire", gm, model, moderngl.LINES, n)
        self._lap("wires")

    def _draw_ghosts(self, frame: Frame, ghosts: list, vp_bytes: bytes) -> None:
        """The ghost drawables and batches, back to front per drawable; depth test on (solids
        hide ghosts) but no depth writes (ghosts don't hide each other or what follows)."""
        ghost_batches = [tb for tb in frame.batches if tb.style == "ghost"]
        if not (ghosts or ghost_batches):
            return
        ctx, fbo = self.ctx, self.ctx.fbo
        ghosts.sort(key=lambda g: -g[0])
        ctx.enable(moderngl.BLEND)
        # Keep destination alpha at 1 so screenshots stay opaque.
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
        fbo.depth_mask = False
        for _, d, gm, model in ghosts:
            _, prog = self.programs.get("ghost", gm.flat_normals)
            self._set(prog, "u_tint", tuple(float(x) for x in (w_cues.ghost_tint(d.tint, d.pattern) or _NO_TINT)))
            self._set(prog, "u_pattern", GHOST_PATTERNS[d.pattern])
            self._set(prog, "u_opacity", max(0.0, float(d.opacity)))
            self._draw_mesh("ghost", gm, model, moderngl.TRIANGLES, gm.n_indices, d)
        for tb in ghost_batches:
            _, prog = self.programs.get("ghost", flat_batch(tb))
            self._set(prog, "u_tint", tuple(float(x) for x in (w_cues.ghost_tint(tb.tint, tb.pattern) or _NO_TINT)))
            self._set(prog, "u_pattern", GHOST_PATTERNS[tb.pattern])
            self._set(prog, "u_opacity", max(0.0, float(tb.opacity)))
            self._draw_batch(tb, vp_bytes, self.look == "scifi")
        fbo.depth_mask = True
        ctx.disable(moderngl.BLEND)

    def draw_overlay(self, frame: Frame, viewport: tuple[int, int, int, int], radar: bool = True) -> None:
        """Draw ``frame``'s radar (when not None and ``radar``) and HUD over the bound framebuffer.

        :meth:`draw` does it with ``hud=True``; a scene drawn at a lower render scale and
        upscaled gets its HUD at the window's full resolution, and its radar before the
        upscale (:meth:`draw_radar`, then ``radar=False`` here).
        """
        viewport = tuple(int(x) for x in viewport)
        if radar:
            self.draw_radar(frame, viewport)
        # A radar giving way to what lies behind it (see radar_yield) goes without its labels;
        # the gauges give way the same.
        labels = None if frame.radar is None or radar_yields(frame, *viewport[2:]) else frame.radar
        self.hud.draw(frame.hud, viewport, labels, interest_on_screen(frame, *viewport[2:]))

    def draw_radar(self, frame: Frame, viewport: tuple[int, int, int, int], scale: float = 1.0) -> None:
        """Draw ``frame``'s radar (when not None) in its corner of the window's ``viewport``.

        With ``scale`` below 1 the bound framebuffer is the scene's at that render scale: the
        radar is a 3D thing like the scene, and drawn there (before the upscale) it shades a
        quarter of the pixels at scale 0.5, which on llvmpipe is about a millisecond of CPU a
        frame. Its labels stay sharp: the HUD draws them at full size.
        """
        if frame.radar is not None:
            viewport = tuple(int(x) for x in viewport)
            alpha = YIELD_ALPHA if radar_yields(frame, *viewport[2:]) else 1.0
            self.radar.draw(frame.radar, viewport, scale, alpha)
            self.stats.draw_calls += self.radar.draw_calls
            self._lap("radar")

    def _order_pieces(self, gm: GpuMesh, model: np.ndarray, eye: np.ndarray) -> None:
        """Hold ``gm``'s pieces nearest ``eye`` (world) first in its index buffer, rewritten
        only when that order changes (see :mod:`.near_first`)."""
        try:
            local = np.linalg.solve(model[:3, :3], eye - model[:3, 3])
        except np.linalg.LinAlgError:
            return  # a flattened model: any order will do
        order = nearest_first(gm.piece_boxes, local)
        if gm.piece_order is not None and np.array_equal(order, gm.piece_order):
            return
        gm.piece_order = order
        faces = gm.piece_faces[faces_in_order(gm.parts, order)]
        gm.ibo.write(faces.tobytes())
        self.stats.upload_bytes += faces.nbytes

    def _depth_prepass(self, opaque: list, batches: list, vp_bytes: bytes) -> None:
        """Lay down the depth of ``opaque`` (the drawables not drawn in pieces: sections of 4D
        worlds) and of the 4D things' ``batches`` with an empty shader, then let the shading pass
        (``<=``) colour each pixel once: a 4D thing in front of the scenery, drawn after it,
        would otherwise be shaded over shaded walls. Batches of many small triangles
        (:data:`PREPASS_MAX_TRIANGLES`) are left out: there llvmpipe's cost is setting
        triangles up, which a pre-pass would pay twice."""
        ctx, fbo = self.ctx, self.ctx.fbo
        if self._depth_prog is None:
            self._depth_prog = ctx.program(vertex_shader=DEPTH_VERTEX, fragment_shader=DEPTH_FRAGMENT)
        prog = self._depth_prog
        prog["u_view_proj"].write(vp_bytes)
        color_writes(fbo, False)
        for _, d, gm, model in opaque:
            prog["u_model"].write(mat4_bytes(model))
            vao = gm.vaos.get("depth")
            if vao is None:
                vao = gm.vaos["depth"] = ctx.vertex_array(
                    prog, [(gm.vbo, "3f 12x 16x", "in_pos")], index_buffer=gm.ibo, index_element_size=4
                )
            self._cull_inner(d.outside_only, model)
            vao.render(moderngl.TRIANGLES, vertices=gm.n_indices)
            self.stats.depth_calls += 1
        for tb in batches:
            # Sections only: frustum images (indexed) already draw just their outline faces.
            if not tb.prepass and tb.faces is None and self.batches.triangles(tb) <= PREPASS_MAX_TRIANGLES:
                self._cull_inner(tb.outside_only)
                self.stats.depth_calls += self.batches.draw_depth(tb, vp_bytes)
        self._cull_inner(False)
        color_writes(fbo, True)
        ctx.depth_func = "<="

    def _cull_inner(self, outside_only: bool, model: np.ndarray | None = None) -> None:
        """Skip inner faces of closed surfaces (see :attr:`Drawable.outside_only`), or draw both sides."""
        if not outside_only:
            self.ctx.disable(moderngl.CULL_FACE)
            return
        mirrored = self._view_mirrored != (model is not None and np.linalg.det(model[:3, :3]) < 0.0)
        self.ctx.front_face = "cw" if mirrored else "ccw"
        self.ctx.enable(moderngl.CULL_FACE)

    def _draw_batch(self, tb, vp_bytes: bytes, scifi: bool) -> None:
        # Batches hold many 4D things: in the sci-fi look their solids are 4D matter ("hyper"),
        # and each vertex's colour alpha carries its thing's w offset (the w cue; see
        # game/entity_sections.py), since one uniform cannot hold one per thing.
        cued = scifi and tb.w_cue and tb.style in ("solid", "glow")
        name, prog = self.programs.get("hyper" if cued and tb.style == "solid" else tb.style, flat_batch(tb))
        if cued:
            self._set(prog, "u_w_from_alpha", 1.0)
        self.batches.programs = self._programs
        self._cull_inner(tb.outside_only)
        calls, tris, lines = self.batches.draw(tb, vp_bytes, name)
        self._cull_inner(False)
        if cued:
            self._set(prog, "u_w_from_alpha", 0.0)
        self.stats.draw_calls += calls
        self.stats.triangles += tris
        self.stats.lines += lines

    def _draw_mesh(self, style: str, gm: GpuMesh, model: np.ndarray, mode: int, count: int, d=None) -> None:
        style, prog = self.programs.get(style, gm.flat_normals, gm.faceted)
        self._set(prog, "u_model", mat4_bytes(model))
        if isinstance(d, _Cued):
            self._set(prog, "u_w_offset", float(d.w_offset))
            self._set(prog, "u_band_scale", d.band_scale)
        lin = model[:3, :3]
        try:
            nm = np.linalg.inv(lin).T
        except np.linalg.LinAlgError:
            nm = lin  # degenerate model (flattened): any normal will do
        # mat3 uniform: 9 floats, column-major.
        self._set(prog, "u_normal_mat", np.ascontiguousarray(nm.T, np.float32).tobytes())
        culled = d is not None and d.outside_only and mode == moderngl.TRIANGLES
        if culled:
            self._cull_inner(True, model)
        self.meshes.vao(gm, prog, self.look, style).render(mode, vertices=count)
        if culled:
            self._cull_inner(False)
        if isinstance(d, _Cued):
            self._set(prog, "u_w_offset", 0.0)  # the next drawable of this program may have no cue
        self.stats.draw_calls += 1
        if mode == moderngl.LINES:
            self.stats.lines += count // 2
        else:
            self.stats.triangles += count // 3

    def _lap(self, name: str) -> None:
        """End the pass ``name`` for the profile, when one is set (see :mod:`.passes`)."""
        if self.profile is not None:
            self.profile.mark(name)

    _set = staticmethod(set_uniform)
