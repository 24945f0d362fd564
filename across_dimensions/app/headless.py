"""Headless frames: draw the game offscreen (EGL) and save PNGs.

Only created when images are asked for, so a plain headless replay needs no
OpenGL at all.
"""

from __future__ import annotations

from pathlib import Path

from ..core.fileio import FileProblem
from ..render.context import Offscreen, create_offscreen_context
from ..render.renderer import Renderer


class Screenshotter:
    """Saves ``game.frame()`` every ``every`` ticks as ``DIR/frame_NNNNN.png``.

    Parameters
    ----------
    game : Game
    folder : Path
        Created if missing, but not its parents: a typo must not scatter
        folders over the disk.
    size : (int, int)
        Width and height in pixels.
    every : int
        Ticks between images; tick 0 is always saved.
    """

    def __init__(self, game, folder: Path, size: tuple[int, int], every: int):
        self.folder = ensure_folder(folder)
        self.ctx = create_offscreen_context()
        self.target = Offscreen(self.ctx, *size)
        self.renderer = self._renderer()
        self.every = every
        self.count = 0
        self(game)  # the starting view

    def _renderer(self):
        return Renderer(self.ctx)

    def __call__(self, game) -> None:
        if game.tick % self.every:
            return
        self.save(game, self.folder / f"frame_{game.tick:05d}.png")

    def save(self, game, path: Path) -> None:
        from .onboarding import with_keys
        from .settings import default_settings

        frame = game.frame()
        # The game's prompts and labels name actions ({manipulate}); the window shows the
        # player's keys, and a screenshot the default ones, never the raw placeholders.
        keys = default_settings()
        frame.hud.message = with_keys(frame.hud.message, keys)
        for label in frame.hud.labels:
            label.text = with_keys(label.text, keys)
        self.target.use()
        self.renderer.draw(frame, self.target.viewport)
        self.target.save_png(path)
        self.count += 1

    def close(self) -> None:
        self.renderer.release()
        self.target.release()
        self.ctx.release()


class FlatScreenshotter(Screenshotter):
    """:class:`Screenshotter` for a Flatland prologue game: its side view with its hint (the default
    keys filled in) and, after the goal, the turn to the 3D world."""

    def __init__(self, game, folder: Path, size: tuple[int, int], every: int):
        from ..game.flatland.hints import StateHints
        from .settings import default_settings

        self.hints = StateHints(game.level.hints)
        self.settings = default_settings()
        super().__init__(game, folder, size, every)

    def _renderer(self):
        from ..render.flatland import FlatRenderer

        return FlatRenderer(self.ctx)

    def __call__(self, game) -> None:
        if game.tick:  # called after every tick: the hints follow the game's state
            self.hints.tick(game, game.dt)
        super().__call__(game)

    def save(self, game, path: Path) -> None:
        from ..game.flatland.view import flat_frame
        from .onboarding import fill_keys

        h, i = self.hints.current(), self.hints.current_index()
        text = fill_keys(h.text, self.settings) if h is not None else ""
        label = f"hint {i + 1}/{len(self.hints.specs)}" if h is not None else ""
        self.target.use()
        self.renderer.draw(flat_frame(game, hint=text, hint_label=label), self.target.viewport)
        self.target.save_png(path)
        self.count += 1


def ensure_folder(folder) -> Path:
    """``folder``, created if missing when its parent exists.

    Raises
    ------
    FileProblem
        The parent is missing, or ``folder`` is a file, or cannot be created.
    """
    folder = Path(folder)
    if folder.is_dir():
        return folder
    if folder.exists():
        raise FileProblem(f"{folder}: is a file (expected a folder for the screenshots)")
    if not folder.parent.is_dir():
        raise FileProblem(f"{folder}: the folder {folder.parent} does not exist (only {folder.name} is created)")
    try:
        folder.mkdir()
    except OSError as e:
        raise FileProblem(f"{folder}: cannot create it ({e.strerror or e})") from None
    return folder
