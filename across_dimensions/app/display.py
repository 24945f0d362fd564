"""Whether a window can be opened here, asked without importing pyglet."""

from __future__ import annotations

import os
import sys


def display_problem() -> str | None:
    """A one-line reason no window can open, or None if one probably can."""
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        return "no display found (DISPLAY is not set)"
    return None
