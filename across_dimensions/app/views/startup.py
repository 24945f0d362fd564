"""The start-up view: a level named on the command line waits here for the kernels to compile."""

from __future__ import annotations

from pathlib import Path

from ..menu import MenuView
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
    """

    def __init__(self, session, path: Path, checkpoint: int | None = None, edit: bool = False):
        super().__init__(session)
        self.path, self.checkpoint, self.edit = path, checkpoint, edit

    def on_show(self) -> None:
        self.window.set_exclusive_mouse(True)

    def _progress(self) -> tuple[int, int, str]:
        w = self.session.warm
        return (w.done, w.total, w.label) if w is not None and not w.ready else (1, 1, "ready")

    def on_update(self, dt: float) -> None:
        warm = self.session.warm
        if warm is None or warm.ready:
            self.session.start_level(self.path, self.checkpoint)
            if self.edit:
                self.session.open_editor(self.window.current_view, from_play=False)

    def on_draw(self, target, viewport) -> None:
        target.use()
        self.window.ctx.clear(*BACKDROP)
        title = "Starting the editor..." if self.edit else "Starting..."
        view = MenuView("title", "ACROSS DIMENSIONS", [], 0, 0, 0, title, progress=self._progress())
        self.session.menu_renderer.draw(view, viewport)

    def still_frame(self):
        return self._progress(), self.session.notice_text

    def on_key_press(self, symbol, modifiers) -> None:
        action = self.session.bindings.action_of("key", symbol)
        if action == "screenshot":
            self.window_key(action)
