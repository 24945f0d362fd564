"""Onboarding: hints that stay until done, the settings warning line and its log, the font for every hint."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from across_dimensions.app.onboarding import Onboarding, fill_keys, key_label
from across_dimensions.app.settings import default_settings, load_settings
from across_dimensions.app.settings_log import report_warnings
from across_dimensions.game.actions import Actions
from across_dimensions.game.frame import Hud
from across_dimensions.game.hints import HOLD_SECONDS, HintBook, placeholders, reading_seconds
from across_dimensions.render.font import missing_glyphs
from across_dimensions.render.hud import HudMetrics, health_bar_rect, hint_rect, hud_quads, quads_text, warning_rect
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import level_files, resolve_level

DT = 1.0 / 60.0
ROOT = Path(__file__).resolve().parents[1]


def run(book: HintBook, actions: Actions, seconds: float) -> None:
    for _ in range(int(round(seconds / DT))):
        book.tick(actions, DT)


def with_keys(text: str) -> str:
    """The window's filling of placeholders, with the default QWERTY keys."""
    return fill_keys(text, default_settings())


# ------------------------------------------------------------------ hints


def test_a_hold_hint_stays_until_the_key_is_held_long_enough():
    book = HintBook(["Hold {w_ana} to move along w.", "Walk to the pad."])
    run(book, Actions(), 60.0)  # a minute of standing still: still there
    assert book.current_index() == 0
    run(book, Actions(forward=1.0), 5.0)  # walking is not what it asks
    assert book.current_index() == 0
    run(book, Actions(w=1.0), HOLD_SECONDS / 2)  # a tap is not a hold
    assert book.current_index() == 0
    run(book, Actions(w=1.0), HOLD_SECONDS / 2 + DT)
    assert book.current_index() == 1


def test_a_press_hint_is_done_on_the_first_press_and_a_read_hint_after_its_reading_time():
    book = HintBook(["Fire with {fire}.", "The switch sits ana."])
    run(book, Actions(), 30.0)
    assert book.current_index() == 0
    book.tick(Actions(presses=(("fire", 1),)), DT)
    assert book.current_index() == 1
    run(book, Actions(), reading_seconds("The switch sits ana.") - 0.5)
    assert book.current_index() == 1
    run(book, Actions(), 1.0)
    assert book.current() is None


def test_the_hints_key_dismisses_then_shows_them_again():
    book = HintBook(["Hold {w_ana}.", "Hold {jump}."])
    book.toggle()
    assert book.current_index() == 1
    book.toggle()
    assert book.current() is None
    book.toggle()  # nothing on screen: all of them again, from the first
    assert book.current_index() == 0 and book.remaining() == 2


def test_a_key_press_the_simulation_sees_is_judged_by_the_ticks_not_by_the_key():
    book = HintBook(["Hold {w_ana}.", "Show the frame rate with {toggle_fps}."])
    book.note("w_ana")  # the key went down: not yet a hold
    assert book.current_index() == 0
    book.toggle()
    book.note("toggle_fps")  # a window-only action: its key press is the doing
    assert book.current() is None


def test_hints_name_the_players_own_keys_in_words():
    from across_dimensions.app.settings import Settings

    azerty = Settings(preset="azerty", bindings={"fire": ("MOUSE_LEFT", "LCTRL"), "seek": ()})
    text = "Hold {w_kata}, fire with {fire}, switch with {next_weapon}, seek with {seek}, {nonsense} {{x}}"
    assert fill_keys(text, azerty) == (
        "Hold A, fire with left click or Left Ctrl, switch with R or wheel down, seek with (unbound), {nonsense} {x}"
    )
    assert fill_keys("a stray { brace", azerty) == "a stray { brace"
    assert [key_label(k) for k in ("_1", "F3", "SPACE", "NUM_5", "SEMICOLON")] == [
        "1",
        "F3",
        "Space",
        "keypad 5",
        "Semicolon",
    ]


def test_placeholders_name_the_asked_actions_and_braces_stay_literal():
    assert placeholders("Hold {w_ana} ({w_kata} back), {{not}} this") == ("w_ana", "w_kata")
    assert placeholders("stray { brace") == ()


def test_onboarding_shows_hints_in_their_panel_with_the_players_keys_and_never_as_a_message():
    ob = Onboarding("Settings: 2 problems in s.toml; details in log")
    ob.level_started(["Hold {w_ana} to move along w."])
    hud = Hud(message="Screenshot saved: shot.png")
    ob.decorate(hud, with_keys)
    assert hud.hint == "Hold E to move along w." and "H hides" in hud.hint_label
    assert hud.message == "Screenshot saved: shot.png" and hud.warning.startswith("Settings:")
    quads = hud_quads(hud, 1280, 720)
    text = quads_text(quads)
    assert "HoldEtomovealongw." in text and "Screenshotsaved" in text and "Settings:" in text

    def overlap(a, b):
        return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]

    assert not overlap(hint_rect(hud, 1280, 720), warning_rect(hud.warning, 1280, 720))


@pytest.mark.parametrize("size", [(1280, 720), (1920, 1080), (1024, 768), (800, 450), (640, 360)])
def test_a_long_hint_stays_clear_of_the_health_bar_and_its_value(size):
    """The hint panel (top centre) never covers the health bar's column (top left), where the
    bar's value ("85/100") is right-aligned: a long hint wraps to more lines instead."""
    w, h = size
    text = (
        "Enemies wait off your slice: their pins rise and sink on the radar. One that glows "
        "and flickers is about to fire: step aside or along w (E/Q)."
    )
    hud = Hud(hint=text, hint_label="Hint 1/3 \u00b7 H hides")
    hx, _, hw, _ = hint_rect(hud, w, h)
    bx, _, bw, _ = health_bar_rect(HudMetrics(w, h))
    assert hx > bx + bw, "the hint panel overlaps the health bar's column"
    assert hx + hw < w - (bx + bw), "the hint panel is not centred"
    quads = hud_quads(hud, w, h)
    assert "flickersisabouttofire" in quads_text(quads).replace(" ", "")


def test_a_hint_done_by_the_player_is_ticked_off_then_the_next_one_shows():
    ob = Onboarding()
    ob.level_started(["Hold {jump}.", "Walk to the pad."])
    for _ in range(int(HOLD_SECONDS / DT) + 2):
        ob.ticked(Actions(jump=True), DT)
    hud = Hud()
    ob.decorate(hud, with_keys)
    assert hud.hint == "\u2713 Hold Space." and hud.hint_label == "Done"
    ob.wall(1.0)
    hud = Hud()
    ob.decorate(hud, with_keys)
    assert hud.hint == "Walk to the pad." and hud.hint_label.startswith("Hint 2/2")


def test_the_card_opens_before_the_first_move_along_w_and_any_key_closes_it():
    ob = Onboarding()
    assert not ob.before_tick(False)
    assert ob.before_tick(True) and ob.blocking  # the first push along w waits for the card
    hud = Hud()
    ob.decorate(hud, with_keys)
    assert hud.card is not None and "E and Q slide your slice" in " ".join(hud.card.lines)
    assert ob.key("move_forward", "W") and ob.blocking  # swallowed, the card stays
    assert ob.key(None, "RETURN") and not ob.blocking
    assert ob.take_ui_cues() == ["menu_select", "menu_select"] and ob.take_ui_cues() == []  # opened, closed
    assert not ob.before_tick(True)  # once a session
    assert not Onboarding(card=False).before_tick(True)  # a scripted recording skips it


def test_the_card_draws_a_ball_whose_cut_grows_and_shrinks():
    from across_dimensions.render.cards import PERIOD, ball_height, section_radius

    r = 10.0
    cuts = [section_radius(ball_height(t, r), r) for t in [i * PERIOD / 24 for i in range(24)]]
    assert cuts[0] == 0.0 and max(cuts) == pytest.approx(r, rel=0.05)  # off the plane, then through its middle
    hud = Hud()
    ob = Onboarding()
    ob.before_tick(True)
    ob.wall(PERIOD / 4)
    ob.decorate(hud, with_keys)
    assert "Youaretheflatbeing" in quads_text(hud_quads(hud, 1280, 720))


# ------------------------------------------------------------------- font


def test_the_font_draws_every_hint_of_every_level_and_the_card():
    texts = [with_keys(h.text) for path in level_files() for h in load_level(path).hints]
    texts += [with_keys(t) for t in __import__("across_dimensions.app.onboarding", fromlist=["x"]).FLATLAND_LINES]
    assert texts, "no hints found"
    missing = {t: missing_glyphs(t) for t in texts if missing_glyphs(t)}
    assert not missing


# ------------------------------------------------------------- settings


def test_a_corrupt_settings_file_gives_one_line_and_a_log(tmp_path, monkeypatch):
    monkeypatch.setenv("ACROSS_DIMENSIONS_LOG_DIR", str(tmp_path / "log"))
    bad = tmp_path / "settings.toml"
    bad.write_text('fov_deg = "wide"\nvolume = 7\nnonsense = 1\n[bindings]\njump = ["NOPE"]\n')
    settings, warnings = load_settings(bad)
    assert len(warnings) == 4 and settings.volume == 0.8
    line = report_warnings(warnings, bad)
    assert "\n" not in line and "4 problems" in line and str(bad) in line
    log = tmp_path / "log" / "settings.log"
    assert line.endswith(f"details in {log}")
    assert log.read_text().splitlines() == warnings
    garbage = tmp_path / "garbage.toml"
    garbage.write_bytes(b"\x00\xff[[[ not toml")
    _, warnings = load_settings(garbage)
    assert "a problem in" in report_warnings(warnings, garbage)
    assert report_warnings([], bad) == ""


def test_the_command_line_prints_one_warning_line_for_a_corrupt_settings_file(tmp_path):
    """``check-settings``-free check: the play command's first output line, without a window."""
    bad = tmp_path / "settings.toml"
    bad.write_text('fov_deg = "wide"\nwidth = -5\nheight = "x"\n')
    code = (
        "import sys; from across_dimensions.app.settings import load_settings;"
        "from across_dimensions.app.settings_log import report_warnings;"
        f"s, w = load_settings({str(bad)!r}); line = report_warnings(w, {str(bad)!r});"
        "print('warning: ' + line, file=sys.stderr)"
    )
    env = dict(os.environ, ACROSS_DIMENSIONS_LOG_DIR=str(tmp_path / "log"), PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=60)
    assert out.returncode == 0
    assert len(out.stderr.strip().splitlines()) == 1 and "3 problems" in out.stderr
    assert len((tmp_path / "log" / "settings.log").read_text().splitlines()) == 3


def test_the_screen_line_fits_between_the_energy_bar_and_the_radar(tmp_path):
    from across_dimensions.app.settings_log import warning_screen_line
    from across_dimensions.render.font import text_width
    from across_dimensions.render.hud import HudMetrics

    line = warning_screen_line(["a", "b", "c"], tmp_path / "settings.toml")
    assert line == "3 problems in settings.toml: see settings.log"
    assert warning_screen_line(["a"], tmp_path / "settings.toml").startswith("A problem in settings.toml")
    m = HudMetrics(1280, 720)
    room = m.radar_rect()[0] - m.margin - (m.energy_bar()[0] + m.energy_bar()[2] + m.margin)
    assert text_width(line, m.text_scale) < room


# ------------------------------------------------------------- the window


@pytest.fixture(scope="module")
def xvfb():
    """A virtual X display for a real window; skipped when Xvfb is not installed."""
    from conftest import xvfb_display

    with xvfb_display(63, "ACROSS_DIMENSIONS_ONBOARDING_TEST_DISPLAY") as display:
        yield display


def test_play_with_a_corrupt_settings_file_warns_once_and_shows_the_hint_clear_of_the_warning(tmp_path, xvfb):
    from conftest import shots_in

    from across_dimensions.render.hud import HudMetrics
    from across_dimensions.render.png import read_png

    bad = tmp_path / "settings.toml"
    bad.write_text('fov_deg = "wide"\nvolume = 7\nnonsense = 1\n')
    env = dict(os.environ, DISPLAY=xvfb, ACROSS_DIMENSIONS_LOG_DIR=str(tmp_path / "log"))
    env["ACROSS_DIMENSIONS_SCREENSHOT_DIR"] = str(tmp_path / "screenshots")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    env.pop("WAYLAND_DISPLAY", None)
    args = ["play", "01_first_steps", "--settings", bad, "--screenshot-after", "1.5", "--quit-after", "3"]
    r = subprocess.run(
        [sys.executable, "-m", "across_dimensions", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=240,
        cwd=tmp_path,
        env=env,
    )
    assert r.returncode == 0, r.stderr
    warnings = [ln for ln in r.stderr.splitlines() if ln.startswith("warning:")]
    assert len(warnings) == 1 and "3 problems" in warnings[0] and "Traceback" not in r.stderr
    assert len((tmp_path / "log" / "settings.log").read_text().splitlines()) == 3
    shots = shots_in(tmp_path / "screenshots")
    assert shots, r.stdout
    img = read_png(shots[0]).astype(int)
    h, w = img.shape[:2]
    first_hint = load_level(resolve_level("01_first_steps")).hints[0].text
    hud = Hud(hint=with_keys(first_hint), hint_label="Hint 1/2 \u00b7 H hides")
    hx, hy, hw, hh = hint_rect(hud, w, h)
    # The hint's accent bar is drawn at the panel's left edge, in the accent colour (cyan).
    bar = img[hy + 2 : hy + hh - 2, hx : hx + max(2, HudMetrics(w, h).text_scale)]
    assert (bar[..., 2] > 200).mean() > 0.9 and (bar[..., 0] < 120).mean() > 0.9
    # The warning line's amber text sits at the bottom, below the hint and clear of it.
    wx, wy, ww, wh = warning_rect("3 problems in settings.toml: see settings.log", w, h)
    strip = img[wy : wy + wh, wx : wx + ww]
    amber = (strip[..., 0] > 200) & (strip[..., 1] > 150) & (strip[..., 2] < 140)
    assert amber.sum() > 50 and wy > hy + hh
