"""What the editor does to several entries at once: move, rotate, scale, delete, copy and paste.

Each operation is one undo step of the :class:`~.level_edit.LevelEditor` (its ``batch``), and
works on the level file's values: an entry's place is its ``position`` (x, y, z and, for 4D
entries, w) or ``center`` (3D boxes; a world's box is at its world's ``w``); a world moves its
parts and its ``w``. Rotations turn places about the group's pivot and compose with an entry's
own ``rotation`` exactly (through :func:`core.transform.angles_to_rotation` and back); a 3D box
cannot turn, so only its centre moves (and its size swaps on quarter turns of a 3D plane).

The clipboard holds entries as TOML text (``[[crystal]] ...``), so a copy pastes into another
level, in this editor or another one, through the system clipboard.
"""

from __future__ import annotations

import copy

import numpy as np
import tomlkit

from ..core.transform import PLANES, angles_to_rotation, rotation4, rotation_to_angles
from .level_edit import WORLD_CHILDREN, LevelEditor, Ref, _plain
from .level_style import entry_lines

CLIP_HEAD = "# Across Dimensions level entries (paste into a level in the editor, or into its file)\n"
#: Where snapping puts things: metres on the grid, degrees per turn step, w per step.
GRID, ANGLE_STEP, W_STEP = 0.25, 15.0, 0.1
DIGITS = 4  # places kept in the file: a drag writes 1.25, not 1.2500000476837158


def snap(x: float, step: float) -> float:
    """``x`` on the nearest multiple of ``step`` (``step`` 0: unchanged)."""
    return round(float(x) / step) * step + 0.0 if step else float(x)


def _tidy(x: float) -> float:
    return round(float(x), DIGITS) + 0.0


def place_key(ed: LevelEditor, ref: Ref) -> str | None:
    """The field that places the entry (``position`` or ``center``), or None (a world, a setting)."""
    t = ed.table(ref)
    return "center" if "center" in t else "position" if "position" in t else None


def place_of(ed: LevelEditor, ref: Ref) -> np.ndarray | None:
    """The entry's place ``(4,) float64``: xyz and its w (its world's for a world's part, 0 for a
    3D entry), or None. A world's place is the centre of its parts' centres at its w."""
    if ref[0] == "world" and len(ref) == 2:
        parts = [place_of(ed, ref + (c, j)) for c in WORLD_CHILDREN for j in range(len(ed.get(ref, c, [])))]
        parts = [p for p in parts if p is not None]
        w = float(ed.get(ref, "w", 0.0))
        return np.array([*np.mean(parts, axis=0)[:3], w]) if parts else np.array([0.0, 0.0, 0.0, w])
    key = place_key(ed, ref)
    v = ed.get(ref, key) if key else None
    if not isinstance(v, list) or len(v) < 3:
        return None
    w = v[3] if len(v) > 3 else float(ed.get(ref[:2], "w", 0.0)) if ref[0] == "world" else 0.0
    return np.array([*v[:3], w], np.float64)


def pivot(ed: LevelEditor, refs) -> np.ndarray | None:
    """The centre of the entries' places ``(4,)``, or None when none has one."""
    places = [p for p in (place_of(ed, r) for r in refs) if p is not None]
    return np.mean(places, axis=0) if places else None


def _top(refs) -> list:
    """``refs`` without the parts of a world also in ``refs`` (moving the world moves them)."""
    worlds = {r[:2] for r in refs if r[0] == "world" and len(r) == 2}
    return [r for r in refs if not (len(r) == 4 and r[:2] in worlds)]


def _set_place(ed: LevelEditor, ref: Ref, new4, worlds_w: bool = True) -> None:
    if ref[0] == "world" and len(ref) == 2:
        old = place_of(ed, ref)
        d = np.asarray(new4) - old
        for c in WORLD_CHILDREN:
            for j in range(len(ed.get(ref, c, []))):
                p = place_of(ed, ref + (c, j))
                if p is not None:
                    _set_place(ed, ref + (c, j), p + np.array([*d[:3], 0.0]))
        if d[3]:
            ed.set(ref, "w", _tidy(old[3] + d[3]))
        return
    key = place_key(ed, ref)
    v = ed.get(ref, key)
    ed.set(ref, key, [_tidy(x) for x in new4[: len(v)]])


def move(ed: LevelEditor, refs, delta, grid: float = 0.0, w_step: float = 0.0, merge: bool = False) -> None:
    """Move the entries by ``delta (4,)`` (xyz and w; w moves only 4D entries and worlds); with
    ``grid`` / ``w_step`` the first entry lands on the grid and the others keep their offsets."""
    refs = _top(refs)
    delta = np.asarray(delta, np.float64)
    first = next((place_of(ed, r) for r in refs if place_of(ed, r) is not None), None)
    if first is None:
        return
    target = first + delta
    steps = (grid, grid, grid, w_step)
    target = np.array([snap(target[i], steps[i]) for i in range(4)])
    delta = target - first
    with ed.batch(f"move {len(refs)} entr{'y' if len(refs) == 1 else 'ies'}", key=("move", tuple(refs)), merge=merge):
        for r in refs:
            p = place_of(ed, r)
            if p is not None:
                _set_place(ed, r, p + delta)


def set_rotation(ed: LevelEditor, ref: Ref, r4: np.ndarray, step: float = 0.0) -> None:
    """Write the entry's ``rotation`` as the angles of ``r4 (4, 4)`` (snapped to ``step`` degrees)."""
    angles = rotation_to_angles(r4)
    old = ed.get(ref, "rotation", {}) or {}
    out = {}
    for p in [*old, *PLANES]:
        deg = snap(np.degrees(angles.get(p, 0.0)), step)
        if p not in out and (abs(deg) > 1e-9 or p in old):
            out[p] = _tidy(deg)
    ed.set(ref, "rotation", out or None)


def rotation_of(ed: LevelEditor, ref: Ref) -> np.ndarray:
    """The entry's own rotation ``(4, 4)`` from its ``rotation`` angles (degrees in the file)."""
    angles = ed.get(ref, "rotation", {}) or {}
    return angles_to_rotation({p: np.radians(float(a)) for p, a in angles.items()})


def rotate(ed: LevelEditor, refs, plane: str, degrees: float, center=None, step: float = 0.0) -> None:
    """Turn the entries by ``degrees`` in ``plane`` about ``center (4,)`` (their pivot by default);
    ``step`` snaps the entries' own angles to multiples of it."""
    turn(ed, refs, rotation4(plane, np.radians(degrees)), center, step, label=f"rotate in {plane}")


def turn(ed: LevelEditor, refs, r4, center=None, step: float = 0.0, label: str = "rotate", merge=False) -> None:
    """Turn the entries by the rotation ``r4 (4, 4)`` about ``center (4,)`` (their pivot by default).

    An entry with a ``rotation`` field turns with it; a mesh's ``yaw`` follows a turn in the xz
    plane; a box keeps its axes (a quarter turn swaps its sizes). One entry turns in place.
    """
    refs = _top(refs)
    center = pivot(ed, refs) if center is None else np.asarray(center, np.float64)
    if center is None:
        return
    r4 = np.asarray(r4, np.float64)
    perm = np.abs(np.round(r4[:3, :3]))
    quarter = np.allclose(np.abs(r4[:3, :3]), perm, atol=1e-6) and np.allclose(r4[3], [0, 0, 0, 1], atol=1e-9)
    xz_only = np.allclose(r4[[1, 3]], np.eye(4)[[1, 3]], atol=1e-9)
    with ed.batch(label, key=("turn", tuple(refs)), merge=merge):
        for ref in refs:
            p = place_of(ed, ref)
            if p is not None and len(refs) > 1:
                _set_place(ed, ref, center + r4 @ (p - center))
            fields = _model_fields(ref)
            if "rotation" in fields:
                set_rotation(ed, ref, r4 @ rotation_of(ed, ref), step)
            elif "yaw" in fields and xz_only:
                yaw = float(ed.get(ref, "yaw", 0.0)) - np.degrees(np.arctan2(r4[2, 0], r4[0, 0]))
                ed.set(ref, "yaw", _tidy(snap(yaw, step)))
            elif "size" in fields and quarter and isinstance(ed.get(ref, "size"), list):
                size = np.asarray(ed.get(ref, "size"), np.float64)
                ed.set(ref, "size", [_tidy(x) for x in perm @ size])


def scale(ed: LevelEditor, refs, factors, step: float = 0.0, merge: bool = False) -> None:
    """Scale each entry's size by ``factors (4,)`` (x, y, z and w: the hyper-depth of 4D objects)."""
    f = np.asarray(factors, np.float64)
    with ed.batch(f"scale {len(refs)}", key=("scale", tuple(refs)), merge=merge):
        for ref in _top(refs):
            fields = _model_fields(ref)
            key = "scale" if "scale" in fields else "size" if "size" in fields else None
            if key is None:
                continue
            n = getattr(fields[key], "n", 1)
            v = ed.value(ref, key)
            v = [float(v)] * n if isinstance(v, (int, float)) else [float(x) for x in v]
            new = [_tidy(max(snap(v[i] * f[i], step), step or 1e-3)) for i in range(len(v))]
            ed.set(ref, key, new[0] if key == "scale" and len(set(new)) == 1 else new)


def _model_fields(ref: Ref) -> dict:
    from .level_edit import model_of

    return model_of(ref)


def delete(ed: LevelEditor, refs) -> None:
    """Delete the entries (from the last, so the indices of the others hold)."""
    refs = sorted((r for r in _top(refs) if len(r) >= 2), reverse=True)
    with ed.batch(f"delete {len(refs)}"):
        for r in refs:
            ed.delete(r)
    ed.selection = None


def copy_text(ed: LevelEditor, refs) -> str:
    """The entries as TOML (``[[kind]]`` tables; a world with its parts), for the clipboard."""
    lines = [CLIP_HEAD.rstrip("\n")]
    for ref in _top(refs):
        if len(ref) >= 2:
            values = copy.deepcopy(_plain(ed.table(ref)))
            lines += ["", *entry_lines(ref[-2], values, spaced=ed.spaced)]
    return "\n".join(lines) + "\n"


def paste(ed: LevelEditor, text: str, offset=(0.0, 0.0, 0.0, 0.0), world: Ref | None = None) -> list[Ref]:
    """Add the entries of clipboard ``text`` (as :func:`copy_text` writes), moved by ``offset (4,)``;
    boxes and meshes go into the selected ``world`` when there is one. Returns the new entries
    (also the selection); an empty list when the text holds no entries.

    Raises
    ------
    ValueError
        The text is not TOML.
    """
    from tomlkit.exceptions import TOMLKitError

    try:
        data = tomlkit.parse(text).unwrap()
    except TOMLKitError as e:
        raise ValueError(f"the clipboard holds no level entries ({e})") from None
    new: list[Ref] = []
    with ed.batch("paste"):
        for kind, items in data.items():
            if not isinstance(items, list) or kind not in _addable():
                continue
            for values in items:
                if not isinstance(values, dict):
                    continue
                parent = world if world is not None and kind in WORLD_CHILDREN else None
                ref = ed.add(kind, values, parent=parent)
                p = place_of(ed, ref)
                if p is not None and np.any(offset):
                    _set_place(ed, ref, p + np.asarray(offset, np.float64))
                new.append(ref)
    ed.selected = list(new)
    return new


def _addable() -> tuple:
    from .level import MODELS
    from .level_edit import SINGLE_TABLES

    return tuple(k for k in MODELS if k not in SINGLE_TABLES)


def duplicate(ed: LevelEditor, refs, offset=(0.5, 0.0, 0.5, 0.0)) -> list[Ref]:
    """Copies of the entries, a little to the side (selected); a world's part stays in its world."""
    refs = list(refs)
    world = refs[0][:2] if refs and len(refs[0]) == 4 else None
    return paste(ed, copy_text(ed, refs), offset, world=world)
