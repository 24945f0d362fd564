"""The game window: pyglet for the window and input, the renderer for pixels.

The main loop is a fixed-tick accumulator: wall-clock time (measured here, in
the app, never in the simulation) fills an accumulator that is drained in
steps of ``1 / TICK_RATE``, at most ``MAX_CATCH_UP`` per frame so a long stall
does not spiral; the frame is drawn interpolated by the remainder.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import time
from pathlib import Path

import pyglet

from ..core.errors import InputError
from ..core.fileio import FileProblem, check_folder
from ..game.actions import CAMERA_BUTTONS, MAX_PRESSES, PRESSES, Actions
from ..game.replay import Recorder
from ..game.sim import DT, Game, RadarView
from ..game.systems.ghosts import GhostView
from ..render.context import Offscreen, RenderError, wrap_current_context
from ..render.debug_draw import DebugOverlay
from ..render.pip import draw_pip
from ..render.renderer import Renderer
from ..world.level import load_level
from ..world.resources import level_files, resolve_level
from .settings import Settings, load_settings, look_delta, save_settings, settings_path
from .warmup import warm_up

MAX_CATCH_UP = 5
HINT_SECONDS = 7.0
NEXT_LEVEL_DELAY = 3.0


_MOUSE = {
    "MOUSE_LEFT": "LEFT",
    "MOUSE_MIDDLE": "MIDDLE",
    "MOUSE_RIGHT": "RIGHT",
    "MOUSE_4": "MOUSE4",
    "MOUSE_5": "MOUSE5",
}


def _key_code(name: str):
    """pyglet code for a settings key name: ('key', code), ('mouse', button) or ('wheel', +1 | -1)."""
    if name in ("MOUSE_WHEEL_UP", "MOUSE_WHEEL_DOWN"):
        return "wheel", 1 if name.endswith("UP") else -1
    if name.startswith("MOUSE_"):
        return "mouse", getattr(pyglet.window.mouse, _MOUSE[name])
    return "key", getattr(pyglet.window.key, name)


class GameWindow(pyglet.window.Window):
    """One window playing levels in order, starting from ``level_path``."""

    def __init__(
        self,
        settings: Settings,
        level_path: Path,
        seed: int = 0,
        record: str | None = None,
        warnings=(),
        screenshot_after: float | None = None,
        quit_after: float | None = None,
    ):
        config = pyglet.gl.Config(
            major_version=3, minor_version=3, forward_compatible=True, depth_size=24, double_buffer=True
        )
        super().__init__(
            settings.width,
            settings.height,
            caption="Across Dimensions",
            resizable=True,
            vsync=settings.vsync,
            config=config,
            fullscreen=settings.fullscreen,
        )
        self.settings = settings
        self.ctx = wrap_current_context()
        self.renderer = Renderer(self.ctx)
        self.keys = pyglet.window.key.KeyStateHandler()
        self.push_handlers(self.keys)
        self.mouse_buttons: set = set()
        # One-shot presses since the last tick, by action (delivered with the next tick's actions),
        # and actions held for one tick by a wheel notch.
        self.presses: dict[str, int] = {}
        self.wheel_held: set = set()
        self.bindings = {a: [_key_code(k) for k in settings.keys_for(a)] for a in settings.bindings}
        self.seed = seed
        self.record_path = record
        self.recorder: Recorder | None = None
        self.show_fps = settings.show_fps
        self.pip_on = settings.pip  # the picture-in-picture inset (render/pip.py)
        self.debug_overlay: DebugOverlay | None = None  # made on first use, drawn while on
        self.show_debug_draw = False
        self.ghost_view = GhostView(
            settings.ghosts, settings.ghost_distance, settings.ghost_strength, settings.ghost_layers
        )
        self.fps = 0.0
        self.notice = ("; ".join(warnings), 8.0) if warnings else ("", 0.0)
        self.look = [0.0, 0.0]
        self.accumulator = 0.0
        self.paused = False
        self.screenshot_after = screenshot_after
        self.quit_after = quit_after
        self.wall_time = 0.0
        self.finished_for = 0.0
        self.terminated_by: int | None = None
        self.editor = None  # the level editor (app/editor), made on first use
        self.load(level_path)
        if record:
            self.start_recording()
        self.set_exclusive_mouse(True)
        self.last_draw: float | None = None

    # ----------------------------------------------------------------- levels
    def load(self, path: Path) -> None:
        self.level_path = Path(path)
        self.game = Game(load_level(path), seed=self.seed)
        self.renderer.forget_meshes()  # a new world: its meshes reuse the old one's keys and revisions
        s = self.settings
        self.game.radar_view = RadarView(s.radar, s.radar_range_scale, s.radar_height_scale)
        self.game.show_ghosts = self.settings.ghosts  # a view option: not part of the simulation's state
        self.game.ghost_view = self.ghost_view  # drawing only: never part of a replay
        self.level_time = 0.0
        self.finished_for = 0.0
        self.set_caption(f"Across Dimensions - {self.game.level.name}")

    def next_level(self) -> None:
        files = level_files()
        try:
            i = [f.resolve() for f in files].index(self.level_path.resolve())
        except ValueError:
            i = len(files)
        if i + 1 < len(files):
            self.load(files[i + 1])
        else:
            self.say("All levels complete - thanks for playing!", 1e9)

    def say(self, text: str, seconds: float = 4.0) -> None:
        self.notice = (text, seconds)

    # -------------------------------------------------------------- recording
    def start_recording(self) -> None:
        """Recording restarts the level: a replay always starts at the spawn.

        The replay file is written from the start and grows every simulated
        second (see :class:`~across_dimensions.game.replay.Recorder`), so a
        crash loses at most the last second. Without ``--record`` it goes to
        the game's own replay folder, named by level and time.
        """
        self.load(self.level_path)
        try:
            if self.record_path:
                path = Path(self.record_path)
            else:
                folder = _replay_folder()
                folder.mkdir(parents=True, exist_ok=True)  # the game's own folder: ours to create
                path = _unused(folder / f"{self.level_path.stem}_{time.strftime('%Y%m%d-%H%M%S')}.json")
            self.recorder = Recorder(self.game, self.level_path.stem, path)
        except (FileProblem, OSError) as e:
            self.recorder = None
            self._recording_failed(f"Cannot record: {e}")
            return
        self.say("Recording (level restarted)")

    def stop_recording(self) -> None:
        """Finish the recording in progress, if any, and save it over its journal."""
        if self.recorder is None:
            return
        recorder, self.recorder = self.recorder, None
        self.record_path = None  # the next F9 recording goes to the replay folder
        try:
            recorder.finish()
        except FileProblem as e:  # the journal written so far stays, and still loads
            self._recording_failed(f"Replay not saved: {e}")
            return
        self.say(f"Replay saved: {recorder.path}")
        print(f"replay saved: {recorder.path}", flush=True)

    def _recording_failed(self, message: str) -> None:
        self.say(message, 8.0)
        print(f"warning: {message}", file=sys.stderr, flush=True)

    def terminate(self, signum: int) -> None:
        """A SIGTERM or SIGHUP arrived: leave the main loop; the recording is saved on the way out."""
        self.terminated_by = signum
        pyglet.app.exit()

    # ------------------------------------------------------------------ input
    def held(self, action: str) -> bool:
        if action in self.wheel_held:
            return True
        for kind, code in self.bindings.get(action, ()):
            if (kind == "key" and self.keys[code]) or (kind == "mouse" and code in self.mouse_buttons):
                return True
        return False

    def pressed_action(self, kind: str, code) -> str | None:
        for action, codes in self.bindings.items():
            if (kind, code) in codes:
                return action
        return None

    def count_press(self, kind: str, code, times: int = 1) -> None:
        """A key, button or wheel notch went down: count it for every one-shot action bound to it."""
        if self.paused:
            return
        for action, codes in self.bindings.items():
            if (kind, code) in codes:
                if action == "seek" and self.settings.reduce_motion:
                    action = "seek_jump"  # a press of its own, so replays land the same way
                if action in PRESSES:
                    self.presses[action] = min(self.presses.get(action, 0) + times, MAX_PRESSES)
                elif kind == "wheel":
                    self.wheel_held.add(action)

    def read_actions(self) -> Actions:
        """This tick's actions; the mouse motion since the last tick goes to it."""
        dyaw, dpitch = self.look
        self.look = [0.0, 0.0]
        axis = lambda pos, neg: float(self.held(pos)) - float(self.held(neg))  # noqa: E731
        # clamped(): a replay stores exactly these frames, and Replay.load
        # refuses non-finite or out-of-bound rows (a huge mouse jump, a driver's NaN).
        actions = Actions(
            forward=axis("move_forward", "move_back"),
            right=axis("strafe_right", "strafe_left"),
            yaw=dyaw,
            pitch=dpitch,
            w=axis("w_ana", "w_kata"),
            jump=self.held("jump"),
            fire=self.held("fire"),
            alt_fire=self.held("alt_fire"),
            switch_camera=self.held("switch_camera"),
            manipulate=self.held("manipulate"),
            next_weapon=self.held("next_weapon"),
            **{b: self.held(b) for b in CAMERA_BUTTONS},
            presses=Actions.count_presses(self.presses),
        ).clamped()
        self.presses.clear()
        self.wheel_held.clear()
        return actions

    def on_mouse_motion(self, x, y, dx, dy):
        if not self.paused:
            dyaw, dpitch = look_delta(self.settings, dx, dy)
            self.look[0] += dyaw
            self.look[1] += dpitch

    def on_mouse_drag(self, x, y, dx, dy, buttons, modifiers):
        self.on_mouse_motion(x, y, dx, dy)

    def on_mouse_press(self, x, y, button, modifiers):
        if self.paused:
            self.set_paused(False)
            return
        self.mouse_buttons.add(button)
        self.count_press("mouse", button)

    def on_mouse_release(self, x, y, button, modifiers):
        self.mouse_buttons.discard(button)

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y):
        if scroll_y:
            notches = max(1, round(abs(scroll_y)))
            self.count_press("wheel", 1 if scroll_y > 0 else -1, notches)

    def on_key_press(self, symbol, modifiers):
        self.count_press("key", symbol)
        action = self.pressed_action("key", symbol)
        if action == "pause":
            self.set_paused(not self.paused)
        elif action == "toggle_fullscreen":
            self.set_fullscreen(not self.fullscreen)
        elif action == "toggle_fps":
            self.show_fps = not self.show_fps
        elif action == "toggle_pip":
            self.pip_on = not self.pip_on
            self.say("Picture in picture on" if self.pip_on else "Picture in picture off", 1.5)
        elif action == "toggle_ghosts":
            self.ghost_view.enabled = not self.ghost_view.enabled
            self.say("Ghosts on" if self.ghost_view.enabled else "Ghosts off", 1.5)
        elif action == "debug_draw":
            self.show_debug_draw = not self.show_debug_draw
        elif action == "screenshot":
            self.screenshot()
        elif action == "record":
            self.stop_recording() if self.recorder else self.start_recording()
        elif action == "editor":
            self.open_editor()
        return pyglet.event.EVENT_HANDLED  # keep Esc from closing the window

    def open_editor(self, from_play: bool = True) -> None:
        """Switch to the level editor (an optional extra); its own key brings the game back."""
        from .editor import missing_message

        problem = missing_message()
        if problem:
            self.say(problem, 8.0)
            return
        from .editor.mode import EditorMode

        if self.editor is None:
            self.editor = EditorMode(self, self.level_path)
        self.editor.enter(from_play)

    def on_activate(self):
        self.was_active = True

    def on_deactivate(self):
        # Losing focus pauses, as in any game; but a window that never had focus
        # (no window manager, e.g. under Xvfb) keeps running.
        if getattr(self, "was_active", False):
            self.set_paused(True)

    def set_paused(self, paused: bool) -> None:
        self.paused = paused
        self.set_exclusive_mouse(not paused)
        self.mouse_buttons.clear()
        self.presses.clear()
        self.wheel_held.clear()
        self.look = [0.0, 0.0]

    def on_close(self):
        self.stop_recording()
        super().on_close()

    # ------------------------------------------------------------------- loop
    def update(self, dt: float) -> None:
        """Advance by ``dt`` wall-clock seconds: as many fixed ticks as fit."""
        self.wall_time += dt
        if dt > 0:
            self.fps = 0.9 * self.fps + 0.1 / dt if self.fps else 1.0 / dt
        text, left = self.notice
        self.notice = (text, left - dt)
        if self.screenshot_after is not None and self.wall_time >= self.screenshot_after:
            self.screenshot_after = None
            self._pending_shot = True
        if self.quit_after is not None and self.wall_time >= self.quit_after:
            pyglet.app.exit()
            return
        if self.paused:
            return
        self.accumulator += dt
        steps = 0
        while self.accumulator >= DT and steps < MAX_CATCH_UP:
            actions = self.read_actions()
            self.game.step(actions)
            if self.recorder:
                try:
                    self.recorder.record(actions)
                except FileProblem as e:  # e.g. the disk is full: keep playing, say so
                    with contextlib.suppress(FileProblem):
                        self.recorder.close()
                    self.recorder = None
                    self._recording_failed(f"Recording stopped: {e}")
            self.accumulator -= DT
            steps += 1
        if steps == MAX_CATCH_UP:
            self.accumulator = 0.0  # too far behind: drop time rather than spiral
        self.level_time += steps * DT
        if self.game.outcome == "complete":
            if self.recorder:
                self.stop_recording()
            self.finished_for += steps * DT
            if self.finished_for >= NEXT_LEVEL_DELAY:
                self.next_level()

    def current_frame(self):
        """The game's frame with the app's HUD additions (fps, pause, notices)."""
        frame = self.game.frame(alpha=self.accumulator / DT, fov_y_deg=self.settings.fov_deg, pip=self.pip_on)
        hud = frame.hud
        if hud.message:  # the game's prompts name actions ({manipulate}); show the player's keys
            hud.message = self.with_keys(hud.message)
        hud.fps = self.fps if self.show_fps else None
        hud.paused = self.paused
        if self.paused and not (self.notice[1] > 0 and self.notice[0]):
            hud.message = "Click to resume"
        text, left = self.notice
        if left > 0 and text:
            hud.message = text
        elif not hud.message and self.level_time < HINT_SECONDS * len(self.game.level.hints):
            hud.message = self.hint(int(self.level_time // HINT_SECONDS))
        if self.recorder and not hud.message:
            hud.message = "REC"
        return frame

    def hint(self, i: int) -> str:
        """Level hint ``i`` with ``{action}`` replaced by the keys bound to it."""
        return self.with_keys(self.game.level.hints[i])

    def with_keys(self, text: str) -> str:
        """``text`` with each ``{action}`` replaced by the keys bound to it."""
        keys = {
            a: "/".join(
                k.replace("MOUSE_", "mouse ").lower() if k.startswith("MOUSE_") else k.lstrip("_")
                for k in self.settings.keys_for(a)
            )
            or "(unbound)"
            for a in self.settings.bindings
        }
        try:
            return text.format_map(_Missing(keys))
        except (ValueError, IndexError):  # a stray brace in a game prompt: show it as written
            return text

    def on_draw(self):
        # One update per drawn frame: the wall clock is read here, in the app,
        # and reaches the simulation only as a whole number of fixed ticks.
        now = time.perf_counter()
        self.update(0.0 if self.last_draw is None else min(now - self.last_draw, 0.25))
        self.last_draw = now
        frame = self.current_frame()
        fw, fh = self.get_framebuffer_size()
        self.ctx.screen.use()
        self.renderer.draw(frame, (0, 0, fw, fh))
        if self.pip_on:
            draw_pip(self.renderer, frame, (0, 0, fw, fh), self.settings.pip_size)
        if self.show_debug_draw:
            self.debug_overlay = self.debug_overlay or DebugOverlay(self.ctx)
            self.debug_overlay.draw_game(self.game, frame.camera, (0, 0, fw, fh))
        if getattr(self, "_pending_shot", False):
            self._pending_shot = False
            self.screenshot()

    def screenshot(self) -> Path:
        """Save what the window shows as a PNG in ./screenshots/.

        The frame is drawn again into an offscreen framebuffer of the window's
        size (reading the window's own back buffer is not portable in a core
        profile).
        """
        fw, fh = self.get_framebuffer_size()
        folder = Path("screenshots")
        folder.mkdir(exist_ok=True)
        path = folder / f"shot_{len(list(folder.glob('shot_*.png'))):04d}.png"
        with Offscreen(self.ctx, fw, fh) as target:
            target.use()
            frame = self.current_frame()
            self.renderer.draw(frame, target.viewport)
            if self.show_debug_draw and self.debug_overlay is not None:
                self.debug_overlay.draw_game(self.game, frame.camera, target.viewport)
            target.save_png(path)
        self.ctx.screen.use()
        print(f"screenshot saved: {path}", flush=True)
        self.say(f"Screenshot saved: {path}", 2.0)
        return path


class _Missing(dict):
    """format_map helper: unknown ``{names}`` stay as written."""

    def __missing__(self, key):
        return "{" + key + "}"


def _replay_folder() -> Path:
    import platformdirs

    return Path(platformdirs.user_data_dir("across-dimensions")) / "replays"


def _unused(path: Path) -> Path:
    """``path``, or ``name-2.json``, ``name-3.json``... if it exists (two recordings in one second)."""
    n = 1
    candidate = path
    while candidate.exists():
        n += 1
        candidate = path.with_name(f"{path.stem}-{n}{path.suffix}")
    return candidate


def check_record_path(path) -> None:
    """Refuse ``--record FILE`` before a window opens when FILE cannot be written.

    Raises
    ------
    FileProblem
        The folder is missing (folders are never created for it), is not a
        folder, or is not writable; or FILE is a folder.
    """
    path = check_folder(path)
    if not os.access(path.parent, os.W_OK | os.X_OK):
        raise FileProblem(f"{path}: cannot write in the folder {path.parent} (permission denied)")


def run_window(args) -> int:
    """Open the window and play until it closes. Returns the exit status."""
    settings, warnings = load_settings(args.settings)
    for w in warnings:
        print(f"warning: {w}", file=sys.stderr)
    if args.settings is None and not settings_path().exists():
        try:  # first run: leave a settings file for the player to edit
            save_settings(settings)
        except (OSError, InputError) as e:
            print(f"warning: could not write {settings_path()} ({e}); playing with the defaults", file=sys.stderr)
    if args.fullscreen:
        settings.fullscreen = True
    path = resolve_level(args.level) if args.level else level_files()[0]
    load_level(path)  # a broken level is reported before a window opens
    if args.record:
        check_record_path(args.record)
    warm_up()
    try:
        window = GameWindow(
            settings,
            path,
            seed=args.seed,
            record=args.record,
            warnings=warnings,
            screenshot_after=args.screenshot_after,
            quit_after=args.quit_after,
        )
        if getattr(args, "edit", False):
            window.open_editor(from_play=False)
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
            window.stop_recording()  # also on a crash in the loop: the replay so far is kept
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)
            window.close()
    return 128 + window.terminated_by if window.terminated_by else 0
