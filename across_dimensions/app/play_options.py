"""The play view's toggles, as the settings start them (kept from level to level)."""

from __future__ import annotations

from dataclasses import dataclass

from ..game.systems.ghosts import GhostView
from .settings import Settings


@dataclass
class PlayOptions:
    """The play view's toggles, kept from level to level: the FPS counter, the
    picture-in-picture inset (render/pip.py), the ghosts and the physics debug overlay."""

    show_fps: bool
    pip: bool
    ghosts: GhostView
    debug_draw: bool = False


def play_options(settings: Settings) -> PlayOptions:
    """The play view's toggles as the settings start them."""
    ghosts = GhostView(settings.ghosts, settings.ghost_distance, settings.ghost_strength, settings.ghost_layers)
    return PlayOptions(settings.show_fps, settings.pip, ghosts)
