"""A level's hints and the level state that completes each (``[level] hints``, ``levels/README.md``).

A hint is a string, or a table ``{ text = "...", until = { ... } }`` whose ``until`` names what
the player must have *done* for the hint to be done: an event of the game (``event =
"crystal_collected"``), an object gone from the level (``gone = "door_b"``: a door a switch
opened, a crystal taken), the player past a place (``z_min = 2.5``, ``w_min = 0.7``), or the weapon
in hand (``weapon = "blast"``); all the conditions given must hold. A hint without ``until`` is
done when the player performs an action it names (``game.hints``), or after its reading time.

The 4D loader (:mod:`.level`) reads them here, and the prologue's loader (:mod:`.flat_level`)
shares :class:`HintSpec`, so a hint means the same in both formats.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .fields import Field
from .limits import COORD, MAX_COUNTS, MAX_NAME_CHARS, Range

#: The game events a hint may wait for (kinds of ``game.events``; a test keeps them in step).
EVENTS = (
    "blast",
    "bullet_hit",
    "camera_switched",
    "checkpoint_reached",
    "crystal_collected",
    "enemy_defeated",
    "enemy_hit",
    "entered_frustum_object",
    "field",
    "level_complete",
    "loot_released",
    "manipulated",
    "manipulation_ended",
    "manipulation_started",
    "respawned",
    "seek_arrived",
    "seek_started",
    "shot_fired",
    "slab_knocked",
    "slice_aligned",
    "target_hit",
    "weapon_selected",
)
#: Weapon kinds ``until.weapon`` may name (the kinds of ``[[weapon]]``).
WEAPONS = ("gun", "blast", "field")
#: Where the player's feet must be: ``<axis>_min`` / ``<axis>_max`` for x, y, z and w.
PLACES = tuple(f"{a}_{b}" for a in "xyzw" for b in ("min", "max"))

UNTIL = {k: Field("number", default=None, range=COORD) for k in PLACES}
UNTIL["event"] = Field("string", default=None, choices=EVENTS)
UNTIL["gone"] = Field("text", default=None, range=Range(1, MAX_NAME_CHARS))
UNTIL["weapon"] = Field("string", default=None, choices=WEAPONS)


@dataclass(frozen=True)
class HintSpec:
    """A hint's text (``{action}`` placeholders unfilled) and the level state that completes it.

    ``until`` maps condition names (:data:`UNTIL` here, the prologue's own in ``flat_level``) to
    values; empty when the hint is done by the actions it names or by reading.
    """

    text: str
    until: dict = field(default_factory=dict)


def read_hints(r, meta: dict, problem_of) -> list[HintSpec]:
    """The ``hints`` field of ``[level]`` read by the level reader ``r`` (problems go to it).

    ``problem_of(text)`` says why a hint's text cannot be shown, or None.
    """
    hints = meta.get("hints", [])
    if not (isinstance(hints, list) and all(isinstance(h, (str, dict)) for h in hints)):
        r.problem("[level]", "field 'hints': expected a list of strings or { text, until } tables")
        return []
    limit, what = MAX_COUNTS["hints"]
    if len(hints) > limit:
        r.problem("[level]", f"field 'hints': a level may have at most {limit} {what}, got {len(hints)}")
        hints = hints[:limit]
    out = []
    for i, h in enumerate(hints, 1):
        where = f"[level] hints #{i}"
        text, until = (h, {}) if isinstance(h, str) else _table(r, h, where)
        why = problem_of(text)
        if why:
            r.problem("[level]", f"field 'hints': hint #{i}: {why}")
        out.append(HintSpec(text, until))
    return out


def _table(r, h: dict, where: str) -> tuple[str, dict]:
    r.unknown(h, ("text", "until"), where)
    text = h.get("text")
    if not isinstance(text, str) or not text:
        r.problem(where, f"field 'text': expected the hint's words, got {text!r}")
        text = ""
    v = h.get("until")
    if v is None:
        return text, {}
    if not isinstance(v, dict) or not v:
        r.problem(where, f"field 'until': expected a table of {', '.join(UNTIL)}, got {v!r}")
        return text, {}
    r.unknown(v, UNTIL, f"{where} > until")
    got = r.read(v, UNTIL, f"{where} > until", keys=[k for k in UNTIL if k in v])
    return text, {k: x for k, x in got.items() if x is not None}


def hint_name_problems(path, hints: list[HintSpec], names: set[str]) -> list[str]:
    """Problems of ``until.gone`` entries that name nothing of the level (``names``)."""
    known = ", ".join(sorted(n for n in names if n)) or "none"
    return [
        f"{path}: [level] hints #{i}: field 'gone': nothing named {h.until['gone']!r} in the level (named: {known})"
        for i, h in enumerate(hints, 1)
        if "gone" in h.until and h.until["gone"] not in names
    ]
