"""The level-complete screen: a finished level's results and the way on, nothing automatic.

The model and its layout headless; the view's results with a stand-in session and play view;
the window's flow in a fresh process with a headless pyglet window (as tests/test_menus.py):
Arrival finished by its shipped replay fed as the player's input, the results by keyboard and
mouse, a time trial against the run just kept; and the game itself under Xvfb, played with
xdotool as a player would, its screenshots read back.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import headless_window, shots_in, xvfb_display
from levels_builder import LevelBuilder

from across_dimensions.app.menu import Menu
from across_dimensions.app.saves import Progress
from across_dimensions.app.settings import Settings
from across_dimensions.render.menu import hit, menu_layout, menu_quads
from across_dimensions.render.png import read_png
from across_dimensions.world.campaign import load_campaign

RESULTS = (("Time", "0:09.7", False), ("Best time", "0:09.7  new best!", True), ("Deaths", "0", False))


# ---- the model and its layout ----------------------------------------------------------------
def test_the_results_screen_offers_the_way_on_and_never_goes_back_by_itself():
    menu = Menu(Settings(), Progress(), load_campaign())
    menu.open_results(RESULTS, "First Steps", time_trial=True)
    assert [(i.key, i.label, i.value) for i in menu.items()] == [
        ("next", "Continue", "First Steps"),
        ("retry", "Retry", ""),
        ("time_trial", "Time trial", "race your best run"),
        ("levels", "Level select", ""),
    ]
    view = menu.view()
    assert view.title == "LEVEL COMPLETE" and view.summary == RESULTS and view.dim and "Esc" not in view.footer
    assert menu.input("select") == "next"
    assert menu.input("back") is None and menu.screen == "complete"  # Esc leaves nothing behind
    menu.input("down")
    assert menu.input("select") == "retry"
    menu.input("down")
    assert menu.input("select") == "time_trial"
    assert menu.click(3) is None and menu.screen == "levels"  # Level select, over the results
    assert menu.input("back") is None and menu.screen == "complete"
    menu.open_results(RESULTS, "the title screen", time_trial=False)  # the prologue: no time trial
    assert [i.key for i in menu.items()] == ["next", "retry", "levels"]


def test_the_level_select_starts_time_trials_when_its_row_is_on():
    p = Progress()
    p.finish("00_arrival", 9.7)
    menu = Menu(Settings(), p, load_campaign())
    menu.open("title")
    menu.push("levels")
    keys = [i.key for i in menu.items()]
    assert keys[-2:] == ["trial_mode", "back"] and menu.items()[-2].value == "off"
    arrival = keys.index("level:00_arrival")
    assert menu.click(arrival) == "play:00_arrival"
    assert menu.click(len(keys) - 2) is None and menu.trial and menu.items()[-2].value == "on"
    assert menu.click(arrival) == "trial:00_arrival"
    menu.selected["levels"] = len(keys) - 2
    menu.input("left")  # Left/Right switch it as any on/off row
    assert not menu.trial and menu.click(arrival) == "play:00_arrival"


@pytest.mark.parametrize("size", [(1280, 720), (640, 360)])
def test_the_results_stand_above_the_rows_and_the_rows_take_the_pointer(size):
    w, h = size
    menu = Menu(Settings(), Progress(), load_campaign())
    menu.open_results(RESULTS, "First Steps", time_trial=True)
    view = menu.view()
    boxes = menu_layout(view, w, h)
    assert [b.index for b in boxes] == [0, 1, 2, 3]  # every row shown
    quads = menu_quads(view, w, h)
    gold = quads[np.all(np.isclose(quads[:, 8:11], (1.0, 0.9, 0.45), atol=0.01), axis=1)]  # the new best's value
    assert len(gold) and gold[:, 1].max() < boxes[0].rect[1]  # above the first row
    for box in boxes:
        x, y, bw, bh = box.rect
        assert hit(view, w, h, x + bw / 2, y + bh / 2) == (box.index, None)


# ---- the view, with a stand-in session ---------------------------------------------------------
def _finished(secrets=(), **counts):
    """A level-complete view over a stand-in of Crystal Cache finished at tick 600 (shown at 603)."""
    from across_dimensions.app.views.complete import LevelCompleteView

    said = []
    session = SimpleNamespace(
        window=None,
        progress=Progress(),
        campaign=load_campaign(),
        save_progress=lambda: None,
        say=lambda text, seconds=4.0: said.append(text),
        warn=said.append,
        recording=SimpleNamespace(stop=lambda: said.append("stopped")),
    )
    level = SimpleNamespace(crystals=(1, 2, 3), **({"secrets": secrets} if secrets else {}))
    game = SimpleNamespace(completed_tick=600, tick=603, dt=1 / 60, level=level, event_counts=Counter(counts))
    play = SimpleNamespace(game=game, crystals_found=2, level_path=Path("02_crystal_cache.toml"), run_log=None)
    view = LevelCompleteView(session, play)
    view.on_show()
    return view, session, said


def test_the_results_say_time_best_crystals_secrets_and_deaths():
    view, session, said = _finished(secrets=("a", "b", "c"), secret_found=1, player_died=2)
    assert view.results == (
        ("Time", "0:10.0", False),  # the tick the goal was reached, not the frame the view came
        ("Best time", "0:10.0  new best!", True),
        ("Crystals found", "2/3", False),
        ("Secrets found", "1/3", False),
        ("Deaths", "2", False),
    )
    assert said == ["Level complete in 10.0 s - best time!", "stopped"]
    assert session.progress.finished == {"02_crystal_cache": 10.0}
    assert session.progress.crystals == {"02_crystal_cache": (2, 3)}
    assert session.progress.current == "03_tumbling_hall" and not view.results_shown
    view, _, _ = _finished()  # a level without secrets: no such line
    assert [line[0] for line in view.results] == ["Time", "Best time", "Crystals found", "Deaths"]


# ---- the window's flow, headless (a fresh process) -------------------------------------------------
_FLOW = headless_window(r"""
from pyglet.window import key, mouse
from across_dimensions.game.actions import Actions
from across_dimensions.game.replay import Replay
from across_dimensions.game.sim import DT
from across_dimensions.render.ghost_figure import KEY
from across_dimensions.render.menu import menu_layout
from across_dimensions.world.resources import levels_dir
view = lambda: type(w.current_view).__name__
s.after_first_frame()  # as the window does once its first frame is up
s.warm.join()
w.update(DT)

def finish(play, idle=0):
    frames = iter([Actions()] * idle + list(Replay.load(levels_dir() / "replays" / "00_arrival.json").actions))
    play.read_actions = lambda: next(frames, Actions())
    drawn = 0
    while play.game.outcome != "complete":
        w.update(DT)
        drawn += any(d.key == KEY for d in play.current_frame().drawables)
    return drawn

def click(label):
    fw, fh = w.get_framebuffer_size()
    index = [i.label for i in s.menu.items()].index(label)
    box = next(b for b in menu_layout(s.menu.view(), fw, fh) if b.index == index)
    x, y = box.rect[0] + 5, box.rect[1] + box.rect[3] // 2
    sx, sy = w.width / fw, w.height / fh
    w.on_mouse_motion(x * sx, w.height - y * sy, 0, 0)
    w.on_mouse_press(x * sx, w.height - y * sy, mouse.LEFT, 0)

s.start_level(levels_dir() / "00_arrival.toml")
play = w.current_view
finish(play)
print("finished", play.game.completed_tick)
for _ in range(int(6 / DT)):                        # the results come, then stay
    w.update(DT * 1.0001)
print("after 6 s:", view(), s.menu.screen, w.current_view.play is play)
print("rows:", [i.label for i in s.menu.items()])
print("lines:", [line[0] for line in s.menu.view().summary])
w.on_key_press(key.DOWN, 0); w.on_key_press(key.DOWN, 0); w.on_key_press(key.RETURN, 0)   # Time trial
trial = w.current_view
print("trial:", view(), trial.trial, trial.race.ghost.ticks, "|", s.notice_text)
drawn = finish(trial, idle=30)                      # half a second behind the ghost
print("figure drawn", drawn > 100, "at", trial.game.completed_tick)
for _ in range(int(2 / DT)):
    w.update(DT * 1.0001)
print("ghost line:", [line for line in s.menu.view().summary if line[0] == "Ghost"])
click("Level select")
print("levels:", view(), s.menu.screen)
w.on_key_press(key.ESCAPE, 0)
print("back:", view(), s.menu.screen)
click("Continue")
print("next:", view(), w.current_view.level_path.stem)
import os
from pathlib import Path
course = Path(os.environ["CHECKPOINT_LEVEL"])                    # a level with a checkpoint: the split said
s.start_level(course)
run = w.current_view
run.read_actions = lambda: Actions(forward=1.0)
while run.game.outcome != "complete":
    w.update(DT)
for _ in range(int(2 / DT)):
    w.update(DT * 1.0001)
s.start_level(course, trial=True)
race = w.current_view
frames = iter([Actions()] * 30)
race.read_actions = lambda: next(frames, Actions(forward=1.0))
while race.game.checkpoint is None:
    w.update(DT)
print("split:", s.notice_text, "| ghost at", race.race.ghost.splits[0], "live at", race.game.tick)
from across_dimensions.app.ghost_saves import ghost_path
ghost_path("01_first_steps").write_text("{ not a ghost")           # a corrupt ghost: a warning, a race without it
s.start_level(levels_dir() / "01_first_steps.toml", trial=True)
w.update(DT)
print("corrupt:", view(), w.current_view.race.ghost, "|", s.notice_text)
""")


def test_window_flow_results_time_trial_and_continue(tmp_path):
    course = (
        LevelBuilder("Split test", spawn=(0.0, 0.0, -5.0, 0.0), goal=(0.0, 1.0, 5.0))
        .table("health", max=100.0)
        .add("checkpoint", name="middle", position=[0.0, 0.0, 0.0, 0.0], size=[6.0, 3.0, 1.0])
        .write(tmp_path, "course.toml")
    )
    env = dict(os.environ, ACROSS_DIMENSIONS_DATA_DIR=str(tmp_path), ACROSS_DIMENSIONS_CONFIG_DIR=str(tmp_path))
    env["CHECKPOINT_LEVEL"] = str(course)
    env.pop("DISPLAY", None)
    env["PYGLET_HEADLESS"] = "1"
    r = subprocess.run([sys.executable, "-c", _FLOW], env=env, capture_output=True, text=True, timeout=900)
    if r.returncode == 77:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    ticks = int(out.split("finished ")[1].split()[0])
    assert "after 6 s: LevelCompleteView complete True" in out  # no jump to the next level
    assert "rows: ['Continue', 'Retry', 'Time trial', 'Level select']" in out
    assert "lines: ['Time', 'Best time', 'Crystals found', 'Deaths', 'Ghost']" in out
    assert f"trial: PlayView True {ticks} | Time trial: race your best run, 0:09.7" in out
    assert f"figure drawn True at {ticks + 30}" in out
    assert "ghost line: [('Ghost', '0:09.7  +0.5 s', False)]" in out  # half a second behind
    assert "levels: LevelSelectView levels" in out and "back: LevelCompleteView complete" in out
    assert "next: PlayView 01_first_steps" in out
    split = out.split("split: ")[1].splitlines()[0]
    ghost_tick, live_tick = int(split.split("ghost at ")[1].split()[0]), int(split.split("live at ")[1])
    behind = (live_tick - ghost_tick) / 60  # half a second, give or take the tick the idle start settles in
    assert abs(behind - 0.5) < 0.05
    assert split.startswith(f"Checkpoint middle: 0:{live_tick / 60:04.1f}   +{behind:.1f} s")
    assert "corrupt: PlayView None | Time trial: your ghost could not be read (kept aside)" in out
    warning = "01_first_steps.json: not a ghost this game can read"
    assert warning in r.stderr and "kept as 01_first_steps.corrupt-1.json" in r.stderr
    kept = ["00_arrival.json", "00_arrival.replay.json", "01_first_steps.corrupt-1.json"]
    kept += ["course.json", "course.replay.json"]
    assert sorted(p.name for p in (tmp_path / "ghosts").iterdir()) == kept


# ---- the game in a real window, played with xdotool -------------------------------------------------
@pytest.fixture(scope="module")
def xvfb():
    with xvfb_display(67, "ACROSS_DIMENSIONS_COMPLETE_TEST_DISPLAY") as display:
        yield display


@pytest.mark.slow
def test_in_the_window_arrival_finished_shows_its_results_and_its_ghost(env, tmp_path, xvfb):
    if shutil.which("xdotool") is None:
        pytest.skip("xdotool is not installed")
    shots, data = tmp_path / "shots", tmp_path / "data"
    shots.mkdir()
    e = dict(env, DISPLAY=xvfb, ACROSS_DIMENSIONS_DATA_DIR=str(data), ACROSS_DIMENSIONS_CONFIG_DIR=str(tmp_path))
    e["ACROSS_DIMENSIONS_SCREENSHOT_DIR"] = str(shots)
    e.pop("WAYLAND_DISPLAY", None)

    def xdo(*args, then=0.0):
        subprocess.run(["xdotool", *args], env=e, check=True)
        time.sleep(then)

    def shot(count: int) -> np.ndarray:
        """Press F12 and read the ``count``-th screenshot once it is written whole."""
        xdo("key", "F12")
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            try:
                return read_png(shots_in(shots)[count - 1]).astype(int)
            except (IndexError, ValueError):  # not there yet, or still being written
                time.sleep(0.2)
        raise AssertionError(f"screenshot {count} was not saved")

    game = subprocess.Popen(
        [sys.executable, "-m", "across_dimensions", "play", "00_arrival"],
        cwd=tmp_path,
        env=e,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        for _ in range(900):  # the level's name in the caption: the kernels are loaded and it plays
            if subprocess.run(["xdotool", "search", "--name", "Arrival"], env=e, capture_output=True).stdout.strip():
                break
            time.sleep(0.2)
        xdo("keydown", "w")  # walk, jumping all along: over the barrier, up the steps, onto the pad
        for _ in range(240):
            if (data / "ghosts" / "00_arrival.json").exists():
                break
            xdo("key", "space", then=0.5)
        xdo("keyup", "w", then=3.0)
        assert (data / "ghosts" / "00_arrival.json").exists(), "the level was not finished"
        results = shot(1)
        xdo("key", "Down", then=0.3)
        xdo("key", "Down", then=0.3)
        xdo("key", "Return", then=1.0)  # Time trial: the player stands, the ghost walks ahead
        # Three pictures while it walks away, jumping all along (one may catch it small or high).
        racing = [shot(2), shot(3), shot(4)]
        time.sleep(12.0)  # the ghost has reached the pad, far away
        alone = shot(5)
        assert game.poll() is None, "the game ended"
    finally:
        game.terminate()
        _, err = game.communicate(timeout=60)
    assert "Traceback" not in err, err
    h, w = results.shape[:2]
    # The results: the panel's dark middle, and the gold of "new best!" in it.
    middle = results[h // 4 : 3 * h // 4, w // 4 : 3 * w // 4, :3]
    assert middle.mean() < 60
    assert (np.abs(middle - [255, 230, 115]).max(axis=2) < 40).sum() > 50
    # The ghost: between the two pictures of the standing player, a figure-sized warm change
    # below the notices, away from the pad and its turning beacon.
    region = (slice(h * 37 // 100, h), slice(w * 3 // 10, w * 7 // 10))

    def change(picture):
        diff = picture[region][..., :3] - alone[region][..., :3]
        changed = np.abs(diff).max(axis=2) > 25
        changed[: h * 16 // 100, w * 17 // 100 : w * 23 // 100] = False  # the pad and the beacon
        return diff, changed

    diff, changed = max((change(p) for p in racing), key=lambda dc: dc[1].sum())
    assert changed.sum() > 800, [change(p)[1].sum() for p in racing]
    assert (diff[changed][:, 0] - diff[changed][:, 2]).mean() > 0  # gold: more red than blue
