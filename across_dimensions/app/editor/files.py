"""The editor's File menu: New (from the empty-room template or a copy of a shipped level), Open,
Save, Save As, the recent files, and the prompt before unsaved changes are lost.

Paths are typed (a text field, with the level's folder filled in): the editor runs where no file
dialog may exist. The recent files live in ``editor_recent.json`` in the game's data folder,
written atomically; a missing or broken list is an empty one.
"""

from __future__ import annotations

import json
from pathlib import Path

from imgui_bundle import imgui

from ...core import fileio
from ...core.errors import InputError
from ...world.level_template import TEMPLATE_NAME, template_names, template_text
from ..saves import data_folder

RECENT_FILE = "editor_recent.json"
RECENT_MAX = 8
RECENT_LIMIT = 64 * 1024  # bytes: a list of 8 paths
PROMPT = "Unsaved changes"


def load_recent() -> list[str]:
    """The recent level files, newest first (an unreadable list is an empty one)."""
    try:
        data = json.loads(fileio.read_bytes(data_folder() / RECENT_FILE, limit=RECENT_LIMIT, what="recent files"))
    except (OSError, InputError, ValueError):
        return []
    return [p for p in data if isinstance(p, str)][:RECENT_MAX] if isinstance(data, list) else []


class Files:
    """The File menu and its dialogs for an :class:`~.mode.EditorView`."""

    def __init__(self, mode):
        self.mode = mode
        self.recent = load_recent()
        self.dialog = None  # "New level", "Open level", "Save as" or PROMPT: opened on the next frame
        self.pending = None  # what the unsaved-changes prompt goes on with: a callable
        self.path_text = ""
        self.name_text = "New level"
        self.template = 0

    @property
    def model(self):
        return self.mode.model

    # ------------------------------------------------------------ actions
    def remember(self, path) -> None:
        """``path`` was opened or saved: first in the recent list (saved; a failure is only said)."""
        p = str(Path(path).resolve())
        self.recent = [p, *[r for r in self.recent if r != p]][:RECENT_MAX]
        try:
            fileio.atomic_write(data_folder() / RECENT_FILE, json.dumps(self.recent, indent=1).encode("utf-8"))
        except (OSError, InputError) as e:
            self.mode.message = f"recent files not saved: {e}"

    def _unsaved_then(self, action) -> None:
        """Do ``action``, after asking when there are unsaved changes."""
        if self.model.dirty:
            self.pending, self.dialog = action, PROMPT
        else:
            action()

    def _folder(self) -> Path:
        return self.model.path.resolve().parent

    def ask_new(self) -> None:
        def go():
            self.path_text = str(_unused(self._folder() / "new_level.toml"))
            self.dialog = "New level"

        self._unsaved_then(go)

    def ask_open(self, path: str | None = None) -> None:
        def go():
            if path is not None:
                self.open(path)
            else:
                self.path_text, self.dialog = str(self._folder()) + "/", "Open level"

        self._unsaved_then(go)

    def save_as(self) -> None:
        self.path_text, self.dialog = str(self.model.path.resolve()), "Save as"

    def new(self, path: str, choice: str, name: str) -> bool:
        """Start a new level at ``path`` (not written until saved); False when it cannot start."""
        target = Path(path).expanduser()
        if target.exists():
            self.mode.message = f"{target.name} exists: open it, or choose another name"
            return False
        if not target.parent.is_dir():
            self.mode.message = f"no folder {target.parent}"
            return False
        self.mode.open(target, template_text(choice, name))
        self.mode.message = f"new level {target.name} from {choice} - Ctrl+S saves it"
        return True

    def open(self, path: str) -> bool:
        try:
            self.mode.open(Path(path).expanduser())
        except (InputError, OSError) as e:
            self.mode.message = f"cannot open: {str(e).splitlines()[0]}"
            return False
        self.remember(path)
        self.mode.message = f"opened {Path(path).name}"
        return True

    def save_to(self, path: str) -> bool:
        try:
            saved = self.model.save_as(Path(path).expanduser())
        except (InputError, OSError) as e:
            self.mode.message = f"not saved: {str(e).splitlines()[0]}"
            return False
        self.remember(saved)
        self.mode.message = f"saved as {saved.name}"
        return True

    def confirm_close(self) -> bool:
        """The window is asked to close: True keeps it open (to ask about unsaved changes first)."""
        if not self.model.dirty:
            return False
        self.pending, self.dialog = self.mode.window.close, PROMPT
        return True

    # ------------------------------------------------------------ drawing
    def menu(self) -> None:
        """The File menu's items (inside ``begin_menu("File")``)."""
        m, mode = self.model, self.mode
        if imgui.menu_item("New...", "Ctrl+N", False)[0]:
            self.ask_new()
        if imgui.menu_item("Open...", "Ctrl+O", False)[0]:
            self.ask_open()
        if imgui.begin_menu("Open recent", bool(self.recent)):
            for p in self.recent:
                if imgui.menu_item(p, "", False)[0]:
                    self.ask_open(p)
            imgui.end_menu()
        imgui.separator()
        if imgui.menu_item("Save", "Ctrl+S", False, m.dirty)[0]:
            mode.save()
        if imgui.menu_item("Save as...", "Ctrl+Shift+S", False)[0]:
            self.save_as()
        if imgui.menu_item("Revert to saved", "", False, m.dirty and m.path.exists())[0]:
            mode.revert()

    def draw(self) -> None:
        """The dialog asked for, if any (a modal window in the middle of the view)."""
        if self.dialog is not None:
            imgui.open_popup(self.dialog)
            self.dialog = None
        io = imgui.get_io()
        center = imgui.ImVec2(io.display_size.x / 2, io.display_size.y / 2)
        for title, body in (("New level", self._new), ("Open level", self._open), ("Save as", self._save_as)):
            imgui.set_next_window_pos(center, imgui.Cond_.appearing, imgui.ImVec2(0.5, 0.5))
            imgui.set_next_window_size(imgui.ImVec2(560, 0), imgui.Cond_.appearing)
            if imgui.begin_popup_modal(title, None, imgui.WindowFlags_.no_saved_settings)[0]:
                body()
                imgui.end_popup()
        imgui.set_next_window_pos(center, imgui.Cond_.appearing, imgui.ImVec2(0.5, 0.5))
        if imgui.begin_popup_modal(PROMPT, None, imgui.WindowFlags_.always_auto_resize)[0]:
            self._prompt()
            imgui.end_popup()

    def _path_field(self, label: str) -> bool:
        """The path's text field, filled in (click it to change it); True when Enter was pressed in it."""
        imgui.push_item_width(-1)
        imgui.text(label)
        _, self.path_text = imgui.input_text("##path", self.path_text)
        entered = imgui.is_item_deactivated() and imgui.is_key_pressed(imgui.Key.enter)
        imgui.pop_item_width()
        return entered

    def _buttons(self, ok: str) -> bool | None:
        """OK and Cancel: True for OK, False for Cancel (the popup is closed), None for neither."""
        if imgui.button(ok, imgui.ImVec2(120, 0)) or imgui.is_key_pressed(imgui.Key.enter):
            return True
        imgui.same_line()
        if imgui.button("Cancel", imgui.ImVec2(120, 0)) or imgui.is_key_pressed(imgui.Key.escape):
            imgui.close_current_popup()
            return False
        return None

    def _new(self) -> None:
        names = template_names()
        imgui.text("Start from")
        imgui.push_item_width(-1)
        _, self.template = imgui.combo("##template", self.template, names)
        imgui.pop_item_width()
        if names[self.template] == TEMPLATE_NAME:
            imgui.text("Level name")
            imgui.push_item_width(-1)
            _, self.name_text = imgui.input_text("##name", self.name_text)
            imgui.pop_item_width()
        self._path_field("Save it as (written by Save)")
        if self._buttons("Create") and self.new(self.path_text, names[self.template], self.name_text):
            imgui.close_current_popup()

    def _open(self) -> None:
        self._path_field("Level file")
        if self._buttons("Open") and self.open(self.path_text):
            imgui.close_current_popup()

    def _save_as(self) -> None:
        self._path_field("Save the level as")
        if self._buttons("Save") and self.save_to(self.path_text):
            imgui.close_current_popup()

    def _prompt(self) -> None:
        imgui.text(f"{self.model.path.name} has unsaved changes.")
        if imgui.button("Save", imgui.ImVec2(110, 0)):
            imgui.close_current_popup()
            if self.mode.save():
                self._go_on()
            else:
                self.pending = None
        imgui.same_line()
        if imgui.button("Discard", imgui.ImVec2(110, 0)):
            imgui.close_current_popup()
            self.model.saved_text = self.model.text()  # nothing left to lose
            self._go_on()
        imgui.same_line()
        if imgui.button("Cancel", imgui.ImVec2(110, 0)) or imgui.is_key_pressed(imgui.Key.escape):
            imgui.close_current_popup()
            self.pending = None

    def _go_on(self) -> None:
        action, self.pending = self.pending, None
        if action is not None:
            action()


def _unused(path: Path) -> Path:
    """``path``, or ``path`` with a number added when it exists (``new_level_2.toml``)."""
    k = 2
    out = path
    while out.exists():
        out = path.with_name(f"{path.stem}_{k}{path.suffix}")
        k += 1
    return out
