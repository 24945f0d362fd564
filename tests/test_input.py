"""Input that never loses a press: one-shot actions counted between ticks, mouse
buttons and the wheel bound like keys, and replays that carry the presses."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from across_dimensions.game.actions import PRESSES, Actions
from across_dimensions.game.replay import Replay, ReplayError
from across_dimensions.world.resources import levels_dir

# ---- the window's input, in a fresh process ------------------------------------
# A headless pyglet window needs its own process: once the suite has made a
# standalone EGL context (the GL tests), wrapping a window's context fails.
_NO_WINDOW = 77


def _window():
    """A headless window on level 1 with jump also on the 4th mouse button and
    manipulate also on the wheel; ``stepped`` collects the actions of every tick."""
    try:
        from across_dimensions.app.settings import Settings
        from across_dimensions.app.window import GameWindow

        settings = Settings(bindings={"jump": ("SPACE", "MOUSE_4"), "manipulate": ("F", "MOUSE_WHEEL_UP")})
        w = GameWindow(settings, levels_dir() / "01_first_steps.toml")
    except Exception as e:  # no EGL here: no headless window
        print(f"no headless pyglet window: {e}")
        sys.exit(_NO_WINDOW)
    stepped = []
    step = w.game.step
    w.game.step = lambda a: (stepped.append(a), step(a))
    return w, stepped


def _tick(window):
    from across_dimensions.game.sim import DT

    window.update(DT * 1.0001)


def _tap_shorter_than_a_tick():
    from pyglet.window import mouse

    w, stepped = _window()
    w.on_mouse_press(0, 0, mouse.LEFT, 0)  # fire is on the left button by default
    w.on_mouse_release(0, 0, mouse.LEFT, 0)  # ...released before any tick ran
    _tick(w)
    _tick(w)
    assert [a.pressed("fire") for a in stepped] == [1, 0], stepped
    assert not any(a.fire for a in stepped)  # it was never held at a tick


def _two_taps_in_one_tick():
    from pyglet.window import key

    w, stepped = _window()
    for _ in range(2):  # switch_camera, tapped twice between two ticks
        w.on_key_press(key.TAB, 0)
    _tick(w)
    assert stepped[-1].pressed("switch_camera") == 2, stepped


def _wheel_and_extra_buttons():
    from pyglet.window import mouse

    w, stepped = _window()
    w.on_mouse_scroll(0, 0, 0, -3.0)  # next_weapon is on the wheel by default
    w.on_mouse_scroll(0, 0, 0, 1.0)
    w.on_mouse_press(0, 0, mouse.MOUSE4, 0)
    _tick(w)
    a = stepped[-1]
    assert a.pressed("next_weapon") == 3 and a.pressed("manipulate") == 1, a
    assert a.jump  # held while the button is down
    w.on_mouse_release(0, 0, mouse.MOUSE4, 0)
    _tick(w)
    assert not stepped[-1].jump and stepped[-1].presses == ()


def _presses_while_paused():
    w, stepped = _window()
    w.set_paused(True)
    w.on_mouse_scroll(0, 0, 0, -1.0)
    w.set_paused(False)
    _tick(w)
    assert stepped[-1].presses == ()


def _run_fresh(name: str) -> None:
    code = f"import pyglet, runpy; pyglet.options['headless'] = True; runpy.run_path({__file__!r})[{name!r}]()"
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join([str(Path(__file__).parent.parent), os.environ.get("PYTHONPATH", "")])
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env=env)
    if r.returncode == _NO_WINDOW:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stdout + r.stderr


@pytest.mark.parametrize(
    "scenario",
    ["_tap_shorter_than_a_tick", "_two_taps_in_one_tick", "_wheel_and_extra_buttons", "_presses_while_paused"],
)
def test_window_counts_every_press(scenario):
    """A tap shorter than a tick fires exactly once; two taps are two; the wheel
    and extra mouse buttons bind like keys; presses while paused are dropped."""
    _run_fresh(scenario)


# ---- replays ------------------------------------------------------------------
def test_presses_survive_a_replay_round_trip(tmp_path):
    rep = Replay("01_first_steps", "0" * 64)
    frames = [Actions(), Actions(presses=Actions.count_presses({"fire": 2, "weapon_3": 1})), Actions()]
    for a in frames:
        rep.actions.append(a)
    rep.final_ticks = len(frames)
    path = tmp_path / "r.json"
    rep.save(path)
    data = json.loads(path.read_text())
    assert data["version"] == 3
    assert data["actions"][1][1][6] == {"fire": 2, "weapon_3": 1}
    back = list(Replay.load(path).actions)
    assert [a.presses for a in back] == [a.presses for a in frames]
    assert back[1].pressed("fire") == 2 and back[1].pressed("alt_fire") == 0


def _v1(tmp_path, version=1, row=(0.0, 0.0, 0.0, 0.0, 0.0, 0)):
    data = {
        "format": "across-dimensions-replay",
        "version": version,
        "level": "01_first_steps",
        "level_hash": "0" * 64,
        "seed": 0,
        "tick_rate": 60,
        "hash_every": 60,
        "actions": [[3, list(row)]],
        "hashes": {},
        "final": {"ticks": 3, "hash": "", "outcome": None},
    }
    path = tmp_path / "old.json"
    path.write_text(json.dumps(data))
    return path


def test_version_one_replays_still_load(tmp_path):
    rep = Replay.load(_v1(tmp_path))
    assert len(rep.actions) == 3 and all(a.presses == () for a in rep.actions)


def test_unknown_versions_and_bad_presses_are_refused_naming_the_file(tmp_path):
    with pytest.raises(ReplayError, match=r"old\.json: replay format version 4; this game reads versions 1, 2 and 3"):
        Replay.load(_v1(tmp_path, version=4))
    for presses, why in (
        ({"sneeze": 1}, "unknown action"),
        ({"fire": 0}, "from 1 to"),
        ({"fire": 1.5}, "from 1 to"),
        ({}, "a table of action"),
    ):
        with pytest.raises(ReplayError, match=why) as e:
            Replay.load(_v1(tmp_path, version=2, row=(0.0, 0.0, 0.0, 0.0, 0.0, 0, presses)))
        assert "old.json" in str(e.value)


def test_every_press_action_is_bindable():
    from across_dimensions.app.settings import ACTIONS

    assert set(PRESSES) <= set(ACTIONS)
