"""The start-up view: a level waits here for the kernels to compile (Esc goes back to the title,
where the compile goes on)."""

from __future__ import annotations

from pathlib import Path

import pyglet

from ..menu import MenuView
from ..warmup import warm_progress
from .base import View
from .menus import BACKDROP


class StartupView(View):
    """The title's backdrop with the kernel compile's progress, until the level can start.

    Parameters
    ----------
    session : Session
    path : Path
        The level waiting.
    checkpoint : int or None
        Where in it to start.
    edit : bool
        Open it in the level editor (``edit LEVEL``), which builds games from its first frame.
    trial : bool
        Play it as a time trial.
    """

    def __init__(self, session, path: Path, checkpoint: int | None = None, edit: bool = False, trial: bool = False):
        super().__init__(session)
        self.path, self.checkpoint, self.edit, self.trial = path, checkpoint, edit, trial

    def on_show(self) -> None:
        self.window.set_exclusive_mouse(True)

    def _progress(self) -> tuple:
        return warm_progress(self.session.warm) or (1, 1, "ready")

    def on_update(self, dt: float) -> None:
        warm = self.session.warm
        if warm is None or warm.ready:
            self.session.start_level(self.path, self.checkpoint, self.trial)
            if self.edit:
                self.session.open_editor(self.window.current_view, from_play=False)

    def on_draw(self, target, viewport) -> None:
        target.use()
        self.window.ctx.clear(*BACKDROP)
        title = "Starting the editor..." if self.edit else "Starting..."
        footer = f"{title}  Esc: back to the title (the preparation goes on)"
        view = MenuView("title", "ACROSS DIMENSIONS", [], 0, 0, 0, footer, progress=self._progress())
        self.session.menu_renderer.draw(view, viewport)

    def still_frame(self):
        return self._progress(), self.session.notice_text

    def on_key_press(self, symbol, modifiers) -> None:
        action = self.session.bindings.action_of("key", symbol)
        if symbol == pyglet.window.key.ESCAPE or action == "pause":
            self.session.to_title()
        elif action == "screenshot":
            self.window_key(action)
