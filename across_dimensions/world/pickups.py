"""``[[pickup]]``: a weapon lying in the level, and the arsenal the player brings along the campaign.

A level never hands out weapons. The player finds each one lying somewhere (a
``[[pickup]]``), walks into it and owns it from then on, in this level and in every
later level of the campaign::

    [[pickup]]
    weapon = "gun"                    # gun, blast or field
    position = [0.0, 1.0, -9.0, 0.0]  # where it floats, x y z w

A level's *starting arsenal* is what the campaign has given by then: the weapons of the
pickups in the levels before it in ``levels/campaign.toml`` (:func:`campaign_arsenal`),
so playing a later level from the command line, from a fresh save or from a replay gives
the same weapons. A level outside the campaign starts with none.

``[[weapon]]`` tables only say how a weapon behaves in this level (its cost, its swing,
...); they give nothing. A kind the level does not tune has the defaults of
:data:`~.gameplay.WEAPON_FIELDS`.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .fields import Field
from .gameplay import MILLI, WEAPON_FIELDS, WEAPON_KINDS, WeaponSpec, read_weapons
from .limits import COORD, MAX_NAME_CHARS, Range

PICKUP_SIZE = Range(0.1, 2.0, "m")
PICKUP_TABLE = {
    "weapon": Field("string", choices=WEAPON_KINDS),
    "name": Field("text", default=None, range=Range(0, MAX_NAME_CHARS)),
    "position": Field("vector", 4, range=COORD),
    "size": Field("number", default=0.35, range=PICKUP_SIZE, sign="positive"),
}
#: The number key that takes each kind (``weapon_1`` the gun, ...): fixed, whatever else is owned.
KEY_OF = {kind: f"weapon_{k + 1}" for k, kind in enumerate(WEAPON_KINDS)}


@dataclass
class PickupSpec:
    """A ``[[pickup]]``: the weapon ``kind`` waiting at ``position (4,) float64``, ``size`` its radius."""

    name: str
    weapon: str
    position: np.ndarray
    size: float = 0.35


def read_pickups(r, data, w_range) -> list[PickupSpec]:
    """The ``[[pickup]]`` tables (``r`` is the level loader's reader; ``w_range`` the level's, or
    None when it is broken). Each lies within the w range; a weapon lies in one pickup at most."""
    out, seen = [], {}
    for i, t in enumerate(r.entries(data, "pickup", "top level", lambda k: f"[[pickup]] #{k}"), 1):
        where = f"[[pickup]] #{i}"
        r.unknown(t, PICKUP_TABLE, where)
        n = len(r.problems)
        v = r.read(t, PICKUP_TABLE, where)
        if len(r.problems) > n:
            continue
        kind = v["weapon"]
        name = v["name"] or WEAPON_FIELDS[kind]["name"]
        where = f"[[pickup]] #{i} '{name}'"
        w = float(v["position"][3])
        if w_range is not None and not w_range[0] <= w <= w_range[1]:
            r.problem(
                where,
                f"field 'position': w = {w:g} is outside the level's w_range [{w_range[0]:g}, {w_range[1]:g}], "
                "so the weapon can never be picked up",
            )
        if kind in seen:
            r.problem(where, f"field 'weapon': the {kind} already lies in [[pickup]] #{seen[kind]} (one per weapon)")
        seen.setdefault(kind, i)
        out.append(PickupSpec(name, kind, v["position"], float(v["size"])))
    return out


def read_tuning(r, data) -> dict[str, WeaponSpec]:
    """The ``[[weapon]]`` tables: how each kind behaves in this level, by kind (one table per kind)."""
    out: dict[str, WeaponSpec] = {}
    first: dict[str, int] = {}
    for i, spec in read_weapons(r, data):
        if spec.kind in first:
            earlier = f"[[weapon]] #{first[spec.kind]}"
            r.problem(f"[[weapon]] #{i}", f"field 'kind': the {spec.kind} is already tuned by {earlier} (one per kind)")
            continue
        first[spec.kind] = i
        out[spec.kind] = spec
    return out


def default_spec(kind: str) -> WeaponSpec:
    """A weapon of ``kind`` with the defaults of :data:`~.gameplay.WEAPON_FIELDS`."""
    d = dict(WEAPON_FIELDS[kind])
    name, cost, cooldown = d.pop("name"), d.pop("cost"), d.pop("cooldown")
    counts = {k: int(d.pop(k)) for k in ("max_live", "ammo", "max_ammo", "refill") if k in d}
    return WeaponSpec(kind, name, int(round(cost * MILLI)), cooldown, **counts, **d)


def available(tuning: dict, arsenal, pickups) -> list[WeaponSpec]:
    """The weapons a run of a level can have: its starting ``arsenal`` and its ``pickups``'
    weapons, in key order, each as the level tunes it."""
    kinds = set(arsenal) | {p.weapon for p in pickups}
    return [tuning.get(k) or default_spec(k) for k in WEAPON_KINDS if k in kinds]


def _pickup_kinds(path: Path) -> set[str]:
    """The weapons lying in a level file's pickups (an unreadable file gives none: its own check
    reports it)."""
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, RecursionError):
        return set()
    tables = data.get("pickup", [])
    if not isinstance(tables, list):
        return set()
    return {t.get("weapon") for t in tables if isinstance(t, dict) and t.get("weapon") in WEAPON_KINDS}


def campaign_arsenal(level_path) -> tuple[str, ...]:
    """The weapons the campaign has given by the start of the level at ``level_path``: those of
    the pickups in every level before it, in key order. The campaign file beside the level is
    used, else the shipped one; () for a level in neither."""
    from .campaign import CampaignError, campaign_path, load_campaign

    level_path = Path(level_path)
    beside = level_path.parent / "campaign.toml"
    try:
        entries = load_campaign(beside if beside.is_file() else campaign_path())
    except (CampaignError, OSError):
        return ()
    stems = [e.stem for e in entries]
    if level_path.stem not in stems:
        return ()
    kinds: set[str] = set()
    for e in entries[: stems.index(level_path.stem)]:
        kinds |= _pickup_kinds(e.path)
    return tuple(k for k in WEAPON_KINDS if k in kinds)


def arsenal_problem(kinds) -> str | None:
    """Why ``kinds`` (from a replay or a save) is not an arsenal, or None."""
    if not isinstance(kinds, (list, tuple)) or not all(isinstance(k, str) for k in kinds):
        return f"expected a list of weapon names ({', '.join(WEAPON_KINDS)}), got {kinds!r}"
    bad = [k for k in kinds if k not in WEAPON_KINDS]
    if bad:
        return f"unknown weapon {bad[0]!r}: expected some of {', '.join(WEAPON_KINDS)}"
    if len(set(kinds)) != len(kinds):
        return f"a weapon is named twice in {list(kinds)!r}"
    return None
