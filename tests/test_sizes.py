"""Size guides of CONVENTIONS.md (*Sizes*), checked on the syntax tree of every module.

Modules under 600 lines; functions under 80 lines and with at most 8 parameters, unless the
line above the function (or above its decorators) says why with a ``# size: ...`` comment.
``DEBT`` lists what does not meet the guides yet; an entry that is met fails the test until it is
removed, so the list only shrinks.
"""

from __future__ import annotations

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "across_dimensions"
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 80
MAX_PARAMETERS = 8

#: Modules and functions still over a guide: ``"path"`` for a module, ``"path:function"`` for a function.
DEBT: set[str] = set()


def _excused(lines: list[str], node: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    first = min([node.lineno, *(d.lineno for d in node.decorator_list)])
    return first >= 2 and lines[first - 2].strip().startswith("# size:")


def offenders() -> set[str]:
    """Every module and function over a guide and not excused, as ``DEBT`` names them."""
    found = set()
    for path in sorted(PKG.rglob("*.py")):
        rel = path.relative_to(PKG).as_posix()
        text = path.read_text(encoding="utf-8")
        lines = text.splitlines()
        if len(lines) >= MAX_MODULE_LINES:
            found.add(rel)
        for node in ast.walk(ast.parse(text)):
            if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) or _excused(lines, node):
                continue
            a = node.args
            params = [x.arg for x in (*a.posonlyargs, *a.args, *a.kwonlyargs) if x.arg not in ("self", "cls")]
            if node.end_lineno - node.lineno + 1 >= MAX_FUNCTION_LINES or len(params) > MAX_PARAMETERS:
                found.add(f"{rel}:{node.name}")
    return found


def test_no_new_module_or_function_over_the_guides():
    new = sorted(offenders() - DEBT)
    assert not new, "over the size guides of CONVENTIONS.md (split it, or mark a kernel '# size: why'):\n" + "\n".join(
        new
    )


def test_debt_only_shrinks():
    paid = sorted(DEBT - offenders())
    assert not paid, "these now meet the size guides; remove them from DEBT in tests/test_sizes.py:\n" + "\n".join(paid)
