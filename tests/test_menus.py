"""Menus, saves and the campaign, driven headless through the same calls the window makes."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import headless_window

from across_dimensions.app.menu import VISIBLE_ROWS, Menu, menu_verb
from across_dimensions.app.saves import Progress, load_progress, save_progress
from across_dimensions.app.settings import ACTIONS, PRESETS, Settings, load_settings, save_settings
from across_dimensions.world.campaign import CampaignError, load_campaign, next_in_campaign
from across_dimensions.world.flat_level import load_flat_level
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import level_files, levels_dir, prologue_files

ROOT = Path(__file__).resolve().parents[1]


# ---- campaign -------------------------------------------------------------------------
def test_campaign_order_skips_missing_files_and_every_entry_loads():
    campaign = load_campaign()
    stems = [e.stem for e in campaign]
    order = [
        "prologue",
        "00_arrival",
        "01_first_steps",
        "02_crystal_cache",
        "03_tumbling_hall",
        "04_armory",
        "05_blast_and_field",
        "06_bridge",
        "07_orthogonal_worlds",
        "08_around_the_corner",
        "09_hive",
        "10_cloister",
        "11_crossfire",
        "12_folded_stair",
    ]
    shipped = {p.stem for p in level_files() + prologue_files()}
    assert stems == [s for s in order if s in shipped]  # the campaign's order, minus what is not shipped
    assert stems[:7] == order[:7]
    for entry in campaign:
        level = (load_flat_level if entry.stem == "prologue" else load_level)(entry.path)  # raises on a broken level
        assert level.name and entry.title
    assert [e.stem for e in campaign if e.optional] == ["prologue"]  # the prologue may be skipped
    assert next_in_campaign(campaign, "prologue").stem == "00_arrival"
    assert next_in_campaign(campaign, "00_arrival").stem == "01_first_steps"
    assert next_in_campaign(campaign, "01_first_steps").stem == "02_crystal_cache"
    assert next_in_campaign(campaign, stems[-1]) is None
    assert "campaign" not in {p.stem for p in level_files()}  # the campaign file is no level


def test_bad_campaign_names_file_and_entry(tmp_path):
    (tmp_path / "a.toml").write_text("")
    bad = tmp_path / "campaign.toml"
    bad.write_text(
        '[[level]]\nfile = "../x"\ntitle = "X"\n[[level]]\nfile = "a"\n[[level]]\nfile = "zz"\ntitle = "Z"\n'
    )
    with pytest.raises(CampaignError) as e:
        load_campaign(bad)
    lines = str(e.value).splitlines()
    assert len(lines) == 2, lines
    assert all(str(bad) in line for line in lines)
    assert "#1" in lines[0] and "'../x'" in lines[0] and "#2" in lines[1] and "title" in lines[1]
    good = tmp_path / "c.toml"
    good.write_text('[[level]]\nfile = "a"\ntitle = "A"\n[[level]]\nfile = "missing"\ntitle = "M"\n')
    assert [e.stem for e in load_campaign(good)] == ["a"]


def test_check_level_checks_the_campaign_file_as_a_campaign(tmp_path):
    def check(*files):
        return subprocess.run(
            [sys.executable, "-m", "across_dimensions", "check-level", *map(str, files)],
            capture_output=True,
            text=True,
            timeout=120,
        )

    # `check-level levels/*.toml` takes the campaign file in too: it is checked as the campaign.
    r = check(*level_files(), levels_dir() / "campaign.toml")
    assert r.returncode == 0, r.stderr
    count = len(load_campaign())  # the shipped levels it names
    assert f"campaign.toml: ok - the campaign, {count} levels: prologue, 00_arrival, 01_first_steps" in r.stdout
    bad = tmp_path / "campaign.toml"
    bad.write_text('[[level]]\nfile = "../outside"\ntitle = "Out"\n', encoding="utf-8")
    r = check(bad)
    assert r.returncode == 2 and "[[level]] #1" in r.stderr and "Traceback" not in r.stderr


# ---- saves ----------------------------------------------------------------------------
def test_progress_round_trip_and_best_times(tmp_path):
    p = Progress()
    assert p.finish("01_first_steps", 50.0) and not p.finish("01_first_steps", 60.0)
    assert p.finish("01_first_steps", 41.5)
    p.found_crystals("02_crystal_cache", 2, 3)
    p.found_crystals("02_crystal_cache", 1, 3)  # a worse run keeps the best
    p.current, p.checkpoint = "03_tumbling_hall", 2
    path = save_progress(p, tmp_path / "progress.json")
    back, warnings = load_progress(path)
    assert warnings == []
    assert back == p and back.finished["01_first_steps"] == 41.5 and back.crystals["02_crystal_cache"] == (2, 3)
    assert json.loads(path.read_text())["version"] == 1
    assert sorted(f.name for f in tmp_path.iterdir()) == [".progress.lock", "progress.json"]  # no temporary file


@pytest.mark.parametrize(
    "text",
    [
        "{not json",
        '{"format": "across-dimensions-progress", "version": 99}',
        '{"format": "across-dimensions-progress", "version": 1, "finished": {"a": -3}}',
        '{"format": "across-dimensions-progress", "version": 1, "crystals": {"a": [5, 3]}}',
        "[]",
    ],
)
def test_corrupt_progress_is_kept_aside_with_one_warning(tmp_path, text):
    path = tmp_path / "progress.json"
    path.write_text(text)
    progress, warnings = load_progress(path)
    assert progress == Progress()
    assert len(warnings) == 1 and str(path) in warnings[0] and "progress.corrupt-1.json" in warnings[0]
    assert (tmp_path / "progress.corrupt-1.json").read_text() == text  # kept, byte for byte
    assert not path.exists()
    path.write_text(text)  # a second corrupt file does not overwrite the first one kept
    load_progress(path)
    assert (tmp_path / "progress.corrupt-2.json").exists()


def test_unlocking_and_continue():
    stems = ["a", "b", "c"]
    p = Progress()
    assert p.unlocked(stems) == [True, False, False] and p.continue_level(stems) == ("a", None)
    p.finish("a", 10.0)
    assert p.unlocked(stems) == [True, True, False] and p.continue_level(stems) == ("b", None)
    p.current, p.checkpoint = "c", 1  # left mid-level (e.g. played from the command line)
    assert p.continue_level(stems) == ("c", 1)
    p.current, p.checkpoint = None, None
    p.finish("b", 1.0)
    p.finish("c", 1.0)
    assert p.continue_level(stems) == (None, None)


def test_an_optional_level_may_be_skipped_and_is_not_offered_again():
    stems, optional = ["prologue", "a", "b"], {"prologue"}
    p = Progress()
    assert p.unlocked(stems, optional) == [True, True, False]  # the level after it is open at once
    assert p.continue_level(stems, optional) == ("prologue", None)  # a new player starts with it
    assert p.play("a", None, stems, optional) and p.continue_level(stems, optional) == ("a", None)
    p.current = None
    p.finish("a", 5.0)
    assert p.continue_level(stems, optional) == ("b", None)  # skipped, then not offered again
    assert Progress().unlocked(stems) == [True, False, False]  # without the campaign's word, nothing is optional


def test_only_an_unlocked_campaign_level_becomes_continue():
    stems = ["a", "b", "c"]
    p = Progress()
    p.finish("a", 10.0)
    p.current, p.checkpoint = "b", 1
    assert not p.play("c", None, stems) and (p.current, p.checkpoint) == ("b", 1)  # c is locked
    assert not p.play("custom", None, stems) and p.continue_level(stems) == ("b", 1)  # not in the campaign
    assert p.play("a", None, stems) and p.continue_level(stems) == ("a", None)  # finished levels stay open


@pytest.fixture(scope="module")
def xvfb():
    """A virtual X display for a real window; skipped when Xvfb is not installed."""
    from conftest import xvfb_display

    with xvfb_display(65, "ACROSS_DIMENSIONS_MENUS_TEST_DISPLAY") as display:
        yield display


@pytest.mark.slow
def test_play_from_the_command_line_never_moves_continue_to_a_locked_level(tmp_path, env, xvfb):
    data = tmp_path / "data"
    data.mkdir()
    p = Progress()
    p.finish("00_arrival", 30.0)  # so 01 is open, and 05 is still locked
    save_progress(p, data / "progress.json")
    e = dict(env, DISPLAY=xvfb, ACROSS_DIMENSIONS_DATA_DIR=str(data), ACROSS_DIMENSIONS_CONFIG_DIR=str(tmp_path))
    e.pop("WAYLAND_DISPLAY", None)
    stems = [entry.stem for entry in load_campaign()]
    optional = {entry.stem for entry in load_campaign() if entry.optional}
    for level, current in (
        ("05_blast_and_field", None),
        ("02_crystal_cache", None),
        ("01_first_steps", "01_first_steps"),
    ):
        r = subprocess.run(
            [sys.executable, "-m", "across_dimensions", "play", level, "--quit-after", "1"],
            capture_output=True,
            text=True,
            timeout=300,
            cwd=tmp_path,
            env=e,
        )
        assert r.returncode == 0, r.stderr
        back, warnings = load_progress(data / "progress.json")
        assert warnings == [] and back.current == current, (level, back)
        # The first level not finished (the prologue, skipped, is not offered again).
        assert back.continue_level(stems, optional) == ("01_first_steps", None), level


# ---- menus ----------------------------------------------------------------------------
def _menu(progress=None, settings=None):
    changed = []
    menu = Menu(settings or Settings(), progress or Progress(), load_campaign(), on_change=changed.append)
    return menu, changed


def _goto(menu, key):
    """Move with the keyboard to the row ``key``, as a player would."""
    for _ in range(len(menu.items()) + 1):
        if menu.items()[menu.selected[menu.screen]].key == key:
            return
        menu.input("down")
    raise AssertionError(f"no row {key!r} reachable on {menu.screen}: {[i.key for i in menu.items()]}")


def _select(menu, key):
    """Move to the row ``key`` and press Enter."""
    _goto(menu, key)
    return menu.input("select")


def test_title_to_level_select_shows_locked_and_finished():
    p = Progress()
    p.finish("00_arrival", 20.0)
    p.finish("01_first_steps", 83.25)
    p.found_crystals("02_crystal_cache", 2, 3)
    menu, _ = _menu(p)
    menu.open("title")
    assert [i.label for i in menu.items()] == ["Continue", "Level select", "Settings", "Quit"]
    assert menu.items()[0].value == "Crystal Cache"  # the first unfinished level
    assert _select(menu, "levels") is None and menu.screen == "levels"
    rows = {i.key: i for i in menu.items()}
    assert rows["level:01_first_steps"].value.startswith("done  1:23.2")
    assert rows["level:02_crystal_cache"].enabled and "crystals 2/3" in rows["level:02_crystal_cache"].value
    assert not rows["level:03_tumbling_hall"].enabled and rows["level:03_tumbling_hall"].value == "locked"
    # Down never lands on a locked level: from level 2 (the fourth row, after the prologue) it goes to
    # the time-trial row, then Back.
    menu.selected["levels"] = 3
    menu.input("down")
    assert menu.items()[menu.selected["levels"]].key == "trial_mode"
    menu.input("down")
    assert menu.items()[menu.selected["levels"]].key == "back"
    assert menu.click(4) is None  # a locked level cannot be clicked either
    assert menu.click(3) == "play:02_crystal_cache"
    assert menu.input("back") is None and menu.screen == "title"
    assert _select(menu, "continue") == "continue"
    assert _select(menu, "quit") == "quit"


def test_pause_menu_commands():
    menu, _ = _menu()
    menu.open("pause")
    assert [i.key for i in menu.items()] == ["resume", "restart", "settings", "quit_to_title"]
    assert menu.input("select") == "resume"
    assert _select(menu, "restart") == "restart"
    assert _select(menu, "settings") is None and menu.screen == "settings" and menu.view().dim
    assert menu.input("back") is None and menu.screen == "pause"
    assert menu.input("back") == "resume"  # Esc on the pause menu resumes
    assert _select(menu, "quit_to_title") == "quit_to_title"


def test_settings_apply_at_once_by_keyboard_and_mouse():
    menu, changed = _menu()
    s = menu.settings
    menu.open("title")
    _select(menu, "settings")
    keys = [i.key for i in menu.items()]
    for name in ("mouse_sensitivity", "invert_x", "invert_y", "fov_deg", "render_scale", "volume"):
        assert f"set:{name}" in keys
    assert "set:colour_blind" in keys and "set:reduce_motion" in keys
    _goto(menu, "set:fov_deg")
    menu.input("right")
    assert s.fov_deg == 80.0 and changed[-1] == "fov_deg"
    for _ in range(20):
        menu.input("right")
    assert s.fov_deg == 120.0  # clamped at the top of its range
    row = keys.index("set:render_scale")
    menu.click(row, 0.0)
    assert s.render_scale == 0.5 and changed[-1] == "render_scale"
    menu.click(row, 0.52)  # snapped to the slider's 0.05 steps
    assert s.render_scale == pytest.approx(0.75)
    menu.click(keys.index("set:invert_y"))
    assert s.invert_y is True and changed[-1] == "invert_y"
    _select(menu, "set:reduce_motion")
    assert s.reduce_motion is True and changed[-1] == "reduce_motion"
    menu.input("left")
    assert s.reduce_motion is False
    Settings(**{f: getattr(s, f) for f in ("fov_deg", "render_scale", "volume", "mouse_sensitivity")})  # all valid


def test_rebinding_conflicts_and_presets(tmp_path):
    menu, changed = _menu()
    s = menu.settings
    menu.open("title")
    _select(menu, "settings")
    _select(menu, "controls")
    # A free key: pressing it replaces the first key and keeps the arrow.
    _select(menu, "bind:move_forward")
    assert menu.capturing == "move_forward" and "Press a key" in menu.view().prompt
    menu.capture("G")
    assert s.keys_for("move_forward") == ("G", "UP") and changed[-1] == "bindings"
    # A mouse button works the same way.
    _select(menu, "bind:jump")
    menu.capture("MOUSE_5")
    assert s.keys_for("jump") == ("MOUSE_5",)
    # Esc cancels and leaves the binding alone.
    menu.input("select")
    menu.capture("ESCAPE")
    assert s.keys_for("jump") == ("MOUSE_5",) and menu.capturing is None
    # A key in use: the conflict screen. Bind to both: both rows are marked.
    _select(menu, "bind:manipulate")
    menu.capture("E")  # w_ana's key
    assert menu.screen == "conflict" and "E is used by" in menu.view().prompt
    _select(menu, "both")
    assert menu.screen == "controls" and s.keys_for("manipulate") == ("E",)
    rows = {i.key: i for i in menu.items()}
    assert rows["bind:manipulate"].warn and rows["bind:w_ana"].warn and "E" in s.conflicts()
    # Resolve by swapping: w_ana takes manipulate's old key back... here F was replaced, so bind F and swap.
    _select(menu, "bind:w_ana")
    menu.capture("F")  # F is free now: no conflict screen
    assert s.conflicts() == {} and not any(i.warn for i in menu.items())
    _select(menu, "bind:w_kata")
    menu.capture("F")
    _select(menu, "swap")
    assert s.keys_for("w_kata") == ("F",) and s.keys_for("w_ana") == ("Q",) and s.conflicts() == {}
    # Backspace unbinds.
    _goto(menu, "bind:screenshot")
    menu.input("clear")
    assert s.keys_for("screenshot") == ()
    # The preset row resets every key to AZERTY, and back.
    _goto(menu, "preset")
    menu.input("select")
    assert s.preset == "azerty" and s.keys_for("move_forward") == PRESETS["azerty"]["move_forward"]
    menu.input("right")
    assert s.preset == "qwerty" and all(s.keys_for(a) == PRESETS["qwerty"].get(a, ()) for a in ACTIONS)
    # What the menu built is a valid settings file that loads back the same.
    menu.input("left")
    _select(menu, "bind:jump")
    menu.capture("X")
    path = save_settings(s, tmp_path / "settings.toml")
    back, warnings = load_settings(path)
    assert warnings == [] and back.bindings == s.bindings and back.preset == "azerty"


def test_long_lists_scroll_with_the_selection():
    menu, _ = _menu()
    menu.open("title")
    _select(menu, "settings")
    _select(menu, "controls")
    n = len(menu.items())
    assert n > VISIBLE_ROWS
    for _ in range(n - 1):
        menu.input("down")
    v = menu.view()
    assert v.selected == n - 1 and v.first <= v.selected < v.first + v.rows
    menu.input("down")  # wraps to the top
    assert menu.view().selected == 0 and menu.view().first == 0
    menu.scroll(5)
    v = menu.view()
    assert v.first == 5 and v.first <= v.selected < v.first + v.rows


def test_menu_verbs_follow_the_players_keys():
    azerty = Settings(preset="azerty")
    assert menu_verb("Z", azerty) == "up" and menu_verb("Q", azerty) == "left"
    assert menu_verb("W", Settings()) == "up" and menu_verb("RETURN", azerty) == "select"
    assert menu_verb("ESCAPE", azerty) == "back" and menu_verb("F12", azerty) is None


# ---- the window's flow, headless (a fresh process: see test_input.py) ---------------------
_FLOW = headless_window(r"""
import os
from pyglet.window import key
from across_dimensions.game.sim import DT
view = lambda: type(w.current_view).__name__
s.after_first_frame()  # as the window does once its first frame is up
s.warm.join()
w.update(DT)
assert s.menu.screen == "title" and view() == "TitleView", (s.menu.screen, view())
w.on_key_press(key.DOWN, 0); w.on_key_press(key.RETURN, 0)      # Level select
assert s.menu.screen == "levels" and view() == "LevelSelectView"
w.on_key_press(key.DOWN, 0); w.on_key_press(key.RETURN, 0)      # Arrival, after the prologue
w.update(DT)
assert view() == "PlayView" and w.current_view.game.level.name == "Arrival"
play = w.current_view
for _ in range(30):
    w.update(DT * 1.0001)
w.on_key_press(key.ESCAPE, 0)                                     # the pause menu
assert s.menu.screen == "pause" and view() == "PauseView"
t = play.game.tick
w.update(DT * 1.0001)
assert play.game.tick == t                                        # paused: no ticks
w.on_key_press(key.DOWN, 0); w.on_key_press(key.DOWN, 0); w.on_key_press(key.RETURN, 0)   # Settings
assert view() == "SettingsView" and w.views[-2:-1] and type(w.views[-2]).__name__ == "PauseView"
for _ in range(4):
    w.on_key_press(key.DOWN, 0)
w.on_key_press(key.RIGHT, 0)                                      # field of view 75 -> 80, saved at once
assert s.settings.fov_deg == 80.0
w.on_key_press(key.ESCAPE, 0); w.on_key_press(key.ESCAPE, 0)      # back, resume
assert view() == "PlayView" and w.current_view is play
w.update(DT * 1.0001)
assert play.game.tick == t + 1
w.on_key_press(key.ESCAPE, 0)
for _ in range(3):
    w.on_key_press(key.DOWN, 0)
w.on_key_press(key.RETURN, 0)                                     # quit to title
assert s.menu.screen == "title" and view() == "TitleView" and len(w.views) == 1
print("current", s.progress.current)
# The mouse: hover and click rows where they are drawn (window coordinates, origin bottom-left).
from across_dimensions.render.menu import menu_layout
from pyglet.window import mouse
def click(index):
    fw, fh = w.get_framebuffer_size()
    box = next(b for b in menu_layout(s.menu.view(), fw, fh) if b.index == index)
    x, y = box.rect[0] + 5, box.rect[1] + box.rect[3] // 2
    sx, sy = w.width / fw, w.height / fh
    w.on_mouse_motion(x * sx, w.height - y * sy, 0, 0)
    assert s.menu.selected[s.menu.screen] == index
    w.on_mouse_press(x * sx, w.height - y * sy, mouse.LEFT, 0)
click(1)
assert s.menu.screen == "levels"
click(1)
w.update(DT)
assert view() == "PlayView"
# Finishing a level through the window: level 2's shipped replay, fed as the player's input.
from across_dimensions.game.replay import Replay
from across_dimensions.world.resources import levels_dir
from across_dimensions.game.actions import Actions
frames = iter(Replay.load(levels_dir() / "replays" / "02_crystal_cache.json").actions)
s.start_level(levels_dir() / "02_crystal_cache.toml")
play = w.current_view
play.read_actions = lambda: next(frames, Actions())
for _ in range(100000):
    if play.game.outcome == "complete":
        break
    w.update(DT)
assert play.game.outcome == "complete"
w.update(DT)
assert view() == "LevelCompleteView"
p = s.progress
print("finished", sorted(p.finished), "crystals", p.crystals, "current", p.current)
for _ in range(int(4 / DT)):                                      # the results stay until the player chooses
    w.update(DT * 1.0001)
assert view() == "LevelCompleteView" and s.menu.screen == "complete"
w.on_key_press(key.RETURN, 0)                                     # Continue: the next level of the campaign
print("next", w.current_view.level_path.stem)
""")


def test_window_flow_title_level_pause_settings(tmp_path):
    env = dict(os.environ, ACROSS_DIMENSIONS_DATA_DIR=str(tmp_path), ACROSS_DIMENSIONS_CONFIG_DIR=str(tmp_path))
    env.pop("DISPLAY", None)
    env["PYGLET_HEADLESS"] = "1"
    r = subprocess.run([sys.executable, "-c", _FLOW], env=env, capture_output=True, text=True, timeout=600)
    if r.returncode == 77:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stdout + r.stderr
    assert "current 00_arrival" in r.stdout  # quitting mid-level keeps the level to continue
    settings, warnings = load_settings(tmp_path / "settings.toml")
    assert warnings == [] and settings.fov_deg == 80.0
    saved = json.loads((tmp_path / "progress.json").read_text())
    assert "finished ['02_crystal_cache'] crystals {'02_crystal_cache': (2, 3)} current 03_tumbling_hall" in r.stdout
    assert "next 03_tumbling_hall" in r.stdout
    # The shipped replay takes 2 of the 3 crystals.
    assert saved["finished"]["02_crystal_cache"] > 0 and saved["crystals"] == {"02_crystal_cache": [2, 3]}
    assert levels_dir().is_dir()


def test_a_saved_checkpoint_resumes_where_the_level_still_has_it():
    from across_dimensions.app.saves import checkpoint_of, resume_at_checkpoint
    from across_dimensions.game.sim import Game

    plain = Game(load_level(levels_dir() / "01_first_steps.toml"))
    assert checkpoint_of(plain) is None
    assert not resume_at_checkpoint(plain, 0)  # a level without checkpoints: its start
    hive = Game(load_level(levels_dir() / "09_hive.toml"))
    count = len(hive.level.checkpoints)
    assert count >= 1 and checkpoint_of(hive) is None
    assert resume_at_checkpoint(hive, count - 1) and checkpoint_of(hive) == count - 1
    cp = hive.level.checkpoints[count - 1].position
    assert np.array_equal(hive.player.position, cp)  # standing there
    assert not resume_at_checkpoint(hive, count)  # the level changed since the save: its start
    assert not resume_at_checkpoint(hive, None)


def test_warm_up_child_reports_every_step():
    """The child process the title screen starts: one ``step`` line per step, then done."""
    from across_dimensions.app.warmup import STEPS

    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions.app.warmup"], capture_output=True, text=True, timeout=900
    )
    assert r.returncode == 0, r.stdout + r.stderr
    lines = [ln for ln in r.stdout.splitlines() if ln.startswith("step ")]
    n = len(STEPS)
    assert lines == [f"step {i} {n} {label}" for i, (label, _) in enumerate(STEPS)] + [f"step {n} {n} ready"]
    # Between them, the kernels every half second: ready of all, never more, and never falling.
    counts = [tuple(map(int, ln.split()[1:])) for ln in r.stdout.splitlines() if ln.startswith("kernels ")]
    assert all(0 <= ready <= total and compiled <= total for ready, total, compiled in counts)
    assert [c[0] for c in counts] == sorted(c[0] for c in counts)
