"""The level editor's model: a level file being edited, with no window and no GUI.

The editor edits the level's TOML *document* (parsed with tomlkit, which keeps
comments, blank lines and the order of entries), not the loader's specs, so a
saved file differs from the original only where a value was changed. Every
change is a command on an undo stack; undoing restores the document's exact
text. The level is checked by the loader itself (:func:`.level.load_level`
with the unsaved text), so the editor shows the very messages ``check-level``
and ``play`` would give, and :meth:`LevelEditor.save` writes nothing invalid.
Saving goes through :func:`core.fileio.atomic_write` (whole file or nothing).

Entries are addressed by a :data:`Ref`: a tuple of table keys and indices into
arrays of tables, e.g. ``("box", 0)``, ``("world", 1, "box", 0)`` or
``("spawn",)``. Values read and written are plain Python (floats, lists,
dicts of plane = degrees).
"""

from __future__ import annotations

import copy
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import tomlkit

from ..core import fileio
from ..core.errors import InputError
from . import gameplay, level_style
from .fields import REQUIRED, Field
from .level import MODELS, Level, LevelError, load_level

Ref = tuple  # ("box", 0), ("world", 1, "box", 0), ("spawn",)

#: Tables that appear once (``[spawn]``); every other model is an array of tables.
SINGLE_TABLES = ("level", "spawn", "goal", "physics", "energy", "radar", "design")
#: Arrays of tables nested inside a ``[[world]]``.
WORLD_CHILDREN = ("box", "mesh")

_NAMES = {"box": "box", "mesh": "mesh", "world": "world", "object": "4D object", "crystal": "crystal"}

#: Fields a new entry is given (beyond the required ones filled from their model).
TEMPLATES = {
    "box": {"center": [0.0, 0.5, 0.0], "size": [1.0, 1.0, 1.0]},
    "object": {"name": "new object", "shape": "tesseract", "position": [0.0, 1.0, 0.0, 0.0], "solid": False},
    "world": {"name": "new world", "w": 0.0, "depth": 1.0, "profile": "round"},
    "crystal": {"name": "new crystal", "position": [0.0, 1.0, 0.0, 0.0]},
    "mesh": {"asset": "meshes/crate.obj", "position": [0.0, 0.0, 0.0]},
}


class LevelEditError(InputError):
    """A level file the editor cannot open (not UTF-8 text, not TOML); the message names it."""


def _plain(value):
    """A tomlkit value as plain Python (floats, lists, dicts)."""
    if hasattr(value, "unwrap"):
        return value.unwrap()
    return value


def _required_value(f: Field):
    """A placeholder for a required field of a new entry: zeros, or ones where it must be positive."""
    fill = 1.0 if f.sign == "positive" else 0.0
    if f.kind in ("vector", "scale"):
        return [fill] * f.n
    if f.kind == "number":
        return fill
    if f.kind in ("string", "text"):
        return f.choices[0] if f.choices else ""
    return None


def model_of(ref: Ref) -> dict:
    """The loader's model (field name -> :class:`~.fields.Field`) of the table at ``ref``."""
    key = [k for k in ref if isinstance(k, str)][-1]
    return MODELS[key]


@dataclass
class Command:
    """One undoable change: the document's text before and after it.

    ``key`` identifies the field it set, so consecutive changes of one field
    (dragging a slider) merge into one step, as in any editor.
    """

    label: str
    before: str
    after: str
    key: tuple | None = None


class LevelEditor:
    """A level file open for editing.

    Parameters
    ----------
    path : path-like
        The level file. It is read through the bounded reader; it may be broken
        (the problems are listed, and it can be fixed in the editor).
    """

    def __init__(self, path, text: str | None = None):
        self.path = Path(path)
        if text is None:
            raw = fileio.read_bytes(self.path, limit=_max_bytes(), what="level")
            try:
                self.saved_text = raw.decode("utf-8-sig")
            except UnicodeDecodeError as e:
                raise LevelEditError(
                    f"{self.path}: not a text file (byte {e.start} is not UTF-8; expected a level)"
                ) from None
        else:  # a new level, not yet on disk: everything in it is unsaved
            self.saved_text = ""
        self.doc = _parse(self.path, self.saved_text if text is None else text)
        self.undo_stack: list[Command] = []
        self.redo_stack: list[Command] = []
        self.selected: list[Ref] = []  # the selection, its primary (last clicked) entry last
        self._checked: tuple[str, Level | None, list[str]] | None = None
        self._batch: list | None = None

    @classmethod
    def new(cls, path, text: str) -> LevelEditor:
        """A new level to be saved at ``path``, starting as ``text`` (a template or a copy of a level)."""
        return cls(path, text=text)

    # -------------------------------------------------------- selection
    @property
    def selection(self) -> Ref | None:
        """The primary selected entry (the inspector's), or None."""
        return self.selected[-1] if self.selected else None

    @selection.setter
    def selection(self, ref: Ref | None) -> None:
        self.selected = [] if ref is None else [tuple(ref)]

    def select(self, ref: Ref, toggle: bool = False) -> None:
        """Select ``ref`` alone, or (``toggle``: shift-click) add it to the selection or take it out."""
        ref = tuple(ref)
        if not toggle:
            self.selected = [ref]
        elif ref in self.selected:
            self.selected.remove(ref)
        else:
            self.selected.append(ref)

    # ------------------------------------------------------------- text
    @property
    def spaced(self) -> bool:
        """Inline tables written ``{ xy = 20.0 }`` (the file's own style)."""
        return level_style.inline_spaced(self.saved_text)

    def text(self) -> str:
        """The document as it would be saved."""
        return tomlkit.dumps(self.doc)

    @property
    def dirty(self) -> bool:
        """Unsaved changes?"""
        return self.text() != self.saved_text

    # ----------------------------------------------------------- entries
    def table(self, ref: Ref):
        """The tomlkit table at ``ref`` (KeyError or IndexError if there is none)."""
        t = self.doc
        for k in ref:
            t = t[k]
        return t

    def exists(self, ref: Ref) -> bool:
        try:
            return isinstance(_plain(self.table(ref)), dict)
        except (KeyError, IndexError, TypeError):
            return False

    def entries(self) -> list[Ref]:
        """Every entry of the level in file order of kinds: single tables first, then each array."""
        out: list[Ref] = [(k,) for k in SINGLE_TABLES if k in self.doc]
        for key in self.doc:
            if key in SINGLE_TABLES or key not in MODELS:
                continue
            items = self.doc[key]
            if not isinstance(items, list):
                continue
            for i, t in enumerate(items):
                out.append((key, i))
                if key == "world" and isinstance(t, dict):
                    for child in WORLD_CHILDREN:
                        sub = t.get(child, [])
                        if isinstance(sub, list):
                            out.extend(("world", i, child, j) for j in range(len(sub)))
        return out

    def label(self, ref: Ref) -> str:
        """How the entry is shown in the list: the loader's name for it plus its name or comment."""
        if len(ref) == 1:
            return f"[{ref[0]}]"
        t = self.table(ref)
        kind = ref[-2]
        base = f"[[{kind}]] #{ref[-1] + 1}" if len(ref) == 2 else f"  {kind} #{ref[-1] + 1}"
        name = t.get("name") if isinstance(t, dict) else None
        if name is None:
            comment = getattr(getattr(t, "trivia", None), "comment", "") or ""
            name = comment.lstrip("# ").strip() or None
        return f"{base} {name}" if name else base

    def where(self, ref: Ref) -> str:
        """The entry's name as the loader's messages start (``[[crystal]] #2``, ``[goal]``)."""
        if len(ref) == 1:
            return f"[{ref[0]}]"
        if len(ref) == 2:
            return f"[[{ref[0]}]] #{ref[1] + 1}"
        return f"[[world]] #{ref[1] + 1}"  # a world's box/mesh messages name the world first

    def get(self, ref: Ref, key: str, default=None):
        """Field ``key`` of the entry as plain Python, or ``default`` when it is not written."""
        t = self.table(ref)
        return _plain(t[key]) if key in t else default

    def value(self, ref: Ref, key: str):
        """Field ``key`` as the loader would read it: written value or the model's default."""
        f = model_of(ref).get(key)
        default = None if f is None or f.default is REQUIRED else f.default
        if key == "color" and len(ref) == 4 and ref[0] == "world":  # a world's parts take its colour
            default = self.get(ref[:2], "color", default)
        if key == "spin" and ref[0] == "crystal":  # crystals turn unless told otherwise
            default = dict(gameplay.CRYSTAL_SPIN)
        return self.get(ref, key, default)

    # ----------------------------------------------------------- editing
    def _do(self, label: str, change, key: tuple | None = None, merge: bool = False) -> None:
        if self._batch is not None:  # inside batch(): one step for all its changes
            change()
            return
        before = self.text()
        change()
        after = self.text()
        if after == before:
            return
        top = self.undo_stack[-1] if self.undo_stack else None
        if merge and top is not None and key is not None and top.key == key:
            top.after = after  # one step for a whole drag
        else:
            self.undo_stack.append(Command(label, before, after, key))
        self.redo_stack.clear()
        self._checked = None

    @contextmanager
    def batch(self, label: str, key: tuple | None = None, merge: bool = False):
        """Changes made inside the ``with`` block are one undo step (a group move, a paste)."""
        if self._batch is not None:
            yield
            return
        self._batch = []
        before = self.text()
        try:
            yield
        finally:
            self._batch = None
            after = self.text()
            self.restore_text(before)
            self._do(label, lambda: self.restore_text(after), key=key, merge=merge)

    def restore_text(self, text: str) -> None:
        """Put the document back to ``text`` with no undo step: a drag redoes its whole change from
        where it began (so snapping works on the total), and the step is recorded by that change."""
        self.doc = tomlkit.parse(text)
        self._checked = None

    def set(self, ref: Ref, key: str, value, merge: bool = False) -> None:
        """Set field ``key`` of the entry at ``ref`` to ``value`` (None removes it: the default applies).

        The field's comment and position in the table are kept. ``merge`` joins
        this change to the previous one if it set the same field (a slider drag).
        """
        table = self.table(ref)

        def change():
            if value is None:
                if key in table:
                    del table[key]
            elif key in table and _same_keys(table[key], value):
                inner = table[key]  # an inline table { xy = 20.0 }: keep its style and order
                for k in [k for k in inner if k not in value]:
                    del inner[k]
                for k, v in value.items():
                    inner[k] = v
            elif key in table:
                table[key] = level_style.styled_item(value, self.spaced)  # tomlkit keeps its comment
            else:
                level_style.set_new_key(table, key, level_style.styled_item(value, self.spaced))

        self._do(f"set {self.where(ref)} {key}", change, key=(ref, key), merge=merge)

    def seal(self) -> None:
        """End the current drag: the next change of the same field is a step of its own."""
        if self.undo_stack:
            self.undo_stack[-1].key = None

    def add(self, kind: str, values: dict | None = None, parent: Ref | None = None) -> Ref:
        """Add a new ``[[kind]]`` (inside the world ``parent`` for ``box`` or ``mesh``) after the last
        one, in the file's style (:func:`.level_style.insert_entry`), and select it.

        Required fields get :data:`TEMPLATES` values or placeholders; ``values`` override them.
        """
        fields = dict(TEMPLATES.get(kind, {}))
        for k, f in MODELS[kind].items():
            if f.default is REQUIRED and k not in fields:
                fields[k] = _required_value(f)
        fields.update(values or {})
        if kind == "world" and "box" not in fields:
            fields["box"] = [dict(TEMPLATES["box"])]
        holder = self.doc if parent is None else self.table(parent)
        index = len(holder[kind]) if kind in holder else 0
        world = None if parent is None else parent[1]

        def change():
            self.doc = tomlkit.parse(level_style.insert_entry(self.text(), kind, fields, world))

        self._do(f"add {kind}", change)
        self.selection = (() if parent is None else tuple(parent)) + (kind, index)
        return self.selection

    def delete(self, ref: Ref) -> None:
        """Delete the entry at ``ref`` (an array's entry; single tables are not deleted)."""
        if len(ref) < 2:
            raise ValueError(f"{self.where(ref)} cannot be deleted")
        holder = self.table(ref[:-2]) if len(ref) > 2 else self.doc
        kind, index = ref[-2], ref[-1]

        def change():
            arr = holder[kind]
            if len(arr) == 1:
                del holder[kind]
            else:
                del arr[index]

        self._do(f"delete {self.where(ref)}", change)
        self.selection = None

    def duplicate(self, ref: Ref) -> Ref:
        """Add a copy of the entry at ``ref`` (a world with its parts) after its kind's last and select it."""
        values = copy.deepcopy(_plain(self.table(ref)))
        if isinstance(values.get("name"), str):
            values["name"] += " copy"
        return self.add(ref[-2], values, parent=ref[:-2] or None)

    def _restore(self, text: str) -> None:
        self.restore_text(text)
        self.selected = [r for r in self.selected if self.exists(r)]

    def undo(self) -> str | None:
        """Undo the last change; returns its label, or None when there is nothing to undo."""
        if not self.undo_stack:
            return None
        c = self.undo_stack.pop()
        self._restore(c.before)
        self.redo_stack.append(c)
        return c.label

    def redo(self) -> str | None:
        """Redo the last undone change; returns its label, or None."""
        if not self.redo_stack:
            return None
        c = self.redo_stack.pop()
        self._restore(c.after)
        self.undo_stack.append(c)
        return c.label

    # -------------------------------------------------------- validation
    def check(self) -> tuple[Level | None, list[str]]:
        """The level as the loader reads the unsaved text, or None and the loader's problems."""
        text = self.text()
        if self._checked is None or self._checked[0] != text:
            try:
                level, problems = load_level(self.path, source=text.encode("utf-8")), []
            except LevelError as e:
                level, problems = None, list(e.problems)
            self._checked = (text, level, problems)
        return self._checked[1], self._checked[2]

    @property
    def problems(self) -> list[str]:
        return self.check()[1]

    def problems_for(self, ref: Ref, key: str | None = None) -> list[str]:
        """The loader's problems about the entry at ``ref`` (and its field ``key``), to show beside it."""
        head = f"{self.path}: {self.where(ref)}"
        out = []
        for p in self.problems:
            if not (p.startswith(head + ":") or p.startswith(head + " ")):
                continue
            if len(ref) > 2 and f"> {ref[-2]} #{ref[-1] + 1}" not in p:
                continue
            if len(ref) == 2 and ref[0] == "world" and " > " in p.split(": ")[1]:
                continue
            if key is not None and f"'{key}" not in p and f"field '{key}" not in p:
                continue
            out.append(p)
        return out

    # --------------------------------------------------------------- save
    def save(self, path=None) -> Path:
        """Check the level and write it atomically; nothing is written when it has problems.

        Raises
        ------
        LevelError
            The loader's problems with the unsaved text.
        """
        target = Path(path) if path is not None else self.path
        level, problems = self.check()
        if level is None:
            raise LevelError(target, problems)
        text = self.text()
        fileio.atomic_write(target, text.encode("utf-8"))
        if path is None or target.resolve() == self.path.resolve():
            self.saved_text = text
        return target

    def save_as(self, path) -> Path:
        """Save to ``path`` (checked as :meth:`save`) and go on editing that file."""
        old = self.path
        self.path = Path(path)
        self._checked = None  # the loader's messages name the file
        try:
            return self.save()
        except Exception:
            self.path, self._checked = old, None
            raise


def _parse(path: Path, text: str) -> tomlkit.TOMLDocument:
    """``text`` as a tomlkit document, or one line naming ``path`` and where the TOML breaks.

    Raises
    ------
    LevelEditError
    """
    from tomlkit.exceptions import TOMLKitError

    try:
        return tomlkit.parse(text)
    except (TOMLKitError, ValueError) as e:  # ParseError has the line and column in its text
        raise LevelEditError(f"{path}: not valid TOML: {e}") from None
    except RecursionError:
        raise LevelEditError(f"{path}: not valid TOML: arrays or tables nested too deeply") from None


def _same_keys(item, value) -> bool:
    """Is ``value`` a dict with no key the inline table ``item`` lacks (so it is edited in place)?"""
    return isinstance(_plain(item), dict) and isinstance(value, dict) and set(value) <= set(item)


def _max_bytes() -> int:
    from .limits import MAX_LEVEL_BYTES

    return MAX_LEVEL_BYTES


__all__ = ["Command", "LevelEditError", "LevelEditor", "Ref", "SINGLE_TABLES", "TEMPLATES", "model_of"]
