"""The energy bar's own tick and its place on the HUD (spending and gaining live in
the systems that pay or collect, through ``game.energy``)."""

from __future__ import annotations

from ..energy import FLASH_TICKS
from ..frame import EnergyGauge


def step(game, actions) -> None:
    if game.energy is not None:
        game.energy.tick()


def draw(game, frame, alpha) -> None:
    bar = game.energy
    if bar is not None:
        frame.hud.energy = EnergyGauge(bar.value, bar.maximum, bar.flash / FLASH_TICKS, empty=bar.milli == 0)
