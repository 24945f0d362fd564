"""Writing new entries and fields in the style of the level file being edited.

A level file is written by hand: sections headed by a comment (``# ---- props ...``), a blank
line between tables, world parts indented, inline tables written ``{ xy = 20.0 }``. tomlkit
appends a new ``[[object]]`` after everything that follows the last one, section comments
included, and writes its own ``{xy = 20.0}``; so the editor places new text itself:

- a new entry goes after the last entry of its kind (inside its world for a world's part),
  before the comments that head the next section, with one blank line before and after it;
- a new field goes after the entry's last field, not after the comments that follow it;
- inline tables follow the file's spacing (:func:`inline_spaced`).

Everything here works on plain text lines or on one tomlkit table, and never changes a value.
"""

from __future__ import annotations

import re

import tomlkit

#: A table header on a line of its own (``[[world.box]]   # the wall``); a line of a multi-line
#: array (``[0.0, 1.0],``) never matches, as a header names a table by a bare key.
HEADER = re.compile(r"^(\s*)\[(\[?)\s*([A-Za-z_][\w.-]*)\s*\]\]?\s*(#.*)?$")
CHILD_INDENT = "  "  # a world's parts, when the file has none yet to copy


def inline_spaced(text: str) -> bool:
    """Does the file write inline tables with spaces inside the braces (``{ xy = 20.0 }``)?
    The shipped levels do; a file with only ``{xy = 20.0}`` keeps that."""
    tight = len(re.findall(r"=\s*\{[^\s}]", text))
    spaced = len(re.findall(r"=\s*\{\s[^}]*\s\}", text))
    return spaced >= tight


def render_value(value, spaced: bool = True) -> str:
    """A plain value (number, string, bool, list, dict of numbers) as TOML text on one line."""
    if isinstance(value, dict):
        if not value:
            return "{}"
        inner = ", ".join(f"{k} = {render_value(v, spaced)}" for k, v in value.items())
        return f"{{ {inner} }}" if spaced else f"{{{inner}}}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(render_value(v, spaced) for v in value) + "]"
    return tomlkit.item(value).as_string()


def entry_lines(name: str, values: dict, indent: str = "", spaced: bool = True) -> list[str]:
    """The lines of a new ``[[name]]`` table: its fields in order, then its own arrays of tables
    (a world's ``box`` and ``mesh`` lists of dicts) as ``[[name.box]]`` indented one step more."""
    lines = [f"{indent}[[{name}]]"]
    children = {}
    for k, v in values.items():
        if isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            children[k] = v
        elif v is not None:
            lines.append(f"{indent}{k} = {render_value(v, spaced)}")
    for k, items in children.items():
        for item in items:
            lines += ["", *entry_lines(f"{name}.{k}", item, indent + CHILD_INDENT, spaced)]
    return lines


def _headers(lines: list[str]) -> list[tuple[int, str, str]]:
    """``(line index, table name, indent)`` of every table header."""
    out = []
    for i, line in enumerate(lines):
        m = HEADER.match(line)
        if m:
            out.append((i, m.group(3), m.group(1)))
    return out


def _span_end(headers, k: int, n_lines: int, prefix: str) -> int:
    """The line after the table at ``headers[k]`` and its own sub-tables (names starting ``prefix``)."""
    for i, name, _ in headers[k + 1 :]:
        if not name.startswith(prefix):
            return i
    return n_lines


def _content_end(lines: list[str], start: int, end: int) -> int:
    """The line after the last field in ``lines[start:end]``: comments and blank lines at its end
    head what follows, so a new entry goes before them."""
    i = end
    while i > start + 1 and (not lines[i - 1].strip() or lines[i - 1].lstrip().startswith("#")):
        i -= 1
    return i


def insert_entry(text: str, kind: str, values: dict, world: int | None = None) -> str:
    """``text`` with a new ``[[kind]]`` (or, with ``world``, a ``[[world.kind]]`` in that world,
    counted from 0) after the last one, in the file's style."""
    lines = text.splitlines()
    headers = _headers(lines)
    name, lo, hi, indent = kind, 0, len(lines), ""
    if world is not None:
        worlds = [k for k, h in enumerate(headers) if h[1] == "world"]
        k = worlds[world]
        name = f"world.{kind}"
        lo, hi = headers[k][0], _span_end(headers, k, len(lines), "world.")
        indent = next((h[2] for h in headers if h[1].startswith("world.")), CHILD_INDENT)
    own = [k for k, h in enumerate(headers) if h[1] == name and lo <= h[0] < hi]
    if own:
        k = own[-1]
        indent = headers[k][2]
        at = _content_end(lines, headers[k][0], _span_end(headers, k, hi, name + "."))
    elif world is not None:
        at = _content_end(lines, lo, hi)
    else:
        at = _content_end(lines, -1, len(lines))
    new = entry_lines(name, values, indent, inline_spaced(text))
    before = [""] if at > 0 and lines[at - 1].strip() else []
    after = [""] if at < len(lines) and lines[at].strip() else []
    lines[at:at] = before + new + after
    return "\n".join(lines) + "\n"


def set_new_key(table, key: str, item) -> None:
    """Add ``key`` to the tomlkit ``table`` after its last field (tomlkit would put it after the
    comments that close the table, i.e. under the next section's heading)."""
    last = None
    for i, (k, v) in enumerate(table.value.body):
        if k is not None and not isinstance(v, (tomlkit.items.Table, tomlkit.items.AoT)):
            last = i, k
    if last is None:
        table[key] = item
        return
    at, last_key = last
    indent = table.value.item(last_key).trivia.indent
    if at + 1 < len(table.value.body):
        # tomlkit has no public ordered insert; ``_insert_at`` is the one its own ``append`` uses
        # (its ``_insert_after`` went away in 0.15.3, so the index is found here).
        table.value._insert_at(at + 1, key, item)  # noqa: SLF001
    else:
        table[key] = item  # nothing follows the last field: appending is in order
    table.value.item(key).trivia.indent = indent


def styled_item(value, spaced: bool):
    """A tomlkit item for ``value``; an inline table keeps the file's spacing."""
    if isinstance(value, dict):
        return tomlkit.parse(f"v = {render_value(value, spaced)}\n")["v"]
    return tomlkit.item(list(value) if isinstance(value, tuple) else value)
