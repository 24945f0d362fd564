"""The window's camera keys: held turn and orbit buttons reach the tick, P toggles the inset."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

_NO_WINDOW = 77


def _camera_keys():
    from pyglet.window import key

    from across_dimensions.app.session import Start
    from across_dimensions.app.settings import Settings
    from across_dimensions.app.window import GameWindow
    from across_dimensions.game.sim import DT
    from across_dimensions.world.resources import levels_dir

    try:
        w = GameWindow(Settings(), Start(levels_dir() / "07_orthogonal_worlds.toml"))
    except Exception as e:  # no EGL here: no headless window
        print(f"no headless pyglet window: {e}")
        sys.exit(_NO_WINDOW)
    stepped = []
    play = w.current_view
    step = play.game.step
    play.game.step = lambda a: (stepped.append(a), step(a))
    w.keys.on_key_press(key.L, 0)  # turn_xw_pos, held (the window's key state sees it down)
    w.on_key_press(key._9, 0)  # step_zw_pos, a press
    w.update(DT * 1.0001)
    a = stepped[-1]
    assert a.turn_xw_pos and not a.turn_xw_neg and a.pressed("step_zw_pos") == 1, a
    w.keys.on_key_release(key.L, 0)
    w.update(DT * 1.0001)
    assert not stepped[-1].turn_xw_pos
    assert not w.session.options.pip and play.current_frame().pip is None  # off by default: nothing computed
    w.on_key_press(key.P, 0)
    assert w.session.options.pip and play.current_frame().pip is not None


def _run_fresh(name: str) -> None:
    code = f"import pyglet, runpy; pyglet.options['headless'] = True; runpy.run_path({__file__!r})[{name!r}]()"
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join([str(Path(__file__).parent.parent), os.environ.get("PYTHONPATH", "")])
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env=env)
    if r.returncode == _NO_WINDOW:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stdout + r.stderr


def test_window_camera_keys():
    _run_fresh("_camera_keys")
