"""The level editor: Dear ImGui panels (imgui-bundle) over the game's own view, in the game's window.

- :mod:`across_dimensions.world.level_edit`: the model (edits, undo/redo, checks, saving); no GUI.
- :mod:`.view`: what the view shows (preview game, picking, outlines, w previews, frustum view); no GUI.
- :mod:`.panels`: the ImGui panels (outline, inspector, w scrubber, menus).
- :mod:`.mode`: the editor's view on the window's stack (:class:`~.mode.EditorView`: events, drawing,
  play from here).

The GUI libraries are an optional extra; :func:`missing` says which are absent
so the command line can say in one line what to install.
"""

from __future__ import annotations

import importlib.util

#: What the optional extra ``editor`` brings, by import name.
EXTRA_MODULES = {"imgui_bundle": "imgui-bundle", "tomlkit": "tomlkit", "OpenGL": "PyOpenGL"}
#: The install line for the game's source folder, as the README gives it.
INSTALL_HINT = 'pip install -e ".[editor]" (in the source folder)'


def missing() -> list[str]:
    """The editor's packages that are not installed (distribution names)."""
    return [dist for mod, dist in EXTRA_MODULES.items() if importlib.util.find_spec(mod) is None]


def missing_message() -> str | None:
    """One line saying what to install, or None when the editor can run."""
    absent = missing()
    if not absent:
        return None
    return f"the level editor needs the optional extra 'editor' ({', '.join(absent)} missing): {INSTALL_HINT}"
