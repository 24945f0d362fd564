"""Frame cost of each 4D camera mode on the camera level, next to cross-section, in one run
(see :func:`bench_camera`)."""

from __future__ import annotations

import time

import numpy as np

from ..game.actions import Actions
from ..game.energy import EnergyBar
from ..game.sim import Game
from ..world.level import load_level
from ..world.resources import levels_dir

CAMERA_LEVEL = "08_around_the_corner.toml"


def bench_camera(cycles: int = 4, ticks: int = 60) -> dict:
    """Frame cost of each 4D camera mode on the camera level, next to cross-section, in one run.

    The player stands at the level's mark looking down the hall; each cycle runs
    ``ticks`` ticks synced (cross-section, the player turning), switches, runs frustum
    with the camera still while the player turns (cached projections), frustum while
    orbiting (every 4D thing re-projected each frame), then the glide back. The bar is
    filled so the frustum never runs dry. Timed per tick: ``Game.step`` plus
    ``Game.frame`` (without the GPU), and the same with the picture-in-picture on.

    Returns
    -------
    dict
        ``<mode>_ms`` median milliseconds per tick for ``synced``, ``frustum_still``,
        ``frustum_orbit``, ``returning``, ``synced_pip``, ``frustum_pip``; ``switch_ms`` and
        ``handover_ms`` the slowest switch tick and first synced tick after a return;
        ``level`` the level's name.
    """
    game = Game(load_level(levels_dir() / CAMERA_LEVEL))
    game.energy = EnergyBar.of(1e5, 1e5)
    times: dict[str, list] = {k: [] for k in ("synced", "frustum_still", "frustum_orbit", "returning")}
    times |= {"synced_pip": [], "frustum_pip": [], "switch": [], "handover": []}

    def tick(label: str, actions: Actions, pip: bool = False) -> None:
        t0 = time.perf_counter()
        game.step(actions)
        game.frame(0.5, pip=pip)
        times[label].append(time.perf_counter() - t0)

    for _ in range(14):
        game.step(Actions(forward=1.0))
    look = Actions(yaw=0.004)
    switch = Actions(presses=(("switch_camera", 1),))
    for _ in range(ticks):  # warm-up: the kernels' first calls
        game.step(look)
        game.frame(0.5, pip=True)
    return_ticks = max(1, round(game.level.camera.return_time / game.dt))
    for _ in range(cycles):
        for _ in range(ticks):
            tick("synced", look)
        for _ in range(ticks // 4):
            tick("synced_pip", look, pip=True)
        tick("switch", switch)
        for _ in range(ticks):
            tick("frustum_still", look)
        for _ in range(ticks):
            tick("frustum_orbit", Actions(orbit_right=True))
        for _ in range(ticks // 4):
            tick("frustum_pip", Actions(orbit_left=True), pip=True)
        tick("returning", switch)
        for _ in range(return_ticks - 1):
            tick("returning", look)
        tick("handover", look)
    out = {f"{k}_ms": 1e3 * float(np.median(v)) for k, v in times.items() if k not in ("switch", "handover")}
    out["switch_ms"] = 1e3 * float(np.max(times["switch"]))
    out["handover_ms"] = 1e3 * float(np.max(times["handover"]))
    out["level"] = game.level.name
    return out
