"""Headless frames: draw the game offscreen (EGL) and save PNGs.

Only created when images are asked for, so a plain headless replay needs no
OpenGL at all.
"""

from __future__ import annotations

from pathlib import Path

from ..render.context import Offscreen, create_offscreen_context
from ..render.renderer import Renderer


class Screenshotter:
    """Saves ``game.frame()`` every ``every`` ticks as ``DIR/frame_NNNNN.png``.

    Parameters
    ----------
    game : Game
    folder : Path
        Created if missing.
    size : (int, int)
        Width and height in pixels.
    every : int
        Ticks between images; tick 0 is always saved.
    """

    def __init__(self, game, folder: Path, size: tuple[int, int], every: int):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.ctx = create_offscreen_context()
        self.target = Offscreen(self.ctx, *size)
        self.renderer = Renderer(self.ctx)
        self.every = every
        self.count = 0
        self(game)  # the starting view

    def __call__(self, game) -> None:
        if game.tick % self.every:
            return
        self.save(game, self.folder / f"frame_{game.tick:05d}.png")

    def save(self, game, path: Path) -> None:
        self.target.use()
        self.renderer.draw(game.frame(), self.target.viewport)
        self.target.save_png(path)
        self.count += 1

    def close(self) -> None:
        self.renderer.release()
        self.target.release()
        self.ctx.release()
