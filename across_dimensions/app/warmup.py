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

NOTICE_AFTER = 1.5  # seconds: a cache hit finishes well before this


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
    _physics_world().tick()


def _queries() -> None:
    world = _physics_world()
    world.push_box_out((0.0, 0.875, 0.0, 0.0), (0.3, 0.875, 0.3, 0.05))
    world.raycast((0.0, 3.0, 0.0, 0.0), (0.0, -1.0, 0.0, 0.0))


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
    ("a first level", _game),
)


def warm_up(progress: Callable[[int, int, str], None] | None = None) -> None:
    """Run each kernel the game uses once on a tiny input.

    Parameters
    ----------
    progress : callable, optional
        Called as ``progress(done, total, label)`` before each step and once at the end;
        without it, a terminal notice appears when the compile takes longer than a cache hit.
    """
    notice = None
    if progress is None:
        notice = threading.Timer(
            NOTICE_AFTER,
            lambda: print("Compiling the 4D kernels (first run only, about a minute)...", file=sys.stderr, flush=True),
        )
        notice.daemon = True
        notice.start()
    try:
        for i, (label, step) in enumerate(STEPS):
            if progress:
                progress(i, len(STEPS), label)
            step()
        if progress:
            progress(len(STEPS), len(STEPS), "ready")
    finally:
        if notice is not None:
            notice.cancel()


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

    def _progress(self, done: int, total: int, label: str) -> None:
        self.done, self.total, self.label = done, total, label

    def _loading(self, done: int, total: int, label: str) -> None:
        # Loading from the cache the child filled: quick; the bar stays full until it is done.
        self.label = "loading" if done < total else label

    def _compile_in_child(self) -> None:
        """Fill the kernel cache from a child process, following its progress; on any failure
        the in-process warm-up that follows compiles (and reports) instead."""
        if getattr(sys, "frozen", False):
            return
        stamp = stamp_path()
        if stamp is not None and stamp.exists():  # warm: loading on the thread takes a second
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
            for line in child.stdout:  # blocks in a read that releases the interpreter lock
                parts = line.split(maxsplit=3)
                if len(parts) >= 3 and parts[0] == "step" and parts[1].isdigit() and parts[2].isdigit():
                    self._progress(int(parts[1]), int(parts[2]), parts[3].strip() if len(parts) > 3 else "")
            child.wait()
        finally:
            atexit.unregister(stop)

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


def main() -> int:
    """The child process's work: each step, announced as ``step DONE TOTAL LABEL`` on stdout."""
    warm_up(lambda done, total, label: print(f"step {done} {total} {label}", flush=True))
    return 0


if __name__ == "__main__":
    # Imported as part of the package (``-m``), so ``across_dimensions.app`` has already pointed
    # numba's cache at the game's folder, the same one the window's process reads.
    sys.exit(main())
