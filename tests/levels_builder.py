"""Level files for tests, built from defaults instead of pasted TOML.

A test names only what it is about; everything else is a small valid level: the player at the
origin facing ``+z``, a 10 m x 12 m floor with its top at ``y = 0``, the goal 5 m ahead, ``w``
from -1 to 1::

    path = LevelBuilder(w_range=(-0.5, 0.5)).crystal([0.0, 1.0, 2.0, 0.3]).write(tmp_path)
    level = LevelBuilder(spawn=(0.0, 0.0, -6.0, 0.0)).object([0.0, 1.0, 3.0, 0.0], name="door").load(tmp_path)

Every method that adds something returns the builder, so calls chain. Field values are written as
given (an ``int`` stays an ``int``), since some messages quote them. Tests about how a specific
text is read (a typo, a value of the wrong type, a broken file) keep that text inline.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

__all__ = ["LevelBuilder", "toml_text", "write_text"]


def _value(v) -> str:
    if hasattr(v, "tolist"):  # numpy arrays and scalars
        v = v.tolist()
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_value(x)}" for k, x in v.items()) + " }" if v else "{}"
    return "[" + ", ".join(_value(x) for x in v) + "]"


def _is_tables(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _section(header: str, fields: dict, indent: str = "") -> list[str]:
    """``[header]`` (or ``[[header]]`` when it is given with its brackets) with its fields, then its
    own arrays of tables (a world's boxes) as ``[[header.key]]`` below it."""
    lines = [f"{indent}{header}"]
    nested = []
    for k, v in fields.items():
        if _is_tables(v):
            nested.append((k, v))
        else:
            lines.append(f"{indent}{k} = {_value(v)}")
    name = header.strip("[]")
    for k, entries in nested:
        for entry in entries:
            lines += _section(f"[[{name}.{k}]]", entry, indent + "  ")
    return lines


def toml_text(doc: dict) -> str:
    """``doc`` (tables and arrays of tables, one level of sub-arrays) as compact TOML."""
    lines = []
    for k, v in doc.items():
        if isinstance(v, dict):
            lines += ["", *_section(f"[{k}]", v)]
        else:
            for entry in v:
                lines += ["", *_section(f"[[{k}]]", entry)]
    return "\n".join(lines[1:]) + "\n"


class LevelBuilder:
    """A level file with defaults for everything a test does not name.

    Parameters
    ----------
    name : str
        ``[level] name``.
    format : int or str or None
        ``[level] format``: ``2`` by default (crystals, enemies, weapons...), ``None`` to leave it out.
    w_range : (2,) floats or None
        ``[level] w_range``; ``None`` leaves it out (the loader's default).
    spawn : (4,) floats
        The player's feet, ``[spawn] position``.
    yaw : float or None
        ``[spawn] yaw`` (left out when ``None``).
    goal : (3,) floats
        The goal's centre.
    goal_size : (3,) floats
        The goal's full size.
    goal_w : (2,) floats or None
        The goal's ``w_range``.
    floor : (3,) floats or None
        Size of the floor box centred under the origin with its top at ``y = 0``; ``None`` for none.
    """

    def __init__(
        self,
        name: str = "test",
        *,
        format: int | str | None = 2,
        w_range=(-1.0, 1.0),
        spawn=(0.0, 0.0, 0.0, 0.0),
        yaw=None,
        goal=(0.0, 1.0, 5.0),
        goal_size=(1.0, 2.0, 1.0),
        goal_w=None,
        floor=(10.0, 1.0, 12.0),
    ):
        level = {"name": name}
        if format is not None:
            level["format"] = format
        if w_range is not None:
            level["w_range"] = list(w_range)
        self.doc: dict = {"level": level, "spawn": {"position": list(spawn)}}
        if yaw is not None:
            self.doc["spawn"]["yaw"] = yaw
        self.doc["goal"] = {"center": list(goal), "size": list(goal_size)}
        if goal_w is not None:
            self.doc["goal"]["w_range"] = list(goal_w)
        if floor is not None:
            self.box([0.0, -0.5 * floor[1], 0.0], floor)

    @classmethod
    def flatland(
        cls,
        name: str | None = None,
        *,
        z_range=(-3.0, 3.0),
        spawn=(0.0, 0.0, 0.0),
        goal=(18.0, 1.0),
        goal_size=(2.0, 2.0),
        floor=(40.0, 2.0, 8.0),
    ) -> LevelBuilder:
        """A Flatland prologue level: ``spawn`` is ``[x, y, z]``, the goal a rectangle in x-y, and
        the floor a box named ``"floor"`` with its top at ``y = 0``. Without a ``name`` the level is
        named for its file."""
        b = cls.__new__(cls)
        level = (
            {"format": "flatland", "z_range": list(z_range)}
            if name is None
            else {"name": name, "format": "flatland", "z_range": list(z_range)}
        )
        b.doc = {
            "level": level,
            "spawn": {"position": list(spawn)},
            "goal": {"center": list(goal), "size": list(goal_size)},
        }
        if floor is not None:
            b.box([0.0, -0.5 * floor[1], 0.0], floor, name="floor")
        return b

    # ------------------------------------------------------------ tables
    def level(self, **fields) -> LevelBuilder:
        """Set fields of ``[level]`` (``hints``, ``description``...)."""
        self.doc["level"].update(fields)
        return self

    def table(self, name: str, **fields) -> LevelBuilder:
        """Set fields of a top-level table: ``[physics]``, ``[energy]``, ``[radar]``, ``[camera]``..."""
        self.doc.setdefault(name, {}).update(fields)
        return self

    def without(self, name: str) -> LevelBuilder:
        """Leave out a table or every entry of an array of tables (``"goal"``, ``"box"``...)."""
        self.doc.pop(name, None)
        return self

    # ------------------------------------------------------------ entries
    def add(self, kind: str, /, **fields) -> LevelBuilder:
        """Append a ``[[kind]]`` entry with ``fields``."""
        self.doc.setdefault(kind, []).append(fields)
        return self

    def box(self, center, size, **fields) -> LevelBuilder:
        return self.add("box", center=list(center), size=list(size), **fields)

    def mesh(self, asset: str, position=None, **fields) -> LevelBuilder:
        """A 3D asset at every ``w`` (at the origin unless ``position`` is given)."""
        if position is not None:
            fields = {"position": list(position), **fields}
        return self.add("mesh", asset=asset, **fields)

    def object(self, position, shape: str | None = "tesseract", **fields) -> LevelBuilder:
        """A 4D object, a tesseract unless ``shape`` (or ``asset`` with ``shape=None``) says otherwise;
        ``name`` among ``fields`` comes first in the file."""
        head = {"name": fields.pop("name")} if "name" in fields else {}
        if shape is not None:
            head["shape"] = shape
        return self.add("object", **head, position=list(position), **fields)

    def world(self, w: float, depth: float, *, boxes=(), meshes=(), **fields) -> LevelBuilder:
        """A ``[[world]]``; ``boxes`` and ``meshes`` are dicts of its parts' fields."""
        parts = {}
        if boxes:
            parts["box"] = [dict(b) for b in boxes]
        if meshes:
            parts["mesh"] = [dict(m) for m in meshes]
        return self.add("world", w=w, depth=depth, **fields, **parts)

    def crystal(self, position, **fields) -> LevelBuilder:
        return self.add("crystal", position=list(position), **fields)

    def enemy(self, name: str, position, **fields) -> LevelBuilder:
        return self.add("enemy", name=name, position=list(position), **fields)

    def weapon(self, kind: str = "gun", **fields) -> LevelBuilder:
        """Tune a weapon (``[[weapon]]``); :meth:`load` starts the player with it."""
        return self.add("weapon", kind=kind, **fields)

    def pickup(self, weapon: str, position, **fields) -> LevelBuilder:
        return self.add("pickup", weapon=weapon, position=list(position), **fields)

    # ------------------------------------------------------------ out
    def text(self, extra: str = "") -> str:
        """The level as TOML, with ``extra`` (TOML text) appended."""
        return toml_text(self.doc) + ("\n" + extra if extra else "")

    def write(self, where: Path, name: str = "level.toml", extra: str = "") -> Path:
        """Write the level into the folder ``where`` (or to ``where`` itself when it ends in
        ``.toml``) and return its path."""
        where = Path(where)
        path = where if where.suffix == ".toml" else where / name
        path.write_text(self.text(extra), encoding="utf-8")
        return path

    def load(self, where: Path, name: str = "level.toml", extra: str = "", arsenal=None):
        """Write the level (see :meth:`write`) and load it, the player owning ``arsenal`` at the
        start (default: the weapons it tunes, as if earlier levels had given them)."""
        from across_dimensions.world.level import load_level

        level = load_level(self.write(where, name, extra))
        return level.with_arsenal(level.tuning if arsenal is None else arsenal)


def write_text(where: Path, text: str, name: str = "level.toml") -> Path:
    """Write ``text`` as it is, for the tests about how a specific text is read (a typo, a value of
    the wrong type, a broken file); everything else builds its level with :class:`LevelBuilder`."""
    path = Path(where) / name
    path.write_text(text, encoding="utf-8")
    return path
