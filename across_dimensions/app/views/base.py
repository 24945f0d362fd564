"""The base of every view: one screen of the window that takes the input while it is on top.

As in arcade's ``View``: the window owns the OS window, the clock and a stack of views
(:class:`~across_dimensions.app.window.GameWindow`); it hands every event to the view on top
of the stack, calls its :meth:`View.on_update` once a frame with the wall-clock seconds since
the last one, and has it draw with :meth:`View.on_draw`. A view that draws another one under
it (the pause menu over the paused level) asks that view to draw first.
"""

from __future__ import annotations


class View:
    """One screen. Subclasses override what they use; the defaults ignore the event.

    Parameters
    ----------
    session : Session
        What the views share (:class:`~across_dimensions.app.session.Session`).
    """

    #: The view shows a level (``--screenshot-after`` and ``--quit-after`` count from the first
    #: frame of such a view when a level was named on the command line).
    shows_level = False

    def __init__(self, session):
        self.session = session
        self.window = session.window

    # ----------------------------------------------------------------- life
    def on_show(self) -> None:
        """Now on top of the stack: shown first, or the view above it went away."""

    def on_update(self, dt: float) -> None:
        """``dt`` wall-clock seconds passed since the last frame."""

    def on_draw(self, target, viewport: tuple[int, int, int, int]) -> None:
        """Draw into ``target`` (the window's screen, or a screenshot's framebuffer) at ``viewport``."""

    def still_frame(self):
        """A value that changes whenever this view's picture would, or None when it moves every
        frame. A still view is drawn again only when it changes (and once in a while), so a
        software rasterizer does not redraw a still menu 120 times a second."""
        return None

    def on_screenshot(self, path) -> None:
        """A screenshot of this view was saved at ``path``."""
        self.session.say(f"Screenshot saved: {path}", 2.0)

    def on_close(self) -> bool:
        """The window is asked to close; True keeps it open."""
        return False

    # ---------------------------------------------------------------- input
    def on_key_press(self, symbol, modifiers) -> None:
        pass

    def on_key_release(self, symbol, modifiers) -> None:
        pass

    def on_text(self, text) -> None:
        pass

    def on_mouse_motion(self, x, y, dx, dy) -> None:
        pass

    def on_mouse_drag(self, x, y, dx, dy, buttons, modifiers) -> None:
        self.on_mouse_motion(x, y, dx, dy)

    def on_mouse_press(self, x, y, button, modifiers) -> None:
        pass

    def on_mouse_release(self, x, y, button, modifiers) -> None:
        pass

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y) -> None:
        pass

    def on_resize(self, width, height) -> None:
        pass

    def on_deactivate(self) -> None:
        """The window lost the focus (after having had it)."""

    def window_key(self, action: str | None) -> bool:
        """Do the actions that work on every screen (screenshot, fullscreen); True when it was one."""
        if action == "screenshot":
            self.window.request_screenshot()
        elif action == "toggle_fullscreen":
            self.window.set_fullscreen(not self.window.fullscreen)
        else:
            return False
        return True
