"""Mutations of parsed data trees (dicts, lists, scalars) and of raw bytes.

Every function takes a ``numpy.random.Generator`` and returns the mutated
value plus a short description for the failure report; the inputs are never
changed in place. Values that no sane file holds are the point: numbers at the
ends of the float range, NaN, integers far beyond 64 bits, wrong types,
missing and repeated entries, nesting thousands of levels deep.
"""

from __future__ import annotations

import copy
import math

import numpy as np

from .emit import Raw

__all__ = [
    "EXTREMES",
    "TYPE_SWAPS",
    "describe",
    "nodes",
    "get_at",
    "set_at",
    "delete_at",
    "where",
    "number_extreme",
    "type_swap",
    "delete_entry",
    "duplicate_tables",
    "deep_nesting",
    "long_string",
    "unknown_field",
    "truncate",
    "random_bytes",
    "bit_flips",
    "duplicate_line",
    "delete_lines",
    "bad_encoding",
    "pick",
]

#: Numbers at the edges: zero, negatives, the largest and smallest floats, NaN,
#: infinities, and integers too big for 64 bits (10**5000 is past Python's
#: 4300-digit str/int conversion limit).
EXTREMES = (
    0,
    -1,
    1e308,
    -1e308,
    5e-324,
    math.nan,
    math.inf,
    -math.inf,
    10**30,
    -(10**30),
    10**5000,
    2**63,
    2**64,
    1e300,
    1e-300,
    -0.0,
    1e-9,
)

#: Values of the wrong type for almost any entry.
TYPE_SWAPS = ("text", "", True, False, [], [1, 2, 3], {}, {"x": 1}, 0, 2.5, [{"a": 1}], ["a", "b"])


def pick(rng: np.random.Generator, seq):
    """One element of ``seq``, chosen by ``rng`` (works for any sequence, unlike ``rng.choice``)."""
    return seq[int(rng.integers(len(seq)))]


def describe(v) -> str:
    """A short readable form of a value (huge integers as powers of ten, long strings by length)."""
    if isinstance(v, bool) or v is None:
        return repr(v)
    if isinstance(v, int) and abs(v) > 10**18:
        return f"{'-' if v < 0 else ''}~10**{int(math.log10(abs(v)))}"
    if isinstance(v, Raw):
        return repr(v)
    if isinstance(v, str) and len(v) > 40:
        return f"a string of {len(v)} chars starting {v[:12]!r}"
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


def where(path) -> str:
    """``("object", 2, "scale")`` -> ``object[2].scale``."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "<root>"


def nodes(tree, path=()):
    """Every ``(path, value)`` below ``tree`` (containers and leaves, root excluded), in document order."""
    items = tree.items() if isinstance(tree, dict) else enumerate(tree) if isinstance(tree, list) else ()
    for k, v in items:
        p = (*path, k)
        yield p, v
        yield from nodes(v, p)


def get_at(tree, path):
    for p in path:
        tree = tree[p]
    return tree


def set_at(tree, path, value):
    get_at(tree, path[:-1])[path[-1]] = value


def delete_at(tree, path):
    del get_at(tree, path[:-1])[path[-1]]


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def number_extreme(rng, tree, value=None):
    """Set one number (chosen at random among all numbers in ``tree``) to an extreme."""
    tree = copy.deepcopy(tree)
    numbers = [p for p, v in nodes(tree) if _is_number(v)]
    if not numbers:
        return type_swap(rng, tree)
    path = pick(rng, numbers)
    new = pick(rng, EXTREMES) if value is None else value
    set_at(tree, path, new)
    return tree, f"{where(path)} = {describe(new)}"


def type_swap(rng, tree):
    """Replace one entry (leaf or table) by a value of another type."""
    tree = copy.deepcopy(tree)
    path, old = pick(rng, list(nodes(tree)))
    choices = [v for v in TYPE_SWAPS if type(v) is not type(old)]
    new = copy.deepcopy(pick(rng, choices))
    set_at(tree, path, new)
    return tree, f"{where(path)}: {type(old).__name__} -> {describe(new)}"


def delete_entry(rng, tree):
    """Remove one field, table or list element."""
    tree = copy.deepcopy(tree)
    path, _ = pick(rng, list(nodes(tree)))
    delete_at(tree, path)
    return tree, f"deleted {where(path)}"


def duplicate_tables(rng, tree, counts=(2, 3, 10)):
    """Repeat one element of a list of tables ``count`` times (``counts`` may be 10**4..10**6)."""
    tree = copy.deepcopy(tree)
    lists = [(p, v) for p, v in nodes(tree) if isinstance(v, list) and v and isinstance(v[0], (dict, list))]
    if not lists:
        return delete_entry(rng, tree)
    path, seq = pick(rng, lists)
    i = int(rng.integers(len(seq)))
    count = int(pick(rng, counts))
    # Large floods share one copy: the writers emit it repeatedly, and deep-copying 10**6 tables is slow.
    copies = [copy.deepcopy(seq[i]) for _ in range(count - 1)] if count <= 100 else [seq[i]] * (count - 1)
    seq.extend(copies)
    return tree, f"{where(path)}[{i}] repeated {count} times"


def deep_nesting(rng, tree, depths=(200, 1000, 10_000, 100_000), json_style=False):
    """Replace one entry by arrays (or tables) nested ``depth`` levels deep."""
    tree = copy.deepcopy(tree)
    path, _ = pick(rng, list(nodes(tree)))
    depth = int(pick(rng, depths))
    if rng.random() < 0.5:
        text, what = "[" * depth + "1" + "]" * depth, "arrays"
    elif json_style:
        text, what = '{"a":' * depth + "1" + "}" * depth, "objects"
    else:
        text, what = "{ a = " * depth + "1" + " }" * depth, "inline tables"
    set_at(tree, path, Raw(text, f"{depth} nested {what}"))
    return tree, f"{where(path)} = {what} nested {depth} deep"


def long_string(rng, tree, lengths=(10_000, 1_000_000, 8_000_000)):
    """Replace one entry (or a key) by a very long string."""
    tree = copy.deepcopy(tree)
    path, _ = pick(rng, list(nodes(tree)))
    n = int(pick(rng, lengths))
    unit = pick(rng, ("A", "\u00e9", "{w_ana}", "{", "%s", "\u202e", "\x01", "\U0001f600", "\\"))
    text = (unit * (n // len(unit) + 1))[:n]
    parent = get_at(tree, path[:-1])
    if isinstance(parent, dict) and rng.random() < 0.25:  # as a key instead of a value
        parent[text] = parent.pop(path[-1])
        return tree, f"key {where(path)} renamed to {describe(text)}"
    set_at(tree, path, text)
    return tree, f"{where(path)} = {describe(text)}"


def unknown_field(rng, tree):
    """Add a field nobody expects to one table."""
    tree = copy.deepcopy(tree)
    tables = [((), tree)] + [(p, v) for p, v in nodes(tree) if isinstance(v, dict)]
    path, table = pick(rng, tables)
    name = pick(rng, ("colour", "__proto__", "", " ", "position ", "SCALE", "\u00e9t\u00e9", "a.b"))
    table[name] = pick(rng, (1, "x", [1], {"y": 2}))
    return tree, f"added field {name!r} to {where(path)}"


# ------------------------------------------------------------------ bytes
def truncate(rng, data: bytes):
    cut = int(rng.integers(0, max(len(data), 1)))
    return data[:cut], f"truncated to {cut} of {len(data)} bytes"


def random_bytes(rng, data: bytes):
    n = int(pick(rng, (0, 1, 16, 4096)))
    junk = rng.integers(0, 256, n, dtype=np.uint8).tobytes()
    if rng.random() < 0.5:
        return junk, f"replaced by {n} random bytes"
    at = int(rng.integers(0, len(data) + 1))
    return data[:at] + junk + data[at:], f"{n} random bytes inserted at byte {at}"


def bit_flips(rng, data: bytes):
    if not data:
        return b"\xff", "one byte 0xff"
    buf = bytearray(data)
    k = int(rng.integers(1, 17))
    where_ = sorted(int(i) for i in rng.integers(0, len(buf) * 8, k))
    for bit in where_:
        buf[bit // 8] ^= 1 << (bit % 8)
    return bytes(buf), f"{k} bit flips at bits {where_[:6]}{'...' if k > 6 else ''}"


def duplicate_line(rng, data: bytes):
    lines = data.split(b"\n")
    i = int(rng.integers(len(lines)))
    k = int(pick(rng, (1, 2, 1000)))
    lines[i + 1 : i + 1] = [lines[i]] * k
    return b"\n".join(lines), f"line {i + 1} repeated {k} more time(s): {lines[i][:40]!r}"


def delete_lines(rng, data: bytes):
    lines = data.split(b"\n")
    i = int(rng.integers(len(lines)))
    k = int(rng.integers(1, 4))
    del lines[i : i + k]
    return b"\n".join(lines), f"deleted lines {i + 1}..{i + k}"


def bad_encoding(rng, data: bytes):
    kind = pick(rng, ("utf-16", "nul", "latin-1", "bom-twice", "crlf"))
    if kind == "utf-16":
        return data.decode("utf-8", "replace").encode("utf-16"), "re-encoded as UTF-16"
    if kind == "nul":
        at = int(rng.integers(0, len(data) + 1))
        return data[:at] + b"\x00" + data[at:], f"NUL byte at {at}"
    if kind == "latin-1":
        at = int(rng.integers(0, len(data) + 1))
        return data[:at] + b"\xe9\xff" + data[at:], f"Latin-1 bytes at {at}"
    if kind == "bom-twice":
        return b"\xef\xbb\xbf\xef\xbb\xbf" + data, "two byte-order marks"
    return data.replace(b"\n", b"\r\n").replace(b"\r\n", b"\r", 3), "CRLF line ends with lone CRs"
