"""No Linux-only assumption in the code a Windows or macOS build of the game would run.

The standalone game is built and tested on Linux only (README, *Standalone game*), but the
package and the frozen entry point are written to run elsewhere. This scans their sources:

* no ``os.fork`` (Windows has none; macOS forbids it once a GUI framework is loaded);
* no module only Unix has (``fcntl``, ``resource``, ``pwd``...) imported unguarded at the top
  of a module, where its absence would stop every command;
* no per-user folder spelled out (``~/.cache``, ``XDG_*``, ``$HOME``): they come from platformdirs;
* a path into a Unix system folder (``/proc``, ``/sys``, ``/etc``, ``/tmp``, ``/usr``, ``/lib``)
  only in a function that survives its absence: it catches ``OSError`` or checks the platform.

The last rule can be fooled, as any scan can; it catches the usual slip, a ``/proc`` read with
no way out on a system that has no ``/proc``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sorted((ROOT / "across_dimensions").rglob("*.py")) + sorted((ROOT / "packaging").glob("*.py"))
UNIX_ONLY_MODULES = {"fcntl", "termios", "tty", "pty", "pwd", "grp", "resource", "posix", "readline", "curses"}
SYSTEM_FOLDERS = ("/proc", "/sys/", "/etc/", "/tmp/", "/usr/", "/lib", "/dev/")
USER_FOLDERS = ("~/", "XDG_", "$HOME")
PLATFORM_CHECKS = ("sys.platform", "platform.system", "os.name")


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the string constants that are docstrings (they may name any path)."""
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                ids.add(id(first.value))
    return ids


def _survives(scope: ast.AST) -> bool:
    """Does ``scope`` (a function, or a module-level block) catch OSError or check the platform?"""
    for node in ast.walk(scope):
        if isinstance(node, ast.ExceptHandler):
            caught = ast.unparse(node.type) if node.type is not None else "BaseException"
            if any(name in caught for name in ("OSError", "FileNotFoundError", "Exception")):
                return True
        if isinstance(node, ast.If) and any(check in ast.unparse(node.test) for check in PLATFORM_CHECKS):
            return True
    return False


def _reads_home(node: ast.AST) -> bool:
    """``os.environ["HOME"]``, ``os.environ.get("HOME")`` or ``os.getenv("HOME")`` (Windows has no HOME)."""
    if isinstance(node, ast.Subscript) and ast.unparse(node.value) == "os.environ":
        key = node.slice
    elif isinstance(node, ast.Call) and ast.unparse(node.func) in ("os.environ.get", "os.getenv") and node.args:
        key = node.args[0]
    else:
        return False
    return isinstance(key, ast.Constant) and key.value == "HOME"


def _problems(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docs, found = _docstrings(tree), []
    where = f"{path.relative_to(ROOT)}"

    def visit(scope: ast.AST, parents: list[ast.AST]) -> None:
        for node in ast.iter_child_nodes(scope):
            inner = parents
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.If | ast.Try):
                inner = [*parents, node]
            if _reads_home(node):
                found.append(f"{where}:{node.lineno}: $HOME read: a per-user folder comes from platformdirs")
            if isinstance(node, ast.Attribute) and ast.unparse(node) in ("os.fork", "os.forkpty"):
                found.append(f"{where}:{node.lineno}: {ast.unparse(node)}")
            if isinstance(node, ast.Import | ast.ImportFrom) and not any(isinstance(p, ast.Try) for p in parents):
                names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
                functions = [p for p in parents if isinstance(p, ast.FunctionDef | ast.AsyncFunctionDef)]
                unix = [n for n in names if n.split(".")[0] in UNIX_ONLY_MODULES]
                if unix and not functions:
                    found.append(f"{where}:{node.lineno}: imports {unix[0]} (Unix only) at module level")
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
                text = node.value
                if text.startswith(USER_FOLDERS):
                    found.append(f"{where}:{node.lineno}: {text!r}: a per-user folder comes from platformdirs")
                elif text.startswith(SYSTEM_FOLDERS) and not any(map(_survives, parents)):
                    found.append(f"{where}:{node.lineno}: {text!r} with no fallback when it does not exist")
            visit(node, inner)

    visit(tree, [])
    return found


def test_the_scan_finds_what_it_looks_for(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text(
        "import os\nimport fcntl\n"
        "def cores():\n    return open('/proc/cpuinfo').read()\n"
        "def child():\n    return os.fork()\n"
        "CACHE = '~/.cache/game'\nHOME = os.environ['HOME']\n",
        encoding="utf-8",
    )
    good = tmp_path / "good.py"
    good.write_text(
        "import sys\ntry:\n    import fcntl\nexcept ImportError:\n    fcntl = None\n"
        "def cores():\n    try:\n        return open('/proc/cpuinfo').read()\n    except OSError:\n        return ''\n",
        encoding="utf-8",
    )
    global ROOT
    saved, ROOT = ROOT, tmp_path
    try:
        assert len(_problems(bad)) == 5, _problems(bad)
        assert _problems(good) == []
    finally:
        ROOT = saved


@pytest.mark.parametrize("path", SOURCES, ids=[str(p.relative_to(ROOT)) for p in SOURCES])
def test_no_linux_only_assumption(path):
    assert _problems(path) == []
