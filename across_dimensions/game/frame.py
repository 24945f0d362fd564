"""What one rendered frame shows, as plain data.

The simulation fills a :class:`Frame`; ``render`` draws it. Nothing here knows
about OpenGL or windows, so the same frame can be drawn on screen, offscreen
for a test, or not at all in a headless replay.

Coordinates are 3D world coordinates, the space the cross-section hyperplane
is mapped to by the synced camera (axes and handedness: ``CONVENTIONS.md``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.mesh import TriMesh3

#: Widest window (width / height) a frame is made for: the game does not know the window's, so
#: what it culls from the view, and where it leaves the sky out, holds for any view up to this
#: wide. The renderer draws a wider window's sky everywhere.
WIDEST_VIEW = 3.0


@dataclass
class Camera3:
    """A 3D perspective camera, and the w of the slice it stands in.

    Parameters
    ----------
    position : (3,) float64
    yaw : float
        Radians; 0 looks along +z, positive turns towards +x.
    pitch : float
        Radians; positive looks up.
    fov_y_deg : float
        Vertical field of view.
    near, far : float
    w : float
        The eye's w: the slice the camera looks at, drawn ``alpha`` of the way between
        ticks as ``position`` is. Every 4D thing a frame shows is cut at this w.
    """

    position: np.ndarray
    yaw: float = 0.0
    pitch: float = 0.0
    fov_y_deg: float = 75.0
    near: float = 0.05
    far: float = 500.0
    w: float = 0.0

    @property
    def eye4(self) -> np.ndarray:
        """The 4D eye ``(4,) float64``: ``position`` and ``w``."""
        return np.append(np.asarray(self.position, dtype=np.float64), self.w)

    def forward(self) -> np.ndarray:
        """Unit view direction ``(3,) float64``."""
        cp = np.cos(self.pitch)
        return np.array([np.sin(self.yaw) * cp, np.sin(self.pitch), np.cos(self.yaw) * cp])

    def axes(self) -> np.ndarray:
        """The eye's axes in world coordinates ``(3, 3) float64``, unit: the rows are the
        screen's x (``r``), its y (``u``) and the view direction (``f``)."""
        fx, fy, fz = self.forward().tolist()
        # r = up x f with up = +y, then u = f x r: the cross products written out (numpy's
        # np.cross costs more than the rest of the frame's camera work).
        nr = np.sqrt(fz * fz + fx * fx)
        rx, rz = (fz / nr, -fx / nr) if nr > 1e-9 else (np.cos(self.yaw), -np.sin(self.yaw))
        return np.array([[rx, 0.0, rz], [fy * rz, fz * rx - fx * rz, -fy * rx], [fx, fy, fz]])

    def view_matrix(self) -> np.ndarray:
        """World-to-eye ``(4, 4) float64`` in OpenGL's convention (eye looks down -z)."""
        # The world is left-handed and OpenGL's eye space right-handed, so this
        # matrix includes a reflection (det -1); see CONVENTIONS.md.
        m = np.eye(4)
        m[:3, :3] = self.axes()
        m[2, :3] *= -1.0
        m[:3, 3] = -m[:3, :3] @ np.asarray(self.position, dtype=np.float64)
        return m

    def projection_matrix(self, aspect: float) -> np.ndarray:
        """OpenGL perspective ``(4, 4) float64`` for ``aspect = width / height``."""
        t = 1.0 / np.tan(np.radians(self.fov_y_deg) / 2.0)
        n, f = self.near, self.far
        m = np.zeros((4, 4))
        m[0, 0] = t / aspect
        m[1, 1] = t
        m[2, 2] = (f + n) / (n - f)
        m[2, 3] = 2 * f * n / (n - f)
        m[3, 2] = -1.0
        return m


@dataclass
class Drawable:
    """One mesh to draw.

    Parameters
    ----------
    key : str
        Stable identity; the renderer keeps one GPU buffer per key.
    revision : int
        Bumped whenever ``mesh`` changes; the renderer re-uploads only then.
    mesh : TriMesh3
        In world coordinates (cross-sections) or in the 3D space of a frustum
        projection placed by ``model``.
    model : (4, 4) float64
        Mesh-to-world transform.
    style : str
        ``"solid"`` lit opaque, ``"ghost"`` translucent (previews, frustum
        views), ``"wire"`` edges only, ``"glow"`` emissive (crystals).
    tint : (4,) float or None
        Ghosts only: linear RGB the colour is pulled towards, and how far (the
        fourth number, 0 to 1). The w ghosts tint ana and kata differently.
    pattern : str
        Ghosts only: ``""`` plain, ``"stripes"`` or ``"dots"``, a screen-space
        pattern in the opacity so two kinds of ghost differ in more than hue.
    opacity : float
        Ghosts only: times the renderer's ghost opacity (fading, emphasis).
    w_offset : float or None
        4D things only (cross-sections of worlds and entities): where the slice cuts the thing
        along w, ``(w of its middle - w of the slice) / half its extent in w``, so 0 in the
        middle, positive when the thing lies ana (+w) of the slice, +-1 where it ends. The
        renderer draws it as 4D matter with bands that encode this (the w cue); None for 3D
        scenery.
    outside_only : bool
        The mesh is a closed surface wound counter-clockwise seen from outside (cross-sections
        of closed 4D meshes are): the renderer skips its inner faces, which from outside are
        always hidden behind outer ones. That halves the triangles a software rasterizer sets
        up and the pixels it shades twice; for ghosts it makes a translucent layer one film,
        not two, and a ghost around the player does not veil the whole view.
    parts : (k + 1,) int array or None
        Opaque scenery only: the mesh's faces in ``k`` runs, run ``i`` the faces
        ``parts[i]:parts[i + 1]`` of one piece (a box, a surface), ``parts[-1]`` their count.
        The renderer draws the pieces nearest the eye first, so that the depth test, not a
        depth pre-pass, keeps it from shading what lies behind; such drawables are drawn
        before the other opaque ones, in the frame's order.
    """

    key: str
    revision: int
    mesh: TriMesh3
    model: np.ndarray = field(default_factory=lambda: np.eye(4))
    style: str = "solid"
    tint: tuple | None = None
    pattern: str = ""
    opacity: float = 1.0
    w_offset: float | None = None  # 4D things: (w of the thing - w of the slice) / its half extent in w (the w cue)
    outside_only: bool = False
    parts: np.ndarray | None = None


@dataclass
class Hud:
    """Heads-up display state.

    Parameters
    ----------
    w, w_min, w_max : float
        The player's w and the level's allowed range (the w indicator).
    fps : float or None
        Shown when not None.
    paused : bool
    message : str
        A centred line (level complete, paused, no energy ...).
    crosshair : bool
    """

    w: float = 0.0
    w_min: float = -1.0
    w_max: float = 1.0
    fps: float | None = None
    paused: bool = False
    message: str = ""
    crosshair: bool = True
    energy: EnergyGauge | None = None
    weapon: WeaponPanel | None = None
    hit_marker: float = 0.0  # 1 right after a bullet hits a body or a target, fading to 0 (crosshair marks)
    hint: str = ""  # the level hint on screen (keys filled in), in its own panel at the top: never a message
    hint_label: str = ""  # the small line under it: which hint, and the key that dismisses it
    warning: str = ""  # one line at the bottom (settings problems: the details are in the log file)
    card: Card | None = None  # a teaching card drawn over the view (the flat being), or None
    health: HealthGauge | None = None  # the player's health bar (levels with enemies)
    damage_flash: float = 0.0  # 1 when the player is hit, fading to 0 (the view flashes red)
    damage_dir: float | None = None  # where the last hit came from: radians from straight ahead, + to the right
    labels: list = field(default_factory=list)  # ScreenLabel: text placed next to a thing on screen
    slice: SliceGauges | None = None  # the 4D camera's gauges, in levels with a [camera] table
    w_blocked: tuple = ()  # +1 and/or -1: a ghost layer ana / kata holds something solid where the player stands
    captions: list = field(default_factory=list)  # Caption: sounds made visible (a setting, off by default)


@dataclass(frozen=True)
class EnergyGauge:
    """The energy bar: crystal energy that pays for moving along w and other 4D actions.

    Parameters
    ----------
    value, maximum : float
        ``0 <= value <= maximum``; the bar shows ``value / maximum`` and the value as a number.
    flash : float
        1 right after a crystal is collected, fading to 0 (the bar flashes).
    empty : bool
        True while the player asked for something the bar cannot pay for (the bar says "NO ENERGY").
    costs : str
        What each 4D action of the level costs, one line over the bar ("W 4/UNIT  GUN 1 ..."),
        so the player knows before taking it; "" when nothing costs anything.
    spent : float
        Energy just spent, shown after the fill until it sinks in (the window's
        :class:`~across_dimensions.app.energy_trail.EnergyTrail`; 0 from the game).
    """

    value: float
    maximum: float
    flash: float = 0.0
    empty: bool = False
    costs: str = ""
    spent: float = 0.0


@dataclass(frozen=True)
class WeaponPanel:
    """The weapon panel: the weapon in hand, what it costs and when it is ready.

    Parameters
    ----------
    name : str
    slot, count : int
        Its number (from 1) and how many weapons the player has.
    cost : float
        Energy per use.
    cooldown : float
        Fraction of the cooldown still to run, 1 just after use, 0 when ready.
    flash : float
        1 on the tick it fired, fading to 0 (muzzle flash).
    refused : str
        A line shown while the last try failed ("NOT ENOUGH ENERGY"), else "".
    live : int
        Bullets in flight (the gun), or -1.
    ammo : int
        Rounds left for a gun that fires rounds, or -1 for a weapon paid in energy.
    """

    name: str
    slot: int
    count: int
    cost: float
    cooldown: float = 0.0
    flash: float = 0.0
    refused: str = ""
    live: int = -1
    ammo: int = -1


@dataclass(frozen=True)
class SliceGauges:
    """How the slice is turned, and what the 4D camera is doing (three small gauges).

    Parameters
    ----------
    angles : (float, float, float)
        The slice's x, y and z axes' angles towards w, degrees in [-180, 180]; 0 is the
        plain slice, a multiple of 90 an axis-aligned one.
    mode : str
        ``"synced"``, ``"frustum"`` or ``"returning"``.
    orbit : float
        The frustum camera's orbit angle, degrees.
    """

    angles: tuple
    mode: str = "synced"
    orbit: float = 0.0


#: Pin kinds the radar draws, each with its own head shape (never colour alone).
RADAR_KINDS = ("crystal", "body", "enemy", "bullet", "target", "camera_focus", "camera_eye", "object")


@dataclass(frozen=True)
class RadarPin:
    """One 4D entity on the holographic radar, in the radar's own frame.

    The radar is a disc in the player's x-z plane, centred on the player and turned with the
    player's yaw, so "ahead" is always the same direction on the disc.

    Parameters
    ----------
    kind : str
        One of :data:`RADAR_KINDS`; sets the pin's head shape and colour.
    x, z : float
        Position on the disc in disc radii: ``x`` to the player's right, ``z`` ahead. Entities
        beyond the radar's range are not listed.
    height : float
        ``(w_entity - w_player) * w_scale``, in disc radii: positive (ana) stands above the disc,
        negative (kata) hangs below it, 0 lies on the disc (visible in the slice now).
    visible : bool
        The entity's cross-section is in the player's slice this frame.
    sought : bool
        The entity the player's seek is heading for (or last headed for).
    """

    kind: str
    x: float
    z: float
    height: float
    visible: bool
    sought: bool = False


@dataclass
class Radar:
    """What the holographic radar shows this frame.

    Parameters
    ----------
    range : float
        Metres from the player to the disc's rim.
    w_scale : float
        Disc radii per unit of w offset (pin height = w offset * w_scale).
    pins : list of RadarPin
    interest : (n, 4) float64
        What the player may be looking for in the slice now (crystals, switches, bodies,
        enemies whose cross-section shows): centre ``x, y, z`` in the frame's 3D space and a
        radius. The renderer fades the radar while one of them lies behind it on screen.
    """

    range: float
    w_scale: float
    pins: list[RadarPin] = field(default_factory=list)
    interest: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))


@dataclass
class Frame:
    """Everything one image shows."""

    camera: Camera3
    drawables: list[Drawable] = field(default_factory=list)
    hud: Hud = field(default_factory=Hud)
    radar: Radar | None = None
    sky_color: tuple[float, float, float] = (0.05, 0.06, 0.10)
    light_dir: tuple[float, float, float] = (0.4, 1.0, 0.25)
    sky: str = "flat"  # "flat": one colour (sky_color); "dome": the renderer's procedural sky
    #: The boxes solid in the slice that may hide the dome, ``(k, 2, 3) float64`` lower and upper
    #: corners, none holding the eye (game/occlusion.py); None: the dome may show anywhere (the
    #: slice is turned or the camera detached). The renderer draws no sky where one covers the view.
    sky_boxes: np.ndarray | None = None
    time: float = 0.0  # seconds of play, for animated shading (pulses, bands); never read by the game
    batches: list = field(default_factory=list)  # TriangleBatch: many objects, one draw call per pass
    pip: list[Drawable] | None = None  # the other projection of the same moment (picture in picture), if asked


@dataclass(frozen=True)
class Card:
    """A teaching card over the view: an animated drawing and a few lines of text.

    Parameters
    ----------
    kind : str
        Which drawing: ``"flatland"`` (a flat being in a plane and a ball passing through it).
    time : float
        Seconds since the card opened (drives the animation).
    lines : tuple of str
        Captions, first the title; keys already filled in.
    """

    kind: str
    time: float
    lines: tuple = ()


@dataclass(frozen=True)
class HealthGauge:
    """The player's health bar.

    Parameters
    ----------
    value, maximum : float
        ``0 <= value <= maximum``.
    flash : float
        1 right after a hit, fading to 0.
    safe : bool
        True while the player cannot be hurt (just after coming back from a death).
    """

    value: float
    maximum: float
    flash: float = 0.0
    safe: bool = False


@dataclass
class Caption:
    """A sound made visible: what was heard, from where, and along w.

    Parameters
    ----------
    text : str
        The caption as shown, e.g. ``"crystal hum, ana, left"``.
    side : int
        +1 heard ana (+w), -1 kata (-w), 0 on the slice: a mark at the screen's edge shows it.
    pan : float
        -1 left to +1 right, where the mark goes.
    fade : float
        1 when new, falling to 0 as it goes.
    """

    text: str
    side: int = 0
    pan: float = 0.0
    fade: float = 1.0


@dataclass
class ScreenLabel:
    """Text shown on screen next to a point of the world (the manipulation keys beside the object).

    Parameters
    ----------
    text : str
        Lines separated by ``\n``; ``{action}`` placeholders become the player's
        keys (the window fills them in, as for hints).
    x, y : float
        Where its left edge's middle goes: the point's direction from the eye,
        in units of half the screen height from the centre, x right and y up
        (so it does not depend on the window's aspect ratio).
    x_left : float or None
        Where its right edge goes instead when it does not fit right of ``x``
        (the thing's left side, same units).
    """

    text: str
    x: float
    y: float
    x_left: float | None = None

    @classmethod
    def beside(cls, text: str, camera: Camera3, points) -> ScreenLabel | None:
        """A label just right of the points ``(k, 3)`` as ``camera`` sees them (their rightmost
        projection, at their middle height; left of them when that is off screen), or None when
        all of them are behind the eye."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        eye = camera.view_matrix()[:3] @ np.c_[p, np.ones(len(p))].T  # (3, k), looking down -z
        front = eye[2] < -camera.near
        if not front.any():
            return None
        t = np.tan(np.radians(camera.fov_y_deg) / 2.0)
        sx = eye[0, front] / (-eye[2, front] * t)
        sy = eye[1, front] / (-eye[2, front] * t)
        return cls(text, float(sx.max()), float(0.5 * (sy.min() + sy.max())), float(sx.min()))


@dataclass
class TriangleBatch:
    """Many objects' triangles in one vertex array, drawn with one call per pass.

    What :class:`~across_dimensions.core.section_batch.SectionBatch` and
    :class:`~across_dimensions.core.frustum_batch.FrustumBatch` produce. The arrays
    come from the engine's own kernels, so the renderer trusts them (no range
    checks) and uploads only what changed.

    Parameters
    ----------
    key : str
        Stable identity; the renderer keeps one growing GPU buffer per key.
    revision : int
        Bumped whenever ``vertices`` changed.
    vertices : (k, 10) float32
        Interleaved rows: position xyz, normal xyz (zero: shade flat), colour rgba; world coordinates.
    style : str
        As :attr:`Drawable.style`.
    changed_from : int
        Rows before this one are the same as at ``revision - 1`` (only the rest is uploaded).
    faces : (f, 3) uint32, optional
        Triangles as rows of ``vertices``; None: every three rows are one triangle.
    edges : (e, 2) uint32, optional
        Lines drawn over the triangles (unlit, in ``edge_color``).
    topology_revision : int
        Bumped whenever ``faces`` or ``edges`` changed.
    prepass : bool
        Lay down depth first, then shade each pixel once (cuts overdraw of a
        dense projection on a software rasterizer).
    edge_color : (4,) float
    members : tuple of str
        The drawable keys the batch stands for (``"entity:7"``), for code that
        asks what a frame shows.
    w_cue : bool
        Each vertex's colour alpha is its thing's w offset (see
        :func:`~across_dimensions.game.entity_sections.w_offset`): the renderer shades
        the batch as 4D matter with the w cue, as it does a drawable with a ``w_offset``.
    outside_only : bool
        As :attr:`Drawable.outside_only`: closed surfaces wound counter-clockwise from outside.
    tint, pattern, opacity
        As :class:`Drawable`'s, for a ``"ghost"`` batch (a layer of ghosts along w).
    """

    key: str
    revision: int
    vertices: np.ndarray
    style: str = "solid"
    changed_from: int = 0
    faces: np.ndarray | None = None
    edges: np.ndarray | None = None
    topology_revision: int = 0
    prepass: bool = False
    edge_color: tuple = (0.05, 0.05, 0.07, 1.0)
    members: tuple = ()
    w_cue: bool = False  # each vertex's colour alpha is its thing's w offset (4D things: the renderer's w cue)
    outside_only: bool = False  # closed surfaces, wound counter-clockwise from outside: inner faces skipped
    tint: tuple | None = None
    pattern: str = ""
    opacity: float = 1.0
