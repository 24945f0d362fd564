"""Checks on where things are and what names mean, once every entry of a level is read.

Each entry can be right on its own and the level still broken:

- the spawn inside a wall or a fixed solid 4D object (a closed gate): the player starts
  stuck (a rigid body there falls or is pushed away, so it is left alone);
- an enemy whose centre is inside a wall: it cannot be reached or shot;
- two ``[[object]]`` tables with one name that a ``[[manipulable]]``, a target's or
  an enemy's ``opens`` refers to: which one is meant is a guess.

Walls are the level's boxes (every w) and its worlds' boxes at the w in question
(scaled by the world's profile there); solid objects are tested exactly, by
counting the crossings of a ray with their boundary tets. Every problem names
the file, the table and its index, as the loader's own do.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

#: Heights above the spawn point (the feet) that the player's body covers and that
#: must be in open space: ankles, waist, eye. The body is 1.75 m tall.
BODY_HEIGHTS = (0.1, 0.9, 1.6)
#: Walls are shrunk by this much before a point is called inside: a spawn standing
#: on a floor, or an enemy touching a wall, is not inside it.
INSIDE_MARGIN = 1e-3
#: A direction no level geometry lines up with, so a ray never grazes an edge.
_RAY = np.array([0.5377, 0.2113, 0.8034, 0.1419]) / np.linalg.norm([0.5377, 0.2113, 0.8034, 0.1419])


def placement_problems(level) -> list[str]:
    """Every placement and naming problem of ``level``, one line each (empty: none).

    Parameters
    ----------
    level : Level
        Read without problems so far.
    """
    path = level.path
    out = [f"{path}: [spawn]: {msg}" for msg in _blocked(level, level.spawn, BODY_HEIGHTS, "the player")]
    for i, e in enumerate(level.enemies, 1):
        label = f"[[enemy]] #{i}" + (f" '{e.name}'" if e.name else "")
        for msg in _blocked(level, e.position, (0.0,), "the enemy", objects=False):
            out.append(f"{path}: {label}: {msg}; an enemy must start in open space")
    out += [f"{path}: {msg}" for msg in _ambiguous_names(level)]
    return out


def _blocked(level, position, heights, who: str, objects: bool = True) -> list[str]:
    """Why points ``heights`` above ``position (4,)`` are not in open space, one line per wall."""
    p = np.asarray(position, dtype=np.float64)
    points = [p + np.array([0.0, h, 0.0, 0.0]) for h in heights]
    found = []
    for where, lo, hi in _walls(level, float(p[3])):
        if any(np.all(q[:3] > lo + INSIDE_MARGIN) and np.all(q[:3] < hi - INSIDE_MARGIN) for q in points):
            found.append(f"{_fmt(p)} puts {who} inside the wall {where} (from {_fmt(lo)} to {_fmt(hi)})")
    if objects:
        for i, o in enumerate(level.objects, 1):
            fixed = o.solid and o.body == "none" and o.shape is not None
            if fixed and any(_inside_solid(o, q) for q in points):
                found.append(f"{_fmt(p)} puts {who} inside the solid [[object]] #{i} '{o.name}'")
    return found


def _walls(level, w: float):
    """``(where, lo (3,), hi (3,))`` of every box that is a wall at ``w``."""
    for i, b in enumerate(level.boxes, 1):
        yield f"[[box]] #{i}", b.center - b.size / 2, b.center + b.size / 2
    for j, world in enumerate(level.worlds, 1):
        if abs(w - world.w) >= world.depth / 2:
            continue
        from ..core.lift import profile_scales

        s = float(profile_scales([w], world.w, world.depth / 2, world.profile)[0])
        for i, b in enumerate(world.boxes, 1):
            yield (
                f"[[world]] #{j} '{world.name}' [[world.box]] #{i}",
                b.center - s * b.size / 2,
                b.center + s * b.size / 2,
            )


def _inside_solid(spec, point: np.ndarray) -> bool:
    """Is ``point (4,)`` inside the 4D object ``spec`` as placed at the level's start?"""
    from ..core.transform import pose

    vertices, tets = _shape(spec.shape, tuple(sorted(spec.params.items())))
    model = pose(spec.position, {p: np.radians(a) for p, a in spec.rotation_deg.items()}, spec.scale)
    v = vertices @ model[:4, :4].T + model[:4, 4]
    lo, hi = v.min(axis=0), v.max(axis=0)
    if np.any(point < lo) or np.any(point > hi):
        return False
    a = v[tets[:, 0]]
    # point + t * ray = a + u (b - a) + v (c - a) + s (d - a): one 4x4 system per boundary tet.
    m = np.stack([v[tets[:, 1]] - a, v[tets[:, 2]] - a, v[tets[:, 3]] - a, np.broadcast_to(-_RAY, a.shape)], axis=2)
    ok = np.abs(np.linalg.det(m)) > 1e-12
    uvst = np.linalg.solve(m[ok], (point - a[ok])[:, :, None])[:, :, 0]
    u, vv, s, t = uvst.T
    hits = (u >= 0) & (vv >= 0) & (s >= 0) & (u + vv + s <= 1) & (t > 0)
    return bool(np.count_nonzero(hits) % 2)


@lru_cache(maxsize=32)
def _shape(name: str, params: tuple) -> tuple[np.ndarray, np.ndarray]:
    from ..core.shapes import make_shape

    mesh = make_shape(name, **dict(params))
    return mesh.vertices.astype(np.float64), mesh.tets.astype(np.int64)


def _ambiguous_names(level) -> list[str]:
    """References to an object name that two or more ``[[object]]`` tables carry."""
    tables: dict[str, list[int]] = {}
    for i, o in enumerate(level.objects, 1):
        tables.setdefault(o.name, []).append(i)
    refs = [(f"[[manipulable]] #{i}", "object", m.object) for i, m in enumerate(level.manipulables, 1)]
    refs += [(f"[[target]] #{i} '{t.name}'", "opens", t.opens) for i, t in enumerate(level.targets, 1)]
    refs += [(f"[[enemy]] #{i}", "opens", e.opens) for i, e in enumerate(level.enemies, 1)]
    out = []
    for where, key, name in refs:
        if len(tables.get(name, ())) > 1:
            which = " and ".join(f"[[object]] #{i}" for i in tables[name])
            out.append(f"{where}: field '{key}': '{name}' names {which}; expected one object of that name")
    return out


def _fmt(v) -> str:
    return "[" + ", ".join(f"{float(x):g}" for x in v) + "]"
