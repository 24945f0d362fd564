"""A level that can no longer be won says so, and one key restarts it from the last checkpoint;
a key object pushed out of its beacon's range comes back to its start, said on screen; the
HUD lists what each 4D action costs."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from levels_builder import LevelBuilder

from across_dimensions.game.actions import IDLE, Actions
from across_dimensions.game.sim import Game
from across_dimensions.game.stranded import stranded
from across_dimensions.game.systems.energy import cost_line
from across_dimensions.world.level import LevelError

_NO_WINDOW = 77


def switch_room(opens: str = "door", goal_w=None) -> LevelBuilder:
    """A switch behind the player opens the door to the exit; the bar holds one shot."""
    return (
        LevelBuilder(
            w_range=(-0.5, 0.5),
            spawn=(0.0, 0.0, -6.0, 0.0),
            goal=(0.0, 1.0, 8.0),
            goal_size=(3.0, 2.0, 2.0),
            goal_w=goal_w,
            floor=(8.0, 1.0, 20.0),
        )
        .table("energy", start=1.0, max=5.0, w_cost=2.0)
        .weapon("gun", cost=1.0, cooldown=0.1)
        .pickup("gun", [0.0, 1.0, -6.0, 0.0])  # at the spawn: the window's game takes it on its first tick
        .object([0.0, 2.0, 4.0, 0.0], name="door", scale=[8.0, 4.0, 0.4, 3.0])
        .add("target", name="switch", position=[0.0, 1.6, 0.0, 0.0], opens=opens)
    )


def _fire_at_the_floor(game: Game) -> None:
    """One shot into the floor (the switch stays whole), then a few ticks for it to land."""
    game.step(Actions(pitch=-1.4))  # look down
    game.step(Actions(presses=(("fire", 1),)))
    for _ in range(30):
        game.step(IDLE)


def test_a_level_out_of_energy_says_it_is_lost_and_names_the_restart_key(tmp_path):
    game = Game(switch_room().load(tmp_path))
    game.step(IDLE)
    assert stranded(game) is None and "restart" not in game.frame().hud.message
    _fire_at_the_floor(game)
    assert game.energy.milli == 0 and game.event_counts["target_hit"] == 0
    why = stranded(game)
    assert why and "a shot at 'switch'" in why
    message = game.frame().hud.message
    assert "Press {restart_checkpoint} to restart from the start" in message


def test_a_crystal_or_the_switch_thrown_means_the_level_is_not_lost(tmp_path):
    game = Game(switch_room().crystal([3.0, 1.0, -4.0, 0.0], energy=1.0).load(tmp_path))
    game.step(IDLE)
    _fire_at_the_floor(game)
    assert game.energy.milli == 0 and stranded(game) is None  # the crystal can refill it
    game = Game(switch_room(opens="").load(tmp_path))
    game.step(IDLE)
    _fire_at_the_floor(game)
    assert stranded(game) is None  # nothing left to pay for


def test_the_way_along_w_to_an_exit_counts(tmp_path):
    game = Game(switch_room(opens="", goal_w=(0.4, 0.5)).load(tmp_path))
    game.step(IDLE)
    assert stranded(game) is None  # 0.8 of the bar's 1.0 takes the player to w = 0.4
    _fire_at_the_floor(game)
    assert "the way along w to the exit" in stranded(game)


def test_the_hud_lists_what_each_4d_action_costs(tmp_path):
    level = switch_room().load(tmp_path)
    assert cost_line(level) == "W 2/UNIT  GUN 1"
    game = Game(level)
    game.step(IDLE)
    assert game.frame().hud.energy.costs == "W 2/UNIT  GUN 1"


# ------------------------------------------------------------------ beacons
BEACON = {"object": "crate", "min": [-1.0, -1.0, -2.0, -0.5], "max": [1.0, 3.0, 2.0, 0.5], "after": 0.5}


def crate_room(body: bool = True) -> LevelBuilder:
    """A hypercube crate (a rigid body unless ``body`` is false) on the floor ahead."""
    crate = {"body": "hypercube", "mass": 3.0} if body else {}
    return LevelBuilder(
        w_range=(-0.5, 0.5),
        spawn=(0.0, 0.0, -6.0, 0.0),
        goal=(0.0, 1.0, 8.0),
        goal_size=(3.0, 2.0, 2.0),
        floor=(8.0, 1.0, 20.0),
    ).object([0.0, 0.55, 0.0, 0.0], name="crate", scale=1.1, **crate)


def test_a_body_out_of_its_beacons_range_comes_back_and_it_is_said(tmp_path):
    game = Game(crate_room().add("beacon", **BEACON).load(tmp_path))
    game.step(IDLE)
    crate = game.entities.named("crate")
    start = np.array(crate.center(game))
    game.physics.set_pose(crate.motion.body, start + [3.0, 0.0, 0.0, 0.0])  # pushed off its range
    for _ in range(29):
        game.step(IDLE)
    assert game.event_counts["object_reset"] == 0  # half a second out of range before it is brought back
    game.step(IDLE)
    game.step(IDLE)
    assert game.event_counts["object_reset"] == 1
    assert np.allclose(crate.center(game)[[0, 2, 3]], start[[0, 2, 3]], atol=0.02)
    assert "crate went out of reach: its beacon brought it back" in game.frame().hud.message


def test_a_body_without_a_beacon_stays_where_it_went(tmp_path):
    game = Game(crate_room().load(tmp_path))
    game.step(IDLE)
    crate = game.entities.named("crate")
    game.physics.set_pose(crate.motion.body, np.array(crate.center(game)) + [3.0, 0.0, 0.0, 0.0])
    for _ in range(90):
        game.step(IDLE)
    assert game.event_counts["object_reset"] == 0 and crate.center(game)[0] > 2.5


@pytest.mark.parametrize(
    ("entry", "says"),
    [
        ('object = "box"', "no [[object]] is named 'box'"),
        ("min = [1.0, -1.0, -2.0, -0.5]\nmax = [-1.0, 3.0, 2.0, 0.5]", "expected min < max on every axis"),
        ("min = [2.0, -1.0, -2.0, -0.5]\nmax = [3.0, 3.0, 2.0, 0.5]", "outside [min, max]"),
        ("wide = 2", "unknown field 'wide'"),
    ],
)
def test_check_level_names_a_bad_beacon(tmp_path, entry, says):
    table = dict(BEACON)
    for line in entry.splitlines():  # the entry's fields (as text) take the place of the beacon's
        table.pop(line.split("=")[0].strip(), None)
    with pytest.raises(LevelError) as e:
        crate_room().add("beacon", **table).load(tmp_path, extra=entry + "\n")
    assert any("[[beacon]] #1" in p and says in p for p in e.value.problems), e.value.problems


def test_a_beacon_on_an_object_that_is_no_body_is_refused(tmp_path):
    with pytest.raises(LevelError, match="is not a rigid body"):
        crate_room(body=False).add("beacon", **BEACON).load(tmp_path)


# ------------------------------------------------------------------ the window
def _restart_key():
    """A headless window on a level that is lost once its one shot is wasted: the notice names
    Backspace; Backspace before that does nothing, after it restarts the level."""
    import tempfile

    import pyglet

    try:
        from across_dimensions.app.session import Start
        from across_dimensions.app.settings import Settings
        from across_dimensions.app.window import GameWindow

        path = switch_room().write(Path(tempfile.mkdtemp()), "lost.toml")
        w = GameWindow(Settings(), Start(path))
    except Exception as e:  # no EGL here: no headless window
        print(f"no headless pyglet window: {e}")
        sys.exit(_NO_WINDOW)
    from across_dimensions.game.sim import DT

    play = w.current_view
    w.update(DT * 1.0001)
    first = play.game
    w.on_key_press(pyglet.window.key.BACKSPACE, 0)
    assert play.game is first  # not lost yet: the key does nothing
    _fire_at_the_floor(first)
    assert "Press BACKSPACE to restart from the start" in play.current_frame().hud.message
    w.on_key_press(pyglet.window.key.BACKSPACE, 0)
    assert play.game is not first and play.game.tick == 0 and play.game.energy.milli == 1000
    assert w.current_view is play


def test_the_restart_key_restarts_a_lost_level_in_the_window():
    code = f"import pyglet, runpy; pyglet.options['headless'] = True; runpy.run_path({__file__!r})['_restart_key']()"
    root = str(Path(__file__).parent.parent)
    tests = str(Path(__file__).parent)  # for levels_builder
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([root, tests, os.environ.get("PYTHONPATH", "")]))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env=env)
    if r.returncode == _NO_WINDOW:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stdout + r.stderr
