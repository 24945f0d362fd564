"""The paper's "Rendering performance" figure on this engine: FPS against rotating 120-cells.

For each N, N 120-cells (3,240 tets each) fill a 1280x720 offscreen view in a
grid, each turning in xw, yw and zw every frame, and are drawn

- ``section``: as their cross-sections by the player's hyperplane, sliced by one
  :class:`~across_dimensions.core.section_batch.SectionBatch` call (each cut
  dodecahedral cell one polygon; those facing away from the eye left out, as the
  game's batches do, since the rasterizer would cull them), solid;
- ``frustum``: through their own 4D frustums (a 4D camera 3 units along -w),
  projected by one :class:`~across_dimensions.core.frustum_batch.FrustumBatch`
  call, drawn as solid faces with their edges. Only the faces on the outline of
  each projected solid are kept (between a cell facing the 4D camera and one
  facing away), and of those only the ones facing the 3D eye, with their edges:
  drawn opaque, the others are hidden, so dropping them removes the overdraw
  without changing the picture. (A depth pre-pass,
  ``TriangleBatch.prepass``, was measured slower on llvmpipe: its cost is
  setting up triangles, not shading them.)

Each frame is timed in three parts, in wall time: ``projection`` (the batch
update, the kernel plus its Python set-up), ``submit`` (``Renderer.draw``:
uploads and draw calls; llvmpipe shades the vertices inside the draw call) and
``raster`` (``ctx.finish()``: the rasterizer finishing the frame). The kernel
and the per-object overhead are CPU times of this thread (``time.thread_time``),
which other jobs on a shared machine do not inflate.
``baseline_fps`` is measured in the same run: the same triangles, static,
already uploaded (draw and finish only). Medians over the measured frames.

The per-object path this replaces (one ``cross_section`` call, one drawable and
one GPU buffer per object) can be measured in the same run for comparison
(``per_object=True``: rows with mode ``section_per_object``).
"""

from __future__ import annotations

import math
import statistics
import sys
import time

import numpy as np

from ..core import section_batch as _sb
from ..core.frustum_batch import FrustumBatch
from ..core.section import cross_section
from ..core.section_batch import SectionBatch
from ..core.shapes import make_shape
from ..core.transform import translation
from ..game.frame import Camera3, Drawable, Frame, TriangleBatch
from ..render.context import Offscreen, create_offscreen_context
from ..render.gl_math import frustum_planes
from ..render.renderer import Renderer
from ..render.scale import ScaledTarget, resolve_render_scale

#: The paper's figure's x axis.
DEFAULT_NS = (1, 2, 5, 10, 20, 50, 100, 200)
MODES = ("section", "frustum")
#: Keys of every row (``--json``), as the issue fixes them.
ROW_KEYS = ("mode", "n", "fps", "projection_ms", "submit_ms", "raster_ms", "baseline_fps")
#: Targets on a 2-core machine with llvmpipe at 1280x720.
TARGET_SECTION = (100, 60.0)  # N, FPS
TARGET_FRUSTUM = (100, 30.0)
TARGET_OVERHEAD_MS = 0.02  # per object, projection + submission beyond the kernel
FRUSTUM_DISTANCE = 3.0  # the 4D camera's distance along -w
FRUSTUM_FOV = 60.0
SPIN = (0.9, 0.7, 0.5)  # rad/s in xw, yw, zw
FRAME_DT = 1.0 / 60.0


def grid(n: int, aspect: float = 16 / 9, fov_y_deg: float = 75.0) -> tuple[np.ndarray, float]:
    """Centres ``(n, 3)`` of a grid of ``n`` unit-radius cells that fills the view, and the spacing.

    The camera sits at the origin looking along +z; the grid is as far as it
    must be for its width and height to fit the view.
    """
    cols = max(1, math.ceil(math.sqrt(n * aspect)))
    rows = math.ceil(n / cols)
    cols = math.ceil(n / rows)
    spacing = 2.3
    half_h = math.tan(math.radians(fov_y_deg) / 2)
    dist = max(rows * spacing / 2 / half_h, cols * spacing / 2 / (half_h * aspect)) * 1.05
    i = np.arange(n)
    x = (i % cols - (cols - 1) / 2) * spacing
    y = ((rows - 1) / 2 - i // cols) * spacing
    return np.stack([x, y, np.full(n, dist)], axis=1), dist


def _plane_rotations(n: int, plane: str, angles: np.ndarray) -> np.ndarray:
    """``(n, 5, 5)`` rotations in one plane (as :func:`core.transform.rotation`), vectorised."""
    i, j = "xyzw".index(plane[0]), "xyzw".index(plane[1])
    out = np.zeros((n, 5, 5))
    out[:, range(5), range(5)] = 1.0
    c, s = np.cos(angles), np.sin(angles)
    out[:, i, i] = c
    out[:, j, j] = c
    out[:, j, i] = s  # turns axis i towards axis j
    out[:, i, j] = -s
    return out


def spin(n: int, t: float) -> np.ndarray:
    """Rotations ``(n, 5, 5)`` in xw, yw, zw at time ``t`` (each object its own phase)."""
    ph = 0.37 * np.arange(n)
    return (
        _plane_rotations(n, "xw", SPIN[0] * t + ph)
        @ _plane_rotations(n, "yw", SPIN[1] * t + 2 * ph)
        @ _plane_rotations(n, "zw", SPIN[2] * t + ph)
    )


class _KernelTimer:
    """Adds up the CPU time spent inside the slicing kernel (wraps the module's function)."""

    def __init__(self):
        self.seconds = 0.0
        self._orig = _sb._slice_batch

    def __enter__(self):
        orig = self._orig

        def timed(*a):
            t0 = time.thread_time()
            r = orig(*a)
            self.seconds += time.thread_time() - t0
            return r

        _sb._slice_batch = timed
        return self

    def __exit__(self, *exc):
        _sb._slice_batch = self._orig


class _Scene:
    """N 120-cells in a grid, one batch for their geometry."""

    def __init__(self, mode: str, n: int, mesh):
        self.mode, self.n, self.mesh = mode, n, mesh
        self.centers, dist = grid(n)
        self.camera = Camera3(np.zeros(3), fov_y_deg=75.0, far=max(500.0, 4 * dist))
        self.batch = SectionBatch() if mode == "section" else FrustumBatch()
        self.keys = list(range(n))
        self.meshes = [mesh] * n
        self.revision = 0
        if mode == "frustum":
            f = 1.0 / math.tan(math.radians(FRUSTUM_FOV) / 2)
            # Scale so a projected 120-cell (radius at most f / (d - 1)) fits its cell.
            s = (FRUSTUM_DISTANCE - 1.0) / f
            self.place = np.concatenate([np.full((n, 1), s), self.centers], axis=1)
            self.cam4 = translation((0.0, 0.0, 0.0, FRUSTUM_DISTANCE))  # object to 4D camera

    def project(self, rot: np.ndarray, planes) -> TriangleBatch:
        """The batch for rotations ``rot`` (:func:`spin`): one kernel call."""
        self.revision += 1
        if self.mode == "section":
            models = rot.copy()
            models[:, :3, 4] = self.centers
            self.batch.update(self.keys, self.meshes, models, None, planes, eye=self.camera.position)
            b = self.batch
            return TriangleBatch("bench", b.revision, b.vertices, "solid", b.changed_from, outside_only=True)
        b = self.batch
        b.update(self.meshes, self.cam4 @ rot, self.place, FRUSTUM_FOV, eye=self.camera.position)
        return TriangleBatch("bench", b.revision, b.vertices, "solid", 0, b.faces, b.edges, b.topology_revision)

    def per_object(self, rot: np.ndarray) -> list[Drawable]:
        """The per-object path: one ``cross_section`` call and one drawable per object."""
        self.revision += 1
        out = []
        for i in range(self.n):
            m = rot[i].copy()
            m[:3, 4] = self.centers[i]
            out.append(Drawable(f"obj:{i}", self.revision, cross_section(self.mesh, None, m), outside_only=True))
        return out


def _maxrss_mb() -> float:
    """Peak resident memory in MB; NaN where the system does not say (Windows has no ``resource``)."""
    try:
        import resource
    except ImportError:
        return math.nan
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return rss / 1024.0 / (1024.0 if sys.platform == "darwin" else 1.0)  # KiB on Linux, bytes on macOS


def run(
    ns=DEFAULT_NS,
    modes=MODES,
    frames: int = 30,
    size=(1280, 720),
    render_scale="auto",
    per_object: bool = False,
    out=print,
) -> list[dict]:
    """Measure every (mode, N); returns the rows (see :data:`ROW_KEYS`, plus extras).

    Extra keys per row: ``kernel_ms`` (CPU time inside the numba kernel; section
    only), ``overhead_ms_per_object`` (CPU time of the batch's Python set-up and of
    the upload, beyond the kernel, per object: the issue's "per-object CPU
    overhead"; the driver's own vertex work, which llvmpipe does inside the draw
    call, is part of ``submit_ms`` and of the baseline alike),
    ``frame_ms``, ``triangles``, ``gpu_bytes`` (the renderer's buffers),
    ``peak_rss_mb`` (the process's peak resident memory so far), ``render_scale``.

    ``render_scale`` is a number from 0.5 to 1 or ``"auto"``, what the game picks for
    this GL renderer (0.5 on llvmpipe); below 1 the scene is drawn at that fraction of
    ``size`` and upscaled to it, and the upscale is timed with the raster, as in the game.
    """
    mesh = make_shape("120-cell")
    ctx = create_offscreen_context()
    rows = []
    try:
        target = _Target(ctx, size, resolve_render_scale(render_scale, ctx))
        out(
            f"Rotating 120-cells (3,240 tets each), {size[0]}x{size[1]} offscreen at render scale "
            f"{target.scale:g} ({ctx.info.get('GL_RENDERER', '?')}); medians in ms:"
        )
        out(HEADER)
        for mode in modes:
            kinds = [mode] + (["section_per_object"] if per_object and mode == "section" else [])
            for kind in kinds:
                for n in ns:
                    renderer = Renderer(ctx)
                    scene = _Scene("section" if kind == "section_per_object" else mode, n, mesh)
                    row = _measure(ctx, target, renderer, scene, kind, frames)
                    row["gpu_bytes"] = renderer.gpu_bytes()
                    row["render_scale"] = target.scale
                    row["peak_rss_mb"] = round(_maxrss_mb(), 1)
                    renderer.release()
                    rows.append(row)
                    out(_format_row(row))
        target.release()
    finally:
        ctx.release()
    return rows


class _Target:
    """The 1280x720 image, drawn at the render scale and upscaled as the game does."""

    def __init__(self, ctx, size, scale: float):
        self.scale = scale
        self.screen = Offscreen(ctx, *size)
        self.scaled = ScaledTarget(ctx, scale)
        self.size = size

    def use(self) -> None:
        if not self.scaled.begin(self.size):
            self.screen.use()

    @property
    def viewport(self):
        return self.scaled.viewport if self.scaled.active else self.screen.viewport

    def present(self) -> None:
        """Stretch the scaled image over the full size (part of the frame's raster time)."""
        if self.scaled.active:
            self.scaled.present(self.screen.fbo, self.screen.viewport)

    def release(self) -> None:
        self.scaled.release()
        self.screen.release()


def _measure(ctx, target: _Target, renderer: Renderer, scene: _Scene, kind: str, frames: int) -> dict:
    warm = 3
    proj, sub, ras, kern, over = [], [], [], [], []
    frame = None
    target.use()
    aspect = target.viewport[2] / target.viewport[3]
    planes = None
    if scene.mode == "section":
        planes = frustum_planes(scene.camera.projection_matrix(aspect) @ scene.camera.view_matrix())
    for i in range(warm + frames):
        target.use()
        rot = spin(scene.n, i * FRAME_DT)  # the animation is the game's work, not the projection's
        with _KernelTimer() as kt:
            t0, c0 = time.perf_counter(), time.thread_time()
            if kind == "section_per_object":
                frame = Frame(scene.camera, drawables=scene.per_object(rot))
            else:
                frame = Frame(scene.camera, batches=[scene.project(rot, planes)])
            t1, c1 = time.perf_counter(), time.thread_time()
        renderer.draw(frame, target.viewport, hud=False)
        t2 = time.perf_counter()
        target.present()
        ctx.finish()
        t3 = time.perf_counter()
        if i >= warm:
            proj.append(t1 - t0)
            sub.append(t2 - t1)
            ras.append(t3 - t2)
            kern.append(kt.seconds)
            # Our own CPU time beyond the kernel: the batch's Python set-up and the upload.
            over.append((c1 - c0) - kt.seconds + 1e-3 * renderer.stats.batch_sync_cpu_ms)
    triangles = renderer.stats.triangles
    # Baseline: the same triangles, static, already uploaded.
    base = []
    for _ in range(frames):
        t0 = time.perf_counter()
        target.use()
        renderer.draw(frame, target.viewport, hud=False)
        target.present()
        ctx.finish()
        base.append(time.perf_counter() - t0)
    med = {k: 1e3 * statistics.median(v) for k, v in (("p", proj), ("s", sub), ("r", ras), ("k", kern), ("o", over))}
    frame_ms = 1e3 * statistics.median([a + b + c for a, b, c in zip(proj, sub, ras)])
    return {
        "mode": kind,
        "n": scene.n,
        "fps": round(1e3 / frame_ms, 2),
        "projection_ms": round(med["p"], 3),
        "submit_ms": round(med["s"], 3),
        "raster_ms": round(med["r"], 3),
        "baseline_fps": round(1e3 / (1e3 * statistics.median(base)), 2),
        "kernel_ms": round(med["k"], 3) if kind == "section" else None,
        "overhead_ms_per_object": round(med["o"] / scene.n, 4) if kind == "section" else None,
        "frame_ms": round(frame_ms, 3),
        "triangles": int(triangles),
    }


HEADER = (
    f"{'mode':19s} {'N':>4s} {'fps':>7s} {'proj ms':>8s} {'submit':>7s} {'raster':>7s} "
    f"{'kernel':>7s} {'ovh/obj':>8s} {'base fps':>8s} {'tris':>8s}"
)


def _format_row(r: dict) -> str:
    k = f"{r['kernel_ms']:7.2f}" if r.get("kernel_ms") is not None else f"{'-':>7s}"
    o = f"{r['overhead_ms_per_object']:8.4f}" if r.get("overhead_ms_per_object") is not None else f"{'-':>8s}"
    return (
        f"{r['mode']:19s} {r['n']:4d} {r['fps']:7.1f} {r['projection_ms']:8.2f} {r['submit_ms']:7.2f} "
        f"{r['raster_ms']:7.2f} {k} {o} {r['baseline_fps']:8.1f} {r['triangles']:8d}"
    )


def targets(rows: list[dict]) -> list[tuple[str, str, bool | None]]:
    """Each target of the issue next to the measured figure: ``(target, measured, passed)``.

    ``passed`` is None when the run did not measure it (N not in the list).
    """

    def row(mode, n):
        return next((r for r in rows if r["mode"] == mode and r["n"] == n), None)

    out = []
    for mode, (n, fps) in (("section", TARGET_SECTION), ("frustum", TARGET_FRUSTUM)):
        r = row(mode, n)
        name = f"{'cross-section' if mode == 'section' else mode}, {n} rotating 120-cells: >= {fps:.0f} FPS"
        if r is None:
            out.append((name, "not run", None))
            continue
        # The targets are for full size: a run at a lower render scale measures, but does not pass.
        full = r.get("render_scale", 1.0) >= 1.0
        measured = (
            f"{r['fps']:.1f} FPS at render scale {r.get('render_scale', 1.0):g} "
            f"(static baseline {r['baseline_fps']:.1f} FPS, same run)"
        )
        out.append((name + " at 1280x720", measured, (r["fps"] >= fps) if full else None))
    sec = [r for r in rows if r["mode"] == "section" and r.get("overhead_ms_per_object") is not None]
    if sec:
        big = max(sec, key=lambda r: r["n"])
        over = big["overhead_ms_per_object"]
        out.append(
            (
                f"per-object CPU overhead beyond the kernel: <= {TARGET_OVERHEAD_MS} ms",
                f"{over:.4f} ms per object (N = {big['n']})",
                over <= TARGET_OVERHEAD_MS,
            )
        )
    else:
        out.append((f"per-object CPU overhead beyond the kernel: <= {TARGET_OVERHEAD_MS} ms", "not run", None))
    out.append(("every shipped level >= 60 FPS everywhere a player can stand", "see: bench levels", None))
    return out


def print_targets(rows, out=print) -> None:
    out("Targets (2 cores, llvmpipe, 1280x720):")
    for name, measured, ok in targets(rows):
        mark = "n/a " if ok is None else ("PASS" if ok else "FAIL")
        out(f"  [{mark}] {name:62s} measured: {measured}")


def plot(rows: list[dict], path, title: str = "") -> None:
    """FPS against N for each mode (log-scaled N), with the baselines dashed. Needs matplotlib."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=110)
    colors = {"section": "#1f77b4", "frustum": "#d62728", "section_per_object": "#7f7f7f"}
    labels = {
        "section": "cross-section",
        "frustum": "frustum (solid + edges)",
        "section_per_object": "cross-section, per-object path (before)",
    }
    for mode in dict.fromkeys(r["mode"] for r in rows):
        rs = sorted((r for r in rows if r["mode"] == mode), key=lambda r: r["n"])
        ns = [r["n"] for r in rs]
        c = colors.get(mode, None)
        ax.plot(ns, [r["fps"] for r in rs], "o-", color=c, label=labels.get(mode, mode))
        if mode in ("section", "frustum"):
            ax.plot(ns, [r["baseline_fps"] for r in rs], ":", color=c, label=f"{labels[mode]}: static baseline")
    ax.axhline(60, color="k", lw=0.6, ls="--")
    ax.axhline(30, color="k", lw=0.6, ls="--")
    ax.set_xscale("log")
    ax.set_yscale("log")
    from matplotlib.ticker import FormatStrFormatter, NullFormatter

    ns = [r["n"] for r in rows]
    fps = [r[k] for r in rows for k in ("fps", "baseline_fps")] + [30.0, 60.0]
    ax.set_xticks([x for x in (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000) if min(ns) <= x <= max(ns)])
    ax.set_yticks([y for y in (1, 2, 3, 5, 10, 20, 30, 60, 100, 200, 500) if min(fps) / 1.5 <= y <= max(fps) * 1.5])
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(FormatStrFormatter("%g"))
        axis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("rotating 120-cells on screen (N)")
    ax.set_ylabel("frames per second")
    ax.set_title(title or "Rendering performance, 1280x720")
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
