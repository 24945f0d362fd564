"""The game window: the OS window, the clock, and a stack of views.

Flow: the window opens at once on the title screen (or, with a level named on the command line,
straight into it) while the kernels load behind its first frame (:class:`~.warmup.BackgroundWarmUp`);
levels start only once that is done. Every screen is a view (:mod:`.views`, as arcade's
``View``): the title, the level select, the settings, the start-up progress, a level being played,
the pause menu over it, the level-complete view and the level editor. The window hands each event
to the view on top of its stack, gives it the wall-clock seconds of each frame and has it draw;
what the views share (settings, progress, renderer, sound...) is the :class:`~.session.Session`.

The clock is read here, in the app, never in the simulation: the play view turns it into whole
fixed ticks. ``--screenshot-after`` and ``--quit-after`` count from the first frame of a level
when one was named (a busy machine may take seconds to load the kernels), else from the start.
"""

from __future__ import annotations

import signal
import sys
import time
from pathlib import Path

import pyglet

from ..core.errors import InputError
from ..render.context import Offscreen, RenderError, wrap_current_context
from ..world.flat_level import load_flat_level
from ..world.level import load_level
from ..world.resources import is_prologue_file, level_files, resolve_level
from . import pyglet_options  # noqa: F401  (before pyglet.window or pyglet.gl load)
from .screenshots import save_screenshot
from .session import Session, Start, timing
from .settings import Settings, load_settings, save_settings, settings_path, window_options
from .settings_log import report_warnings, warning_screen_line
from .views.base import View

#: Seconds between updates of a still view (a menu): its clock, notices and the warm-up's
#: progress need no more, and the loop's 120 wakes a second then cost next to nothing while the
#: kernels compile. Below ``draw``'s 0.25 s clamp, so time keeps pace.
IDLE_UPDATE = 0.1


class GameWindow(pyglet.window.Window):
    """One window: the OS window, the clock and the stack of views.

    Parameters
    ----------
    settings : Settings
    start : Start, optional
        The command line's choices (a level to play at once, recording, timers...); the
        title screen without one.
    """

    def __init__(self, settings: Settings, start: Start | None = None):
        start = start or Start()
        config = pyglet.gl.Config(
            major_version=3, minor_version=3, forward_compatible=True, depth_size=24, double_buffer=True
        )
        super().__init__(caption="Across Dimensions", resizable=True, config=config, **window_options(settings))
        self.ctx = wrap_current_context()
        self.keys = pyglet.window.key.KeyStateHandler()  # which keys are down
        self.push_handlers(self.keys)
        self.views: list[View] = []
        self.was_active = False
        self.terminated_by: int | None = None
        # The clock.
        self.fps = 0.0
        self.last_draw: float | None = None
        self.wall_time = 0.0
        self.waiting_for_level = start.level_path is not None
        self.level_drawn = False
        self.last_frame_view: str | None = None
        self.screenshot_after, self.quit_after = start.screenshot_after, start.quit_after
        self.shot_pending = False
        self._drawn_signature, self._drawn_times = None, 0
        self.session = Session(self, settings, start)
        self.session.first_view(start)
        timing("window open")

    # ----------------------------------------------------------------- the stack
    @property
    def current_view(self) -> View:
        """The view on top: it takes the input and draws."""
        return self.views[-1]

    def show_view(self, view: View) -> None:
        """Show ``view`` alone (every view under it goes)."""
        self.views = [view]
        view.on_show()

    def push_view(self, view: View) -> None:
        """Show ``view`` over the current one, which comes back when it is popped."""
        self.views.append(view)
        view.on_show()

    def pop_view(self) -> None:
        """Remove the view on top; the one under it is shown again."""
        self.views.pop()
        self.current_view.on_show()

    # ----------------------------------------------------------------- the clock
    def update(self, dt: float) -> None:
        """``dt`` wall-clock seconds passed: the timers, then the view on top."""
        if self.current_view.shows_level:
            self.waiting_for_level = False
        if not self.waiting_for_level:
            self.wall_time += dt
        if dt > 0:
            self.fps = 0.9 * self.fps + 0.1 / dt if self.fps else 1.0 / dt
        self.session.tick(dt)
        if self.screenshot_after is not None and self.wall_time >= self.screenshot_after:
            self.screenshot_after = None
            self.shot_pending = True
        if self.quit_after is not None and self.wall_time >= self.quit_after:
            pyglet.app.exit()
            return
        self.current_view.on_update(dt)

    def draw(self, dt: float) -> None:
        """pyglet's redraw: the clock first, then the picture, skipped (no draw, no buffer swap)
        while a still view shows what both buffers already hold. A still view (a menu, the title
        over the kernel compile) is drawn only when what it shows changes, so it leaves the CPU to
        the compile."""
        # One update per pass: the wall clock is read here, in the app, and reaches the
        # simulation only as a whole number of fixed ticks.
        now = time.perf_counter()
        if self.last_draw is None or now - self.last_draw >= IDLE_UPDATE or self.current_view.still_frame() is None:
            self.update(0.0 if self.last_draw is None else min(now - self.last_draw, 0.25))
            self.last_draw = now
        signature = self.current_view.still_frame()
        if signature is None or self.shot_pending:
            self._drawn_signature = None
        else:
            fresh = signature != self._drawn_signature
            if not fresh and self._drawn_times >= 2:
                return  # both buffers already hold this picture
            self._drawn_times = 1 if fresh else self._drawn_times + 1
            self._drawn_signature = signature
        super().draw(dt)

    def on_draw(self):
        fw, fh = self.get_framebuffer_size()
        self.current_view.on_draw(self.ctx.screen, (0, 0, fw, fh))
        if self.last_frame_view is None:  # the title (or the start-up view) is up and takes input
            timing("first frame")
            # After this frame is on screen, not before it is: the next pass of the loop.
            pyglet.clock.schedule_once(lambda _dt: self.session.after_first_frame(), 0.0)
        self.last_frame_view = type(self.current_view).__name__
        if self.current_view.shows_level and not self.level_drawn:
            self.level_drawn = True
            timing("first level frame")
        if self.shot_pending:
            self.shot_pending = False
            self.screenshot()

    def request_screenshot(self) -> None:
        """Take a screenshot after the next frame is drawn."""
        self.shot_pending = True

    def screenshot(self) -> Path | None:
        """Save what the window shows as a PNG in the player's pictures folder (see
        :mod:`.screenshots`); a failure is a notice, never an exit.

        The view is drawn again into an offscreen framebuffer of the window's
        size (reading the window's own back buffer is not portable in a core
        profile), through the same render scale as the window.
        """
        fw, fh = self.get_framebuffer_size()

        def write(path):
            with Offscreen(self.ctx, fw, fh) as target:
                self.current_view.on_draw(target.fbo, target.viewport)
                target.save_png(path)

        try:
            path, message = save_screenshot(write)
        finally:
            self.ctx.screen.use()
        if path is None:
            self.session.warn(message)
            return None
        print(f"screenshot saved: {path}", flush=True)
        self.current_view.on_screenshot(path)
        return path

    # ----------------------------------------------------------------- the OS window's events
    def on_key_press(self, symbol, modifiers):
        self.current_view.on_key_press(symbol, modifiers)
        return pyglet.event.EVENT_HANDLED  # keep Esc from closing the window

    def on_key_release(self, symbol, modifiers):
        self.current_view.on_key_release(symbol, modifiers)

    def on_text(self, text):
        self.current_view.on_text(text)

    def on_mouse_motion(self, x, y, dx, dy):
        self.current_view.on_mouse_motion(x, y, dx, dy)

    def on_mouse_drag(self, x, y, dx, dy, buttons, modifiers):
        self.current_view.on_mouse_drag(x, y, dx, dy, buttons, modifiers)

    def on_mouse_press(self, x, y, button, modifiers):
        self.current_view.on_mouse_press(x, y, button, modifiers)

    def on_mouse_release(self, x, y, button, modifiers):
        self.current_view.on_mouse_release(x, y, button, modifiers)

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y):
        self.current_view.on_mouse_scroll(x, y, scroll_x, scroll_y)

    def on_resize(self, width, height):
        super().on_resize(width, height)
        if self.views:
            self.current_view.on_resize(width, height)

    def on_activate(self):
        self.was_active = True

    def on_deactivate(self):
        # Losing focus pauses, as in any game; but a window that never had focus
        # (no window manager, e.g. under Xvfb) keeps running.
        if self.was_active:
            self.current_view.on_deactivate()

    def on_close(self):
        if any(view.on_close() for view in reversed(self.views)):
            return  # a view keeps the window open (the editor's unsaved changes)
        self.session.recording.stop()
        super().on_close()

    def terminate(self, signum: int) -> None:
        """A SIGTERM or SIGHUP arrived: leave the main loop; the recording is saved on the way out."""
        self.terminated_by = signum
        pyglet.app.exit()


def run_window(args) -> int:
    """Open the window and play until it closes. Returns the exit status."""
    settings, warnings = load_settings(args.settings)
    line = report_warnings(warnings, args.settings)
    if line:  # one line, here and on screen; every detail is in the log file
        print(f"warning: {line}", file=sys.stderr)
    if args.settings is None and not settings_path().exists():
        try:  # first run: leave a settings file for the player to edit
            save_settings(settings)
        except (OSError, InputError) as e:
            print(f"warning: could not write {settings_path()} ({e}); playing with the defaults", file=sys.stderr)
    if args.fullscreen:
        settings.fullscreen = True
    path = None
    editing = getattr(args, "edit", False)
    if args.level or args.record or editing:  # a level named, or needed: straight into it
        path = resolve_level(args.level) if args.level else level_files()[0]
        # A broken level is reported before a window opens.
        (load_flat_level if is_prologue_file(path) else load_level)(path)
    start = Start(
        level_path=path,
        seed=args.seed,
        record=args.record,
        warnings=[warning_screen_line(warnings, args.settings)] if line else [],
        screenshot_after=args.screenshot_after,
        quit_after=args.quit_after,
        warm_first=path is not None,
        settings_file=args.settings,
        edit=editing,
    )
    try:
        window = GameWindow(settings, start)  # opens at once; the kernels compile behind its first view
    except (pyglet.window.NoSuchConfigException, pyglet.gl.ContextException, RenderError) as e:
        print(
            f"across-dimensions: cannot open an OpenGL 3.3 window here ({e}); "
            f"try the headless demo: across-dimensions demo --screenshots out/",
            file=sys.stderr,
        )
        return 1
    # SIGTERM (and SIGHUP, a closed terminal) would end the process on the spot
    # and lose the recording's last second; instead leave the loop and save.
    # Python runs the handler in the main thread between bytecodes, and the
    # loop wakes at least every 1/120 s, so it runs promptly.
    signums = [s for s in (getattr(signal, "SIGTERM", None), getattr(signal, "SIGHUP", None)) if s is not None]
    previous = {s: signal.signal(s, lambda signum, _frame: window.terminate(signum)) for s in signums}
    try:
        pyglet.app.run(1 / 120)  # redraw up to 120 Hz; vsync, when on, paces it to the display
    finally:
        try:
            window.session.recording.stop()  # also on a crash in the loop: the replay so far is kept
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)
            window.close()
    return 128 + window.terminated_by if window.terminated_by else 0
