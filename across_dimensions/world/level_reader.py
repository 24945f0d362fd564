"""Reading a level file: its bounded TOML parse, the reader that checks tables against their
models, and :class:`LevelError` listing every problem found.

:class:`TableReader` reads any table against its model (a dict of :class:`~.fields.Field`),
collecting problems instead of raising, so a file's every mistake is reported at once, each naming
the file, the entry, the field and what was expected. The 4D levels (:mod:`.level`) and the Flatland
prologue levels (:mod:`.flat_level`) both read their files with it.
"""

from __future__ import annotations

import math
import string
import tomllib
from pathlib import Path

import numpy as np

from ..core import fileio
from ..core.errors import InputError
from ..core.transform import PLANES
from . import limits, resources
from .fields import REQUIRED, Field
from .limits import COLOR, MAX_COUNTS, MAX_TEXT_CHARS

DEFAULT_COLOR = (0.7, 0.7, 0.72, 1.0)
MESH_SUFFIXES = (".obj", ".glb", ".gltf", ".stl")  # what world/bake.py reads
_INT64 = (-(2**63), 2**63 - 1)  # TOML integers are 64-bit; tomllib accepts any size


def is_number(x) -> bool:
    """A finite int or float, not a bool."""
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def big_ints(value):
    """Dotted paths of integers outside TOML's 64-bit range (iterative: nesting depth is the file's)."""
    stack = [("", value)]
    while stack:
        where, v = stack.pop()
        if isinstance(v, dict):
            stack.extend((f"{where}.{k}" if where else k, x) for k, x in reversed(list(v.items())))
        elif isinstance(v, list):
            stack.extend((f"{where}[{i}]", x) for i, x in reversed(list(enumerate(v))))
        elif isinstance(v, int) and not isinstance(v, bool) and not _INT64[0] <= v <= _INT64[1]:
            yield where


class LevelError(InputError):
    """Every problem found in one level file, one per line."""

    def __init__(self, path, problems: list[str]):
        self.path = Path(path)
        self.problems = problems
        super().__init__("\n".join(problems))


def hint_problem(hint: str) -> str | None:
    """Why the window cannot show ``hint`` ({action} placeholders, {{ }} for braces)."""
    if len(hint) > MAX_TEXT_CHARS:
        return f"expected at most {MAX_TEXT_CHARS} characters, got {len(hint)}"
    try:
        parts = list(string.Formatter().parse(hint))
    except ValueError as e:
        return f"{e} (write {{{{ and }}}} for a brace)"
    for _, name, spec, conv in parts:
        if name is not None and (not name.isidentifier() or spec or conv):
            shown = f"{{{name}{'!' + conv if conv else ''}{':' + spec if spec else ''}}}"
            return f"'{shown}' is not an {{action}} placeholder"
    return None


class TableReader:
    """Reads tables against their models, collecting problems instead of raising."""

    def __init__(self, path: Path):
        self.path = path
        self.problems: list[str] = []
        self.counts = dict.fromkeys(MAX_COUNTS, 0)
        self.tets = 0  # estimated tetrahedra of the 4D content read so far
        self._tets_reported = False

    def problem(self, where: str, msg: str) -> None:
        self.problems.append(f"{self.path}: {where}: {msg}")

    # ------------------------------------------------------------ tables
    def table(self, data, key, where, required=False) -> dict:
        v = data.get(key)
        if v is None:
            if required:
                self.problem(where, f"missing table [{key}]")
            return {}
        if not isinstance(v, dict):
            self.problem(where, f"'{key}' must be a table, got {type(v).__name__}")
            return {}
        return v

    def array_of_tables(self, data, key, where) -> list[dict]:
        v = data.get(key, [])
        if not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
            self.problem(where, f"'{key}' must be an array of tables ([[{key}]]), got {type(v).__name__}")
            return []
        return v

    def entries(self, data, key, where, label) -> list[dict]:
        """The ``[[key]]`` tables of ``data``, cut at the level's limit for that kind.

        ``label(k)`` names the k-th entry (from 1) for messages. Entries past the
        limit are not read at all, so an enormous file costs no more than one
        just over the limit.
        """
        items = self.array_of_tables(data, key, where)
        limit, what = MAX_COUNTS[key]
        room = limit - self.counts[key]
        if len(items) > room:
            if room >= 0:  # one line per kind: later tables of that kind are just not read
                self.problem(
                    label(room + 1),
                    f"a level may have at most {limit} {what}; this one and those after it are not read",
                )
            items = items[: max(room, 0)]
            room = -1
        self.counts[key] = limit + 1 if room < 0 else self.counts[key] + len(items)
        return items

    def add_tets(self, n: int, where: str) -> None:
        """Count an entry's estimated tetrahedra against the level's total."""
        self.tets += n
        if self.tets > limits.MAX_TOTAL_TETS and not self._tets_reported:
            self._tets_reported = True
            self.problem(
                where,
                f"with this entry the level's 4D content reaches about {self.tets:,} tetrahedra; "
                f"a level may have at most {limits.MAX_TOTAL_TETS:,}",
            )

    def values(self, data, key: str, model: dict) -> dict | None:
        """The checked values of the single table ``[key]``, or None when the level leaves it out."""
        if key not in data:
            return None
        where = f"[{key}]"
        t = self.table(data, key, where)
        self.unknown(t, model, where)
        return self.read(t, model, where)

    def unknown(self, data: dict, allowed, where) -> None:
        for k in data:
            if k not in allowed:
                self.problem(where, f"unknown field '{k}' (expected one of: {', '.join(sorted(allowed))})")

    def read(self, data: dict, model: dict, where: str, keys=None, **defaults) -> dict:
        """Read the fields ``keys`` (default: all but nested tables) of ``data`` by ``model``.

        ``defaults`` override the model's defaults (a colour inherited from a world).
        Returns field name -> value (numbers as float, vectors as float64 arrays).
        """
        out = {}
        for key in keys if keys is not None else model:
            f = model[key]
            if f.kind in ("tables", "params", "hints", "words"):
                continue
            out[key] = getattr(self, f"_{f.kind}")(data, key, where, f, defaults.get(key, f.default))
        return out

    # ------------------------------------------------------------ field kinds
    @staticmethod
    def _fallback(f: Field, default, n: int | None = None):
        """A stand-in for a bad value, so later checks can run (the level is refused anyway)."""
        if n is None:
            if is_number(default):
                return float(default)
            return float(min(max(0.0, f.range.lo), f.range.hi)) if f.range else 0.0
        return np.ones(n) if f.sign == "positive" else np.zeros(n)

    def _number(self, data, key, where, f: Field, default):
        if key not in data:
            if default is REQUIRED:
                self.problem(where, f"missing field '{key}' (a number)")
                return self._fallback(f, None)
            return default if default is None else float(default)
        v = data[key]
        if not is_number(v):
            self.problem(where, f"field '{key}': expected a number, got {v!r}")
        elif f.sign == "positive" and v <= 0:
            self.problem(where, f"field '{key}': expected a number > 0, got {v!r}")
        elif f.sign == "nonnegative" and v < 0:
            self.problem(where, f"field '{key}': expected a number >= 0, got {v!r}")
        elif f.range is not None and v not in f.range:
            self.problem(where, f"field '{key}': expected a number {f.range.text()}, got {v!r}")
        else:
            return float(v)
        return self._fallback(f, default)

    def _vector(self, data, key, where, f: Field, default):
        n, names = f.n, f.names
        if key not in data:
            if default is REQUIRED:
                self.problem(where, f"missing field '{key}' (a list of {n} numbers {list(names[:n])})")
                return np.zeros(n)
            return None if default is None else np.asarray(default, dtype=np.float64)
        v = data[key]
        ok = isinstance(v, list) and len(v) == n and all(is_number(x) for x in v)
        if ok and f.sign == "positive" and any(x <= 0 for x in v):
            self.problem(where, f"field '{key}': expected {n} positive numbers, got {v!r}")
        elif not ok:
            self.problem(where, f"field '{key}': expected a list of {n} numbers {list(names[:n])}, got {v!r}")
        elif f.range is not None and any(x not in f.range for x in v):
            self.problem(where, f"field '{key}': expected {n} numbers {f.range.text()}, got {v!r}")
        elif f.length is not None and math.hypot(*v) > f.length:
            self.problem(
                where,
                f"field '{key}': expected a length of at most {f.length:g}, got {v!r} (length {math.hypot(*v):.4g})",
            )
        else:
            return np.asarray(v, dtype=np.float64)
        return self._fallback(f, default, n)

    def _scale(self, data, key, where, f: Field, default):
        v = data.get(key, default)
        n = f.n
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            if not is_number(v) or v <= 0:
                self.problem(where, f"field '{key}': expected a positive number or {n} positive numbers, got {v!r}")
                return np.ones(n)
            if f.range is not None and v not in f.range:
                self.problem(where, f"field '{key}': expected a number or {n} numbers {f.range.text()}, got {v!r}")
                return np.ones(n)
            return np.full(n, float(v))
        return self._vector(data, key, where, f, REQUIRED)

    def _string(self, data, key, where, f: Field, default):
        if key not in data:
            if default is REQUIRED:
                self.problem(where, f"missing field '{key}' (a string)")
                return ""
            return default
        v = data[key]
        choices = f.choices
        default = None if default is REQUIRED else default
        if not isinstance(v, str):
            self.problem(where, f"field '{key}': expected a string, got {v!r}")
            return default or ""
        if choices and v not in choices:
            self.problem(where, f"field '{key}': expected one of {', '.join(choices)}, got {v!r}")
            return default or choices[0]
        return v

    def _text(self, data, key, where, f: Field, default):
        v = self._string(data, key, where, f, default)
        if isinstance(v, str) and len(v) > f.range.hi:
            self.problem(where, f"field '{key}': expected at most {f.range.hi:g} characters, got {len(v)}")
            return v[: int(f.range.hi)]
        return v

    def _bool(self, data, key, where, f: Field, default):
        v = data.get(key, default)
        if not isinstance(v, bool):
            self.problem(where, f"field '{key}': expected true or false, got {v!r}")
            return default
        return v

    def _color(self, data, key, where, f: Field, default):
        default = DEFAULT_COLOR if default is None else default
        if key not in data:
            return tuple(default)
        v = data[key]
        if (
            isinstance(v, list)
            and len(v) in (3, 4)
            and all(isinstance(x, (int, float)) and not isinstance(x, bool) and x in COLOR for x in v)
        ):
            return tuple(float(x) for x in v) + ((1.0,) if len(v) == 3 else ())
        self.problem(where, f"field '{key}': expected 3 or 4 numbers between 0 and 1 (RGB[A]), got {v!r}")
        return tuple(default)

    def _angles(self, data, key, where, f: Field, default) -> dict:
        v = data.get(key, {})
        if not isinstance(v, dict):
            self.problem(
                where, f"field '{key}': expected a table of plane = degrees with planes {', '.join(PLANES)}, got {v!r}"
            )
            return {}
        out = {}
        for plane, deg in v.items():
            if plane not in PLANES:
                self.problem(
                    where, f"field '{key}': unknown rotation plane '{plane}' (expected one of {', '.join(PLANES)})"
                )
            elif not is_number(deg):
                self.problem(where, f"field '{key}.{plane}': expected degrees as a number, got {deg!r}")
            elif f.range is not None and deg not in f.range:
                self.problem(where, f"field '{key}.{plane}': expected a number {f.range.text()}, got {deg!r}")
            else:
                out[plane] = float(deg)
        return out

    def _asset(self, data, key, where, f: Field, default) -> Path | None:
        if key not in data and default is not REQUIRED:
            return default
        rel = self._string(data, key, where, f, REQUIRED)
        if not rel:
            if isinstance(data.get(key), str):
                self.problem(
                    where,
                    f"field '{key}': expected a path inside the assets folder such as "
                    f'"meshes/crate.obj", got an empty string',
                )
            return None
        try:
            full = resources.resolve_asset(rel)
        except ValueError as e:
            self.problem(where, f"field '{key}': {e}")
            return None
        if full.suffix.lower() not in MESH_SUFFIXES:
            self.problem(where, f"field '{key}': expected a mesh file ({', '.join(MESH_SUFFIXES)}), got {rel!r}")
            return None
        return full


def parse_level(path: Path, source: bytes | None = None) -> tuple[dict, bytes]:
    """Read ``path`` (bounded), or take ``source`` as its text, and parse it as TOML,
    or raise LevelError with one line."""
    if source is not None and len(source) > limits.MAX_LEVEL_BYTES:
        raise LevelError(path, [f"{path}: a level is at most {limits.MAX_LEVEL_BYTES:,} bytes, got {len(source):,}"])
    try:
        raw = source if source is not None else fileio.read_bytes(path, limit=limits.MAX_LEVEL_BYTES, what="level")
    except fileio.FileProblem as e:
        raise LevelError(path, [str(e)]) from None
    try:
        data = tomllib.loads(raw.decode("utf-8-sig"))  # -sig: skip a byte-order mark
    except UnicodeDecodeError:
        raise LevelError(path, [f"{path}: not a text file (expected UTF-8 TOML)"]) from None
    except (tomllib.TOMLDecodeError, ValueError) as e:  # ValueError: an integer over 4300 digits
        raise LevelError(path, [f"{path}: not valid TOML: {e}"]) from None
    except RecursionError:
        raise LevelError(path, [f"{path}: not valid TOML: arrays or tables nested too deeply"]) from None
    big = list(big_ints(data))
    if big:
        raise LevelError(
            path,
            [
                f"{path}: {b}: integer out of range (TOML integers are 64-bit; write a float like 1e30 for huge values)"
                for b in big[:20]
            ],
        )
    return data, raw
