"""Design warnings the editor shows as you edit: quick geometric checks of a level that loads.

Not errors (the loader's problems are those): a level with them still loads and plays, but
probably not as its designer meant.

- a 4D entry (object, crystal, checkpoint) whose w is outside the level's w range: the
  player can never reach its w (targets may be, on purpose: they are shot, not reached);
- a world wholly outside the w range: never seen;
- a spawn or checkpoint that overlaps solid geometry at its w, or two of them at one place;
- a goal the player cannot reach: outside the w range (when it has its own), or with no floor
  within a jump below it.

The design probe (``across-dimensions probe``) answers the deeper question (can the level be
finished, only as meant?); these run on every edit in well under a millisecond.
"""

from __future__ import annotations

import numpy as np

from .level import Level

#: The walker's bounds at a spawn or checkpoint (metres: x, y, z; feet at the bottom).
WALKER = np.array([0.6, 1.75, 0.6])
#: Highest floor step a walker can jump onto (metres): a little above the jump's rise.
JUMP_REACH = 1.4
#: Overlaps thinner than this are contact, not overlap (a spawn standing on its floor).
TOUCH = 0.02
#: The walker steps up onto what is lower than this (a pad under a checkpoint): not an overlap.
STEP = 0.3
#: Kinds placed at a w of their own (enemies are left out: they move along w to the player).
W_KINDS = ("object", "crystal", "checkpoint")


def _solids_at(level: Level, w: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """Bounds ``(lo (3,), hi (3,))`` of the boxes present at ``w``: the 3D ones and each world's
    where its slab reaches ``w``."""
    out = [(b.center - b.size / 2, b.center + b.size / 2) for b in level.boxes]
    for world in level.worlds:
        if abs(w - world.w) < world.depth / 2:
            out += [(b.center - b.size / 2, b.center + b.size / 2) for b in world.boxes]
    return out


def _overlaps(lo, hi, solids) -> bool:
    return any(np.all(np.minimum(hi, h) - np.maximum(lo, l) > TOUCH) for l, h in solids)  # noqa: E741


def lint(model, level: Level) -> dict[tuple, list[str]]:
    """Warnings by entry (``ref -> [text]``) for the :class:`~.level_edit.LevelEditor` ``model``
    whose text loads as ``level``."""
    out: dict[tuple, list[str]] = {}
    lo_w, hi_w = level.w_range

    def warn(ref, text):
        out.setdefault(tuple(ref), []).append(text)

    for ref in model.entries():
        kind = ref[0] if len(ref) == 2 else None
        if kind in W_KINDS:
            p = model.get(ref, "position")
            if isinstance(p, list) and len(p) == 4 and not lo_w - 1e-9 <= p[3] <= hi_w + 1e-9:
                warn(ref, f"at w = {p[3]:g}, outside the level's w range [{lo_w:g}, {hi_w:g}]: out of reach")
        elif kind == "world":
            w, depth = float(model.value(ref, "w") or 0.0), float(model.value(ref, "depth") or 0.0)
            if w + depth / 2 < lo_w or w - depth / 2 > hi_w:
                warn(
                    ref, f"at w = {w:g} (depth {depth:g}), wholly outside the w range [{lo_w:g}, {hi_w:g}]: never seen"
                )
    starts = [(("spawn",), level.spawn)] + [
        (("checkpoint", i), c.position) for i, c in enumerate(getattr(level, "checkpoints", []))
    ]
    for k, (ref, p) in enumerate(starts):
        feet = np.asarray(p[:3], np.float64)
        lo, hi = feet - [WALKER[0] / 2, -STEP, WALKER[2] / 2], feet + [WALKER[0] / 2, WALKER[1], WALKER[2] / 2]
        if _overlaps(lo, hi, _solids_at(level, float(p[3]))):
            warn(ref, "overlaps solid geometry at its w: the player starts stuck")
        for other, q in starts[:k]:
            if np.linalg.norm(np.asarray(q[:3]) - feet) < WALKER[0] and abs(q[3] - p[3]) < 0.1:
                warn(ref, f"at the same place as {other[0]}{'' if len(other) == 1 else f' #{other[1] + 1}'}")
    _goal(level, warn)
    return out


def _goal(level: Level, warn) -> None:
    g = level.goal
    lo_w, hi_w = level.w_range
    if g.w_range is not None and (g.w_range[1] < lo_w or g.w_range[0] > hi_w):
        warn(("goal",), f"its w range {list(g.w_range)} is outside the level's: unreachable")
    bottom = float(g.center[1] - g.size[1] / 2)
    lo, hi = g.center - g.size / 2, g.center + g.size / 2
    everything = [(b.center - b.size / 2, b.center + b.size / 2) for b in level.boxes]
    everything += [(b.center - b.size / 2, b.center + b.size / 2) for wd in level.worlds for b in wd.boxes]
    tops = [  # floors under the goal at some w, not above its top
        float(h[1])
        for l, h in everything  # noqa: E741
        if np.all(l[[0, 2]] < hi[[0, 2]]) and np.all(h[[0, 2]] > lo[[0, 2]]) and h[1] <= hi[1]
    ]
    if not tops or bottom - max(tops) > JUMP_REACH:
        warn(("goal",), "no floor within a jump below it: unreachable on foot")
