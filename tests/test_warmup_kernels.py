"""The warm-up loads every kernel play reaches, so no kernel is first loaded mid-level.

A kernel is machine code loaded from the cache the first time it is called with a set of
argument types: 5-15 ms, a dropped frame when that first call comes mid-level (an enemy's
first shot crossing a solid, a first knock of two bodies). The title screen's warm-up
(:mod:`across_dimensions.app.warmup`) calls each kernel once with the types play passes; here a
fresh process warms up, plays a shipped replay with its frames, and lists what play still
had to load.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

SCRIPT = """
import json, sys
from numba.core.dispatcher import Dispatcher
import across_dimensions.app  # the shipped kernels, as the game uses them
from across_dimensions.app.warmup import warm_up
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import Game
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import levels_dir, resolve_level


def kernels():
    found = {}
    for name, module in list(sys.modules.items()):
        if module is not None and name.startswith("across_dimensions"):
            for attr, v in list(vars(module).items()):
                if isinstance(v, Dispatcher):
                    found[f"{v.py_func.__module__}.{v.py_func.__qualname__}"] = v
    return found


warm_up()
level = sys.argv[1]
before = {k: set(d.signatures) for k, d in kernels().items()}
replay = Replay.load(levels_dir() / "replays" / f"{level}.json")
game = Game(load_level(resolve_level(level), arsenal=replay.arsenal), seed=replay.seed)
for actions in replay.actions:
    game.step(actions)
    if game.tick % 2 == 0:
        game.frame()
late = sorted(
    f"{k}{tuple(str(t) for t in sig)}" for k, d in kernels().items() for sig in set(d.signatures) - before.get(k, set())
)
print(json.dumps({"outcome": game.outcome, "loaded_in_play": late}))
"""


@pytest.mark.slow
@pytest.mark.parametrize("level", ["11_crossfire", "09_hive", "03_tumbling_hall"])
def test_no_kernel_is_first_loaded_in_play(env, level):
    """Crossfire's turning solids and its first knocks each loaded a kernel mid-level before the
    warm-up called them; the Hive's shots and the Tumbling Hall's pile reach the rest."""
    r = subprocess.run([sys.executable, "-c", SCRIPT, level], env=env, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stderr[-2000:]
    result = json.loads(r.stdout.strip().splitlines()[-1])
    assert result["outcome"] == "complete"
    assert result["loaded_in_play"] == []
