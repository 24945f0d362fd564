"""Accessibility settings (issue 35, points 4 to 7): captions, text size, toggles, and the README's
settings section, each documented setting checked to exist and to change something."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.app.captions import CAPTION_SECONDS, CaptionBoard, caption_text
from across_dimensions.app.keymap import TOGGLEABLE_ACTIONS
from across_dimensions.app.menu import VISIBLE_ROWS, Menu
from across_dimensions.app.play_options import play_options
from across_dimensions.app.settings import Settings, look_delta, window_options
from across_dimensions.app.sound import Cue, SoundDirector
from across_dimensions.game.actions import Actions
from across_dimensions.game.frame import Caption, EnergyGauge, Hud, SliceGauges, WeaponPanel
from across_dimensions.game.sim import DT, Game
from across_dimensions.render import palette
from across_dimensions.render.captions import caption_rects, mark_rect
from across_dimensions.render.font import solid_uv
from across_dimensions.render.hud import HudMetrics, hud_quads, quads_text
from across_dimensions.render.menu import menu_layout, menu_quads, rows_that_fit
from across_dimensions.render.text_layout import set_text_size
from across_dimensions.world.level import load_level

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data"
SIZES = (1.0, 1.25, 1.5)
VIEWS = ((1280, 720), (1920, 1080), (640, 360))


@pytest.fixture
def text_size():
    yield set_text_size
    set_text_size(1.0)


# ------------------------------------------------------------------ captions (point 4)
def test_a_caption_says_what_which_side_along_w_and_where():
    assert caption_text(Cue("hum", dw=0.6, pan=-0.8)) == "crystal hum, ana, left"
    assert caption_text(Cue("enemy", dw=-1.0, pan=0.9)) == "enemy, kata, right"
    assert caption_text(Cue("refused")) == "refused"
    assert caption_text(Cue("arrive", kind="slice_aligned")) == "slice aligned"  # not "seek arrived"
    assert caption_text(Cue("arrive", kind="seek_arrived")) == "seek arrived"
    assert caption_text(Cue("step")) is None and caption_text(Cue("jump")) is None  # the player's own


def test_captions_refresh_instead_of_piling_up_and_go_after_a_while():
    board = CaptionBoard()
    board.heard([Cue("hum", dw=0.6, pan=-0.8)], DT)
    board.heard([Cue("hum", dw=0.6, pan=-0.8), Cue("hurt")], DT)
    shown = board.shown()
    assert [c.text for c in shown] == ["crystal hum, ana, left", "you are hit"]
    assert shown[0].side == 1 and shown[1].side == 0
    for _ in range(round(CAPTION_SECONDS / DT) + 1):
        board.heard([], DT)
    assert board.shown() == []


def test_a_crystal_off_the_slice_is_captioned_with_its_side():
    game, director, board = Game(load_level(DATA / "crystals.toml")), SoundDirector(), CaptionBoard()
    texts = set()
    for _ in range(120):
        game.step(Actions())
        board.heard(director.cues(game, DT), DT)
        texts |= {c.text for c in board.shown()}
    assert any(t.startswith("crystal hum, ana") for t in texts), texts
    assert any(t.startswith("crystal hum, kata") for t in texts), texts


def test_captions_and_edge_marks_are_drawn_inside_the_view_only_when_given():
    hud = Hud(energy=EnergyGauge(3.0, 10.0))
    plain = hud_quads(hud, 1280, 720)
    captions = [Caption("crystal hum, ana, left", 1, -0.8), Caption("enemy, kata, right", -1, 0.9), Caption("refused")]
    hud.captions = captions
    quads = hud_quads(hud, 1280, 720)
    assert len(quads) > len(plain)
    text = quads_text(quads)
    for c in captions:
        assert c.text.replace(" ", "") in text
    assert "+w" in text and "-w" in text
    m = HudMetrics(1280, 720)
    rects = caption_rects(captions, m) + [mark_rect(c, m) for c in captions[:2]]
    for x, y, w, h in rects:
        assert 0 <= x and x + w <= 1280 and 0 <= y and y + h <= 720
    left, right = (mark_rect(c, m) for c in captions[:2])
    assert left[0] < 640 < right[0] and left[1] < right[1]  # ana higher, kata lower


# ----------------------------------------------------------------- text size (point 5)
def _busy_hud() -> Hud:
    return Hud(
        w=0.4,
        message="Seeking crystal 'ana' at w = +0.80",
        hint="Hold E to move ana (+w) and Q to move kata (-w); the ghosts show what lies either way.",
        hint_label="hint 2 of 4 - H dismisses",
        warning="settings.toml: fov_deg = 400: expected a number of degrees from 50 to 120",
        energy=EnergyGauge(3.0, 10.0),
        weapon=WeaponPanel("120-cell gun", 1, 1, 0.5, 0.3, refused="NOT ENOUGH ENERGY", live=0),
        slice=SliceGauges((30.0, 0.0, 0.0), "frustum", 30.0),
        captions=[Caption("crystal hum, ana, left", 1, -0.8), Caption("enemy, kata, right", -1, 0.9)],
    )


def _text_boxes(q) -> list:
    """The rectangles of the words drawn (runs of glyphs on one baseline, shadows left out)."""
    q = q[~np.all(q[:, 4:8] == np.float32(solid_uv()), axis=1)]
    q = q[q[:, 8] + q[:, 9] + q[:, 10] > 0]  # not the black drop shadows
    return [tuple(r[:4]) for r in q]


@pytest.mark.parametrize("width, height", VIEWS)
def test_larger_text_grows_the_hud_and_keeps_it_inside_the_view(text_size, width, height):
    scales, counts = [], []
    for size in SIZES:
        text_size(size)
        scales.append(HudMetrics(width, height).text_scale)
        q = hud_quads(_busy_hud(), width, height)
        assert (q[:, 0] >= 0).all() and (q[:, 1] >= 0).all(), size
        assert (q[:, 0] + q[:, 2] <= width).all() and (q[:, 1] + q[:, 3] <= height).all(), size
        counts.append(len(q))
        # No words run into others (the weapon panel's used to run into the slice gauges' label).
        assert len(_overlaps(q)) == 0, size
    assert scales[0] < scales[-1] and scales == sorted(scales)


def _overlaps(q) -> np.ndarray:
    """Pairs of words' glyphs that overlap (shadows left out), as index pairs."""
    b = np.array(_text_boxes(q))
    x0, y0, x1, y1 = b[:, 0] + 1, b[:, 1] + 1, b[:, 0] + b[:, 2] - 1, b[:, 1] + b[:, 3] - 1
    hit = (x0[:, None] < x1[None]) & (x0[None] < x1[:, None]) & (y0[:, None] < y1[None]) & (y0[None] < y1[:, None])
    np.fill_diagonal(hit, False)
    return np.argwhere(hit)


@pytest.mark.parametrize("width, height", VIEWS)
def test_larger_text_keeps_the_teaching_card_inside_its_panel(text_size, width, height):
    from across_dimensions.app.onboarding import FLATLAND_LINES
    from across_dimensions.game.frame import Card

    for size in SIZES:
        text_size(size)
        q = hud_quads(Hud(card=Card("flatland", 0.5, tuple(FLATLAND_LINES))), width, height)
        plain = {tuple(r) for r in hud_quads(Hud(), width, height)}  # the w gauge's words under the card
        q = np.array([r for r in q if tuple(r) not in plain])
        words = np.array(_text_boxes(q))
        px, py = (width - int(width * 0.84)) // 2, (height - int(height * 0.84)) // 2
        assert (words[:, 0] >= px).all() and (words[:, 0] + words[:, 2] <= width - px).all(), size
        assert (words[:, 1] >= py).all() and (words[:, 1] + words[:, 3] <= height - py).all(), size
        assert len(_overlaps(q)) == 0, size


def _menu(settings: Settings, screen: str):
    from across_dimensions.app.saves import Progress
    from across_dimensions.world.campaign import load_campaign

    menu = Menu(settings, Progress(), load_campaign())
    menu.open("pause" if screen == "pause" else "title")
    for step in {"settings": ["settings"], "controls": ["settings", "controls"], "levels": ["levels"]}.get(screen, []):
        menu.push(step)
    return menu


@pytest.mark.parametrize("screen", ["title", "pause", "levels", "settings", "controls"])
@pytest.mark.parametrize("width, height", VIEWS)
def test_larger_text_keeps_every_menu_inside_the_view(text_size, screen, width, height):
    menu = _menu(Settings(), screen)
    rows = []
    for size in SIZES:
        text_size(size)
        menu.fit_rows(rows_that_fit(menu.view(), height))
        for _ in range(len(menu.items())):  # down the whole list: the selection stays shown
            view = menu.view()
            boxes = menu_layout(view, width, height)
            assert any(b.index == view.selected for b in boxes)
            for b in boxes:
                x, y, w, h = b.rect
                assert 0 <= x and x + w <= width and 0 <= y and y + h <= height, (size, b)
            q = menu_quads(view, width, height)
            q = q[~np.all(q[:, 4:8] == np.float32(solid_uv()), axis=1)]  # the text (the backdrop's grid runs off)
            assert (q[:, :2] >= 0).all() and (q[:, 1] + q[:, 3] <= height).all() and (q[:, 0] + q[:, 2] <= width).all()
            menu.input("down")
        rows.append(menu.rows)
    if height >= 720:
        assert rows[0] == VISIBLE_ROWS  # the game's own size shows as many rows as it always did
    assert rows == sorted(rows, reverse=True)  # larger text: fewer rows, never more


# ------------------------------------------------------------------- toggles (point 6)
class _Keys(dict):
    def __getitem__(self, code):
        return self.get(code, False)


def _input(toggles=()):
    pytest.importorskip("pyglet")
    from across_dimensions.app.input import Bindings, PlayInput

    settings = Settings(toggle_actions=list(toggles))
    bindings = Bindings.__new__(Bindings)
    bindings.codes = {a: [("key", i)] for i, a in enumerate(settings.bindings)}  # no pyglet codes needed
    keys = _Keys()
    return PlayInput(bindings, keys, settings), keys, {a: i for i, a in enumerate(settings.bindings)}


def test_a_toggled_action_stays_on_from_one_press_to_the_next_and_lets_go_of_its_opposite():
    inp, keys, code = _input(["w_ana", "w_kata", "turn_xw_pos"])
    inp.press("key", code["w_ana"])
    assert inp.read().w == 1.0
    assert inp.read().w == 1.0  # no key down: still on
    inp.press("key", code["w_kata"])  # the opposite: ana lets go
    assert inp.read().w == -1.0
    inp.press("key", code["w_kata"])
    assert inp.read().w == 0.0
    inp.press("key", code["turn_xw_pos"])
    assert inp.read().turn_xw_pos and inp.read().turn_xw_pos
    inp.forget()  # a pause lets go of everything
    assert not inp.read().turn_xw_pos


def test_a_held_action_is_held_only_while_its_key_is_down_without_the_setting():
    inp, keys, code = _input()
    keys[code["w_ana"]] = True
    assert inp.read().w == 1.0
    keys[code["w_ana"]] = False
    assert inp.read().w == 0.0


def test_controls_switch_hold_and_toggle_per_action():
    settings = Settings()
    menu = _menu(settings, "controls")
    keys = [it.key for it in menu.items()]
    for action in TOGGLEABLE_ACTIONS:
        menu.selected["controls"] = keys.index(f"bind:{action}")
        assert menu.items()[menu.selected["controls"]].value.endswith("[hold]")
        menu.input("right")
        assert action in settings.toggle_actions
        assert menu.items()[menu.selected["controls"]].value.endswith("[toggle]")
    assert settings.toggle_actions == TOGGLEABLE_ACTIONS
    menu.input("left")
    assert TOGGLEABLE_ACTIONS[-1] not in settings.toggle_actions


# ------------------------------------------------------------- the README (point 7)
def documented_settings() -> dict[str, str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("\n## Settings\n", 1)[1].split("\n## ", 1)[0]
    found = {}
    for names, what in re.findall(r"^\| (`[^|]+`) \| [^|]+ \| (.+) \|$", section, re.M):
        for name in re.findall(r"`(\w+)`", names):
            found[name] = what
    return found


def _observe(name: str, s: Settings):
    """Something the game does differently with ``s``, for the setting ``name``."""
    if name == "preset":
        return s.keys_for("move_forward")
    if name in ("mouse_sensitivity", "invert_x", "invert_y"):
        return look_delta(s, 3.0, 2.0)
    if name in ("reduce_motion", "toggle_actions"):
        inp, _, code = _input(s.toggle_actions)
        inp.use(s)
        inp.press("key", code["w_ana"])
        inp.read()
        return inp.read()
    if name in ("colour_blind", "high_contrast"):
        return palette.settings_palette(s.colour_blind, s.high_contrast)
    if name == "text_size":
        set_text_size(s.text_size)
        try:
            return HudMetrics(1280, 720).text_scale
        finally:
            set_text_size(1.0)
    if name == "captions":
        board = CaptionBoard()
        board.heard([Cue("refused")], DT)
        return board.shown(s.captions)
    return _consumer(name, s)


def _consumer(name, s):
    """The settings the window and the session hand on, as they hand them on."""
    if name in ("fullscreen", "vsync", "width", "height"):
        return window_options(s)
    if name in ("ghosts", "ghost_distance", "ghost_strength", "ghost_layers", "show_fps", "pip"):
        return play_options(s)
    if name in ("radar", "radar_range_scale", "radar_height_scale"):
        from across_dimensions.game.sim import RadarView

        return RadarView(s.radar, s.radar_range_scale, s.radar_height_scale)
    if name in ("volume", "mute"):
        return s.volume * (not s.mute)
    if name == "fov_deg":
        game = Game(load_level(DATA / "crystals.toml"))
        return game.frame(fov_y_deg=s.fov_deg).camera.fov_y_deg
    if name == "render_scale":
        from types import SimpleNamespace

        from across_dimensions.render.scale import resolve_render_scale

        return resolve_render_scale(s.render_scale, SimpleNamespace(info={"GL_RENDERER": "llvmpipe"}))
    if name == "pip_size":
        from across_dimensions.render.pip import inset_rect

        return inset_rect((0, 0, 1280, 720), s.pip_size)
    raise AssertionError(f"no check for the setting {name!r}")


#: A value other than the default for each setting.
CHANGED = {
    "preset": "azerty",
    "mouse_sensitivity": 0.005,
    "invert_x": True,
    "invert_y": True,
    "fov_deg": 90.0,
    "fullscreen": True,
    "vsync": False,
    "show_fps": True,
    "width": 800,
    "height": 600,
    "radar": False,
    "radar_range_scale": 2.0,
    "radar_height_scale": 2.0,
    "ghosts": False,
    "ghost_distance": 2.0,
    "ghost_strength": 2.0,
    "ghost_layers": 2,
    "reduce_motion": True,
    "volume": 0.3,
    "mute": True,
    "colour_blind": True,
    "high_contrast": True,
    "text_size": 1.5,
    "captions": True,
    "toggle_actions": ["w_ana"],
    "render_scale": 0.75,
    "pip": True,
    "pip_size": 0.45,
}


def test_the_readme_documents_every_setting_and_only_settings():
    fields = {f.name for f in dataclasses.fields(Settings)} - {"bindings"}
    documented = documented_settings()
    assert set(documented) == fields
    assert set(CHANGED) == fields
    assert all(len(what) > 15 for what in documented.values())


@pytest.mark.parametrize("name", sorted(CHANGED))
def test_each_documented_setting_changes_something(name):
    default, changed = Settings(), Settings(**{name: CHANGED[name]})
    a, b = _observe(name, default), _observe(name, changed)
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        assert not np.array_equal(a, b), name
    else:
        assert a != b, name


def test_the_toggled_actions_that_are_on_are_named_on_screen():
    inp, keys, code = _input(["w_ana", "orbit_left"])
    inp.press("key", code["orbit_left"])
    inp.press("key", code["w_ana"])
    label = inp.latched_label()
    assert label.text == "ON: {w_ana} w ana, {orbit_left} orbit left"
    q = hud_quads(Hud(labels=[label]), 1280, 720)
    assert "ON:" in quads_text(q)
