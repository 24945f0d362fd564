"""A new level made in the editor's window (under Xvfb): from the template, with the handles, snapping,
copy and paste, saved; the saved file passes check-level and the design probe, and plays to its goal.

The window runs in a child process (its own X connection, its own ImGui context); the test drives it
as a user would, through the window's own event handlers (key presses, mouse presses and drags at the
pixels where the handles are drawn), one drawn frame between events as in the real loop.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import xvfb_display

from across_dimensions.app.editor import missing

REPO = Path(__file__).resolve().parents[1]
TIMEOUT = 900


def _frames(w, n: int = 2) -> None:
    for _ in range(n):
        w.switch_to()
        w.dispatch_events()
        w.update(1 / 60)  # what the window's draw pass does first (it skips a still view's redraws)
        w.on_draw()
        w.flip()


def _build(out: str) -> None:
    """In the child: make ``out`` in the editor's window; print the checks made along the way as JSON."""
    from pyglet.window import key, mouse

    from across_dimensions.app.editor.handles import W_BAR, W_RINGS
    from across_dimensions.app.session import Start
    from across_dimensions.app.settings import Settings
    from across_dimensions.app.window import GameWindow
    from across_dimensions.world.resources import levels_dir

    w = GameWindow(Settings(), Start(levels_dir() / "00_arrival.toml", edit=True))
    bar, ring = W_BAR[0], W_RINGS[0][1]  # the w handle's offset, the xw ring's radius (pixels)
    ed = w.session.editor
    _frames(w)
    h = w.get_size()[1]
    said = {}

    def press(symbol, mods=0):
        w.on_key_press(symbol, mods)
        w.on_key_release(symbol, mods)
        _frames(w)

    def drag(x0, y0, x1, y1, steps=6):
        """A left drag from ``(x0, y0)`` to ``(x1, y1)``, pixels from the top left."""
        w.on_mouse_motion(x0, h - y0, 0, 0)
        _frames(w, 1)
        w.on_mouse_press(x0, h - y0, mouse.LEFT, 0)
        _frames(w, 1)
        for k in range(1, steps + 1):
            x, y = x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps
            w.on_mouse_drag(x, h - y, (x1 - x0) / steps, -(y1 - y0) / steps, mouse.LEFT, 0)
            _frames(w, 1)
        w.on_mouse_release(x1, h - y1, mouse.LEFT, 0)
        _frames(w, 1)

    # File > New (Ctrl+N): the dialog, filled in, and Enter creates the level from the template.
    press(key.N, key.MOD_CTRL)
    ed.files.path_text, ed.files.name_text = out, "Wall at w one"
    _frames(w)
    press(key.ENTER)
    m = ed.model
    said["new"] = [str(m.path), m.get(("level",), "name"), m.dirty]
    # A world with a wall across the room at w = 1, through the model (the inspector's path).
    ed.add("world")
    world = m.selection
    m.set(world, "name", "blue")
    m.set(world, "w", 1.0)
    m.set(world, "depth", 0.8)
    m.set(world + ("box", 0), "center", [0.0, 2.0, 0.0])
    m.set(world + ("box", 0), "size", [10.0, 4.0, 0.5])
    # A crystal in front of the camera, then snapping on (G) and the w handle dragged up 1.03 m of w.
    ed.cam.position[:] = [0.0, 3.0, -4.0]
    ed.cam.yaw, ed.cam.pitch, ed.cam.w = 0.0, -0.3, 0.0
    ed.add("crystal")
    crystal = m.selection
    press(key.G)
    _frames(w)
    sx, sy = ed.handles.screen_center
    drag(sx + bar, sy, sx + bar, sy - 103)
    said["w_handle"] = m.get(crystal, "position")[3]
    # Dragging the selection itself moves it in the plane facing the camera, on the 0.25 m grid.
    _frames(w)
    sx, sy = ed.handles.screen_center
    ed.cam.w = 1.0  # the crystal is picked where its section is: at its w
    _frames(w)
    drag(sx, sy, sx + 37, sy + 11)
    said["moved"] = m.get(crystal, "position")
    # The move handle's x arrow (ImGuizmo's): dragged right, the crystal moves along x only, on the grid.
    _frames(w)
    sx, sy = ed.handles.screen_center
    drag(sx + 45, sy, sx + 125, sy, steps=10)
    said["arrow"] = [said["moved"], m.get(crystal, "position")]
    # A 4D object, turned on the xw ring (rotate handle: 2) by a snapped quarter turn, and its
    # hyper-depth doubled on the scale handle (3).
    ed.add("object", parent=None)
    obj = m.selection
    m.set(obj, "position", [0.0, 1.0, 2.0, 0.0])
    ed.cam.w = 0.0
    press(key._2)
    sx, sy = ed.handles.screen_center
    drag(sx + ring, sy, sx, sy + ring, steps=12)
    said["rotation"] = m.get(obj, "rotation")
    press(key._3)
    sx, sy = ed.handles.screen_center
    drag(sx, sy + bar, sx + 69.3, sy + bar)  # exp(0.693) = 2
    said["scale"] = m.get(obj, "scale")
    press(key._1)
    # Copy the crystal and paste it back (the system clipboard), then undo the paste: one step.
    m.select(crystal)
    press(key.C, key.MOD_CTRL)
    said["clipboard"] = w.get_clipboard_text()
    press(key.V, key.MOD_CTRL)
    said["pasted"] = [list(r) for r in m.selected]
    press(key.Z, key.MOD_CTRL)
    said["after_undo"] = len(m.doc["crystal"])
    press(key.V, key.MOD_CTRL)
    m.set(m.selection, "position", [3.0, 1.0, 4.0, 0.0])  # the copy, moved out from behind the wall
    # Shift-click in the Level list is the model's select(toggle=True); box select with a drag.
    m.selection = None
    drag(300, 100, 1000, 600)
    said["box_selected"] = len(m.selected)
    # A quick click on a panel (pressed and released with no frame between, as at a low frame rate)
    # never reaches the view: the selection stays.
    m.select(crystal)
    w.on_mouse_motion(600, h - 400, 0, 0)  # the last frame saw the mouse over the view
    _frames(w)
    w.on_mouse_press(1100, h - 500, mouse.LEFT, 0)  # on the inspector, below its fields
    w.on_mouse_release(1100, h - 500, mouse.LEFT, 0)
    _frames(w)
    said["panel_click"] = list(m.selection or [])
    press(key.S, key.MOD_CTRL)
    said["saved"] = [not m.dirty, ed.message]
    from across_dimensions.app.editor.files import load_recent

    said["recent"] = load_recent()[0]
    # Unsaved changes: New and closing the window ask first (the prompt holds what comes next).
    m.set(("level",), "description", "changed")
    press(key.N, key.MOD_CTRL)
    said["asks"] = [ed.files.pending is not None, w.current_view.on_close()]
    ed.files.pending = None
    said["rects"] = len(ed.panels.rects)
    print(json.dumps(said))
    w.close()


class _Compiling:
    """A kernel warm-up that has not finished (as :class:`~across_dimensions.app.warmup.BackgroundWarmUp`)."""

    ready, done, total, label, seconds, error = False, 2, 5, "4D physics", None, None

    def status(self, now: float | None = None) -> str:
        return f"{self.label}, 12 of 40 kernels, 0:07 so far"

    def fraction(self) -> float:
        return self.done / self.total

    def start_once(self) -> None:
        pass


def _startup() -> None:
    """In the child: ``edit LEVEL`` while the kernels compile shows the start-up view at once, then the editor."""
    from across_dimensions.app.editor.mode import EditorView
    from across_dimensions.app.session import Start
    from across_dimensions.app.settings import Settings
    from across_dimensions.app.views.startup import StartupView
    from across_dimensions.app.window import GameWindow
    from across_dimensions.world.resources import levels_dir

    warm = _Compiling()
    w = GameWindow(Settings(), Start(levels_dir() / "00_arrival.toml", edit=True, warm_first=True, warm=warm))
    _frames(w)
    first = type(w.current_view)
    warm.ready = True
    _frames(w)
    print(json.dumps([first is StartupView, isinstance(w.current_view, EditorView)]))
    w.close()


@pytest.fixture(scope="module")
def xvfb():
    if missing():
        pytest.skip(f"the editor extra is not installed ({', '.join(missing())})")
    with xvfb_display(78, "ACROSS_DIMENSIONS_EDITOR_NEW_DISPLAY") as display:
        yield display


def _run(env, *args):
    return subprocess.run(
        [sys.executable, "-m", "across_dimensions", *args], capture_output=True, text=True, timeout=TIMEOUT, env=env
    )


def _child(xvfb, name: str, *args) -> list | dict:
    env = dict(os.environ, DISPLAY=xvfb, PYTHONPATH=os.pathsep.join([str(REPO), str(REPO / "tests")]))
    env.setdefault("NUMBA_CACHE_DIR", str(REPO / ".numba_cache"))
    code = f"import runpy; runpy.run_path({__file__!r})[{name!r}](*{list(args)!r})"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=TIMEOUT, env=env)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_the_editor_window_shows_the_start_up_progress_while_kernels_compile(xvfb):
    assert _child(xvfb, "_startup") == [True, True]


@pytest.mark.slow
def test_a_new_level_made_in_the_window_checks_probes_and_plays(xvfb, tmp_path):
    out = tmp_path / "wall_w1.toml"
    said = _child(xvfb, "_build", str(out))
    env = dict(os.environ, PYTHONPATH=str(REPO))
    env.setdefault("NUMBA_CACHE_DIR", str(REPO / ".numba_cache"))
    assert said["new"] == [str(out), "Wall at w one", True]
    assert said["w_handle"] == pytest.approx(1.0)  # 103 px * 0.01 = 1.03, on the 0.1 w step
    x, y, z, wv = said["moved"]
    assert all(abs(v / 0.25 - round(v / 0.25)) < 1e-9 for v in (x, y, z)) and wv == pytest.approx(1.0)
    before, after = said["arrow"]
    assert after[0] > before[0] and after[1:] == before[1:] and abs(after[0] / 0.25 - round(after[0] / 0.25)) < 1e-9
    assert said["rotation"] == {"xw": 90.0} or said["rotation"] == {"xw": -90.0}
    assert said["scale"] == [1.0, 1.0, 1.0, 2.0]
    assert "[[crystal]]" in said["clipboard"] and said["pasted"] == [["crystal", 1]] and said["after_undo"] == 1
    assert said["box_selected"] >= 2
    assert said["panel_click"] == ["crystal", 0]
    assert said["saved"][0], said
    assert said["recent"] == str(out.resolve()) and said["asks"] == [True, True]
    text = out.read_text(encoding="utf-8")
    assert "  [[world.box]]\n  center = [0.0, 2.0, 0.0]\n  size = [10.0, 4.0, 0.5]" in text
    # The saved file: check-level, the probe, and a walk from the spawn to the goal at w = 0.
    r = _run(env, "check-level", str(out))
    assert r.returncode == 0 and ": ok - 'Wall at w one'" in r.stdout, r.stdout + r.stderr
    r = _run(env, "probe", str(out), "--json", "--workers", "1")
    assert r.returncode == 0, r.stdout + r.stderr
    row = json.loads(r.stdout.strip().splitlines()[-1])[0]
    assert row["bypasses"] == [] and row["softlocks"] == []
    from across_dimensions.game.actions import Actions
    from across_dimensions.game.sim import Game
    from across_dimensions.world.level import load_level

    game = Game(load_level(out))
    for _ in range(60 * 20):
        game.step(Actions(forward=1.0))
        if game.outcome == "complete":
            break
    assert game.outcome == "complete"
