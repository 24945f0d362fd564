"""The energy bar's own tick and its place on the HUD (spending and gaining live in
the systems that pay or collect, through ``game.energy``)."""

from __future__ import annotations

from .. import slice_pay
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


def cost_line(level, weapons=None) -> str:
    """What each 4D action of ``level`` costs, in the HUD's words: moving along w per unit,
    each weapon per use (of ``weapons``, those the player owns; default the level's), turning
    an object per degree, the frustum camera per second, a 90-degree turn of the slice."""
    parts = []
    if level.energy.w_cost > 0 and level.w_range[1] > level.w_range[0]:
        parts.append(f"W {level.energy.w_cost:g}/UNIT")
    for spec in level.weapons if weapons is None else weapons:
        if spec.cost_milli > 0 and (spec.kind != "gun" or spec.ammo < 0):
            parts.append(f"{spec.kind.upper()} {spec.cost_milli / 1000:g}")
    turns = sorted({m.cost_milli for m in level.manipulables if m.cost_milli > 0})
    if turns:
        parts.append(f"TURN {turns[0] / 1000:g}/DEG" if len(turns) == 1 else f"TURN {turns[0] / 1000:g}+/DEG")
    if level.camera.frustum and level.camera.frustum_cost > 0:
        parts.append(f"VIEW {level.camera.frustum_cost:g}/S")
    if level.camera.turn and level.energy.slice_cost > 0:  # priced by the 90-degree step the keys take
        parts.append(f"SLICE {slice_pay.step_price(level.energy.slice_cost_milli) / 1000:g}/90DEG")
    return "  ".join(parts)


def draw(game, frame, alpha) -> None:
    bar = game.energy
    if bar is not None:
        flash = bar.flash / FLASH_TICKS
        ars = game.states.weapons
        owned = [] if ars is None else [s for s, has in zip(ars.specs, ars.owned) if has]
        costs = cost_line(game.level, owned)
        frame.hud.energy = EnergyGauge(bar.value, bar.maximum, flash, bar.milli == 0, costs=costs)


def state_bytes(game) -> bytes:
    return encode(game.energy)


SYSTEM = System("energy", setup, step, draw, state_bytes)
