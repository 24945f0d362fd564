"""The prologue in the window (headless pyglet, a fresh process as in tests/test_menus.py): a new
player's Continue starts it, its pause menu can skip it, its shipped replay fed as the player's
input finishes it, the view turns to 3D, and Arrival starts with the closing line."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from conftest import headless_window

from across_dimensions.game.replay import Replay
from across_dimensions.world.resources import levels_dir

_FLOW = headless_window(r"""
from pyglet.window import key
from across_dimensions.game.actions import Actions
from across_dimensions.game.flatland.view import CLOSING_LINE
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import DT
from across_dimensions.world.resources import levels_dir
view = lambda: type(w.current_view).__name__
w.update(DT)
assert view() == "TitleView"
print("continue row:", s.menu.items()[0].value)
w.on_key_press(key.RETURN, 0)                                     # Continue: a new player's first level
w.update(DT)
assert view() == "FlatPlayView", view()
play = w.current_view
print("levels:", [(r.label, r.enabled) for r in (s.menu.open("title"), s.menu.push("levels"), s.menu.items())[2]][:3])
s.menu.close()
w.on_key_press(key.ESCAPE, 0)                                     # the pause menu offers to skip it
print("pause rows:", [i.label for i in s.menu.items()])
w.on_key_press(key.ESCAPE, 0)
assert w.current_view is play
frames = iter(Replay.load(levels_dir() / "replays" / "prologue.json").actions)
play.load(play.level_path)                                        # from its start, as a replay is
play.read_actions = lambda: next(frames, Actions())
for _ in range(100000):
    if play.game.outcome == "complete":
        break
    w.update(DT * 1.0001)
print("complete at", play.game.tick, play.game.state_hash())
w.update(DT)
assert view() == "LevelCompleteView"
for _ in range(int(4.5 / DT)):
    w.update(DT * 1.0001)
print("turned", w.current_view.play is play and play.game.time - play.game.completed_tick * DT > 4)
for _ in range(int(6 / DT)):
    w.update(DT * 1.0001)
print("results:", view(), s.menu.screen, [i.label for i in s.menu.items()])
w.on_key_press(key.RETURN, 0)                                     # Continue
while view() == "StartupView":
    s.after_first_frame()  # as the window does once its first frame is up
    s.warm.join()
    w.update(DT)
print("next:", view(), w.current_view.level_path.stem, "|", s.notice_text)
print("finished:", sorted(s.progress.finished), "current:", s.progress.current)
""")


@pytest.mark.slow
def test_a_new_player_starts_with_the_prologue_and_goes_on_to_arrival(tmp_path):
    env = dict(os.environ, ACROSS_DIMENSIONS_DATA_DIR=str(tmp_path), ACROSS_DIMENSIONS_CONFIG_DIR=str(tmp_path))
    env.pop("DISPLAY", None)
    env["PYGLET_HEADLESS"] = "1"
    r = subprocess.run([sys.executable, "-c", _FLOW], env=env, capture_output=True, text=True, timeout=900)
    if r.returncode == 77:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    assert "continue row: Prologue: Flatland" in out
    # Skippable: Arrival is open from the start; what follows it is not.
    assert "levels: [('1. Prologue: Flatland', True), ('2. Arrival', True), ('3. First Steps', False)]" in out
    assert "'Skip the prologue'" in out.split("pause rows:")[1].splitlines()[0]
    rep = Replay.load(levels_dir() / "replays" / "prologue.json")
    assert f"complete at {rep.final_ticks} {rep.final_hash}" in out  # the window plays the replay's game
    assert "turned True" in out
    assert "results: LevelCompleteView complete ['Continue', 'Retry', 'Level select']" in out  # no time trial
    assert "next: PlayView 00_arrival | You are the flat being now, and w is your z." in out
    assert "finished: ['prologue'] current: 00_arrival" in out
