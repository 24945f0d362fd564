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
        from across_dimensions.app.session import Start
        from across_dimensions.app.settings import Settings
        from across_dimensions.app.window import GameWindow

        settings = Settings(bindings={"jump": ("SPACE", "MOUSE_4"), "manipulate": ("F", "MOUSE_WHEEL_UP")})
        w = GameWindow(settings, Start(levels_dir() / "01_first_steps.toml"))
    except Exception as e:  # no EGL here: no headless window
        print(f"no headless pyglet window: {e}")
        sys.exit(_NO_WINDOW)
    stepped = []
    game = w.current_view.game
    step = game.step
    game.step = lambda a: (stepped.append(a), step(a))
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
    from pyglet.window import key

    w, stepped = _window()
    w.on_key_press(key.ESCAPE, 0)  # the pause menu takes the wheel...
    assert type(w.current_view).__name__ == "PauseView"
    w.on_mouse_scroll(0, 0, 0, -1.0)
    w.on_key_press(key.ESCAPE, 0)  # ...and Esc resumes
    assert type(w.current_view).__name__ == "PlayView"
    _tick(w)
    assert stepped[-1].presses == ()


def _tap(window, key_code):
    """A key pressed and released before the next tick, through the window's event path (its
    key-state handler sees both), as the event loop delivers them between two frames."""
    window.dispatch_event("on_key_press", key_code, 0)
    window.dispatch_event("on_key_release", key_code, 0)
    window.dispatch_events()


def _taps_at_five_fps():
    from pyglet.window import key

    from across_dimensions.app.input import COUNTED_ONLY, key_code

    w, stepped = _window()
    play, frame = w.current_view, 0.2  # 5 FPS: a frame is 12 ticks (5 run, the catch-up limit)
    for _ in range(3):
        w.update(frame)
    player = play.game.player
    assert player.on_ground
    _tap(w, key.SPACE)
    n = len(stepped)
    w.update(frame)
    assert [a.jump for a in stepped[n:]] == [True, False, False, False, False], stepped[n:]
    assert not player.on_ground and player.velocity[1] > 0  # it jumped
    # The first w tap of a session opens the flat-being card; Enter closes it; the next tap moves w.
    _tap(w, key.E)
    w.update(frame)
    assert w.session.onboarding.blocking
    _tap(w, key.RETURN)
    w0, n = player.position[3], len(stepped)
    _tap(w, key.E)
    w.update(frame)
    assert [a.w for a in stepped[n:]] == [1.0, 0.0, 0.0, 0.0, 0.0], stepped[n:]
    # One tick of push from rest (W_ACCEL * DT of speed, for DT), then the next tick stops it.
    from across_dimensions.game.player import W_ACCEL
    from across_dimensions.game.sim import DT

    assert abs(player.position[3] - (w0 + W_ACCEL * DT * DT)) < 1e-9, (player.position[3], w0)
    # Every held action the game reads (walking, w, jump, grabbing, slice turns, orbit) sees a tap.
    seen = {
        "move_forward": lambda a: a.forward == 1,
        "move_back": lambda a: a.forward == -1,
        "strafe_right": lambda a: a.right == 1,
        "strafe_left": lambda a: a.right == -1,
        "w_ana": lambda a: a.w == 1,
        "w_kata": lambda a: a.w == -1,
    }
    held = [a for a in w.session.settings.bindings if a not in COUNTED_ONLY and (a in seen or hasattr(stepped[0], a))]
    assert {"jump", "manipulate", "turn_xw_pos", "orbit_left", "move_forward", "w_kata"} <= set(held)
    for action in held:
        kind, code = key_code(w.session.settings.keys_for(action)[0])
        assert kind == "key", action
        _tap(w, code)
        _tick(w)
        _tick(w)
        check = seen.get(action, lambda a, name=action: getattr(a, name))
        assert check(stepped[-2]) and not check(stepped[-1]), (action, stepped[-2:])


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
    [
        "_tap_shorter_than_a_tick",
        "_two_taps_in_one_tick",
        "_wheel_and_extra_buttons",
        "_presses_while_paused",
        "_taps_at_five_fps",
    ],
)
def test_window_counts_every_press(scenario):
    """A tap shorter than a tick fires exactly once; two taps are two; the wheel
    and extra mouse buttons bind like keys; presses while paused are dropped; at 5 FPS a tap of
    a held action is held for one tick (Space jumps, E moves w)."""
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
    refused = r"old\.json: replay format version 5; this game reads versions 1, 2, 3 and 4"
    with pytest.raises(ReplayError, match=refused):
        Replay.load(_v1(tmp_path, version=5))
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
