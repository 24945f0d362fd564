"""Secrets: ``[[secret]]`` read and checked, ``secret_found`` fired once on entering, kept in the progress."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import headless_window

from across_dimensions.app.saves import Progress, load_progress, save_progress
from across_dimensions.game.actions import Actions
from across_dimensions.game.sim import Game
from across_dimensions.world.level import LevelError, load_level

LEVEL = """
[level]
format = 2
name = "Secrets"
w_range = [-1.0, 1.0]

[spawn]
position = [0.0, 0.0, -6.0, 0.0]

[goal]
center = [0.0, 1.0, 30.0]
size = [2.0, 2.0, 2.0]

[[box]]
center = [0.0, -0.5, 0.0]
size = [10.0, 1.0, 70.0]

[[secret]]
name = "the nook"
min = [-1.0, 0.0, -1.0, -0.2]
max = [1.0, 2.0, 1.0, 0.2]

[[secret]]
name = "the ana room"
min = [-1.0, 0.0, 4.0, 0.5]
max = [1.0, 2.0, 6.0, 1.0]
{exit}
"""


BOX = 'name = "a"\nmin = [0, 0, 0, 0]\nmax = [1, 1, 1, 1]'


def _level(tmp_path, text=LEVEL, exit=""):
    path = tmp_path / "secrets.toml"
    path.write_text(text.replace("{exit}", exit), encoding="utf-8")
    return path


def _walk(game, ticks, **kw):
    """Step ``ticks`` ticks with the same actions; the ``secret_found`` events, per tick."""
    found = []
    for _ in range(ticks):
        game.step(Actions(**kw))
        found += [(game.tick, e.name, e.found, e.total) for e in game.events if e.kind == "secret_found"]
    return found


def test_a_secret_is_found_once_when_entered_and_never_otherwise(tmp_path):
    game = Game(load_level(_level(tmp_path)))
    assert [s.name for s in game.level.secrets] == ["the nook", "the ana room"]
    assert isinstance(game.level.secrets, tuple)
    assert _walk(game, 30) == []  # standing at the spawn finds nothing
    found = _walk(game, 200, forward=1.0)  # through the nook at w = 0, past the ana room's z at w = 0
    assert [(name, n, total) for _, name, n, total in found] == [("the nook", 1, 2)]
    assert game.player.position[2] > 5.0  # walked through the ana room's x-z, at the wrong w
    back = _walk(game, 220, forward=-1.0)  # back through the nook: already found
    assert back == [] and game.event_counts["secret_found"] == 1
    assert game.player.position[2] < 0.0
    _walk(game, 60, w=1.0)  # along w to 0.7 or more, away from everything
    assert game.player.position[3] > 0.6
    again = _walk(game, 240, forward=1.0)  # into the ana room, then on through it
    assert [name for _, name, _, _ in again] == ["the ana room"] and again[0][2:] == (2, 2)
    assert game.event_counts["secret_found"] == 2 and game.outcome is None  # no exit: the level goes on


def test_a_secret_exit_finishes_the_level(tmp_path):
    game = Game(load_level(_level(tmp_path, exit="exit = true")))
    _walk(game, 60, w=1.0)
    _walk(game, 200, forward=1.0)
    assert game.event_counts["secret_found"] == 1 and game.event_counts["level_complete"] == 1
    assert game.outcome == "complete" and game.player.position[2] < 25.0  # far short of the goal


def test_levels_without_secrets_spawn_nothing(tmp_path):
    game = Game(load_level(_level(tmp_path, LEVEL.split("[[secret]]")[0])))
    _walk(game, 10, forward=1.0)
    assert game.level.secrets == () and not game.entities.of_kind("secret")


@pytest.mark.parametrize(
    "entry, says",
    [
        (
            f"{BOX}\n[[secret]]\n{BOX}",
            "[[secret]] #2 'a': field 'name': another secret is named 'a'",
        ),
        (
            'name = "a"\nmin = [0, 0, 0, 0]\nmax = [1, 0, 1, 1]',
            "[[secret]] #1 'a': fields 'min', 'max': expected min < max",
        ),
        (
            'name = "a"\nmin = [0, 0, 0, 2]\nmax = [1, 1, 1, 3]',
            "outside the level's w_range [-1.0, 1.0], so it can never be found",
        ),
        ('name = "a"\nmin = [0, 0, 0, 0]\nmax = [1, 1, 1, 1]\ncentre = 1', "[[secret]] #1: unknown field 'centre'"),
        ("min = [0, 0, 0, 0]\nmax = [1, 1, 1, 1]", "[[secret]] #1: missing field 'name'"),
    ],
)
def test_bad_secrets_are_named(tmp_path, entry, says):
    text = LEVEL.split("[[secret]]")[0] + "[[secret]]\n" + entry + "\n"
    with pytest.raises(LevelError) as e:
        load_level(_level(tmp_path, text))
    assert says in str(e.value)
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", "check-level", str(tmp_path / "secrets.toml")],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2 and says in r.stderr and "Traceback" not in r.stderr


def test_progress_keeps_every_secret_found_across_runs_and_games(tmp_path):
    path = tmp_path / "progress.json"
    p = Progress()
    assert p.found_secrets("10_x", (), 2) and p.secrets["10_x"] == ((), 2)  # started: 0 of 2
    assert p.found_secrets("10_x", ["b"], 2) and not p.found_secrets("10_x", ["b"], 2)
    save_progress(p, path)
    other = Progress()
    other.found_secrets("10_x", ["a"], 2)  # another game, same folder: merged, not lost
    save_progress(other, path)
    back, warnings = load_progress(path)
    assert warnings == [] and back.secrets == {"10_x": (("a", "b"), 2)}
    path.write_text(path.read_text().replace('"total": 2', '"total": 1'))  # two found of one: corrupt
    fresh, warnings = load_progress(path)
    assert fresh.secrets == {} and "secrets.10_x" in warnings[0] and "kept as progress.corrupt-1.json" in warnings[0]
    assert not Path(path).exists() and (tmp_path / "progress.corrupt-1.json").exists()


# ---- the window, headless (fresh processes, as tests/test_menus.py does) ----------------
_PLAY = headless_window(r"""
from across_dimensions.game.actions import Actions
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import DT
from across_dimensions.world.resources import levels_dir
s.after_first_frame()  # as the window does once its first frame is up
s.warm.join()
w.update(DT)
frames = iter(Replay.load(levels_dir() / "replays" / "10_cloister.json").actions)
s.start_level(levels_dir() / "10_cloister.toml")
play = w.current_view
play.read_actions = lambda: next(frames, Actions())
print("started", s.progress.secrets)
for _ in range(100000):
    if play.game.event_counts["secret_found"]:
        break
    w.update(DT)
print("found", play.game.event_counts["secret_found"], "saved", s.progress.secrets)
w.on_close()  # the player leaves mid-level: the secret is kept
""")

_SELECT = headless_window(r"""
from pyglet.window import key
from across_dimensions.game.sim import DT
s.after_first_frame()  # as the window does once its first frame is up
s.warm.join()
w.update(DT)
w.on_key_press(key.DOWN, 0); w.on_key_press(key.RETURN, 0)      # Level select
assert type(w.current_view).__name__ == "LevelSelectView"
shown = {i.key: i.value for i in s.menu.view().items}
print("cloister", repr(shown["level:10_cloister"]))
print("hive", repr(shown["level:09_hive"]))
""")


def _window(code, env) -> subprocess.CompletedProcess:
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=900)
    if r.returncode == 77:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stdout + r.stderr
    return r


@pytest.mark.slow
def test_a_secret_found_in_the_window_is_saved_and_counted_on_the_level_select(tmp_path):
    env = dict(os.environ, ACROSS_DIMENSIONS_DATA_DIR=str(tmp_path), ACROSS_DIMENSIONS_CONFIG_DIR=str(tmp_path))
    env.pop("DISPLAY", None)
    env["PYGLET_HEADLESS"] = "1"
    p = Progress()
    p.finish("09_hive", 90.0)  # level 10 is open
    save_progress(p, tmp_path / "progress.json")
    r = _window(_PLAY, env)
    assert "started {'10_cloister': ((), 2)}" in r.stdout  # starting the level tells how many there are
    assert "found 1 saved {'10_cloister': (('the kata garden',), 2)}" in r.stdout
    r = _window(_SELECT, env)
    assert "secrets 1/2" in r.stdout.split("cloister", 1)[1].splitlines()[0]
    assert "secrets" not in r.stdout.split("hive", 1)[1]  # a level without secrets says nothing of them
