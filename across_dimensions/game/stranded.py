"""Telling that a level can no longer be won, so the game can say so and offer a restart.

What the game can tell from its own state, without knowing the player's plan, is the energy
argument of the design probe's proofs (:mod:`across_dimensions.probe.proofs`): the things
every route must still do cost more than the bar holds, and nothing can refill it. Every
route must still

- throw each switch that opens a door still standing (one shot each),
- beat each enemy that opens a gate still standing (one shot per point of health),
- reach the goal's w, when it has a w range the player is outside of.

Each is counted at its least (the cheapest shot, the shortest way along w), so a level
said to be lost is lost whatever the player does next. Nothing can refill the bar when no
crystal lies in the level or grows back and no enemy still carries loot a shot could free.
A key object pushed out of reach is not judged here: a level gives such an object a reset
beacon (``[[beacon]]``, :mod:`.systems.beacons`), which brings it back.
"""

from __future__ import annotations

#: The action that restarts from the last checkpoint once the level is lost (app keymap).
RESTART_ACTION = "restart_checkpoint"


def shot_milli(game) -> int | None:
    """The cheapest shot in thousandths: 0 with rounds in a gun, None without a gun."""
    ars = game.states.weapons
    costs = []
    for k, spec in enumerate(game.level.weapons):  # a gun lying in a pickup counts: it can be taken
        if spec.kind == "gun":
            rounds = ars.rounds[k] if ars is not None else spec.ammo
            costs.append(0 if rounds > 0 else spec.cost_milli)
    return min(costs) if costs else None


def can_refill(game) -> bool:
    """Could the bar still fill: a crystal lying or growing back, or loot a shot can free?"""
    if any(True for _ in game.entities.of_kind("crystal")):
        return True
    regrowth = game.states.crystals
    if regrowth is not None and regrowth.regrowing:
        return True
    hive = game.states.enemies
    loot = hive is not None and any(
        (e := game.entities.get(i)) is not None and e.data.alive and e.data.loot is not None for i in hive.foes
    )
    shot = shot_milli(game)
    bar = game.energy.milli if game.energy is not None else 0
    return loot and (shot == 0 or bar > 0)


def _standing(game, name: str) -> bool:
    return bool(name) and any(e.name == name for e in game.entities.of_kind("object"))


def least_needed(game) -> tuple[int, list[str]]:
    """What every route still has to pay at the least, in thousandths, and for what."""
    need, what = 0, []
    shot = shot_milli(game) or 0
    for t in game.entities.of_kind("target"):
        if not t.data.hit and _standing(game, t.data.spec.opens):
            need += shot
            what.append(f"a shot at '{t.name}'")
    hive = game.states.enemies
    for i in hive.foes if hive is not None else ():
        e = game.entities.get(i)
        if e is not None and e.data.alive and _standing(game, e.data.spec.opens):
            need += shot * e.data.health
            what.append(f"{e.data.health} hits on '{e.name}'")
    wr, w = game.level.goal.w_range, float(game.player.position[3])
    if wr is not None and not wr[0] <= w <= wr[1]:
        need += int(min(abs(w - wr[0]), abs(w - wr[1])) * game.level.energy.w_cost_milli)
        what.append("the way along w to the exit")
    return need, what


def stranded(game) -> str | None:
    """Why the level can no longer be won, in a sentence, or None while it still can."""
    bar = game.energy
    if bar is None or game.outcome is not None or can_refill(game):
        return None
    need, what = least_needed(game)
    if need <= bar.milli:
        return None
    return f"Out of energy ({bar.value:g} left, {need / 1000:g} needed for {', '.join(what)}) and nothing refills it"


def notice(game) -> str | None:
    """The line the HUD shows while the level is lost (``{restart_checkpoint}`` names the key)."""
    why = stranded(game)
    if why is None:
        return None
    where = "the last checkpoint" if game.checkpoint is not None else "the start"
    return f"{why}. Press {{{RESTART_ACTION}}} to restart from {where}."
