"""The menu views: title, level select, pause, and the settings (with the controls and a key conflict).

Every menu screen is a view on the window's stack, and all of them present one model,
:class:`~across_dimensions.app.menu.Menu` (the session's), which knows the screens' rows and
what each input does. A view turns keys, buttons and the wheel into the model's verbs and
pointer positions into rows; when the model goes a screen deeper (Settings, Controls) the view
pushes the view of that screen, and when it goes back the view pops itself. The commands a
screen's rows give (``"continue"``, ``"play:<level>"``, ``"resume"``, ...) are done by that
screen's view. Menus over a paused level draw it, dimmed, under them.
"""

from __future__ import annotations

import pyglet

from ...render.menu import hit, rows_that_fit
from ..input import key_name
from ..menu import menu_verb
from ..warmup import TITLE_PANEL_AFTER, warm_progress
from .base import View

#: The clear colour behind the menus when no level is under them.
BACKDROP = (0.02, 0.03, 0.06, 1.0)


class MenuScreen(View):
    """One screen of the menus.

    Parameters
    ----------
    session : Session
    screen : str
        The model's screen this view shows (``"title"``, ``"levels"``, ``"settings"``...).
    backdrop : PlayView or None
        The paused level drawn under the menu, or None (the title's backdrop colour).
    depth : int
        How many screens deep this one is in the model's stack (1: a root, title or pause).
    """

    def __init__(self, session, screen: str, backdrop=None, depth: int = 1):
        super().__init__(session)
        self.screen, self.backdrop, self.depth = screen, backdrop, depth

    @property
    def menu(self):
        return self.session.menu

    def on_show(self) -> None:
        self.window.set_exclusive_mouse(False)

    def on_draw(self, target, viewport) -> None:
        if self.backdrop is not None:
            self.backdrop.draw_scene(target, viewport, playing=False)
        else:
            target.use()
            self.window.ctx.clear(*BACKDROP)
        target.use()
        self.menu.fit_rows(rows_that_fit(self.menu.view(), viewport[3]))  # larger text: fewer rows
        self.session.menu_renderer.draw(self.menu.view(), viewport)

    def still_frame(self):
        return repr(self.menu.view()), self.session.notice_text

    # ---------------------------------------------------------------- input
    def on_key_press(self, symbol, modifiers) -> None:
        name = key_name("key", symbol)
        verb = menu_verb(name, self.session.settings) if name else None
        if verb:
            self.apply(self.menu.input(verb))
        else:
            self.window_key(self.session.bindings.action_of("key", symbol))

    def on_mouse_motion(self, x, y, dx, dy) -> None:
        found = self._hit(x, y)
        if found is not None:
            self.menu.point(found[0])

    def on_mouse_press(self, x, y, button, modifiers) -> None:
        found = self._hit(x, y)
        if found is not None and button == pyglet.window.mouse.LEFT:
            self.apply(self.menu.click(*found))
        elif button == pyglet.window.mouse.RIGHT:
            self.apply(self.menu.input("back"))

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y) -> None:
        if scroll_y:
            self.menu.scroll(-1 if scroll_y > 0 else 1)

    def _hit(self, x, y):
        """The row under the pointer (window coordinates, origin bottom-left) and a slider fraction."""
        view = self.menu.view()
        if view is None:
            return None
        fw, fh = self.window.get_framebuffer_size()
        sx, sy = fw / max(1, self.window.width), fh / max(1, self.window.height)
        return hit(view, fw, fh, x * sx, fh - y * sy)

    # ------------------------------------------------------------- commands
    def apply(self, command: str | None) -> None:
        """Follow the model to the screen it moved to, then do ``command`` (None: nothing)."""
        self.follow()
        if command is not None:
            self.run(command)

    def follow(self) -> None:
        """The model went a screen deeper: push that screen's view; it went back: pop this one."""
        menu = self.menu
        if menu.screen == self.screen:
            return
        if len(menu.stack) > self.depth:
            view = SCREENS[menu.screen](self.session, menu.screen, self.backdrop, self.depth + 1)
            self.window.push_view(view)
        else:
            self.window.pop_view()

    def run(self, command: str) -> None:
        """Do a command of this screen's rows (see :class:`~across_dimensions.app.menu.Menu`)."""


class TitleView(MenuScreen):
    """The title screen: Continue, Level select, Settings, Quit, and the kernel compile's progress."""

    def __init__(self, session):
        super().__init__(session, "title")

    def on_show(self) -> None:
        super().on_show()
        if self.menu.stack[:1] != ["title"]:  # shown anew, not back from a screen under it
            self.menu.open("title")
        self._show_progress()

    def on_update(self, dt: float) -> None:
        self._show_progress()

    def still_frame(self):
        self._show_progress()
        return super().still_frame()

    def _show_progress(self) -> None:
        if self.session.warm is not None:
            self.menu.progress_bar = warm_progress(self.session.warm, after=TITLE_PANEL_AFTER)

    def run(self, command: str) -> None:
        s = self.session
        if command == "continue":
            stem, checkpoint = s.progress.continue_level([e.stem for e in s.campaign], s.optional)
            if stem is not None:
                s.start_level(next(e.path for e in s.campaign if e.stem == stem), checkpoint)
        elif command == "quit":
            pyglet.app.exit()


class LevelSelectView(MenuScreen):
    """The campaign's levels, locked or open, with best times and crystals; a click plays one
    (as a time trial when the screen's time-trial row is on)."""

    def run(self, command: str) -> None:
        kind, _, stem = command.partition(":")
        if kind in ("play", "trial"):
            s = self.session
            s.start_level(next(e.path for e in s.campaign if e.stem == stem), trial=kind == "trial")


class PauseView(MenuScreen):
    """The pause menu over the paused level: Resume, Restart level, Settings, Quit to title.

    Parameters
    ----------
    session : Session
    play : PlayView
        The level paused, drawn dimmed under the menu.
    """

    def __init__(self, session, play):
        super().__init__(session, "pause", backdrop=play)

    def on_show(self) -> None:
        super().on_show()
        if self.menu.stack[:1] != ["pause"]:  # just paused, not back from the settings
            self.menu.skippable = self.backdrop.level_path.stem in self.session.optional
            self.menu.open("pause")
            self.session.sound.ui("menu_back")
            self.session.save_progress()  # quitting from here (closing the window) keeps the level to continue

    def run(self, command: str) -> None:
        s = self.session
        if command == "resume":
            s.sound.ui("menu_select")
            s.menu.close()
            self.window.pop_view()
        elif command == "restart":
            s.recording.stop()
            s.start_level(self.backdrop.level_path, trial=getattr(self.backdrop, "trial", False))
        elif command == "skip":  # the prologue: on to the level after it
            s.recording.stop()
            s.next_level(self.backdrop.level_path)
        elif command == "quit_to_title":
            s.to_title()


class SettingsView(MenuScreen):
    """The settings, the controls and a key conflict: each change is applied and saved at once
    (:meth:`~across_dimensions.app.session.Session.setting_changed`). A controls row waiting for a
    key takes the next key, mouse button or wheel notch."""

    def on_key_press(self, symbol, modifiers) -> None:
        if self.menu.capturing:
            self._capture(key_name("key", symbol))
        else:
            super().on_key_press(symbol, modifiers)

    def on_mouse_press(self, x, y, button, modifiers) -> None:
        if self.menu.capturing:
            self._capture(key_name("mouse", button))
        else:
            super().on_mouse_press(x, y, button, modifiers)

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y) -> None:
        if self.menu.capturing:
            if scroll_y:
                self._capture(key_name("wheel", scroll_y))
        else:
            super().on_mouse_scroll(x, y, scroll_x, scroll_y)

    def _capture(self, name: str | None) -> None:
        if name:
            self.menu.capture(name)
            self.follow()  # a key in use opens the conflict screen


#: The view of each screen a menu can go deeper to.
SCREENS = {"levels": LevelSelectView, "settings": SettingsView, "controls": SettingsView, "conflict": SettingsView}
