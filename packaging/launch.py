"""The frozen game's entry point: the ``across-dimensions`` executable runs this.

It does what the installed console script does (:func:`across_dimensions.app.cli.main`,
same ``--help``, messages and exit statuses) after two things only a frozen build needs:

* the numba kernel cache goes in the player's cache folder under a name that
  changes with every build. A frozen numba stamps cached kernels with the
  executable's hash, and the executable (PyInstaller's bootloader) is the same
  from one release to the next, so a shared folder could load a previous
  release's kernels.
* the first start of the game from a desktop, where no terminal shows the
  "compiling" notice: a small window says so while the kernels compile.
* the tetrahedralizer's child process (``sys.executable -c WORKER``, see
  :mod:`across_dimensions.world.assets.tetwild`) is served: a frozen
  executable is no Python interpreter, so it runs that one script and nothing else.
"""

import os
import sys


def _numba_cache_dir(bundle: str) -> str:
    try:
        with open(os.path.join(bundle, "BUILD_ID"), encoding="ascii") as f:
            build = f.read().strip()[:16]
    except OSError:
        build = "unknown"
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "across-dimensions", f"numba-{build}")


def _tetwild_worker(argv: list[str]) -> bool:
    """Run the tetrahedralizer's child script if that is what ``argv`` asks for."""
    if len(argv) < 3 or argv[1] != "-c":
        return False
    from across_dimensions.world.assets.tetwild import _WORKER

    if argv[2] != _WORKER:
        return False
    sys.argv = ["-c", *argv[3:]]
    exec(compile(_WORKER, "<tetwild worker>", "exec"), {"__name__": "__main__"})
    return True


def _first_start_notice(argv: list[str]) -> None:
    """Compile the kernels behind a small notice window on the first ``play``.

    Only with a display and no kernel cached yet; anything that goes wrong here
    (no fonts, no OpenGL) leaves the compile to the game, which prints its
    terminal notice as usual.
    """
    from pathlib import Path

    if argv[1:2] not in ([], ["play"]) or any(a in ("-h", "--help") for a in argv[1:]):
        return
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        return
    if any(Path(os.environ["NUMBA_CACHE_DIR"]).rglob("*.nbi")):
        return
    import threading

    done, failed = threading.Event(), []

    def compile_kernels():
        try:
            from across_dimensions.app.warmup import warm_up

            warm_up()
        except Exception as e:  # the game will meet (and report) it again
            failed.append(e)
        finally:
            done.set()

    try:
        import pyglet

        window = pyglet.window.Window(600, 120, caption="Across Dimensions", resizable=False)
        label = pyglet.text.Label(
            "Preparing the 4D world (first start only, about a minute)...",
            x=300,
            y=60,
            anchor_x="center",
            anchor_y="center",
            font_size=13,
        )
    except Exception:
        return
    closed = []

    @window.event
    def on_draw():
        window.clear()
        label.draw()

    @window.event
    def on_close():
        closed.append(True)

    def poll(_dt):
        if done.is_set() or closed:
            if not closed:
                window.close()
            pyglet.app.exit()

    threading.Thread(target=compile_kernels, daemon=True).start()
    pyglet.clock.schedule_interval(poll, 0.1)
    pyglet.app.run(0.1)
    pyglet.clock.unschedule(poll)
    if closed and not done.is_set():
        sys.exit(0)  # the player closed the notice: do not start the game behind it


if getattr(sys, "frozen", False) and "NUMBA_CACHE_DIR" not in os.environ:
    os.environ["NUMBA_CACHE_DIR"] = _numba_cache_dir(getattr(sys, "_MEIPASS", os.path.dirname(sys.executable)))

if __name__ == "__main__":
    if _tetwild_worker(sys.argv):
        sys.exit(0)
    if getattr(sys, "frozen", False):
        try:
            _first_start_notice(sys.argv)
        except Exception:  # a notice must never stop the game
            pass
    from across_dimensions.app.cli import main

    sys.exit(main())
