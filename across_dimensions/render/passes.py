"""What a frame's drawing cost: the renderer's counters, and pass by pass where the time goes.

:class:`RenderStats` counts what every frame drew (draw calls, triangles, uploads).

On a software rasterizer (llvmpipe) a draw call only queues work: the triangles are set up
and shaded when the driver flushes, on its own threads. To see what each pass costs, a
:class:`PassProfile` finishes the GL queue at the end of every pass and charges the CPU time of
the whole process since the previous mark (the rasterizer's threads included: on llvmpipe that
is the drawing's work, and other jobs on a shared machine disturb it far less than wall time)
to that pass, with the triangles it submitted and the samples that
passed the depth test (``samples / pixels`` is the pass's overdraw: how many times it shaded
each pixel of the view). Finishing between passes costs a little itself, so the sum is a bit
more than an unprofiled frame; the split is what it is for.

The renderer calls :meth:`PassProfile.mark` when one is set (``Renderer.profile``), and only
reads GL state: a profiled frame draws the same picture.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import moderngl

#: The passes in the order a frame draws them (a pass not drawn is left at zero); ``game`` is
#: the CPU's ``Game.frame`` before any drawing, ``setup`` the clear, uploads and uniforms.
PASSES = ("game", "setup", "prepass", "scenery", "matter", "wires", "sky", "ghosts", "radar", "upscale", "hud")


@dataclass
class PassCost:
    """One pass's share of a frame: CPU milliseconds (all threads), triangles submitted, samples shaded."""

    ms: float = 0.0
    triangles: int = 0
    samples: int = 0


@dataclass
class PassProfile:
    """Per-pass costs of the frames drawn while it is set on a renderer.

    Parameters
    ----------
    ctx : moderngl.Context
    pixels : int
        Pixels of the view the scene is drawn into (for overdraw).
    """

    ctx: moderngl.Context
    pixels: int
    passes: dict = field(default_factory=lambda: {name: PassCost() for name in PASSES})
    _query: moderngl.Query | None = None
    _t: float = 0.0

    def start(self) -> None:
        """Begin a frame: finish what is queued, so nothing earlier is charged to its first pass."""
        self.ctx.finish()
        self._begin()

    def _begin(self) -> None:
        if self._query is None:  # one query, begun and ended per pass (queries are not freed one by one)
            self._query = self.ctx.query(samples=True, primitives=True)
        self._query.mglo.begin()
        self._t = time.process_time()

    def mark(self, name: str) -> None:
        """End the pass ``name`` (its draw calls were made since the last mark) and begin the next."""
        self.ctx.finish()
        dt = time.process_time() - self._t
        q = self._query
        q.mglo.end()
        cost = self.passes[name]
        cost.ms += 1e3 * dt
        cost.triangles += int(q.primitives)
        cost.samples += int(q.samples)
        self._begin()

    def stop(self) -> None:
        """End the frame (what follows the last mark is not charged); :meth:`start` begins the next."""
        if self._query is not None:
            self._query.mglo.end()

    def rows(self, frames: int = 1) -> list[dict]:
        """Per pass: ``{"pass", "ms", "triangles", "overdraw"}`` averaged over ``frames``."""
        n = max(1, frames)
        return [
            {
                "pass": name,
                "ms": round(c.ms / n, 3),
                "triangles": c.triangles // n,
                "overdraw": round(c.samples / n / max(1, self.pixels), 3),
            }
            for name, c in self.passes.items()
        ]


@dataclass
class RenderStats:
    """Counters a test or a debug overlay can read.

    ``uploads`` and ``releases`` accumulate over the renderer's life; the others
    describe the last :meth:`Renderer.draw`.
    """

    uploads: int = 0  #: mesh uploads (first sight of a key, or a new revision)
    releases: int = 0  #: cached meshes freed because no view uses their key any more
    edge_builds: int = 0  #: wire edge lists derived (per upload, only for wire drawables)
    frames: int = 0
    draw_calls: int = 0  #: shading draws (the depth pre-pass's are ``depth_calls``)
    depth_calls: int = 0  #: depth-only draws of the pre-pass (see :meth:`Renderer._depth_prepass`)
    culled: int = 0  #: drawables skipped last frame because their bounding sphere was outside the view
    triangles: int = 0
    lines: int = 0
    cached: int = 0  #: keys with GPU buffers after the last frame
    upload_bytes: int = 0  #: bytes sent by the last frame's uploads
    batch_sync_cpu_ms: float = 0.0  #: CPU time of the last frame's batch uploads (this thread)
    by_key: dict = field(default_factory=dict)  #: uploads per key (lifetime)
