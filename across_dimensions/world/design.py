"""``[design]``: what a level teaches, so the design probe knows which shortcuts must fail.

A level names the mechanics it is built to demand::

    [design]
    needs = ["manipulation"]

``across-dimensions probe`` (:mod:`across_dimensions.probe`) then runs naive strategies
against the level; one that avoids a needed mechanic and still reaches the goal is a
*bypass*. The words are :data:`NEEDS`; ``levels/README.md`` says what each means. The
table is allowed in every format (it changes nothing in play) and may be left out: a
level that declares nothing needs nothing, and only soft-locks are looked for.
"""

from __future__ import annotations

from .fields import Field

#: The mechanics a level may declare it needs, each with what a strategy avoids to
#: avoid it (the README's table lists the same).
NEEDS = {
    "w_move": "moving the player along w",
    "crystals": "collecting crystals that lie off the starting slice",
    "radar": "using where off-slice things are (radar pins) to choose a w",
    "rigid_bodies": "pushing or climbing 4D rigid bodies",
    "gun": "firing the 120-cell gun",
    "blast": "the w-pull blast",
    "field": "the wire field (finding disguised 4D things)",
    "manipulation": "grabbing a manipulable object and turning it all the way",
    "slice_turn": "turning the slice into another world",
    "frustum": "the frustum camera",
    "orbit": "orbiting the detached frustum camera",
    "enemies": "fighting enemies (aiming at them, their weak spots)",
    "frustum_walk": "walking on an object's frustum image (walkable_in_frustum)",
    "camera_loot": "freeing an enemy's crystal with the frustum camera's hold",
}
DESIGN_TABLE = {"needs": Field("words", default=(), choices=tuple(NEEDS))}


def read_design(r, data) -> tuple[str, ...]:
    """The ``[design]`` table's ``needs`` (``r`` is the level loader's reader); ``()`` when absent."""
    if "design" not in data:
        return ()
    where = "[design]"
    t = r.table(data, "design", where)
    r.unknown(t, DESIGN_TABLE, where)
    needs = t.get("needs", [])
    expected = f"a list of distinct words from: {', '.join(NEEDS)}"
    if not isinstance(needs, list):
        r.problem(where, f"field 'needs': expected {expected}, got {needs!r}")
        return ()
    out: list[str] = []
    for i, word in enumerate(needs, 1):
        if not isinstance(word, str) or word not in NEEDS:
            r.problem(where, f"field 'needs': entry #{i}: expected one of {', '.join(NEEDS)}, got {word!r}")
        elif word in out:
            r.problem(where, f"field 'needs': entry #{i}: {word!r} is listed twice")
        else:
            out.append(word)
    return tuple(out)
