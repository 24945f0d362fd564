"""The player's weapons, before physics runs: pickups, switching, firing, the blast's pull, the field's timer.

Walking into a ``[[pickup]]`` (touching its cross-section, as with a crystal) gives its weapon
and puts it in hand; the HUD then says for a few seconds what it does, its key and its cost.
Presses (``next_weapon``, ``previous_weapon``, ``weapon_1`` ... ``weapon_3``, ``fire``) are
one-shot actions, so a quick tap is never lost; they reach only weapons the player owns, and
each number key always takes the same kind (1 the gun, 2 the blast, 3 the field). Using a weapon
costs its ``cost`` from the energy bar (free in a level without one), or one
round for a gun with ammunition (crystals refill it), and starts its cooldown;
without enough energy or rounds nothing fires and the HUD says so. See
:mod:`..weapons` for what each weapon does.
"""

from __future__ import annotations

from ...core.shapes import make_shape
from ...world.gameplay import WEAPON_KINDS
from ...world.scene import build_physics
from .. import weapons as wp
from ..entities import reach
from ..events import Blast, FieldCast, ShotFired, WeaponRefused, WeaponSelected
from ..frame import WeaponPanel
from ..system import System, encode
from .crystals import touching


def setup(game) -> wp.Arsenal | None:
    """The arsenal, with the level's targets and pickups spawned; None in a level without
    weapons or targets."""
    level = game.level
    specs, targets = list(level.weapons), list(level.targets)
    if not specs and not targets:
        return None
    if game.physics is None and any(s.kind == "gun" for s in specs):
        game.physics, _ = build_physics(game.scene, game.dt)  # bullets are bodies
    mesh = make_shape("120-cell").with_color(wp.BULLET_COLOR)
    rounds = [s.ammo if s.kind == "gun" else -1 for s in specs]
    owned = [s.kind in level.arsenal for s in specs]
    slot = owned.index(True) if any(owned) else 0
    ars = wp.Arsenal(specs, owned, slot, [0] * len(specs), rounds=rounds, bullet_mesh=mesh, bullet_reach=reach(mesh))
    for t in targets:
        wp.spawn_target(game, t)
    for p in level.pickups:
        wp.spawn_pickup(game, p)
    return ars


def state_bytes(game) -> bytes:
    """The arsenal; bullets and targets are entities (their data is hashed with them)."""
    return encode(game.states.weapons)


def _pick_up(game) -> None:
    """Take every pickup the player touches."""
    for e in list(game.entities.of_kind("pickup")):
        if touching(game, e):
            wp.acquire(game, e)


def _select(game, ars, actions) -> None:
    owned = [k for k, has in enumerate(ars.owned) if has]
    step = actions.pressed("next_weapon") - actions.pressed("previous_weapon")
    slot = owned[(owned.index(ars.slot) + step) % len(owned)]
    for k, kind in enumerate(WEAPON_KINDS):
        if actions.pressed(f"weapon_{k + 1}") and ars.slot_of(kind) is not None:
            slot = ars.slot_of(kind)
    if slot != ars.slot:
        ars.slot = slot
        game.emit(WeaponSelected(slot, ars.current.kind))


def _use(game, ars) -> None:
    spec = ars.current
    if game.tick < ars.ready[ars.slot]:
        game.emit(WeaponRefused(spec.kind, "cooldown"))
        return
    if ars.rounds[ars.slot] == 0:
        ars.refused_tick, ars.refused_text = game.tick, "OUT OF AMMO"
        game.emit(WeaponRefused(spec.kind, "ammo"))
        return
    if ars.rounds[ars.slot] > 0:
        ars.rounds[ars.slot] -= 1
    elif game.energy is not None and not game.energy.spend(game, spec.cost_milli, spec.kind):
        ars.refused_tick, ars.refused_text = game.tick, "NOT ENOUGH ENERGY"
        game.emit(WeaponRefused(spec.kind, "energy"))
        return
    ars.ready[ars.slot] = game.tick + max(1, round(spec.cooldown / game.dt))
    ars.fired_tick = game.tick
    w = float(game.player.position[3])
    if spec.kind == "gun":
        e = wp.fire_bullet(game, spec)
        game.emit(ShotFired(e.id, w))
    elif spec.kind == "blast":
        game.emit(Blast(w, tuple(wp.blast(game, spec))))
    else:
        shown = wp.cast_field(game, spec)
        game.emit(FieldCast(tuple(shown), max(1, round(spec.duration / game.dt))))


def step(game, actions) -> None:
    ars = game.states.weapons
    if ars is None:
        return
    wp.expire_field(game)
    _pick_up(game)
    wp.refill(game)
    if ars.armed:
        _select(game, ars, actions)
        for _ in range(actions.pressed("fire")):
            _use(game, ars)
    wp.advance_pulls(game)
    if ars.bullets:
        wp.steer_bullets(game)


def draw(game, frame, alpha) -> None:
    ars = game.states.weapons
    if ars is None or not ars.armed:
        return
    spec = ars.current
    if game.tick - ars.acquired_tick < wp.ACQUIRED_TICKS and not frame.hud.message:
        frame.hud.message = wp.acquired_notice(ars.specs[ars.acquired], game.energy is not None)
    left = ars.ready[ars.slot] - game.tick
    total = max(1, round(spec.cooldown / game.dt))
    owned = [k for k, has in enumerate(ars.owned) if has]
    frame.hud.weapon = WeaponPanel(
        spec.name,
        owned.index(ars.slot) + 1,
        len(owned),
        spec.cost_milli / 1000,
        cooldown=min(max(left / total, 0.0), 1.0),
        flash=max(0.0, 1.0 - (game.tick - ars.fired_tick) / wp.FLASH_TICKS),
        refused=ars.refused_text if game.tick - ars.refused_tick < wp.REFUSED_TICKS else "",
        live=len(ars.bullets) if spec.kind == "gun" else -1,
        ammo=ars.rounds[ars.slot],
    )
    frame.hud.hit_marker = max(0.0, 1.0 - (game.tick - ars.hit_tick) / wp.HIT_MARKER_TICKS)


SYSTEM = System("weapons", setup, step, draw, state_bytes)
