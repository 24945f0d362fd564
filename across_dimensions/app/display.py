"""Whether a window can be opened here, asked without importing pyglet.

pyglet only finds out that ``DISPLAY`` names no running X server when the
first window is made, deep inside the game's start-up, as a
``NoSuchDisplayException``. A connection attempt to the server's socket is
cheap (no X protocol is spoken) and lets ``play`` say so in one line first.
"""

from __future__ import annotations

import os
import re
import socket
import sys

#: Seconds to wait for an X server to accept the connection.
_TIMEOUT = 1.0


def display_problem() -> str | None:
    """A one-line reason no window can open, or None if one probably can."""
    if not sys.platform.startswith("linux"):
        return None
    display = os.environ.get("DISPLAY", "")
    if not display:
        if os.environ.get("WAYLAND_DISPLAY"):
            return None
        return "no display found (DISPLAY is not set)"
    return x_server_problem(display)


def x_server_problem(display: str) -> str | None:
    """Why no X server answers at ``display`` (``":0"``, ``"host:1.0"``), or None if one does.

    Connects to the server's socket and closes it at once: the abstract and
    the file Unix socket for a local display, TCP port ``6000 + n`` for a
    remote one. An address this cannot parse is left for pyglet to judge.
    """
    m = re.fullmatch(r"(?:unix/)?(?P<host>[^:]*):(?P<num>\d+)(?:\.\d+)?", display)
    if not m:
        return None
    host, num = m.group("host"), int(m.group("num"))
    if host in ("", "unix"):
        path = f"/tmp/.X11-unix/X{num}"
        for address in ("\0" + path, path):  # Linux abstract socket first, as Xlib does
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
                s.settimeout(_TIMEOUT)  # a server too busy to accept would otherwise block connect()
                try:
                    s.connect(address)
                    return None
                except OSError:
                    continue
        return f"no X server answers on DISPLAY={display} (nothing listens at {path})"
    try:
        with socket.create_connection((host, 6000 + num), timeout=_TIMEOUT):
            return None
    except OSError as e:
        return f"no X server answers on DISPLAY={display} ({e.strerror or e})"
