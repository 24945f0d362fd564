"""The energy bar's own tick and its place on the HUD (spending and gaining live in
the systems that pay or collect, through ``game.energy``)."""

from __future__ import annotations

from ..energy import FLASH_TICKS, EnergyBar
from ..frame import EnergyGauge
from ..system import System, encode


def setup(game) -> EnergyBar | None:
    """The bar (``game.energy``), or None when the level has no energy rules (moving along w is free)."""
    spec = game.level.energy
    return EnergyBar.of(spec.start, spec.maximum) if spec.enabled else None


def step(game, actions) -> None:
    if game.energy is not None:
        game.energy.tick()


def draw(game, frame, alpha) -> None:
    bar = game.energy
    if bar is not None:
        frame.hud.energy = EnergyGauge(bar.value, bar.maximum, bar.flash / FLASH_TICKS, empty=bar.milli == 0)


def state_bytes(game) -> bytes:
    return encode(game.energy)


SYSTEM = System("energy", setup, step, draw, state_bytes)
