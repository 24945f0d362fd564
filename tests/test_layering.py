"""The package's layering rules, checked on the syntax tree of every module.

* ``core/`` imports only numpy, numba, the standard library and
  ``across_dimensions.core`` itself (no exception: even GLB export is numpy).
* only ``render/`` imports moderngl; only ``app/`` imports pyglet; only the Flatland prologue's
  simulation (``game/flatland/``) imports pymunk, so it never reaches ``core`` or ``physics``.
* ``game/``, ``physics/``, ``world/`` and ``core/`` never read the wall clock
  (benchmarks excepted) and never use global random state: randomness comes
  from seeded ``np.random.default_rng`` generators.
* the packages stand in the order ``core <- physics <- world <- game <- probe <-
  render <- bench <- app``: a package imports only those below it (world never imports
  game, physics never imports world, the design probe never imports the renderer or the
  app, the benchmarks never import the app, ...),
  at module level or inside a function.
* an import inside a function never hides a circle: it may not import a module
  that imports the importer's module, directly or through others.

Every ``.py`` under ``across_dimensions/`` is parsed with :mod:`ast`, so
comments and docstrings that mention a module never count, and relative,
aliased, function-level and ``importlib.import_module("...")`` imports do.
"""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PKG = REPO / "across_dimensions"

CORE_THIRD_PARTY = {"numpy", "numba"}
DETERMINISTIC = ("game/", "physics/", "world/", "core/")
# Benchmarks time the simulation from outside; nothing they measure reaches its state.
CLOCK_ALLOWED = {"core/bench.py", "physics/bench.py"}
CLOCK_FUNCS = {
    "time.time",
    "time.time_ns",
    "time.perf_counter",
    "time.perf_counter_ns",
    "time.monotonic",
    "time.monotonic_ns",
    "datetime.datetime.now",
    "datetime.datetime.utcnow",
    "datetime.datetime.today",
    "datetime.date.today",
}
#: numpy.random names that do not touch the global RandomState.
RANDOM_ALLOWED = {
    "default_rng",
    "Generator",
    "SeedSequence",
    "BitGenerator",
    "PCG64",
    "PCG64DXSM",
    "Philox",
    "SFC64",
    "MT19937",
}


# ----------------------------------------------------------------- the checker
@dataclass(frozen=True)
class Import:
    rel: str  # path under across_dimensions/, e.g. "core/mesh.py"
    line: int
    module: str  # absolute dotted name
    in_function: bool  # inside a def / lambda body (a lazy import)
    text: str  # the statement as written

    def where(self) -> str:
        return f"across_dimensions/{self.rel}:{self.line}: {self.text}"


def module_of(rel: str) -> str:
    parts = ["across_dimensions", *rel[:-3].split("/")]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _package_of(rel: str) -> list[str]:
    mod = module_of(rel).split(".")
    return mod if rel.endswith("__init__.py") else mod[:-1]


def _resolve_from(node: ast.ImportFrom, rel: str) -> str:
    if node.level == 0:
        return node.module or ""
    base = _package_of(rel)
    base = base[: len(base) - (node.level - 1)] if node.level > 1 else base
    return ".".join(base + ([node.module] if node.module else []))


def _walk(tree: ast.AST):
    """Yield ``(node, in_function)`` for every node."""
    stack = [(tree, False)]
    while stack:
        node, in_fn = stack.pop()
        yield node, in_fn
        inner = in_fn or isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
        stack.extend((child, inner) for child in ast.iter_child_nodes(node))


def imports(rel: str, source: str) -> list[Import]:
    """Every import in a module, with absolute module names."""
    out = []
    for node, in_fn in _walk(ast.parse(source, filename=rel)):
        if isinstance(node, ast.Import):
            for a in node.names:
                out.append(Import(rel, node.lineno, a.name, in_fn, ast.unparse(node)))
        elif isinstance(node, ast.ImportFrom):
            base = _resolve_from(node, rel)
            if node.level and not node.module:  # "from . import x": x may be a submodule
                for a in node.names:
                    out.append(Import(rel, node.lineno, f"{base}.{a.name}", in_fn, ast.unparse(node)))
            else:
                out.append(Import(rel, node.lineno, base, in_fn, ast.unparse(node)))
        elif (
            isinstance(node, ast.Call)
            and node.args
            and isinstance(node.args[0], ast.Constant)
            and isinstance(node.args[0].value, str)
            and ast.unparse(node.func) in ("importlib.import_module", "import_module", "__import__")
        ):
            out.append(Import(rel, node.lineno, node.args[0].value, in_fn, ast.unparse(node)))
    return out


def _aliases(tree: ast.AST, rel: str) -> dict[str, str]:
    """Local name -> dotted name it was imported as (``np`` -> ``numpy``)."""
    names: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.asname:
                    names[a.asname] = a.name
                else:
                    root = a.name.split(".")[0]
                    names[root] = root
        elif isinstance(node, ast.ImportFrom) and node.module:
            base = _resolve_from(node, rel)
            for a in node.names:
                names[a.asname or a.name] = f"{base}.{a.name}"
    return names


def _dotted(node: ast.AST, names: dict[str, str]) -> str | None:
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name) or node.id not in names:
        return None
    return ".".join([names[node.id], *reversed(parts)])


def references(rel: str, source: str) -> list[tuple[int, str, str]]:
    """``(line, dotted name, text)`` for every name or attribute chain rooted in an import."""
    tree = ast.parse(source, filename=rel)
    names = _aliases(tree, rel)
    out = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.Name, ast.Attribute)) and isinstance(node.ctx, ast.Load):
            dotted = _dotted(node, names)
            if dotted:
                out.append((node.lineno, dotted, ast.unparse(node)))
        elif isinstance(node, ast.ImportFrom) and node.module:
            base = _resolve_from(node, rel)
            for a in node.names:
                out.append((node.lineno, f"{base}.{a.name}", ast.unparse(node)))
    return sorted(out)


# ------------------------------------------------------------------- the rules
def core_import_problems(rel: str, source: str) -> list[str]:
    out = []
    for imp in imports(rel, source):
        root = imp.module.split(".")[0]
        if root in CORE_THIRD_PARTY or root in sys.stdlib_module_names:
            continue
        if imp.module == "across_dimensions.core" or imp.module.startswith("across_dimensions.core."):
            continue
        out.append(
            f"{imp.where()}  (core may import only numpy, numba, the standard library "
            f"and across_dimensions.core; found {imp.module})"
        )
    return out


def exclusive_import_problems(rel: str, source: str, module: str, owner: str) -> list[str]:
    if rel.startswith(owner):
        return []
    return [
        f"{imp.where()}  (only across_dimensions/{owner} may import {module})"
        for imp in imports(rel, source)
        if imp.module.split(".")[0] == module
    ]


def clock_problems(rel: str, source: str) -> list[str]:
    seen, out = set(), []
    for line, dotted, text in references(rel, source):
        if dotted in CLOCK_FUNCS and (line, dotted) not in seen:
            seen.add((line, dotted))
            out.append(f"across_dimensions/{rel}:{line}: {text}  (reads the wall clock: {dotted})")
    return out


def random_problems(rel: str, source: str) -> list[str]:
    out = [
        f"{imp.where()}  (the random module is global random state; use np.random.default_rng(seed))"
        for imp in imports(rel, source)
        if imp.module.split(".")[0] == "random"
    ]
    seen = set()
    for line, dotted, text in references(rel, source):
        parts = dotted.split(".")
        if parts[:2] == ["numpy", "random"] and len(parts) > 2 and parts[2] not in RANDOM_ALLOWED:
            if (line, parts[2]) not in seen:
                seen.add((line, parts[2]))
                out.append(
                    f"across_dimensions/{rel}:{line}: {text}  (numpy.random.{parts[2]} uses the global "
                    "random state; use a seeded np.random.default_rng)"
                )
    return out


#: The packages, lowest first: each may import only itself and those before it.
PACKAGE_ORDER = ("core", "physics", "world", "game", "probe", "render", "bench", "app")
#: Modules at the top of the package: ``across_dimensions``, ``_blas`` and the shipped kernels'
#: two (the standard library and numba only) under every package (any may import them),
#: ``__main__`` over all of them.
BELOW_ALL = {
    "across_dimensions",
    "across_dimensions._blas",
    "across_dimensions._shipped_kernels",
    "across_dimensions._kernel_locator",
}
#: Lazy imports that hide a circle and are being removed (``"path -> module"``). The list
#: only shrinks: an entry that no longer hides a circle fails until it is removed.
KNOWN_CIRCLES: set[str] = set()


def _rank(module: str) -> int:
    """Where a module of the package stands in :data:`PACKAGE_ORDER` (-1 below all, len above)."""
    if module in BELOW_ALL:
        return -1
    parts = module.split(".")
    if len(parts) > 1 and parts[1] in PACKAGE_ORDER:
        return PACKAGE_ORDER.index(parts[1])
    return len(PACKAGE_ORDER)


def order_problems(rel: str, source: str) -> list[str]:
    """Imports of a package above the importer's own in :data:`PACKAGE_ORDER`."""
    mine = _rank(module_of(rel))
    out = []
    for imp in imports(rel, source):
        if imp.module.split(".")[0] != "across_dimensions":
            continue
        theirs = _rank(imp.module)
        if theirs > mine:
            out.append(
                f"{imp.where()}  ({module_of(rel)} may not import {imp.module}: "
                f"the packages stand in the order {' <- '.join(PACKAGE_ORDER)})"
            )
    return out


def _known(name: str, known: set[str]) -> str | None:
    """The module an import of ``name`` runs: ``name`` itself, or the package of a name taken
    from it (``across_dimensions.physics`` for ``from ..physics import BodyDef``)."""
    parts = name.split(".")
    return next((m for i in range(len(parts), 0, -1) if (m := ".".join(parts[:i])) in known), None)


def import_graph(sources: dict[str, str]) -> dict[str, set[str]]:
    """Module -> the package's modules it imports, at module level or inside functions."""
    known = {module_of(rel) for rel in sources}
    graph: dict[str, set[str]] = {}
    for rel, src in sources.items():
        found = {_known(imp.module, known) for imp in imports(rel, src)}
        for node in ast.walk(ast.parse(src)):  # "from package import module" imports the module
            if isinstance(node, ast.ImportFrom):
                base = _resolve_from(node, rel)
                found |= {f"{base}.{a.name}" for a in node.names} & known
        graph[module_of(rel)] = found - {None, module_of(rel)}
    return graph


def hidden_circles(sources: dict[str, str]) -> list[str]:
    """``"path -> module"`` for every import inside a function whose module imports the
    importer's module back, directly or through others."""
    graph = import_graph(sources)

    def reaches(start: str, goal: str) -> bool:
        seen, todo = set(), [start]
        while todo:
            m = todo.pop()
            if m == goal:
                return True
            if m not in seen:
                seen.add(m)
                todo.extend(graph[m])
        return False

    out = set()
    for rel, src in sources.items():
        me = module_of(rel)
        for imp in imports(rel, src):
            target = _known(imp.module, set(graph))
            if imp.in_function and target is not None and target != me and reaches(target, me):
                out.add(f"{rel} -> {target}")
    return sorted(out)


# ------------------------------------------------------------------- the tree
def _sources() -> dict[str, str]:
    return {p.relative_to(PKG).as_posix(): p.read_text(encoding="utf-8") for p in sorted(PKG.rglob("*.py"))}


SOURCES = _sources()


def _report(problems: list[str]) -> str:
    return "\n" + "\n".join(problems)


def _deterministic_files():
    return {rel: src for rel, src in SOURCES.items() if rel.startswith(DETERMINISTIC)}


def test_the_tree_is_found():
    assert {"core/meshio.py", "core/mesh.py", "game/sim.py", "app/cli.py"} <= set(SOURCES)
    assert any(rel.startswith(layer) for rel in SOURCES for layer in ("physics/", "world/", "render/"))


def test_core_imports_only_numpy_numba_stdlib_and_itself():
    problems = [p for rel, src in SOURCES.items() if rel.startswith("core/") for p in core_import_problems(rel, src)]
    assert not problems, _report(problems)


def test_only_render_imports_moderngl():
    problems = [p for rel, src in SOURCES.items() for p in exclusive_import_problems(rel, src, "moderngl", "render/")]
    assert not problems, _report(problems)


def test_only_app_imports_pyglet():
    problems = [p for rel, src in SOURCES.items() for p in exclusive_import_problems(rel, src, "pyglet", "app/")]
    assert not problems, _report(problems)


def test_only_the_prologue_imports_pymunk():
    problems = [
        p for rel, src in SOURCES.items() for p in exclusive_import_problems(rel, src, "pymunk", "game/flatland/")
    ]
    assert not problems, _report(problems)
    assert any("pymunk" in {i.module for i in imports(rel, src)} for rel, src in SOURCES.items())  # still used


def test_no_wall_clock_in_deterministic_layers():
    problems = [
        p for rel, src in _deterministic_files().items() if rel not in CLOCK_ALLOWED for p in clock_problems(rel, src)
    ]
    assert not problems, _report(problems)


def test_no_global_random_state_in_deterministic_layers():
    problems = [p for rel, src in _deterministic_files().items() for p in random_problems(rel, src)]
    assert not problems, _report(problems)


# ------------------------------------------- the checker catches what it should
@pytest.mark.parametrize(
    "rel, source, expect",
    [
        ("core/mesh.py", "import trimesh\n", "only numpy"),
        ("core/mesh.py", "def f():\n    import trimesh\n", "only numpy"),
        ("core/meshio.py", "import trimesh\n", "only numpy"),
        ("core/meshio.py", "def f():\n    import trimesh.exchange\n", "only numpy"),
        ("core/mesh.py", "from ..physics import world\n", "across_dimensions.physics"),
        ("core/mesh.py", "from . import transform\nfrom .mesh import TetMesh4\nimport json, numpy as np\n", None),
        ("core/mesh.py", "from across_dimensions.core import transform\nfrom numba import njit\n", None),
        ("core/mesh.py", "import importlib\nm = importlib.import_module('scipy')\n", "scipy"),
    ],
)
def test_checker_core_imports(rel, source, expect):
    problems = core_import_problems(rel, source)
    if expect is None:
        assert not problems
    else:
        assert len(problems) == 1 and expect in problems[0] and f"across_dimensions/{rel}:" in problems[0], problems


@pytest.mark.parametrize(
    "rel, source, bad",
    [
        ("game/sim.py", "def f():\n    import moderngl\n", True),
        ("app/window.py", "from moderngl import Context\n", True),
        ("render/hud.py", "import moderngl as gl\n", False),
        ("render/hud.py", "'''import moderngl'''\n# import moderngl\n", False),
    ],
)
def test_checker_moderngl(rel, source, bad):
    problems = exclusive_import_problems(rel, source, "moderngl", "render/")
    assert bool(problems) == bad, problems
    if bad:
        assert f"across_dimensions/{rel}:" in problems[0] and "moderngl" in problems[0]


@pytest.mark.parametrize(
    "rel, bad",
    [("core/flat_section.py", True), ("physics/world.py", True), ("game/sim.py", True), ("game/flatland/x.py", False)],
)
def test_checker_pymunk(rel, bad):
    problems = exclusive_import_problems(rel, "import pymunk\n", "pymunk", "game/flatland/")
    assert bool(problems) == bad, problems


@pytest.mark.parametrize(
    "source, bad",
    [
        ("import time\nt = time.perf_counter()\n", True),
        ("import time as _t\nt = _t.monotonic()\n", True),
        ("from time import perf_counter as pc\nt = pc()\n", True),
        ("import datetime\nd = datetime.datetime.now()\n", True),
        ("from datetime import datetime\nd = datetime.now()\n", True),
        ("import time\nclock = time.time\n", True),
        ("import time\ntime.sleep(0)\n", False),
        ("def time():\n    return 0\nx = time()\n", False),
    ],
)
def test_checker_clock(source, bad):
    problems = clock_problems("game/x.py", source)
    assert bool(problems) == bad, problems
    if bad:
        assert problems[0].startswith("across_dimensions/game/x.py:")


@pytest.mark.parametrize(
    "source, bad",
    [
        ("import random\n", True),
        ("from random import random\n", True),
        ("import numpy as np\nx = np.random.rand(3)\n", True),
        ("import numpy as np\nnp.random.seed(0)\n", True),
        ("from numpy.random import uniform\n", True),
        ("from numpy import random as npr\nx = npr.normal()\n", True),
        ("import numpy as np\nrng = np.random.default_rng(0)\nx = rng.random(3)\n", False),
        ("import numpy as np\ndef f(rng: np.random.Generator):\n    return rng.uniform()\n", False),
    ],
)
def test_checker_random(source, bad):
    problems = random_problems("physics/x.py", source)
    assert bool(problems) == bad, problems


# ------------------------------------------------------------ at import time
def _modules_after_import(*modules: str, tmp_path) -> set[str]:
    code = (
        "import json, sys\n"
        + "".join(f"import {m}\n" for m in modules)
        + "print(json.dumps(sorted({m.split('.')[0] for m in sys.modules})))\n"
    )
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"))
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), env.get("PYTHONPATH")) if p)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=env, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    return set(json.loads(r.stdout.strip().splitlines()[-1]))


def test_importing_the_simulation_loads_no_window_or_gpu(tmp_path):
    loaded = _modules_after_import("across_dimensions.game.sim", "across_dimensions.physics", tmp_path=tmp_path)
    assert "across_dimensions" in loaded
    assert not loaded & {"pyglet", "moderngl", "pymunk"}, sorted(loaded & {"pyglet", "moderngl", "pymunk"})


def test_importing_the_core_loads_no_optional_packages(tmp_path):
    core = [f"across_dimensions.core.{p.stem}" for p in sorted((PKG / "core").glob("*.py")) if p.stem != "__init__"]
    loaded = _modules_after_import("across_dimensions.core", *core, tmp_path=tmp_path)
    unwanted = {"pyglet", "moderngl", "trimesh", "pymunk"}
    assert not loaded & unwanted, sorted(loaded & unwanted)


# ------------------------------------------------------------ package order
def test_packages_import_only_the_packages_below_them():
    problems = [p for rel, src in SOURCES.items() for p in order_problems(rel, src)]
    assert not problems, _report(problems)


def test_no_import_inside_a_function_hides_a_circle():
    found = set(hidden_circles(SOURCES))
    new = sorted(found - KNOWN_CIRCLES)
    assert not new, (
        "imports inside functions that hide a circle (import at the top, or move what both need):" + _report(new)
    )
    gone = sorted(KNOWN_CIRCLES - found)
    assert not gone, "no longer circles: remove them from KNOWN_CIRCLES" + _report(gone)


@pytest.mark.parametrize(
    "rel, source, bad",
    [
        ("world/level.py", "from ..game import sim\n", True),
        ("physics/world.py", "def f():\n    from ..world import scene\n", True),
        ("core/mesh.py", "from ..render import hud\n", True),
        ("game/sim.py", "from ..world.level import Level\nfrom ..core.mesh import TetMesh4\n", False),
        ("app/window.py", "from ..render import hud\nfrom .. import _blas\n", False),
        ("render/hud.py", "import across_dimensions.app.window\n", True),
        ("bench/hud.py", "from ..render import hud\nfrom ..game.sim import Game\n", False),
        ("bench/hud.py", "def f():\n    from ..app import commands\n", True),
        ("render/hud.py", "from ..bench import hud\n", True),
        ("app/commands.py", "from ..bench import report\n", False),
    ],
)
def test_checker_package_order(rel, source, bad):
    problems = order_problems(rel, source)
    assert bool(problems) == bad, problems


def test_checker_hidden_circles():
    tree = {
        "game/a.py": "from . import b\n",
        "game/b.py": "def f():\n    from . import a\n",  # a imports b: this hides a -> b -> a
        "game/c.py": "def f():\n    from . import b\n",  # b never imports c: no circle
        "game/d.py": "def f():\n    from .e import x\n",  # e imports f, f imports d
        "game/e.py": "from . import f\n",
        "game/f.py": "from .d import y\n",
        "game/__init__.py": "",
    }
    assert hidden_circles(tree) == ["game/b.py -> across_dimensions.game.a", "game/d.py -> across_dimensions.game.e"]
