"""The frozen game's entry point: the ``across-dimensions`` executable runs this.

It does what the installed console script does (:func:`across_dimensions.app.cli.main`,
same ``--help``, messages and exit statuses) after two things only a frozen build needs:

* the numba kernel cache goes in the player's cache folder under a name that
  changes with every build. A frozen numba stamps cached kernels with the
  executable's hash, and the executable (PyInstaller's bootloader) is the same
  from one release to the next, so a shared folder could load a previous
  release's kernels.
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


if getattr(sys, "frozen", False) and "NUMBA_CACHE_DIR" not in os.environ:
    os.environ["NUMBA_CACHE_DIR"] = _numba_cache_dir(getattr(sys, "_MEIPASS", os.path.dirname(sys.executable)))

if __name__ == "__main__":
    if _tetwild_worker(sys.argv):
        sys.exit(0)
    from across_dimensions.app.cli import main

    sys.exit(main())
