"""The editor's view: ImGui panels over the level seen through the game's renderer.

:class:`EditorView` is a view (:mod:`across_dimensions.app.views`) pushed over the play view it
was opened from: while the editor is open every event comes here (the game is frozen, not
stepped), and leaving it pops the view, so the game resumes exactly where it was. The editor
talks to the play view only through its methods (its eye, its level file, and
:meth:`~across_dimensions.app.views.play.PlayView.play_game` to play an edited level).

Controls (Unity- and Godot-like): hold the right mouse button and drag to
look, W A S D to fly, Space and C up and down, the wheel to move forward;
E and Q (the game's w keys) move the slice along w, as does the scrubber.
Left click selects; the move gizmo's arrows and squares (ImGuizmo) move the
selection along an axis or in a plane, and dragging the selection itself moves
it in the plane facing the camera. Ctrl+Z / Ctrl+Y (or Ctrl+Shift+Z) undo and redo, Ctrl+S saves,
Ctrl+D duplicates, Delete deletes, F frames the selection, P toggles the
frustum projection. The game's ``editor_play_here`` key (F5) plays from the
editor's camera and w; its ``editor`` key (F2) goes back to the game, and
from the game back to the editor.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pyglet
from imgui_bundle import imgui, imguizmo
from imgui_bundle.python_backends import pyglet_backend

from ...core.errors import InputError
from ...game.sim import Game
from ...world import level_group as group
from ...world.level_edit import LevelEditor
from ...world.scene import SectionCache
from ..views.base import View
from . import view
from .checks import Checks
from .files import Files
from .handles import OPERATIONS, Handles
from .panels import PANEL_LEFT, PANEL_W, Panels

FLY_SPEED = 6.0  # metres per second
W_SPEED = 0.6  # slice w per second with the w keys
LOOK_RATE = 0.005  # radians per pixel of right-drag
REBUILD_EVERY = 0.25  # seconds between preview-game rebuilds during a drag (a rebuild is 10-250 ms)
PREVIEW_SIZE = (128, 96)
PREVIEW_OFFSETS = (-2, -1, 0, 1, 2)  # in steps of preview_step
W_MARGIN = 0.5  # the scrubber reaches a little beyond the level's w_range
MENU_BAR = 20  # pixels: ImGui's main menu bar with its default font


class EditorView(View):
    """The level editor for the level file at ``path``, made once per window (it owns the ImGui context)."""

    shows_level = True

    def __init__(self, session, path):
        super().__init__(session)
        window = self.window
        self.play = None  # the play view the editor was opened from
        imgui.create_context()
        imgui.get_io().set_ini_filename("")  # no imgui.ini left in the player's folder
        # Events reach ImGui through this view's handlers (only while the editor is open), not the backend's own.
        self.impl = pyglet_backend.create_renderer(window, attach_callbacks=False)
        self.impl._window = window  # noqa: SLF001 - what attaching would have set; resizing and cursors need it
        self.panels = Panels(self)
        self.handles = Handles(self)
        self.files = Files(self)
        self.checks = Checks(self)
        self.box_select = None  # (start x, y, shift) of a box being drawn with the mouse, top-left origin
        self.sections = SectionCache()  # the preview strip's slices
        self.frustum = False
        self.animate = False
        self.time = 0.0
        self.preview_step = 0.25
        self.preview_rects: list = []
        self.message = ""
        self.held: set = set()
        self.looking = False
        self.dragging = None
        self._built_at = 0.0
        self.open(path)

    # ------------------------------------------------------------ level
    def open(self, path, text: str | None = None) -> None:
        """Edit the level file at ``path``, or (with ``text``) a new level to be saved there."""
        model = LevelEditor(path) if text is None else LevelEditor.new(path, text)
        level, problems = model.check()
        if level is None:
            raise InputError("\n".join(problems))
        self.model = model
        self.preview = Game(level)
        self.drop_gpu_meshes()
        self.sections = SectionCache()
        self._preview_text = self.model.text()
        self._game_text = self._preview_text
        self.cam = view.EditorCamera.at_spawn(level)

    def _refresh_preview(self, now: float) -> None:
        """Rebuild the preview game when the level changed and is valid (not on every step of a drag)."""
        text = self.model.text()
        if text == self._preview_text:
            return
        if imgui.is_any_item_active() and now - self._built_at < REBUILD_EVERY:
            return
        level, _ = self.model.check()
        if level is not None:
            self.preview = Game(level)
            self._preview_text = text
            self._built_at = now
            self.sections = SectionCache()
            self.drop_gpu_meshes()

    def drop_gpu_meshes(self) -> None:
        """Make the renderer upload every mesh anew (a new game reuses the old one's keys and revisions)."""
        self.session.renderer.forget_meshes()

    def w_limits(self) -> tuple[float, float]:
        lo, hi = self.preview.level.w_range
        return lo - W_MARGIN, hi + W_MARGIN

    def key_name(self, action: str) -> str:
        return "/".join(self.session.settings.keys_for(action))

    # ------------------------------------------------------------ switching
    def enter(self, play, from_play: bool = True) -> None:
        """Open the editor over ``play``; from play, the camera starts at the player's eye and w."""
        self.session.recording.stop()  # a replay starts at the spawn and has no edits in it
        self.play = play
        if Path(play.level_path).resolve() != self.model.path.resolve() and not self.model.dirty:
            self.open(play.level_path)
        if from_play:
            self.cam = view.EditorCamera(*play.eye())
        self.window.push_view(self)

    def on_show(self) -> None:
        self.drop_gpu_meshes()  # the game's meshes and the preview game's share keys
        self.window.set_exclusive_mouse(False)
        self.window.set_caption(f"Across Dimensions - editing {self.model.path.name}")

    def leave(self) -> None:
        """Back to the play view (its own :meth:`on_show` takes the mouse and the caption back)."""
        self.drop_gpu_meshes()
        self.held.clear()
        self.window.pop_view()

    def _new_game(self, cam=None):
        level, problems = self.model.check()
        if level is None:
            self.message = f"cannot play: {len(problems)} problem(s) in the level"
            return None
        self._game_text = self.model.text()
        return view.game_at(level, cam, seed=self.session.seed)

    def play_from_here(self) -> None:
        """Drop the player into the edited level at the editor camera's place, heading and w."""
        game = self._new_game(self.cam)
        if game is not None:
            self._start(game, f"Playing from the editor's camera - {self.key_name('editor')} returns to the editor")

    def back_to_game(self) -> None:
        """Back to the game as it was, or the edited level from its spawn if it changed since."""
        if self.model.text() != self._game_text:
            game = self._new_game()
            if game is None:
                return
            self._start(game, "Playing the edited level from its spawn")
        else:
            self.leave()

    def _start(self, game, notice: str) -> None:
        self.play.play_game(game, notice, self.model.path)
        self.leave()

    def play_and_record(self) -> None:
        """Save the level and play it from its spawn, recording a replay (the record key stops it)."""
        if not self.save():
            return
        self._game_text = self.model.text()
        self.play.play_game(view.game_at(self.preview.level), "", self.model.path)
        self.play.start_recording()
        self.play.from_editor = True  # the level's end comes back here, with the replay saved
        self.session.say(f"Recording a replay of {self.model.path.name} - {self.key_name('record')} stops it", 6.0)
        self.leave()

    # ------------------------------------------------------------ commands
    def save(self) -> bool:
        """Save the level where it is; True when it was (a level with problems is not)."""
        try:
            path = self.model.save()
        except (InputError, OSError) as e:
            self.message = f"not saved: {len(getattr(e, 'problems', [1]))} problem(s)"
            return False
        self.files.remember(path)
        self.message = f"saved {path.name}"
        return True

    def revert(self) -> None:
        self.open(self.model.path)
        self.message = "reverted to the saved file"

    def undo(self) -> None:
        label = self.model.undo()
        self.message = f"undid {label}" if label else "nothing to undo"

    def redo(self) -> None:
        label = self.model.redo()
        self.message = f"redid {label}" if label else "nothing to redo"

    def add(self, kind: str, parent=None) -> None:
        """A new entry a few metres in front of the camera, at the slice's w."""
        spot = self.cam.position + 4.0 * self.cam.camera3().forward()
        spot = [round(float(x), 2) for x in spot]
        values = {}
        if kind in ("object", "crystal"):
            values["position"] = [*spot, round(float(self.cam.w), 3)]
        elif kind == "box":
            values["center"] = spot
        elif kind == "mesh":
            values["position"] = spot
        elif kind == "world":
            values["w"] = round(float(self.cam.w), 3)
            self.model.add(kind, values)
            self.model.set(self.model.selection + ("box", 0), "center", spot)
            self.model.seal()
            return
        self.model.add(kind, values, parent=parent)

    def entries_selected(self) -> list:
        """The selected entries that can be deleted, copied and duplicated (not ``[spawn]`` and the like)."""
        return [r for r in self.model.selected if len(r) >= 2 and self.model.exists(r)]

    def delete(self) -> None:
        if self.entries_selected():
            group.delete(self.model, self.entries_selected())

    def duplicate(self) -> None:
        if self.entries_selected():
            group.duplicate(self.model, self.entries_selected())

    def copy(self) -> None:
        """The selected entries to the system clipboard, as TOML (another level can paste them)."""
        refs = self.entries_selected()
        if refs:
            self.window.set_clipboard_text(group.copy_text(self.model, refs))
            self.message = f"copied {len(refs)} entr{'y' if len(refs) == 1 else 'ies'}"

    def paste(self) -> None:
        """The clipboard's entries, added to this level (boxes and meshes into the selected world)."""
        sel = self.model.selection
        world = sel[:2] if sel is not None and sel[0] == "world" else None
        try:
            new = group.paste(self.model, self.window.get_clipboard_text() or "", world=world)
        except ValueError as e:
            new, self.message = [], str(e)
        if new:
            self.message = f"pasted {len(new)} entr{'y' if len(new) == 1 else 'ies'}"

    def focus(self) -> None:
        """Put the camera in front of the selection, looking at it, at its w."""
        c, r = self._selection_center()
        if c is None:
            return
        f = self.cam.camera3().forward()
        self.cam.position = c[:3] - max(3.0 * r, 2.0) * f
        if len(c) == 4:
            self.cam.w = float(c[3])

    def _selection_center(self):
        sel = self.model.selection
        if sel is None:
            return None, 0.0
        box = view.entry_box(self.preview.level, sel)
        if box is not None:
            lo, hi = box
            return (lo + hi) / 2, float(np.linalg.norm(hi - lo) / 2)
        e = view.entity_of(self.preview, sel)
        if e is not None:
            return e.center(self.preview), e.radius
        if sel[0] == "world" and sel[1] < len(self.preview.level.worlds):
            spec = self.preview.level.worlds[sel[1]]
            if spec.boxes:
                return np.array([*spec.boxes[0].center, spec.w]), float(np.linalg.norm(spec.boxes[0].size) / 2)
        return None, 0.0

    # ------------------------------------------------------------ events
    def _ndc(self, x, y):
        ww, wh = self.window.get_size()
        return 2.0 * x / ww - 1.0, 2.0 * y / wh - 1.0, ww / max(wh, 1)

    def on_key_press(self, symbol, modifiers):
        self.impl.on_key_press(symbol, modifiers)
        key = pyglet.window.key
        ctrl = modifiers & (key.MOD_CTRL | key.MOD_COMMAND)
        io = imgui.get_io()
        if io.want_text_input and not (ctrl and symbol == key.S):
            return  # typing in a field: its keys (Ctrl+C, Ctrl+V, letters) are the field's
        action = self.session.bindings.action_of("key", symbol)
        self.held.add(symbol)
        if ctrl and self._ctrl_key(symbol, modifiers & key.MOD_SHIFT):
            pass
        elif action == "editor":
            self.back_to_game()
        elif action == "editor_play_here":
            self.play_from_here()
        elif self.window_key(action):
            pass
        elif symbol == key.DELETE:
            self.delete()
        elif symbol == key.F:
            self.focus()
        elif symbol == key.P:
            self.frustum = not self.frustum
        elif symbol == key.G:
            self.handles.snapping = not self.handles.snapping
            self.message = f"snapping {'on' if self.handles.snapping else 'off'}"
        elif symbol in (key._1, key._2, key._3):
            self.handles.operation = OPERATIONS[symbol - key._1]

    def _ctrl_key(self, symbol, shift) -> bool:
        """The Ctrl shortcuts (Undo, Save, Copy...); True when ``symbol`` was one."""
        key = pyglet.window.key
        do = {
            key.Z: self.redo if shift else self.undo,
            key.Y: self.redo,
            key.S: self.files.save_as if shift else self.save,
            key.D: self.duplicate,
            key.C: self.copy,
            key.V: self.paste,
            key.N: self.files.ask_new,
            key.O: self.files.ask_open,
        }.get(symbol)
        if do is None:
            return False
        do()
        return True

    def on_key_release(self, symbol, modifiers):
        self.impl.on_key_release(symbol, modifiers)
        self.held.discard(symbol)

    def on_text(self, text):
        self.impl.on_text(text)

    def on_mouse_motion(self, x, y, dx, dy):
        self.impl.on_mouse_motion(x, y, dx, dy)

    def on_mouse_press(self, x, y, button, modifiers):
        self.impl.on_mouse_press(x, y, button, modifiers)
        top = self.window.get_size()[1] - y  # ImGui counts from the top
        if self.panels.covers(x, top) or (button == pyglet.window.mouse.LEFT and self.handles.grab(x, top)):
            return  # a panel has it (also a quick click the panels had no frame to see), or a w handle
        if imgui.get_io().want_capture_mouse or imguizmo.im_guizmo.is_over():
            return  # ImGuizmo's handles
        if button == pyglet.window.mouse.RIGHT:
            self.looking = True
        elif button == pyglet.window.mouse.LEFT:
            shift = bool(modifiers & pyglet.window.key.MOD_SHIFT)
            nx, ny, aspect = self._ndc(x, y)
            hit = view.pick(self.preview, self.cam, nx, ny, aspect, self.model.entries())
            if hit is None:
                self.box_select = (x, top, shift)
                if not shift:
                    self.model.selection = None
            elif shift:
                self.model.select(hit, toggle=True)
            else:
                if hit in self.model.selected:
                    self._start_drag(hit, nx, ny, aspect)
                else:
                    self.model.select(hit)

    def on_mouse_release(self, x, y, button, modifiers):
        self.impl.on_mouse_release(x, y, button, modifiers)
        if button == pyglet.window.mouse.RIGHT:
            self.looking = False
        if button == pyglet.window.mouse.LEFT and self.box_select is not None:
            x0, y0, shift = self.box_select
            self.box_select = None
            top = self.window.get_size()[1] - y
            if abs(x - x0) > 3 and abs(top - y0) > 3:
                self._select_in_box(x0, y0, x, top, shift)
        if button == pyglet.window.mouse.LEFT and (self.dragging is not None or self.handles.release()):
            self.dragging = None
            self.model.seal()

    def _select_in_box(self, x0, y0, x1, y1, add: bool) -> None:
        """Select every entry whose place is inside the box drawn (pixels, top-left origin)."""
        ww, wh = self.window.get_size()
        cam = self.cam.camera3()
        m = cam.projection_matrix(ww / max(wh, 1)) @ cam.view_matrix()
        lo, hi = np.minimum([x0, y0], [x1, y1]), np.maximum([x0, y0], [x1, y1])
        found = [] if not add else list(self.model.selected)
        for ref in self.model.entries():
            p = group.place_of(self.model, ref)
            if p is None or ref in found:
                continue
            c = m @ np.array([*p[:3], 1.0])
            if c[3] <= 0:
                continue
            s = np.array([(c[0] / c[3] + 1) * ww / 2, (1 - c[1] / c[3]) * wh / 2])
            if np.all(s >= lo) and np.all(s <= hi):
                found.append(ref)
        self.model.selected = found
        self.message = f"{len(found)} selected"

    def on_mouse_drag(self, x, y, dx, dy, buttons, modifiers):
        self.impl.on_mouse_drag(x, y, dx, dy, buttons, modifiers)
        if self.looking:
            self.cam.look(dx * LOOK_RATE, dy * LOOK_RATE)
        elif self.handles.busy:
            self.handles.drag(x, self.window.get_size()[1] - y)
        elif self.dragging is not None:
            self._drag(*self._ndc(x, y))

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y):
        self.impl.on_mouse_scroll(x, y, scroll_x, scroll_y)
        if not imgui.get_io().want_capture_mouse:
            self.cam.fly(float(scroll_y), 0.0, 0.0, 1.0)

    def on_resize(self, width, height):
        self.impl.on_resize(width, height)  # and the window's own handler runs too

    def on_close(self) -> bool:
        """Closing the window with unsaved changes asks first (Save, Discard or Cancel)."""
        keep_open = self.files.confirm_close()
        if not keep_open:
            self.checks.stop()  # no check-level or probe left running after the window
        return keep_open

    # ------------------------------------------------------------ dragging (the move gizmo)
    def _start_drag(self, ref, nx, ny, aspect) -> None:
        """Dragging the selection itself moves it in the plane facing the camera."""
        refs = list(self.model.selected)
        c = group.pivot(self.model, refs)
        if c is None:
            return
        o, d = view.ray(self.cam, nx, ny, aspect)
        normal = self.cam.camera3().forward()
        hit = _plane_hit(o, d, c[:3], normal)
        if hit is not None:
            self.dragging = (refs, self.model.text(), c[:3].copy(), normal, hit)

    def _drag(self, nx, ny, aspect) -> None:
        refs, before, point, normal, start_hit = self.dragging
        o, d = view.ray(self.cam, nx, ny, aspect)
        hit = _plane_hit(o, d, point, normal)
        if hit is None:
            return
        self.model.restore_text(before)  # the whole drag is redone from its start (snapping)
        grid = self.handles.steps()[0]
        group.move(self.model, refs, [*(hit - start_hit), 0.0], grid=grid, merge=True)

    # ------------------------------------------------------------ drawing
    def _fly(self, dt: float) -> None:
        k = pyglet.window.key
        if imgui.get_io().want_text_input:  # typing in a field, not flying
            return
        axis = lambda pos, neg: float(pos in self.held) - float(neg in self.held)  # noqa: E731
        f, r, u = axis(k.W, k.S), axis(k.D, k.A), axis(k.SPACE, k.C)
        if f or r or u:
            self.cam.fly(f, r, u, FLY_SPEED * dt)
        keys = self.session.bindings.keys_of
        dw = float(any(s in keys("w_ana") for s in self.held)) - float(any(s in keys("w_kata") for s in self.held))
        if dw:
            lo, hi = self.w_limits()
            self.cam.w = float(np.clip(self.cam.w + dw * W_SPEED * dt, lo, hi))

    def draw_scene(self, viewport) -> None:
        """The level from the editor camera, and the strip of previews of the selection along w."""
        r = self.session.renderer
        frame = view.editor_frame(self.preview, self.cam, self.model.selection, self.frustum, self.time)
        r.draw(frame, viewport, hud=False, view="main")  # the game's HUD would sit under the panels
        self.preview_rects = []
        sel = self.model.selection
        if not self.panels.show_previews or sel is None:
            return
        offsets = [k * self.preview_step for k in PREVIEW_OFFSETS]
        frames = view.preview_frames(self.preview, sel, self.cam.w, offsets, self.sections, self.time)
        x0, y0, vw, vh = viewport
        pw, ph = PREVIEW_SIZE
        # Centred between the outline and the inspector (the panels' default places).
        free_left, free_right = x0 + PANEL_LEFT, x0 + vw - PANEL_W
        left = max(x0, (free_left + free_right - len(frames) * (pw + 6)) // 2)
        for k, (w, f) in enumerate(frames):
            rect = (left + k * (pw + 6), y0 + vh - MENU_BAR - 4 - ph, pw, ph)  # along the top of the view
            r.draw(f, rect, hud=False, view=f"preview{k}")
            self.preview_rects.append((rect, w))

    def draw_gui(self) -> None:
        self.impl.process_inputs()
        imgui.new_frame()
        ww, wh = self.window.get_size()
        self.panels.draw(ww, wh)
        if self.box_select is not None:
            x0, y0, _ = self.box_select
            mx, my = imgui.get_mouse_pos()
            color = imgui.color_convert_float4_to_u32(imgui.ImVec4(1.0, 0.85, 0.1, 1.0))
            imgui.get_foreground_draw_list().add_rect(imgui.ImVec2(x0, y0), imgui.ImVec2(mx, my), color)
        imgui.render()
        self.impl.render(imgui.get_draw_data())

    def on_update(self, dt: float) -> None:
        dt = min(dt, 0.1)
        self._fly(dt)
        if self.animate:
            self.time = (self.time + dt) % 60.0
        self._refresh_preview(time.perf_counter())

    def on_draw(self, target, viewport) -> None:
        """The scene and the panels; ImGui draws into the framebuffer bound, ``target``."""
        target.use()
        self.draw_scene(viewport)
        self.draw_gui()

    def on_screenshot(self, path) -> None:
        self.message = f"screenshot saved: {path}"


def _plane_hit(o, d, point, normal):
    """Where the ray ``o + t d`` meets the plane through ``point`` with ``normal``, or None."""
    den = float(d @ normal)
    if abs(den) < 1e-6:  # the ray runs along the plane: no single point to move to
        return None
    t = float((point - o) @ normal) / den
    return o + t * d if t > 0 else None
