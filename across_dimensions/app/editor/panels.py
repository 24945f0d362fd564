"""The editor's Dear ImGui panels: menus, the level outline, the inspector and the w scrubber.

Every widget edits through the model (:class:`~across_dimensions.world.level_edit.LevelEditor`),
so each change is an undoable command and is checked by the level loader; the
loader's problems about a field are shown in red under it. One drag of a
widget is one undo step (the model merges changes of one field until the
widget is released).

The inspector is generic: it shows each field of the selected table by its
model's :class:`~across_dimensions.world.fields.Field` kind, so a table another
part of the game adds to the format (enemies, targets) is editable with no code here.
"""

from __future__ import annotations

import math

from imgui_bundle import imgui

from ...core.transform import PLANES
from ...world.fields import REQUIRED
from ...world.level import MODELS
from ...world.level_edit import SINGLE_TABLES, WORLD_CHILDREN, model_of
from .handles import OPERATIONS

RED = imgui.ImVec4(1.0, 0.4, 0.35, 1.0)
GREY = imgui.ImVec4(0.6, 0.6, 0.65, 1.0)
YELLOW = imgui.ImVec4(1.0, 0.85, 0.3, 1.0)
#: The Add menu: every array of tables of the format (tables the game's systems add appear by themselves).
ADDABLE = tuple(k for k in MODELS if k not in SINGLE_TABLES)
PANEL_W = 330  # the inspector's width
PANEL_LEFT = 250  # the outline's width
MENU_BAR = 20  # pixels: ImGui's main menu bar with its default font


def _short(problem: str, ref_where: str) -> str:
    """A loader problem without its file and entry prefix (they are where it is shown)."""
    parts = problem.split(": ", 2)
    return parts[2] if len(parts) == 3 else problem


class Panels:
    """Draws the panels for an :class:`~.mode.EditorView` and applies what the user does to its model."""

    def __init__(self, mode):
        self.mode = mode
        self.show_previews = True
        self.search = ""
        self.rects: list = []  # (x, y, w, h) of every panel drawn last frame, top-left origin

    @property
    def model(self):
        return self.mode.model

    # ------------------------------------------------------------ frame
    def draw(self, width: int, height: int) -> None:
        self.mode.handles.draw(width, height)
        self.rects = [(0.0, 0.0, float(width), float(MENU_BAR))]
        self.menu_bar()
        self.outline(height)
        self.inspector(width, height)
        self.scrubber(width, height)
        self.mode.checks.panel(width, height)
        self.mode.files.draw()
        self.status(width, height)

    def track(self) -> None:
        """Keep the current panel's rectangle (call before ``imgui.end``): a click there is the panel's."""
        p, z = imgui.get_window_pos(), imgui.get_window_size()
        self.rects.append((p.x, p.y, z.x, z.y))

    def covers(self, x: float, y: float) -> bool:
        """Is ``(x, y)`` (pixels, top-left origin) on a panel, a menu or a dialog of the last frame?"""
        if imgui.is_popup_open("", imgui.PopupFlags_.any_popup_id | imgui.PopupFlags_.any_popup_level):
            return True
        return any(rx <= x <= rx + rw and ry <= y <= ry + rh for rx, ry, rw, rh in self.rects)

    def _edited(self, ref, key, value) -> None:
        """A widget changed ``key``: one step per drag (sealed when the widget is released)."""
        self.model.set(ref, key, value, merge=True)

    def _after_widget(self) -> None:
        if imgui.is_item_deactivated_after_edit():
            self.model.seal()

    # ------------------------------------------------------------ menus
    def menu_bar(self) -> None:
        m, mode = self.model, self.mode
        if not imgui.begin_main_menu_bar():
            return
        if imgui.begin_menu("File"):
            mode.files.menu()
            imgui.end_menu()
        if imgui.begin_menu("Edit"):
            if imgui.menu_item(
                "Undo " + (m.undo_stack[-1].label if m.undo_stack else ""), "Ctrl+Z", False, bool(m.undo_stack)
            )[0]:
                mode.undo()
            if imgui.menu_item(
                "Redo " + (m.redo_stack[-1].label if m.redo_stack else ""), "Ctrl+Y", False, bool(m.redo_stack)
            )[0]:
                mode.redo()
            sel, some = m.selection, bool(mode.entries_selected())
            if imgui.menu_item("Copy", "Ctrl+C", False, some)[0]:
                mode.copy()
            if imgui.menu_item("Paste", "Ctrl+V", False)[0]:
                mode.paste()
            if imgui.menu_item("Duplicate", "Ctrl+D", False, some)[0]:
                mode.duplicate()
            if imgui.menu_item("Delete", "Delete", False, some)[0]:
                mode.delete()
            if imgui.menu_item("Frame selected", "F", False, sel is not None)[0]:
                mode.focus()
            imgui.end_menu()
        if imgui.begin_menu("Add"):
            for kind in ADDABLE:
                if imgui.menu_item(kind, "", False)[0]:
                    mode.add(kind)
            world = m.selection[:2] if m.selection and m.selection[0] == "world" else None
            for child in WORLD_CHILDREN:
                if imgui.menu_item(f"{child} in the selected world", "", False, world is not None)[0]:
                    mode.add(child, parent=world)
            imgui.end_menu()
        if imgui.begin_menu("View"):
            mode.frustum = imgui.menu_item("Frustum projection", "P", mode.frustum)[1]
            self.show_previews = imgui.menu_item("Previews along w", "", self.show_previews)[1]
            mode.animate = imgui.menu_item("Animate spin", "", mode.animate)[1]
            imgui.end_menu()
        if imgui.begin_menu("Play"):
            if imgui.menu_item("Play from here", mode.key_name("editor_play_here"), False)[0]:
                mode.play_from_here()
            if imgui.menu_item("Save, play from the spawn and record a replay", "", False)[0]:
                mode.play_and_record()
            if imgui.menu_item("Back to the game", mode.key_name("editor"), False)[0]:
                mode.back_to_game()
            imgui.end_menu()
        self.tools()
        imgui.end_main_menu_bar()

    def tools(self) -> None:
        """The handle in use (1 2 3) and snapping (G), in the menu bar."""
        h = self.mode.handles
        imgui.separator()
        for k, op in enumerate(OPERATIONS):
            if imgui.radio_button(f"{op} ({k + 1})", h.operation == op):
                h.operation = op
        imgui.separator()
        _, h.snapping = imgui.checkbox("snap (G)", h.snapping)
        if imgui.is_item_hovered():
            imgui.set_tooltip(f"grid {h.grid} m, {h.angle_step:g} degrees, w {h.w_step}")

    # ------------------------------------------------------------ outline
    def outline(self, height: int) -> None:
        m = self.model
        imgui.set_next_window_pos(imgui.ImVec2(0, 20), imgui.Cond_.first_use_ever)
        imgui.set_next_window_size(imgui.ImVec2(PANEL_LEFT, min(height - 150, 520)), imgui.Cond_.first_use_ever)
        imgui.begin("Level")
        imgui.push_item_width(-1)
        _, self.search = imgui.input_text_with_hint("##search", "search / filter", self.search)
        imgui.pop_item_width()
        bad = {tuple(r) for r in m.entries() if m.problems_for(r)} if m.problems else set()
        flagged = self.mode.checks.flagged()
        for ref in m.entries():
            label = m.label(ref)
            if self.search and self.search.lower() not in label.lower():
                continue
            bad_here = ref in bad or ref in flagged
            if bad_here:
                imgui.push_style_color(imgui.Col_.text, RED)
            clicked, _ = imgui.selectable(f"{_fit(label)}##{ref}", ref in m.selected)
            if bad_here:
                imgui.pop_style_color()
            if clicked:
                m.select(ref, toggle=imgui.get_io().key_shift)
            if imgui.is_item_hovered():
                imgui.set_tooltip(label.strip())
                if imgui.is_mouse_double_clicked(0):
                    self.mode.focus()
        self.track()
        imgui.end()

    # ------------------------------------------------------------ inspector
    def inspector(self, width: int, height: int) -> None:
        m = self.model
        imgui.set_next_window_pos(imgui.ImVec2(width - PANEL_W, 20), imgui.Cond_.first_use_ever)
        imgui.set_next_window_size(imgui.ImVec2(PANEL_W, height - 170), imgui.Cond_.first_use_ever)
        imgui.begin("Inspector")
        ref = m.selection
        if ref is None or not m.exists(ref):
            imgui.text_wrapped("Click something in the view, or pick an entry in the Level list.")
            self.track()
            imgui.end()
            return
        imgui.text_colored(YELLOW, m.label(ref).strip())
        if len(m.selected) > 1:
            imgui.text_colored(GREY, f"and {len(m.selected) - 1} more selected (the handles move them all)")
        # Room for the longest label ("position w", "rotation xw", "params radius"...) inside the panel.
        names = [f"{k} xw" for k in model_of(ref)] + ["hyper-depth"]
        longest = max(imgui.calc_text_size(n).x for n in names) + imgui.get_frame_height()  # and its "x"
        imgui.push_item_width(-min(longest + 12, PANEL_W / 2))
        table = m.table(ref)
        for key, f in model_of(ref).items():
            if f.kind == "tables":
                continue
            if ref[0] == "object" and key in ("shape", "asset", "depth", "params"):
                uses = "asset" if "asset" in table else "shape"
                if key != uses and (key != "depth" or uses != "asset") and (key != "params" or uses != "shape"):
                    continue  # a 4D object is a shape or a lifted asset: only its own fields
            imgui.push_id(key)
            self.field(ref, key, f)
            for p in m.problems_for(ref, key):
                imgui.push_text_wrap_pos(0.0)
                imgui.text_colored(RED, _short(p, m.where(ref)))
                imgui.pop_text_wrap_pos()
            imgui.pop_id()
        imgui.pop_item_width()
        others = [p for p in m.problems_for(ref) if not any(f"'{k}" in p for k in model_of(ref))]
        for p in others:
            imgui.push_text_wrap_pos(0.0)
            imgui.text_colored(RED, _short(p, m.where(ref)))
            imgui.pop_text_wrap_pos()
        self.track()
        imgui.end()

    def field(self, ref, key: str, f) -> None:
        """One field's widget(s), by its model's kind."""
        m = self.model
        written = key in m.table(ref)
        value = m.value(ref, key)
        if not written:
            imgui.push_style_color(imgui.Col_.text, GREY)  # shows the default; editing writes it
        kind = f.kind
        if kind == "number" and isinstance(value, int) and not isinstance(value, bool):
            changed, n = imgui.drag_int(key, value, 0.05)  # written as a whole number (format = 2): keep it one
            self._after_widget()
            if changed:
                self._edited(ref, key, n)
        elif kind == "number":
            speed = 1.0 if key in ("yaw",) else 0.01
            v = float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else 0.0
            changed, v = imgui.drag_float(key, v, speed, 0.0, 0.0, "%.3f")
            self._after_widget()
            if changed and math.isfinite(v):
                self._edited(ref, key, _tidy(v))
        elif kind == "vector":
            self.vector(ref, key, f, value)
        elif kind == "scale":
            self.scale(ref, key, f, value)
        elif kind == "angles":
            self.angles(ref, key, value or {})
        elif kind == "color":
            c = list(value) if value is not None else [0.7, 0.7, 0.72, 1.0]
            c = (c + [1.0])[:4] if len(c) == 3 else c[:4]
            changed, col = imgui.color_edit4(key, imgui.ImVec4(*c))
            self._after_widget()
            if changed:
                self._edited(ref, key, [_tidy(col.x, 3), _tidy(col.y, 3), _tidy(col.z, 3), _tidy(col.w, 3)])
        elif kind == "bool":
            changed, v = imgui.checkbox(key, bool(value))
            if changed:
                m.set(ref, key, v)
        elif kind == "string" and (f.choices or key == "shape"):
            choices = list(f.choices) if f.choices else _shape_names()
            cur = choices.index(value) if value in choices else -1
            changed, i = imgui.combo(key, cur, choices)
            if changed:
                m.set(ref, key, choices[i])
        elif kind in ("string", "text", "asset"):
            changed, v = imgui.input_text(key, "" if value is None else str(value))
            self._after_widget()
            if changed:
                self._edited(ref, key, v)
        elif kind == "params":
            self.params(ref, key, value or {})
        elif kind == "hints":
            self.hints(ref, key, list(value or []))
        elif kind == "words":
            self.words(ref, key, f, list(value or []))
        if not written:
            imgui.pop_style_color()
        elif f.default is not REQUIRED and kind not in ("angles", "params", "hints"):
            imgui.same_line()
            if imgui.small_button("x"):
                m.set(ref, key, None)  # back to the default
            if imgui.is_item_hovered():
                imgui.set_tooltip("remove: use the default")

    def vector(self, ref, key, f, value) -> None:
        v = [float(x) for x in value] if isinstance(value, list) else [0.0] * f.n
        v = (v + [0.0] * f.n)[: f.n]
        speed = 0.01 if f.sign == "positive" else 0.05
        if f.n == 4:  # the 3D position by numbers, w by its own slider: the 4D parameter
            changed, xyz = imgui.drag_float3(key, v[:3], speed)
            self._after_widget()
            lo, hi = self.mode.w_limits()
            changed_w, w = imgui.slider_float(f"{key} w", v[3], lo, hi, "%.3f")
            self._after_widget()
            if changed or changed_w:
                self._edited(ref, key, [_tidy(x) for x in [*xyz, w]])
            return
        widget = {2: imgui.drag_float2, 3: imgui.drag_float3}[f.n]
        changed, out = widget(key, v, speed)
        self._after_widget()
        if changed:
            self._edited(ref, key, [_tidy(x) for x in out])

    def scale(self, ref, key, f, value) -> None:
        """xyz scale, and for 4D objects the hyper-depth (w scale) on its own slider."""
        s = [float(value)] * f.n if isinstance(value, (int, float)) else [float(x) for x in value]
        changed, xyz = imgui.drag_float3(key, s[:3], 0.01, 0.001, 1000.0)
        self._after_widget()
        hyper = s[3] if f.n == 4 else None
        changed_h = False
        if f.n == 4:
            changed_h, hyper = imgui.drag_float("hyper-depth", s[3], 0.01, 0.001, 1000.0, "%.3f")
            self._after_widget()
        if changed or changed_h:
            new = [*xyz, hyper] if f.n == 4 else list(xyz)
            new = [_tidy(x) for x in new]
            self._edited(ref, key, new[0] if len(set(new)) == 1 else new)

    def angles(self, ref, key, value: dict) -> None:
        """The six rotation planes as sliders (degrees; degrees per second for spin)."""
        imgui.text(key + (" (deg/s)" if key == "spin" else " (deg)"))
        if value:
            imgui.same_line()
            if imgui.small_button("x"):
                self.model.set(ref, key, None)
                return
        lim = 360.0 if key == "spin" else 180.0
        out = dict(value)
        changed_any = False
        for plane in PLANES:
            changed, d = imgui.slider_float(f"{key} {plane}", float(value.get(plane, 0.0)), -lim, lim, "%.1f")
            self._after_widget()
            if changed:
                changed_any = True
                out[plane] = _tidy(d, 2)
        if changed_any:
            ordered = {p: out[p] for p in [*value, *PLANES] if p in out and (out[p] != 0.0 or p in value)}
            self._edited(ref, key, ordered)

    def hints(self, ref, key, value: list) -> None:
        """The level's hints, one line each ({action} placeholders become the player's keys)."""
        imgui.text("hints")
        for i, h in enumerate(value):
            changed, text = imgui.input_text(f"hint {i + 1}", h if isinstance(h, str) else "")
            self._after_widget()
            if changed:
                self._edited(ref, key, value[:i] + [text] + value[i + 1 :])
            imgui.same_line()
            if imgui.small_button(f"x##{i}"):
                self.model.set(ref, key, value[:i] + value[i + 1 :] or None)
                return
        if imgui.small_button("add a hint"):
            self.model.set(ref, key, [*value, "New hint: press {w_ana} to move ana."])

    def words(self, ref, key, f, value: list) -> None:
        """A list of words from the field's choices (``[design] needs``), one checkbox each."""
        imgui.text(key)
        for word in f.choices:
            changed, on = imgui.checkbox(f"{word}##{key}", word in value)
            if changed:
                new = [w for w in f.choices if (w in value) != (w == word)]
                self.model.set(ref, key, new or None)
                return

    def params(self, ref, key, value: dict) -> None:
        from ...core.shapes import SHAPE_PARAM_RULES

        imgui.text("params")
        for name, v in value.items():
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                imgui.text(f"  {name} = {v!r}")
                continue
            rule = SHAPE_PARAM_RULES.get(name, ("positive", (0.001, 1000.0)))
            if rule[0] == "whole":
                changed, n = imgui.drag_int(f"params {name}", int(v), 0.05, int(rule[1][0]), int(rule[1][1]))
                new = n
            else:
                changed, x = imgui.drag_float(f"params {name}", float(v), 0.01, 0.001, 1000.0)
                new = _tidy(x)
            self._after_widget()
            if changed:
                self._edited(ref, key, {**value, name: new})

    # ------------------------------------------------------------ w scrubber
    def scrubber(self, width: int, height: int) -> None:
        mode = self.mode
        imgui.set_next_window_pos(imgui.ImVec2(PANEL_LEFT, height - 150), imgui.Cond_.first_use_ever)
        imgui.set_next_window_size(imgui.ImVec2(width - PANEL_LEFT - PANEL_W, 128), imgui.Cond_.first_use_ever)
        imgui.begin("w", None, imgui.WindowFlags_.no_collapse)
        lo, hi = mode.w_limits()
        imgui.push_item_width(-imgui.calc_text_size("preview dw").x - 12)  # the longest label stays inside
        _, mode.cam.w = imgui.slider_float("slice w", float(mode.cam.w), lo, hi, "w = %.3f")
        _, mode.time = imgui.slider_float("time", float(mode.time), 0.0, 60.0, "t = %.2f s")
        _, mode.preview_step = imgui.slider_float("preview dw", float(mode.preview_step), 0.02, 1.0, "%.2f")
        imgui.pop_item_width()
        _, mode.frustum = imgui.checkbox("frustum projection (P)", mode.frustum)
        imgui.same_line()
        _, mode.animate = imgui.checkbox("animate", mode.animate)
        imgui.same_line()
        _, self.show_previews = imgui.checkbox("previews", self.show_previews)
        self.track()
        imgui.end()
        # Labels of the preview strip the view draws under the scrubber window.
        for (x, y, _, h), pw in mode.preview_rects:
            imgui.get_background_draw_list().add_text(
                imgui.ImVec2(x + 4, height - (y + h) + 2), imgui.color_convert_float4_to_u32(YELLOW), f"w = {pw:+.2f}"
            )

    def status(self, width: int, height: int) -> None:
        m, mode = self.model, self.mode
        problems = m.problems
        imgui.set_next_window_pos(imgui.ImVec2(0, height - 22))
        imgui.set_next_window_size(imgui.ImVec2(width, 22))
        flags = imgui.WindowFlags_.no_decoration | imgui.WindowFlags_.no_inputs
        imgui.begin("status", None, flags)
        name = m.path.name + (" *" if m.dirty else "")
        text = f"{name}   {len(problems)} problem(s)" if problems else f"{name}   ok"
        imgui.text_colored(RED if problems else GREY, f"{text}   {mode.message}")
        self.track()
        imgui.end()


def _fit(label: str) -> str:
    """``label`` cut to the width left in the panel, ending in "..." when cut (the tooltip shows it whole)."""
    room = imgui.get_content_region_avail().x
    if imgui.calc_text_size(label).x <= room:
        return label
    while label and imgui.calc_text_size(label + "...").x > room:
        label = label[:-1]
    return label + "..."


def _tidy(x: float, digits: int = 4) -> float:
    """Round what a drag produced, so a saved file reads ``1.25`` rather than ``1.2500000476837158``."""
    return round(float(x), digits) + 0.0


def _shape_names() -> list[str]:
    from ...core.shapes import SHAPES

    return sorted(SHAPES)
