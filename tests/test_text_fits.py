"""Every dialog, hint and notice fits its panel, at 1280x720 and at 1920x1080.

Text is laid out by one path (``render/text_layout``: wrapped to its panel, or cut with an
ellipsis where one line is all there is); these tests read the laid-out glyph quads back and
check that each glyph lies inside the panel it belongs to, that no two pieces of text run over
each other, and that no ``{placeholder}`` reaches the screen.
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.app.keymap import ACTION_DESCRIPTIONS
from across_dimensions.app.menu import Menu
from across_dimensions.app.onboarding import FLATLAND_LINES, fill_keys, with_keys
from across_dimensions.app.saves import Progress
from across_dimensions.app.settings import ACTIONS, Settings, default_settings
from across_dimensions.game.frame import Hud, ScreenLabel
from across_dimensions.render.font import default_font
from across_dimensions.render.hud import hud_quads, quads_text
from across_dimensions.render.hud_layout import hint_rect, label_rect, message_layout, overlap
from across_dimensions.render.menu import _panel, menu_layout, menu_quads
from across_dimensions.world.campaign import load_campaign
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import level_files

SIZES = [(1280, 720), (1920, 1080)]
APP = Path(__file__).resolve().parents[1] / "across_dimensions" / "app"


def glyphs(quads: np.ndarray) -> np.ndarray:
    """The rects ``(n, 4)`` of the glyphs drawn (shadows and solid rectangles left out)."""
    font = default_font()
    is_glyph = (
        np.array([font.char_at(q[4], q[5]) is not None for q in quads], bool) if len(quads) else np.zeros(0, bool)
    )
    lit = quads[:, 8:11].max(axis=1) > 0.05 if len(quads) else is_glyph
    return quads[is_glyph & lit, :4]


def inside(rects: np.ndarray, box, slack: int = 1) -> np.ndarray:
    x, y, w, h = box
    return (
        (rects[:, 0] >= x - slack)
        & (rects[:, 1] >= y - slack)
        & (rects[:, 0] + rects[:, 2] <= x + w + slack)
        & (rects[:, 1] + rects[:, 3] <= y + h + slack)
    )


def runs_over_each_other(rects: np.ndarray) -> int:
    """Pairs of glyphs covering more than half of the smaller one: text drawn over text (letters
    of one word, such as "fl", may touch)."""
    if len(rects) < 2:
        return 0
    x0, y0 = rects[:, 0], rects[:, 1]
    x1, y1 = x0 + rects[:, 2], y0 + rects[:, 3]
    iw = np.clip(np.minimum(x1[:, None], x1[None]) - np.maximum(x0[:, None], x0[None]), 0, None)
    ih = np.clip(np.minimum(y1[:, None], y1[None]) - np.maximum(y0[:, None], y0[None]), 0, None)
    area = rects[:, 2] * rects[:, 3]
    small = np.minimum(area[:, None], area[None])
    low = np.minimum(rects[:, 3][:, None], rects[:, 3][None])
    # Over each other: most of a glyph covered, or two lines crossing (glyphs of one line share
    # their rows; of two lines, a sliver of rows).
    hit = (iw * ih > small / 2) | ((iw > 1) & (ih > 1) & (ih < 0.6 * low))
    np.fill_diagonal(hit, False)
    return int(hit.sum() // 2)


def _menu_screens():
    """Every menu screen at every scroll position, as MenuViews (a conflict with the longest
    description, a level just clicked while locked)."""
    s = Settings()
    menu = Menu(s, Progress(), load_campaign())
    menu.open("title")
    yield menu.view()
    for screen in ("levels", "settings", "controls"):
        menu.push(screen)
        for first in range(max(1, len(menu.items()) - menu.view().rows + 1)):  # each scroll position
            menu.first[screen] = first
            yield menu.view()
        menu.pop()
    menu.open("pause")
    yield menu.view()
    menu.open("title")
    menu.push("levels")
    menu.click(len(menu.items()) - 3)  # the last level (before the time-trial row and Back): locked
    assert menu.message.startswith("Locked")
    yield menu.view()
    longest = max(ACTIONS, key=lambda a: len(ACTION_DESCRIPTIONS.get(a, "")))
    menu.open("title")
    menu.push("settings")
    menu.push("controls")
    menu.capturing = longest
    yield menu.view()  # waiting for a key
    menu.capture(s.keys_for("move_forward")[0])
    assert menu.screen == "conflict"
    yield menu.view()
    yield complete_screen(menu)


def complete_screen(menu):
    """The level-complete screen with every line it may have (secrets, a ghost beaten)."""
    results = (
        ("Time", "12:41.3", False),
        ("Best time", "12:41.3  new best!", True),
        ("Crystals found", "12/14", False),
        ("Secrets found", "2/3", False),
        ("Deaths", "3", False),
        ("Ghost", "12:43.0  -1.7 s", True),
    )
    menu.open_results(results, "Orthogonal Worlds, and a name long enough to be cut", time_trial=True)
    return menu.view()


@pytest.mark.parametrize("size", SIZES)
def test_every_menu_screen_fits_its_panel(size):
    w, h = size
    seen = 0
    for view in _menu_screens():
        quads = menu_quads(view, w, h)
        g = glyphs(quads)
        assert inside(g, (0, 0, w, h)).all(), f"{view.screen}: text off the screen"
        px, py, pw, ph = _panel(view, w, h)
        in_band = (g[:, 1] >= py) & (g[:, 1] + g[:, 3] <= py + ph)
        assert inside(g[in_band], (px, py, pw, ph)).all(), f"{view.screen}: text overflows the panel"
        for box in menu_layout(view, w, h):
            assert inside(np.array([box.rect], float), (px, py, pw, ph)).all(), f"{view.screen}: a row leaves the panel"
        assert runs_over_each_other(g) == 0, f"{view.screen} (first row {view.first}): text over text"
        assert "{" not in quads_text(quads), f"{view.screen}: a raw placeholder"
        seen += 1
    assert seen > 20


@pytest.mark.parametrize("size", SIZES)
def test_the_warm_up_panel_fits(size):
    from across_dimensions.app.menu import MenuView

    w, h = size
    view = MenuView(
        "title", "ACROSS DIMENSIONS", [], 0, 0, 0, "Esc: back to the title",
        progress=(2, 5, "4D physics: 7 of 19 kernels, 3:05 so far, about 2 min left", 0.45),
    )  # fmt: skip
    quads = menu_quads(view, w, h)
    g = glyphs(quads)
    px, py, pw, ph = _panel(view, w, h)
    band = (g[:, 1] >= py) & (g[:, 1] < py + ph)
    assert band.sum() > 40 and inside(g[band], (px, py, pw, ph)).all()
    assert "kernels" in quads_text(quads)


def _texts(node) -> list[str]:
    """The strings an expression may give: a literal, an f-string (sample words for its fields),
    either side of ``a if c else b``."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.JoinedStr):
        return ["".join(v.value if isinstance(v, ast.Constant) else "Orthogonal Worlds 12" for v in node.values)]
    if isinstance(node, ast.IfExp):
        return _texts(node.body) + _texts(node.orelse)
    return []


def _notices() -> list[str]:
    """Every notice the window says (``say(...)`` in the app)."""
    out = []
    for path in sorted(APP.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "say" and node.args:
                out += _texts(node.args[0])
    return out


def _hints() -> list[str]:
    keys = default_settings()
    return [fill_keys(h.text, keys) for p in level_files() for h in load_level(p).hints]


@pytest.mark.parametrize("size", SIZES)
def test_every_hint_and_notice_fits_its_panel_and_keeps_clear_of_the_other(size):
    w, h = size
    notices = _notices()
    assert len(notices) >= 10
    hints = _hints()
    prompt = "[{move_forward}] [{move_back}] turn yw (0 deg)\nlet go of {manipulate} to release"
    label = ScreenLabel(with_keys(prompt, default_settings()), 0.1, 0.95)
    for i, hint in enumerate(hints):
        hud = Hud(hint=hint, hint_label=f"Hint {i % 5 + 1}/5 \u00b7 H hides", message=notices[i % len(notices)])
        hud.labels = [label]
        quads = hud_quads(hud, w, h)
        g = glyphs(quads)
        hr = hint_rect(hud, w, h)
        assert inside(g[g[:, 1] < hr[1] + hr[3]], hr).all(), f"hint overflows its panel: {hint!r}"
        _, _, band, _ = message_layout(hud, w, h)
        assert inside(np.array([band], float), (0, 0, w, h)).all() and not overlap(band, hr), hud.message
        assert not overlap(label_rect(label, w, h, hr), hr), "the label runs over the hint panel"
        assert "{" not in quads_text(quads), "a raw placeholder on screen"
    for notice in notices:
        hud = Hud(message=notice, w_min=0.0, w_max=0.0)  # only the notice on screen
        quads = hud_quads(hud, w, h)
        _, _, band, _ = message_layout(hud, w, h)
        assert inside(glyphs(quads), band, slack=2).all(), f"a notice overflows its band: {notice!r}"


def test_the_card_and_seek_messages_name_things_in_words():
    keys = default_settings()
    assert all("{" not in fill_keys(t, keys) for t in FLATLAND_LINES)
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game

    game = Game(load_level(Path(__file__).resolve().parents[1] / "levels" / "03_tumbling_hall.toml"))
    assert game.level.seek.enabled
    game.energy.gain(5000)  # the hall starts with an empty bar: seek along w costs energy
    game.step(Actions(presses=Actions.count_presses({"seek": 1})))
    msg = game.frame().hud.message
    assert msg.startswith("Seeking the ") and "body '" not in msg and "(" in msg, msg
