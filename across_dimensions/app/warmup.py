"""Compile the numba kernels before play starts, in steps that report progress.

The first run after an install compiles every kernel (about a minute on a
2-core machine; later runs load them from the on-disk cache in well under a
second). The window opens first and runs :class:`BackgroundWarmUp` behind the
title screen, which shows :attr:`BackgroundWarmUp.done` of :attr:`~BackgroundWarmUp.total`
steps; a level starts only when it has finished, so no frame freezes on a
compile. Commands without a window call :func:`warm_up`, which says so on the
terminal when it is slow.

The compile itself runs in a child process (``python -m across_dimensions.app.warmup``)
that fills the on-disk cache and reports each step on its standard output; the
window's process then loads the kernels from that cache. A compile on a thread
of the window's own process would hold the interpreter lock for most of a
minute, and the window (whose every OpenGL call through ctypes gives the lock
up and waits to get it back) would stop answering. A frozen build, which has no
interpreter to start, compiles on the thread. Once a warm-up has finished, a
stamp in the cache folder (:func:`stamp_path`, named by a hash of the package's
sources as numba keys its own cache) says later starts need no child: they load
the kernels on the thread in about a second.

Each step calls the kernels of one part of the game once on tiny inputs; the
last one plays a few ticks of a small level, which reaches the kernels only the
game's systems use (the walker's collision against true sections, the radar...).
"""

from __future__ import annotations

import atexit
import hashlib
import os
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

from .._shipped_kernels import loaded_kernels, serve_all

NOTICE_AFTER = 1.5  # seconds: a cache hit finishes well before this
#: Seconds between the child's kernel counts (``kernels DONE TOTAL COMPILED`` lines).
COUNT_EVERY = 0.5
#: Kernels to have compiled, and seconds to have spent, before an estimate of the time left is
#: said: the first kernels (the cross-section's) are not typical of the rest.
ESTIMATE_AFTER = (5, 5.0)


def kernel_counts() -> tuple[int, int, int]:
    """``(ready, total, compiled)``: the game's numba kernels imported so far, those with machine
    code (compiled here or loaded from the cache) and those compiled here (cache misses).

    Read from the dispatchers' own bookkeeping, so it is cheap enough to poll while a compile runs
    on another thread. A kernel called only from other kernels is compiled into them and may stay
    without code of its own, so ``ready`` ends below ``total``.
    """
    kernels = loaded_kernels()
    ready = sum(bool(d.overloads) for d in kernels)
    compiled = sum(sum(d.stats.cache_misses.values()) > 0 for d in kernels)
    return ready, len(kernels), compiled


def _notice(done: threading.Event) -> None:
    """The terminal's line when kernels are being compiled (after :data:`NOTICE_AFTER`, once the
    first one is): loading them from the cache says nothing, it is never "Compiling"."""
    if done.wait(NOTICE_AFTER):
        return
    while not done.wait(COUNT_EVERY):
        if kernel_counts()[2] > 0:
            print(
                "Compiling the 4D kernels (first run after an install: a few minutes on 2 cores)...",
                file=sys.stderr,
                flush=True,
            )
            return


def _sections() -> None:
    from ..core import cross_section, shapes

    cross_section(shapes.tesseract())


def _frustum() -> None:
    from ..core import frustum_project, shapes
    from ..core.transform import translation

    frustum_project(shapes.tesseract(), translation((0.0, 0.0, 0.0, -3.0)))


def _physics_world():
    from ..physics import BodyDef, PhysicsWorld, WorldDef

    world = PhysicsWorld(WorldDef(ground=False))
    world.set_static_boxes([((0.0, -0.5, 0.0), (5.0, 0.5, 5.0))])
    world.add_body(BodyDef("hypersphere", radius=0.5, position=(0.0, 0.5, 0.0, 0.0)))
    world.add_body(BodyDef("hypercube", size=1.0, position=(0.2, 1.6, 0.0, 0.0)))
    return world


def _contacts() -> None:
    world = _physics_world()
    world.tick()
    _ = world.events  # built on first read, which in a level is a first knock mid-play (its sound)


def _queries() -> None:
    world = _physics_world()
    world.push_box_out((0.0, 0.875, 0.0, 0.0), (0.3, 0.875, 0.3, 0.05))
    world.raycast((0.0, 3.0, 0.0, 0.0), (0.0, -1.0, 0.0, 0.0))
    # A solid 4D mesh's collider (a level's gate or arch) is worked out when it first turns.
    import numpy as np

    from ..physics.tet_mesh import tet_geometry

    tet_geometry(np.eye(4)[None])


def _sightlines() -> None:
    # The occlusion test calls the second kernel only when a sightline crosses a wall, which a
    # few ticks of a level may never see.
    import numpy as np

    from ..physics.sightlines import segments_cross_boxes, segments_cross_their_boxes

    eye, ends = np.zeros(3), np.array([[0.0, 0.0, 3.0]])
    boxes = np.array([[[-1.0, -1.0, 1.0], [1.0, 1.0, 2.0]]])
    segments_cross_boxes(eye, ends, boxes, np.empty((1, 1), bool))
    segments_cross_their_boxes(eye, ends, boxes, np.empty(1, bool))


def _game() -> None:
    from ..game.actions import Actions
    from ..game.sim import Game
    from ..world.level import load_level
    from ..world.resources import levels_dir

    path = levels_dir() / "02_crystal_cache.toml"  # small, with crystals, radar and w walls
    if not path.is_file():
        return
    game = Game(load_level(path))
    for _ in range(3):
        game.step(Actions(forward=1.0, w=1.0))
    game.frame()


#: The warm-up, one step per part of the game: ``(what the title screen says, function)``.
STEPS: tuple[tuple[str, Callable[[], None]], ...] = (
    ("cross-sections", _sections),
    ("the 4D camera", _frustum),
    ("4D physics", _contacts),
    ("collision queries", _queries),
    ("sightlines", _sightlines),
    ("a first level", _game),
)


def warm_up(progress: Callable[[int, int, str], None] | None = None) -> None:
    """Run each kernel the game uses once on a tiny input.

    Parameters
    ----------
    progress : callable, optional
        Called as ``progress(done, total, label)`` before each step and once at the end;
        without it, a terminal notice appears once kernels are being compiled (not for a cache hit).
    """
    import numba.core.dispatcher  # noqa: F401  here, not first on a counting thread mid-import

    done = threading.Event()
    if progress is None:
        threading.Thread(target=_notice, args=(done,), daemon=True).start()
    try:
        for i, (label, step) in enumerate(STEPS):
            if progress:
                progress(i, len(STEPS), label)
            step()
        if progress:
            progress(len(STEPS), len(STEPS), "ready")
    finally:
        done.set()


def stamp_path() -> Path | None:
    """The file whose presence says the kernel cache is warm for these sources, or None when numba
    keeps its cache in its default places (no ``NUMBA_CACHE_DIR``).

    Its name hashes the Python and numba versions and the path, size and modification time of
    every module of the package, which is what numba's own cache is keyed by.
    """
    folder = os.environ.get("NUMBA_CACHE_DIR")
    if not folder:
        return None
    import numba

    package = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(f"{sys.version}|{numba.__version__}|{package}".encode())
    for path in sorted(package.rglob("*.py")):
        st = path.stat()
        h.update(f"{path.relative_to(package)}|{st.st_size}|{st.st_mtime_ns}\n".encode())
    return Path(folder) / f"warm-{h.hexdigest()[:16]}.stamp"


def _write_stamp() -> None:
    from ..core.fileio import FileProblem, atomic_write

    path = stamp_path()
    if path is not None and path.parent.is_dir():
        try:
            atomic_write(path, "the kernels in this folder were compiled for these sources\n")
        except (FileProblem, OSError):  # only costs the next start a child process
            pass


class BackgroundWarmUp(threading.Thread):
    """:func:`warm_up` on a daemon thread, its progress readable from the window's thread.

    Attributes
    ----------
    done, total : int
        Steps finished and steps in all.
    label : str
        The step running.
    error : BaseException or None
        What stopped it, if anything (the game then meets the problem again, and reports it, in play).
    seconds : float or None
        How long it took, once finished.
    """

    def __init__(self):
        super().__init__(name="kernel warm-up", daemon=True)
        self.done, self.total, self.label = 0, len(STEPS), STEPS[0][0]
        self.error: BaseException | None = None
        self.seconds: float | None = None
        self.finished = threading.Event()
        self.kernels = (0, 0, 0)  # the child's last count: ready, total, compiled (kernel_counts)
        self.compiling = False  # a child is compiling (not only loading from the cache)
        self.started = time.perf_counter()

    def start(self) -> None:
        self.started = time.perf_counter()  # the title's clock counts from here
        super().start()

    def start_once(self) -> None:
        """Start, unless it has started already."""
        if self.ident is None:
            self.start()

    def status(self, now: float | None = None) -> str:
        """What the title says of the warm-up: the step, the kernels ready of all, the time so far
        and, once it can be told from this run's own pace, about how long is left."""
        elapsed = (time.perf_counter() if now is None else now) - self.started
        if self.compiling and not self.kernels[1]:  # the child has not reported yet
            return f"{self.label}, starting the compiler, {_clock(elapsed)} so far"
        if not self.compiling or not self.kernels[2]:  # nothing compiled yet: only loading
            return f"{self.label}, loading the kernels, {_clock(elapsed)} so far"
        ready, total, _ = self.kernels
        text = f"{self.label}, {ready} of {total} kernels, {_clock(elapsed)} so far"
        if ready >= ESTIMATE_AFTER[0] and elapsed >= ESTIMATE_AFTER[1] and total > ready:
            # This run's pace over the kernels still without code: an upper bound, as some of
            # them are compiled into others and never need their own.
            text += f", at most about {_clock(elapsed * (total - ready) / ready)} left"
        return text

    def fraction(self) -> float:
        """How far along, 0..1: the steps done, or the kernels ready when that says more."""
        ready, total, _ = self.kernels
        return max(self.done / max(1, self.total), ready / total if total else 0.0)

    def _progress(self, done: int, total: int, label: str) -> None:
        self.done, self.total, self.label = done, total, label

    def _loading(self, done: int, total: int, label: str) -> None:
        # Loading the shipped kernels, or the cache a child filled: quick. The steps count on
        # (after a child's compile they are all done already: the bar stays full to the end).
        self.done, self.total, self.label = max(self.done, done), total, label

    def _compile_in_child(self) -> None:
        """Fill the kernel cache from a child process, following its progress; on any failure
        the in-process warm-up that follows compiles (and reports) instead."""
        if getattr(sys, "frozen", False):
            return
        stamp = stamp_path()
        if (stamp is not None and stamp.exists()) or serve_all():  # warm: loading on the thread takes a second
            return
        try:
            child = subprocess.Popen(
                [sys.executable, "-m", "across_dimensions.app.warmup"],
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                stdin=subprocess.DEVNULL,
                text=True,
            )
        except OSError:
            return
        # The game may close mid-compile: the child goes with it.
        stop = atexit.register(lambda: child.poll() is None and child.kill())
        try:
            self.compiling = True
            for line in child.stdout:  # blocks in a read that releases the interpreter lock
                parts = line.split(maxsplit=3)
                if len(parts) >= 3 and parts[0] == "step" and parts[1].isdigit() and parts[2].isdigit():
                    self._progress(int(parts[1]), int(parts[2]), parts[3].strip() if len(parts) > 3 else "")
                elif len(parts) == 4 and parts[0] == "kernels" and all(p.isdigit() for p in parts[1:]):
                    self.kernels = (int(parts[1]), int(parts[2]), int(parts[3]))
            child.wait()
        finally:
            atexit.unregister(stop)
            self.compiling = False  # what follows loads what the child compiled

    def run(self) -> None:
        start = time.perf_counter()
        try:
            self._compile_in_child()
            warm_up(self._loading)
            _write_stamp()
        except Exception as e:  # noqa: BLE001 - reported by the window, met again in play
            self.error = e
        finally:
            self.seconds = time.perf_counter() - start
            self.finished.set()

    @property
    def ready(self) -> bool:
        return self.finished.is_set()


def _clock(seconds: float) -> str:
    """``75.2`` -> ``"1:15"``."""
    m, s = divmod(int(seconds), 60)
    return f"{m}:{s:02d}"


#: Seconds the warm-up runs before the title shows its panel. Loading the shipped kernels takes
#: about half a second: a panel shown for that long would come and go, moving the menu under the
#: player's pointer. A compile (minutes) shows it after this second.
TITLE_PANEL_AFTER = 1.0


def warm_progress(warm, after: float = 0.0, now: float | None = None) -> tuple | None:
    """The warm-up's line for a panel: ``(steps done, steps, what is happening, fraction)``, or
    None when there is none, it is over, or it has not run ``after`` seconds yet. The time in it
    moves once a second, so a still screen showing it is redrawn once a second, not every frame."""
    if warm is None or warm.ready:
        return None
    if after > 0.0 and (warm.ident is None or (time.perf_counter() if now is None else now) - warm.started < after):
        return None
    return warm.done, warm.total, warm.status(now), round(warm.fraction(), 3)


def main() -> int:
    """The child process's work: each step, announced as ``step DONE TOTAL LABEL`` on stdout, and
    every :data:`COUNT_EVERY` seconds the kernels, as ``kernels READY TOTAL COMPILED``."""
    import numba.core.dispatcher  # noqa: F401  before the counting thread reads it

    lock = threading.Lock()

    def say(line: str) -> None:
        with lock:
            print(line, flush=True)

    stop = threading.Event()

    parent = os.getppid()

    def count() -> None:
        while not stop.wait(COUNT_EVERY):
            if os.getppid() != parent:  # the window is gone (killed): no one waits for the kernels
                os._exit(1)
            say("kernels {} {} {}".format(*kernel_counts()))

    threading.Thread(target=count, daemon=True).start()
    try:
        warm_up(lambda done, total, label: say(f"step {done} {total} {label}"))
    finally:
        stop.set()
    return 0


if __name__ == "__main__":
    # Imported as part of the package (``-m``), so ``across_dimensions.app`` has already pointed
    # numba's cache at the game's folder, the same one the window's process reads.
    sys.exit(main())
