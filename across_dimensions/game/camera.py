"""The camera rig: the player's 3D camera and the 4D camera that makes the slice.

Slice space
-----------
The player lives in *slice space*: three coordinates ``u`` (what the screen shows,
where the 3D world and the walker are) and the slice offset ``s``
(``player.position[3]``, moved by the w keys). The 4D camera maps slice space into
the 4D world::

    X = anchor + rotation @ (u, s)          rotation: (4, 4) orthonormal

With ``rotation = I`` and ``anchor = 0`` this is the identity, the game's
axis-aligned slice, and every system works exactly as it did before the rig
(:attr:`CameraRig.aligned`). Turning the slice (the paper's t, u, v: the xw, yw
and zw planes of the camera's own axes) changes ``rotation`` and moves ``anchor``
so that the point the player's eye is at stays where it is in 4D: the player
does not jump, 3D geometry stays as it is (it is in slice space), and the 4D
content is cut by the turned hyperplane. A 90-degree turn carries the player
into a 3D world placed in an orthogonal subspace.

Modes
-----
``synced``
    Cross-section: the 4D camera follows the 3D camera; what is drawn is the
    section by the hyperplane ``s = player's s``.
``frustum``
    Detached: frustum projection from a 4D camera set at the switch
    ``focal_length(fov)`` behind the slice, looking along the slice's normal,
    so that whatever lies in the slice keeps its place and size on screen and
    only 4D content off the slice is revealed ("no noticeable change"). The
    projection is placed in slice space by a translation to the eye at the
    switch (the paper's "offset correction"); it stays put while the player
    walks. Two keys turn the camera round the focus point ``focus_distance``
    ahead of the eye, in the plane of the eye's direction and the slice normal;
    the focus point keeps its place on screen while everything else morphs.
``returning``
    The 4D camera glides back to the synced pose at the player's current eye
    over ``return_time``, the orbit angle unwinding with it (the focus point
    stays put on screen all along), then hands over to ``synced``.

Every transition emits :class:`~.events.CameraSwitched`. The rig is plain data on
the game (``game.camera``); :func:`state_bytes` is what it adds to the state hash,
nothing while it is at rest in an axis-aligned synced slice.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.frustum import focal_length
from ..core.transform import orthonormalize, rotation4
from .system import derived, fixed

MODES = ("synced", "frustum", "returning")
TURN_PLANES = ("xw", "yw", "zw")
#: A glide (90-degree step or snap) ends exactly on its target once it is this close
#: (Frobenius norm of the difference, about radians * sqrt 2): far below a pixel.
GLIDE_DONE = 1e-6
#: The glides (steps, snap) run this many times faster than held turning.
GLIDE_FACTOR = 2.0
#: Near hyperplane of the frustum camera, metres: a vertex closer than this along the
#: camera's w is clipped (the camera can sit on a vertex, as at the focus point).
FRUSTUM_NEAR = 0.05
#: Share of the return spent gliding the camera back; the rest fades the frustum view out.
GLIDE_SHARE = 0.7
#: Anchor components below this (metres) are rounding left by turning there and back.
ANCHOR_ROUNDING = 1e-9


def nearest_axes(r: np.ndarray) -> np.ndarray:
    """The signed permutation matrix (a rotation, det +1) nearest ``r (4, 4)``.

    Greedy on the largest entries, which is exact whenever ``r`` is within 45 degrees
    of it in every plane; the sign of the weakest pick is flipped if needed for det +1.
    """
    a = np.abs(np.asarray(r, dtype=np.float64))
    out = np.zeros((4, 4))
    rows, cols = set(range(4)), set(range(4))
    picks = []
    for _ in range(4):
        best = max((a[i, j], i, j) for i in rows for j in cols)
        _, i, j = best
        out[i, j] = 1.0 if r[i, j] >= 0 else -1.0
        picks.append(best)
        rows.discard(i)
        cols.discard(j)
    if np.linalg.det(out) < 0:
        _, i, j = min(picks)
        out[i, j] = -out[i, j]
    return out


def plane_rotation(a: np.ndarray, n: np.ndarray, angle: float) -> np.ndarray:
    """4x4 rotation by ``angle`` in the plane of orthonormal ``a, n (4,)``, turning a towards n."""
    c, s = np.cos(angle), np.sin(angle)
    return np.eye(4) + (c - 1.0) * (np.outer(a, a) + np.outer(n, n)) + s * (np.outer(n, a) - np.outer(a, n))


def rigid(rot: np.ndarray, position: np.ndarray) -> np.ndarray:
    """The 5x5 pose with rotation ``rot (4, 4)`` and translation ``position (4,)``."""
    m = np.eye(5)
    m[:4, :4] = rot
    m[:4, 4] = position
    return m


def smoothstep(t: float) -> float:
    """0 at 0, 1 at 1, flat at both ends: a glide that starts and lands softly."""
    t = min(max(t, 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


@dataclass
class CameraRig:
    """The 4D camera's state.

    Attributes
    ----------
    rotation : (4, 4) float64
        Slice axes in the world, as columns; orthonormal, det +1.
    anchor : (4,) float64
        World point of the slice-space origin.
    mode : str
        One of :data:`MODES`.
    glide : (4, 4) float64 or None
        The orientation a 90-degree step or a snap is gliding to.
    focus : (4,) float64
        World position of the orbit's focus point (frustum and returning).
    focus_u : (3,) float64
        The focus point in slice space (where it shows on screen).
    eye_switch : (3,) float64
        The eye in slice space at the switch: where the frustum camera was synced.
    orbit : float
        Orbit angle, radians (0 at the switch).
    orbit_axis : (4,) float64
        Unit world direction from the focus point towards the eye at the switch.
    return_ticks : int
        Ticks the return glide has run; ``return_from`` the orbit angle it started at.
    detached_ticks : int
        Ticks in frustum mode since the switch; ``paid_milli`` what they have cost.
    rest : (4, 4) float64
        The 90-degree orientation the slice last landed on (where turning is measured from);
        ``turn_paid_milli`` what turning away from it has cost since (see ``game/slice_pay.py``).
    version : int
        Bumps whenever the 4D pose changes (caches compare it).
    """

    rotation: np.ndarray = field(default_factory=lambda: np.eye(4))
    anchor: np.ndarray = field(default_factory=lambda: np.zeros(4))
    mode: str = "synced"
    glide: np.ndarray | None = None
    focus: np.ndarray = field(default_factory=lambda: np.zeros(4))
    focus_u: np.ndarray = field(default_factory=lambda: np.zeros(3))
    eye_switch: np.ndarray = field(default_factory=lambda: np.zeros(3))
    orbit: float = 0.0
    orbit_axis: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -1.0, 0.0]))
    return_from: float = 0.0
    return_ticks: int = 0
    detached_ticks: int = 0
    paid_milli: int = 0
    rest: np.ndarray = field(default_factory=lambda: np.eye(4))
    turn_paid_milli: int = 0
    fov_deg: float = fixed(default=60.0)
    #: The tick a turn towards w was last refused (the HUD's notice); display only, not state.
    refused_tick: int = derived(default=-(10**9))
    #: The tick a turn was last cut short by the energy bar, and what a full step would have cost.
    unpaid_tick: int = derived(default=-(10**9))
    unpaid_milli: int = derived(default=0)
    version: int = derived(default=0)
    _aligned: bool = derived(default=True)
    #: The projection stage's frustum meshes (``game.projection.FrustumCache``); not state.
    cache: object = derived(default=None, repr=False, compare=False)

    # ------------------------------------------------------------ slice space
    @property
    def aligned(self) -> bool:
        """True while the slice is the game's plain one (rotation exactly I, anchor exactly 0)."""
        return self._aligned

    @property
    def normal(self) -> np.ndarray:
        """The slice's normal in the world, ``(4,) float64`` (the 4D camera's w axis)."""
        return self.rotation[:, 3]

    def _moved(self) -> None:
        self.version += 1
        self._aligned = bool(np.array_equal(self.rotation, np.eye(4)) and not self.anchor.any())

    def slice_pose(self, s: float) -> np.ndarray:
        """Camera-to-world ``(5, 5) float64`` whose ``w = 0`` hyperplane is the slice at offset ``s``."""
        return rigid(self.rotation, self.anchor + self.rotation[:, 3] * s)

    def slice_of(self, s: float):
        """What the section cache slices by: ``s`` itself while aligned (the game's plain
        slice, computed exactly as without a rig), else the slice's pose."""
        return float(s) if self._aligned else self.slice_pose(s)

    def to_slice(self, points: np.ndarray) -> np.ndarray:
        """World points ``(..., 4)`` in slice space ``(u, s)`` (the same array while aligned)."""
        if self._aligned:
            return points
        return (np.asarray(points, dtype=np.float64) - self.anchor) @ self.rotation

    def to_world(self, points: np.ndarray) -> np.ndarray:
        """Slice-space points ``(..., 4)`` in the world."""
        return self.anchor + np.asarray(points, dtype=np.float64) @ self.rotation.T

    def angles_deg(self) -> tuple[float, float, float]:
        """How far the slice's x, y and z axes are turned towards w, degrees in [-180, 180]:
        the angle of each axis in its own plane with w (what the HUD gauges show)."""
        r = self.rotation
        out = []
        for i in range(3):
            # Axis i of the slice, measured in the world's (i, w) plane.
            out.append(float(np.degrees(np.arctan2(r[3, i], r[i, i]))))
        return tuple(out)

    # ------------------------------------------------------------- turning
    def set_rotation(self, rot: np.ndarray, pivot_u: np.ndarray) -> None:
        """Turn the slice to ``rot`` about the slice-space point ``pivot_u (4,)`` (the eye):
        that point keeps its world position and its slice coordinates."""
        rot = np.asarray(rot, dtype=np.float64)
        if np.array_equal(rot, self.rotation):
            return
        q = self.anchor + self.rotation @ pivot_u
        self.rotation = rot
        self.anchor = q - rot @ pivot_u
        if np.array_equal(rot, np.eye(4)):
            # Back on the world's axes where it started: rounding left the anchor a few
            # ulps from 0, which would keep the game off its plain slice for nothing.
            self.anchor = np.where(np.abs(self.anchor) < ANCHOR_ROUNDING, 0.0, self.anchor)
        self._moved()

    def pose(self) -> tuple[np.ndarray, np.ndarray]:
        """The slice's rotation and anchor (copies), for :meth:`restore`."""
        return self.rotation.copy(), self.anchor.copy()

    def restore(self, pose: tuple[np.ndarray, np.ndarray]) -> None:
        """Put back a pose from :meth:`pose` exactly (a refused turn leaves no rounding behind)."""
        self.rotation, self.anchor = pose[0].copy(), pose[1].copy()
        self._moved()

    def fold_offset(self) -> float:
        """On a slice whose normal is the world's w axis (either way), move the anchor's part
        along the normal into the slice offset: returns what to add to the player's ``s``
        (0 on any other slice). Nothing moves in the world, but afterwards the player's ``s``
        is their world w (up to its sign), so the level's w range bounds the real w again,
        however the slice was turned and walked before it came back."""
        n = self.rotation[:, 3]
        if abs(n[3]) != 1.0:
            return 0.0
        shift = float(self.anchor @ n)
        if shift == 0.0:
            return 0.0
        self.anchor = self.anchor - shift * n
        self.anchor[3] = 0.0  # exactly: n is +-e_w
        self._moved()
        return shift

    def turn(self, rates: tuple[float, float, float], dt: float, pivot_u: np.ndarray) -> None:
        """Turn by ``rates`` (radians/s in the camera's own xw, yw, zw planes) for ``dt``."""
        rot = self.rotation
        for plane, rate in zip(TURN_PLANES, rates):
            if rate != 0.0:
                rot = rot @ rotation4(plane, rate * dt)
        self.glide = None  # held turning takes over from a glide
        self.set_rotation(orthonormalize(rot), pivot_u)

    def step(self, plane: str, sign: int) -> None:
        """Start a 90-degree step in ``plane`` from the current target (steps queue up)."""
        base = self.glide if self.glide is not None else nearest_axes(self.rotation)
        self.glide = nearest_axes(base @ rotation4(plane, sign * np.pi / 2))

    def snap(self) -> None:
        """Start gliding to the nearest 90-degree orientation."""
        self.glide = nearest_axes(self.rotation)

    def advance_glide(self, speed: float, dt: float, pivot_u: np.ndarray) -> bool:
        """Move towards the glide's target at ``speed`` radians/s; True on the tick it lands
        (then the rotation is the target exactly)."""
        target = self.glide
        if target is None:
            return False
        gap = float(np.linalg.norm(self.rotation - target))
        # Frobenius gap of a turn by phi in one plane is 2 sqrt(2) sin(phi / 2).
        phi = 2.0 * np.arcsin(min(1.0, gap / (2.0 * np.sqrt(2.0))))
        stride = speed * dt
        if phi <= stride or gap <= GLIDE_DONE:
            self.set_rotation(target.copy(), pivot_u)
            self.glide = None
            return True
        k = stride / phi
        self.set_rotation(orthonormalize(self.rotation + k * (target - self.rotation)), pivot_u)
        return False

    # -------------------------------------------------------------- frustum
    @property
    def detached(self) -> bool:
        """True in frustum and returning modes: the 4D camera does not follow the player."""
        return self.mode != "synced"

    @property
    def focal(self) -> float:
        return focal_length(self.fov_deg)

    def synced_pose(self, eye_u: np.ndarray, s: float) -> np.ndarray:
        """The frustum camera in sync with an eye at ``eye_u (3,)``: ``focal`` behind the slice
        along its normal, looking along it, axes the slice's."""
        return rigid(self.rotation, self.to_world(np.append(eye_u, s - self.focal)))

    def detach(self, eye_u: np.ndarray, forward_u: np.ndarray, s: float, distance: float) -> None:
        """Switch to frustum: the camera synced at ``eye_u``, the focus ``distance`` ahead
        along the horizontal ``forward_u (3,)``."""
        f = np.array([forward_u[0], 0.0, forward_u[2]])
        norm = np.linalg.norm(f)
        f = f / norm if norm > 0 else np.array([0.0, 0.0, 1.0])
        self.eye_switch = np.asarray(eye_u, dtype=np.float64).copy()
        self.focus_u = self.eye_switch + distance * f
        self.focus = self.to_world(np.append(self.focus_u, s))
        self.orbit_axis = self.rotation @ np.append(-f, 0.0)
        self.orbit = 0.0
        self.detached_ticks = self.paid_milli = self.return_ticks = 0
        self.mode = "frustum"
        self.version += 1

    def start_return(self) -> None:
        self.mode = "returning"
        self.return_from = self.orbit
        self.return_ticks = 0
        self.version += 1

    def return_progress(self, total_ticks: int) -> float:
        """How far the camera's glide back is, 0 to 1, eased: it ends :data:`GLIDE_SHARE` of the
        way through the return, so the rest of it can fade the revealed content away."""
        return smoothstep(self.return_ticks / max(GLIDE_SHARE * total_ticks, 1.0))

    def return_fade(self, total_ticks: int) -> float:
        """How much of the frustum view is still shown at the end of a return, 1 to 0: after
        the glide, the cross-section comes in under the frustum view, which fades out, so
        4D content off the slice melts away instead of vanishing at the hand-over."""
        if self.mode != "returning":
            return 1.0
        t = (self.return_ticks / max(total_ticks, 1) - GLIDE_SHARE) / (1.0 - GLIDE_SHARE)
        return 1.0 - smoothstep(t)

    def frustum_pose(self, eye_u: np.ndarray, s: float, total_ticks: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """The frustum camera's pose ``(5, 5)`` and the projection's placement in slice
        space, ``(4, 4)`` (a translation), for the current mode; ``eye_u`` is the player's
        eye now (the return glides to it)."""
        if self.mode == "returning":
            t = self.return_progress(total_ticks)
            angle = self.return_from * (1.0 - t)
            eye = self.eye_switch + t * (np.asarray(eye_u, dtype=np.float64) - self.eye_switch)
        elif self.mode == "frustum":
            angle, eye = self.orbit, self.eye_switch
        else:
            angle, eye = 0.0, np.asarray(eye_u, dtype=np.float64)
        base = self.synced_pose(eye, s)
        if angle != 0.0:
            g = plane_rotation(self.orbit_axis, self.normal, angle)
            base = base.copy()
            base[:4, :4] = g @ base[:4, :4]
            base[:4, 4] = self.focus + g @ (base[:4, 4] - self.focus)
        place = np.eye(4)
        place[:3, 3] = eye
        return base, place

    def project_points(self, points: np.ndarray, pose: np.ndarray, place: np.ndarray):
        """Where world points ``(k, 4)`` land in slice space through the frustum camera:
        ``(k, 3)`` positions and ``(k,)`` scale factors (``focal / depth``, 0 behind the near
        hyperplane, where the position is NaN)."""
        rel = (np.asarray(points, dtype=np.float64).reshape(-1, 4) - pose[:4, 4]) @ pose[:4, :4]
        depth = rel[:, 3]
        ok = depth >= FRUSTUM_NEAR
        scale = np.where(ok, self.focal / np.where(ok, depth, 1.0), 0.0)
        pos = rel[:, :3] * scale[:, None] + place[:3, 3]
        pos[~ok] = np.nan
        return pos, scale


__all__ = ["CameraRig", "MODES", "TURN_PLANES", "nearest_axes", "plane_rotation"]
