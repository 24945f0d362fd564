"""The frozen game's entry point: the ``across-dimensions`` executable runs this.

It does what the installed console script does (:func:`across_dimensions.app.cli.main`,
same ``--help``, messages and exit statuses) after what only a frozen build needs:

* the kernels compiled by the build, in the folder, are used when the processor runs
  them (:mod:`kernel_target`); otherwise numba compiles into the player's cache folder,
  under a name that changes with every build. A frozen numba stamps cached kernels with
  the executable's hash, and the executable (PyInstaller's bootloader) is the same from
  one release to the next, so a shared folder could load a previous release's kernels.
* no program is run to find a system library: ``ctypes.util.find_library`` runs
  ``ldconfig``, ``gcc`` and ``objdump`` on Linux, and pyglet calls it for every library
  it loads (:func:`_find_library` looks in the loader's folders instead), and pyglet's
  audio drivers are tried in the order a Linux desktop serves them (PulseAudio, which
  PipeWire also speaks, then OpenAL, then silence).
* the first start of the game from a desktop, when kernels must compile and no terminal
  shows the "compiling" notice: a small window says so while they compile.
* the tetrahedralizer's child process (``sys.executable -c WORKER``, see
  :mod:`across_dimensions.world.assets.tetwild`) is served: a frozen
  executable is no Python interpreter, so it runs that one script and nothing else.
"""

import glob
import os
import sys

import kernel_target


def _numba_cache_dir(bundle: str) -> str:
    try:
        with open(os.path.join(bundle, "BUILD_ID"), encoding="ascii") as f:
            build = f.read().strip()[:16]
    except OSError:
        build = "unknown"
    import platformdirs

    return os.path.join(platformdirs.user_cache_dir("across-dimensions"), f"numba-{build}")


def _choose_kernels(bundle: str) -> None:
    """Point numba at the shipped kernels when this processor runs them (or the build fills them)."""
    shipped = os.path.join(bundle, kernel_target.FOLDER)
    if os.environ.get(kernel_target.FILL_ENV) != "1":
        # A CPU target the player chose is honoured: it has no kernels in the folder.
        if "NUMBA_CPU_NAME" in os.environ or not os.path.isdir(shipped) or not kernel_target.runs_baseline():
            return
    os.environ["NUMBA_CPU_NAME"] = kernel_target.BASELINE_CPU
    os.environ["NUMBA_CPU_FEATURES"] = ""  # the features the name implies, not this machine's
    os.environ[kernel_target.SHIPPED_ENV] = shipped
    os.environ["NUMBA_CACHE_LOCATOR_CLASSES"] = (
        "frozen_kernels.ShippedLocator,numba.core.caching.UserProvidedCacheLocator"
    )


def _library_folders() -> list[str]:
    """The dynamic loader's folders: LD_LIBRARY_PATH (the bundle's, set by the bootloader),
    /etc/ld.so.conf and its includes, then the default ones."""
    folders = [d for d in os.environ.get("LD_LIBRARY_PATH", "").split(os.pathsep) if d]
    pending = ["/etc/ld.so.conf"]
    while pending:
        try:
            with open(pending.pop(0), encoding="utf-8", errors="replace") as f:
                lines = [line.split("#")[0].strip() for line in f]
        except OSError:
            continue
        for line in lines:
            if line.startswith("include "):
                pending += sorted(glob.glob(line.split(None, 1)[1]))
            elif line.startswith("/"):
                folders.append(line)
    return folders + ["/lib64", "/usr/lib64", "/lib", "/usr/lib"]


def _find_library(name: str) -> str | None:
    """``ctypes.util.find_library`` without running a program: the file name of the
    first ``libNAME.so.N`` in the loader's folders (lowest version when several)."""
    for folder in _library_folders():
        found = sorted(glob.glob(os.path.join(glob.escape(folder), f"lib{glob.escape(name)}.so.*")), key=len)
        if found:
            return os.path.basename(found[0])
    return None


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
    if kernel_target.SHIPPED_ENV in os.environ or any(Path(os.environ["NUMBA_CACHE_DIR"]).rglob("*.nbi")):
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


if getattr(sys, "frozen", False):
    _bundle = getattr(sys, "_MEIPASS", os.path.dirname(sys.executable))
    if "NUMBA_CACHE_DIR" not in os.environ:
        os.environ["NUMBA_CACHE_DIR"] = _numba_cache_dir(_bundle)
    _choose_kernels(_bundle)
    if sys.platform.startswith("linux"):
        import ctypes.util

        ctypes.util.find_library = _find_library
        os.environ.setdefault("PYGLET_AUDIO", "pulse,openal,silent")

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
