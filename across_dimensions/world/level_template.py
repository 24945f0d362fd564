"""New levels for the editor: the empty-room template, or a copy of a shipped level.

The template is the smallest level worth building on: a closed room (floor and four walls) with
a spawn at one end, the goal pad at the other and a w range, laid out in the sections the
shipped levels use, so entries the editor adds land in the right place
(:mod:`.level_style`).
"""

from __future__ import annotations

from pathlib import Path

from ..core import fileio
from .limits import MAX_LEVEL_BYTES
from .resources import level_files

TEMPLATE_NAME = "Empty room"

EMPTY_ROOM = """\
# {name}: a new level, started from the editor's empty-room template.

[level]
format = 2
name = "{name}"
description = "An empty room: build from here."
w_range = [-1.0, 2.0]   # how far along w the player may move
hints = ["Walk to the glowing pad at the far end."]

[design]   # what the level teaches; the design probe checks that it is needed
needs = []

[spawn]
position = [0.0, 0.0, -8.0, 0.0]   # x, y (feet), z, w
yaw = 0.0                          # degrees; 0 looks along +z

[goal]
center = [0.0, 1.0, 8.0]
size = [2.6, 2.0, 2.0]

# ---- the room ------------------------------------------------------------
[[box]]   # floor
center = [0.0, -0.5, 0.0]
size = [10.0, 1.0, 20.0]
color = [0.32, 0.34, 0.38]

[[box]]   # left wall
center = [-5.25, 2.0, 0.0]
size = [0.5, 4.0, 20.0]
color = [0.55, 0.56, 0.6]

[[box]]   # right wall
center = [5.25, 2.0, 0.0]
size = [0.5, 4.0, 20.0]
color = [0.55, 0.56, 0.6]

[[box]]   # back wall
center = [0.0, 2.0, -10.25]
size = [11.0, 4.0, 0.5]
color = [0.45, 0.46, 0.5]

[[box]]   # far wall
center = [0.0, 2.0, 10.25]
size = [11.0, 4.0, 0.5]
color = [0.45, 0.46, 0.5]

[[box]]   # exit pad
center = [0.0, 0.05, 8.0]
size = [2.6, 0.1, 1.8]
color = [0.95, 0.8, 0.25]
"""


def template_names() -> list[str]:
    """What New can start from: the empty room, then every shipped level by file name."""
    return [TEMPLATE_NAME, *(p.stem for p in level_files())]


def template_text(choice: str, name: str = "New level") -> str:
    """The text of a new level: the empty room named ``name``, or a copy of shipped level ``choice``.

    Raises
    ------
    KeyError
        ``choice`` is neither.
    """
    if choice == TEMPLATE_NAME:
        return EMPTY_ROOM.format(name=name.replace('"', "'"))
    for p in level_files():
        if p.stem == choice:
            return fileio.read_bytes(Path(p), limit=MAX_LEVEL_BYTES, what="level").decode("utf-8-sig")
    raise KeyError(choice)
