"""Write fuzzed data as TOML or JSON text, including what a careful writer refuses.

``tomli_w`` and ``json.dumps`` cannot write everything a hostile file may hold:
NaN in TOML is fine but integers of 5000 digits trip Python's ``int`` to ``str``
limit, and deeply nested arrays overflow any recursive writer. These emitters
write any tree of dicts, lists, strings, numbers and booleans, and splice
:class:`Raw` text in verbatim (deep nesting is built as text, not as a tree).
"""

from __future__ import annotations

import contextlib
import json
import math
import re
import sys

__all__ = ["Raw", "toml_dumps", "json_dumps", "no_int_digit_limit"]

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


class Raw:
    """Text written as it is, in place of a value."""

    def __init__(self, text: str, label: str = "raw"):
        self.text = text
        self.label = label

    def __repr__(self) -> str:
        return f"Raw({self.label}, {len(self.text)} chars)"


@contextlib.contextmanager
def no_int_digit_limit():
    """Let ``str(10**5000)`` work (Python 3.11+ limits it to 4300 digits by default)."""
    get = getattr(sys, "get_int_max_str_digits", None)
    if get is None:
        yield
        return
    old = get()
    sys.set_int_max_str_digits(0)
    try:
        yield
    finally:
        sys.set_int_max_str_digits(old)


def _key(k) -> str:
    k = str(k)
    return k if _BARE_KEY.match(k) else json.dumps(k)


def _toml_value(v) -> str:
    if isinstance(v, Raw):
        return v.text
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)  # JSON escapes are valid TOML basic-string escapes
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"cannot write {type(v).__name__} as TOML")


def _is_table_array(v) -> bool:
    return isinstance(v, list) and len(v) > 0 and all(isinstance(x, dict) for x in v)


def _toml_table(table: dict, prefix: str, out: list) -> None:
    for k, v in table.items():
        if not isinstance(v, dict) and not _is_table_array(v):
            out.append(f"{_key(k)} = {_toml_value(v)}")
    for k, v in table.items():
        name = f"{prefix}.{_key(k)}" if prefix else _key(k)
        if isinstance(v, dict):
            out.append(f"\n[{name}]")
            _toml_table(v, name, out)
        elif _is_table_array(v):
            done: dict[int, str] = {}  # a flood of 10**6 copies shares one dict: write it once
            for item in v:
                if id(item) not in done:
                    sub = [f"\n[[{name}]]"]
                    _toml_table(item, name, sub)
                    done[id(item)] = "\n".join(sub)
                out.append(done[id(item)])


def toml_dumps(doc: dict) -> str:
    """TOML text for ``doc``: tables as ``[name]``, lists of tables as ``[[name]]``."""
    out: list[str] = []
    with no_int_digit_limit():
        _toml_table(doc, "", out)
    return "\n".join(out) + "\n"


def json_dumps(doc, indent: int | None = None) -> str:
    """JSON text for ``doc`` with NaN/Infinity allowed, any integer size and :class:`Raw` spliced in."""
    raws: list[str] = []

    def swap(v):
        if isinstance(v, Raw):
            raws.append(v.text)
            return f"\x00RAW{len(raws) - 1}\x00"
        if isinstance(v, dict):
            return {str(k): swap(x) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [swap(x) for x in v]
        return v

    with no_int_digit_limit():
        text = json.dumps(swap(doc), indent=indent, separators=None if indent else (",", ":"))
    return re.sub(r'"\\u0000RAW(\d+)\\u0000"', lambda m: raws[int(m.group(1))], text)
