"""The game window: pyglet for the window and input, the renderer for pixels.

Flow: the window opens at once on the title screen (or, with a level named on
the command line, straight into it) while the kernels compile behind it
(:class:`~.warmup.BackgroundWarmUp`); levels start only once that is done.
Esc opens the pause menu; the menus (:mod:`.menu`, drawn by
:mod:`across_dimensions.render.menu`) lead to the level select, the settings
(applied and saved at once) and back to the title. Progress (:mod:`.saves`) is
saved when a level starts, reaches a checkpoint, is finished or left.

The main loop is a fixed-tick accumulator: wall-clock time (measured here, in
the app, never in the simulation) fills an accumulator that is drained in
steps of ``1 / TICK_RATE``, at most ``MAX_CATCH_UP`` per frame so a long stall
does not spiral; the frame is drawn interpolated by the remainder.
"""

from __future__ import annotations

import contextlib
import functools
import os
import signal
import sys
import time
from pathlib import Path

import pyglet

from ..core import heap
from ..core.errors import InputError
from ..core.fileio import FileProblem, check_folder
from ..game.actions import CAMERA_BUTTONS, MAX_PRESSES, PRESSES, Actions
from ..game.replay import Recorder
from ..game.sim import DT, Game, RadarView
from ..game.systems.ghosts import GhostView
from ..render.context import Offscreen, RenderError, wrap_current_context
from ..render.debug_draw import DebugOverlay
from ..render.menu import MenuRenderer, hit
from ..render.pip import draw_pip
from ..render.renderer import Renderer
from ..render.scale import ScaledTarget, resolve_render_scale
from ..world.campaign import CampaignEntry, CampaignError, load_campaign, next_in_campaign
from ..world.level import load_level
from ..world.resources import level_files, resolve_level
from . import pyglet_options  # noqa: F401  (before pyglet.window or pyglet.gl load)
from .menu import Menu, menu_verb
from .onboarding import Onboarding, fill_keys
from .saves import checkpoint_of, load_progress, replay_folder, resume_at_checkpoint, save_progress
from .screenshots import save_screenshot
from .settings import (
    KEY_NAMES,
    Settings,
    load_settings,
    look_delta,
    report_warnings,
    save_settings,
    settings_path,
    warning_screen_line,
)
from .sound import SoundDirector, SoundOut
from .warmup import BackgroundWarmUp, warm_up

MAX_CATCH_UP = 5
#: Seconds between redraws of a menu that has not changed (no level running): a software
#: rasterizer would otherwise redraw a still screen 120 times a second, taking the CPU the
#: kernel compile behind the title needs. Below ``update``'s 0.25 s clamp, so time keeps pace.
IDLE_REDRAW = 0.2
NEXT_LEVEL_DELAY = 3.0


_MOUSE = {
    "MOUSE_LEFT": "LEFT",
    "MOUSE_MIDDLE": "MIDDLE",
    "MOUSE_RIGHT": "RIGHT",
    "MOUSE_4": "MOUSE4",
    "MOUSE_5": "MOUSE5",
}


def _key_name(kind: str, code) -> str | None:
    """The settings name of a pyglet key, mouse button or wheel direction (None if it has none)."""
    if kind == "wheel":
        return "MOUSE_WHEEL_UP" if code > 0 else "MOUSE_WHEEL_DOWN"
    if kind == "mouse":
        return next((n for n, attr in _MOUSE.items() if getattr(pyglet.window.mouse, attr) == code), None)
    return _key_names_by_code().get(code)


@functools.cache
def _key_names_by_code() -> dict[int, str]:
    """pyglet key code -> the settings' name for it (pyglet has aliases: RETURN is ENTER, GRAVE is
    QUOTELEFT). Built on first use: ``pyglet.window`` needs a display the moment it is imported."""
    return {getattr(pyglet.window.key, n): n for n in sorted(KEY_NAMES) if not n.startswith("MOUSE_")}


def _key_code(name: str):
    """pyglet code for a settings key name: ('key', code), ('mouse', button) or ('wheel', +1 | -1)."""
    if name in ("MOUSE_WHEEL_UP", "MOUSE_WHEEL_DOWN"):
        return "wheel", 1 if name.endswith("UP") else -1
    if name.startswith("MOUSE_"):
        return "mouse", getattr(pyglet.window.mouse, _MOUSE[name])
    return "key", getattr(pyglet.window.key, name)


class GameWindow(pyglet.window.Window):
    """One window: the title screen and menus, and the levels of the campaign.

    Parameters
    ----------
    settings : Settings
    level_path : Path or None
        A level to play at once (loaded here, before the warm-up, unless ``warm_first``);
        None opens the title screen.
    warm_first : bool
        Compile the kernels behind a loading screen before ``level_path`` starts.
    settings_file : path, optional
        Where menu changes are saved (``--settings``); the default settings file otherwise.
    warm : BackgroundWarmUp, optional
        A warm-up already running (started before the window, so the two overlap); one is
        started here when needed and not given.
    """

    def __init__(
        self,
        settings: Settings,
        level_path: Path | None,
        seed: int = 0,
        record: str | None = None,
        warnings=(),
        screenshot_after: float | None = None,
        quit_after: float | None = None,
        warm_first: bool = False,
        settings_file=None,
        warm: BackgroundWarmUp | None = None,
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
        # The scene at a fraction of the window (settings.render_scale), upscaled; HUD at full size.
        self.scaled = ScaledTarget(self.ctx, resolve_render_scale(settings.render_scale, self.ctx))
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
        self.notice = ("", 0.0)
        self.sound = SoundOut(settings.volume, settings.mute)
        self.sound_director = SoundDirector()
        self.look = [0.0, 0.0]
        self.accumulator = 0.0
        self.paused = False
        self.screenshot_after = screenshot_after
        self.quit_after = quit_after
        # Seconds for --screenshot-after and --quit-after: from the first level frame when a level
        # was named (a busy machine may take seconds to load the kernels), else from the start.
        self.wall_time = 0.0
        self.waiting_for_level = level_path is not None
        self.finished_for = 0.0
        self.terminated_by: int | None = None
        self.editor = None  # the level editor (app/editor), made on first use
        self.settings_file = settings_file
        self.progress, progress_warnings = load_progress()
        self.save_problem_said = False
        for w in progress_warnings:
            print(f"warning: {w}", file=sys.stderr, flush=True)
        # Settings and save warnings: one line at the bottom (details in the log and on the
        # terminal), never over a hint.
        self.onboarding = Onboarding(" ".join([*warnings, *progress_warnings]), card=not record)
        try:
            self.campaign = load_campaign()
        except CampaignError as e:  # still playable: every shipped level, in file order
            print(f"warning: {e}", file=sys.stderr, flush=True)
            self.campaign = [CampaignEntry(p.stem, p.stem, "", p) for p in level_files()]
        self.menu = Menu(settings, self.progress, self.campaign, on_change=self.setting_changed)
        self.menu_renderer = MenuRenderer(self.renderer.hud)
        if settings.colour_blind:
            self.apply_palette()
        self.game: Game | None = None
        self.level_path = Path(level_path) if level_path is not None else None
        self.pending: tuple[Path, int | None] | None = None  # a level waiting for the warm-up
        self.crystals_found = 0
        self.completed_saved = False
        self.warm: BackgroundWarmUp | None = warm
        if (level_path is None or warm_first) and warm is None:
            self.warm = BackgroundWarmUp()
            self.warm.start()
        if level_path is None:
            self.menu.open("title")
            self.set_exclusive_mouse(False)
        elif warm_first:
            self.pending = (Path(level_path), None)
            self.set_exclusive_mouse(True)
        else:
            self.load(level_path)
            if record:
                self.start_recording()
            self.set_exclusive_mouse(True)
        self.last_draw: float | None = None
        self.level_drawn = False
        self._drawn_signature, self._drawn_times, self._drawn_at = None, 0, 0.0
        _timing("window open")

    # ----------------------------------------------------------------- levels
    def load(self, path: Path, checkpoint: int | None = None) -> None:
        self.level_path = Path(path)
        self.game = Game(load_level(path), seed=self.seed)
        self.crystals_found = 0
        self.completed_saved = False
        resume_at_checkpoint(self.game, checkpoint)
        self.progress.current, self.progress.checkpoint = self.level_path.stem, checkpoint_of(self.game)
        self.save_progress()
        self.renderer.forget_meshes()  # a new world: its meshes reuse the old one's keys and revisions
        s = self.settings
        self.game.radar_view = RadarView(s.radar, s.radar_range_scale, s.radar_height_scale)
        self.game.show_ghosts = self.settings.ghosts  # a view option: not part of the simulation's state
        self.game.ghost_view = self.ghost_view  # drawing only: never part of a replay
        self.level_time = 0.0
        self.finished_for = 0.0
        self.onboarding.level_started(self.game.level.hints)
        heap.settle()  # no collector stalls mid-level (see core/heap.py)
        self.sound_director.reset()
        self.set_caption(f"Across Dimensions - {self.game.level.name}")

    def next_level(self) -> None:
        """The next level of the campaign (of the shipped files, for a level outside it); after the
        last one, the title screen."""
        stem = self.level_path.stem
        if stem in [e.stem for e in self.campaign]:
            entry = next_in_campaign(self.campaign, stem)
            following = entry.path if entry else None
        else:
            files = level_files()
            names = [f.resolve() for f in files]
            i = names.index(self.level_path.resolve()) if self.level_path.resolve() in names else len(files)
            following = files[i + 1] if i + 1 < len(files) else None
        if following is not None:
            self.load(following)
        else:
            self.progress.current, self.progress.checkpoint = None, None
            self.save_progress()
            self.to_title()
            self.menu.message = "Campaign complete - thanks for playing!"

    # ----------------------------------------------------------------- menus
    def to_title(self) -> None:
        """Leave the level (its place is saved for Continue) for the title screen."""
        self.stop_recording()
        self.save_progress()
        self.game = None
        self.paused = True
        self.menu.message = ""
        self.menu.open("title")
        self.set_exclusive_mouse(False)

    def start_level(self, path: Path, checkpoint: int | None = None) -> None:
        """Play ``path`` from ``checkpoint`` as soon as the kernels are ready."""
        self.menu.close()
        self.pending = (Path(path), checkpoint)
        self.paused = False
        self.set_exclusive_mouse(True)
        self._start_pending()

    def _start_pending(self) -> None:
        if self.pending is None or (self.warm is not None and not self.warm.ready):
            return
        path, checkpoint = self.pending
        self.pending = None
        if self.warm is not None and self.warm.seconds is not None:
            _timing(f"kernels ready after {self.warm.seconds:.1f} s of warm-up")
        self.load(path, checkpoint)
        if self.record_path:
            self.start_recording()
        self.accumulator = 0.0

    def run_command(self, command: str | None) -> None:
        """Do what a menu row asked for (see :class:`~.menu.Menu`)."""
        if command is None:
            return
        if command == "resume":
            self.set_paused(False)
        elif command == "restart":
            self.stop_recording()
            self.start_level(self.level_path)
        elif command == "quit_to_title":
            self.to_title()
        elif command == "quit":
            pyglet.app.exit()
        elif command == "continue":
            stem, checkpoint = self.progress.continue_level([e.stem for e in self.campaign])
            if stem is not None:
                self.start_level(next(e.path for e in self.campaign if e.stem == stem), checkpoint)
        elif command.startswith("play:"):
            self.start_level(next(e.path for e in self.campaign if e.stem == command[5:]))

    def setting_changed(self, name: str) -> None:
        """A menu changed a setting: apply it now and save the settings file atomically."""
        s = self.settings
        if name == "bindings":
            self.bindings = {a: [_key_code(k) for k in s.keys_for(a)] for a in s.bindings}
        if name == "colour_blind":
            self.apply_palette()
        if name == "render_scale":
            self.scaled.scale = resolve_render_scale(s.render_scale, self.ctx)
        try:
            save_settings(s, self.settings_file)
        except (OSError, InputError, ValueError) as e:
            self.say(f"Settings not saved: {e}", 6.0)

    def apply_palette(self) -> None:
        """Switch the renderer's palette, through its hook when it has one (``set_palette(name)``)."""
        set_palette = getattr(self.renderer, "set_palette", None)
        if set_palette is not None:
            set_palette("colour_blind" if self.settings.colour_blind else "default")

    def save_progress(self) -> None:
        try:
            save_progress(self.progress)
        except (FileProblem, OSError) as e:
            if not self.save_problem_said:  # once: a read-only folder must not flood the screen
                self.save_problem_said = True
                self._recording_failed(f"Progress not saved: {e}")

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
                folder = replay_folder()
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
        if self.paused or self.game is None:
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

    def _menu_hit(self, x, y):
        """The menu row under the pointer (window coordinates, origin bottom-left) and a slider fraction."""
        view = self.menu.view()
        if view is None:
            return None
        fw, fh = self.get_framebuffer_size()
        sx, sy = fw / max(1, self.width), fh / max(1, self.height)
        return hit(view, fw, fh, x * sx, fh - y * sy)

    def on_mouse_motion(self, x, y, dx, dy):
        if self.menu.screen:
            found = self._menu_hit(x, y)
            if found is not None:
                self.menu.point(found[0])
            return
        if not self.paused:
            dyaw, dpitch = look_delta(self.settings, dx, dy)
            self.look[0] += dyaw
            self.look[1] += dpitch

    def on_mouse_drag(self, x, y, dx, dy, buttons, modifiers):
        self.on_mouse_motion(x, y, dx, dy)

    def on_mouse_press(self, x, y, button, modifiers):
        if self.menu.screen:
            if self.menu.capturing:
                name = _key_name("mouse", button)
                if name:
                    self.menu.capture(name)
                return
            found = self._menu_hit(x, y)
            if found is not None and button == pyglet.window.mouse.LEFT:
                self.run_command(self.menu.click(*found))
            elif button == pyglet.window.mouse.RIGHT:
                self.run_command(self.menu.input("back"))
            return
        if self.onboarding.click():
            return
        if self.paused:
            self.set_paused(False)
            return
        self.mouse_buttons.add(button)
        self.count_press("mouse", button)

    def on_mouse_release(self, x, y, button, modifiers):
        self.mouse_buttons.discard(button)

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y):
        if self.menu.screen:
            if self.menu.capturing and scroll_y:
                self.menu.capture(_key_name("wheel", scroll_y))
            elif scroll_y:
                self.menu.scroll(-1 if scroll_y > 0 else 1)
            return
        if scroll_y:
            notches = max(1, round(abs(scroll_y)))
            self.count_press("wheel", 1 if scroll_y > 0 else -1, notches)

    def on_key_press(self, symbol, modifiers):
        action = self.pressed_action("key", symbol)
        if self.menu.screen:
            name = _key_name("key", symbol)
            if self.menu.capturing:
                if name:
                    self.menu.capture(name)
                return pyglet.event.EVENT_HANDLED
            verb = menu_verb(name, self.settings) if name else None
            if verb:
                self.run_command(self.menu.input(verb))
            elif action in ("screenshot", "toggle_fullscreen"):
                self.screenshot() if action == "screenshot" else self.set_fullscreen(not self.fullscreen)
            return pyglet.event.EVENT_HANDLED  # keep Esc from closing the window
        if self.game is None:  # a level waiting for the kernels
            if action == "screenshot":
                self.screenshot()
            return pyglet.event.EVENT_HANDLED
        if self.onboarding.key(action, pyglet.window.key.symbol_string(symbol)):
            return pyglet.event.EVENT_HANDLED  # the card took it, or the hints key
        self.count_press("key", symbol)
        if action == "toggle_mute":
            self.say("Sound muted" if self.sound.toggle_mute() else "Sound on", 1.5)
        elif action == "pause":
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

        try:  # the file may have broken on disk since the level was loaded: the game goes on
            if self.editor is None:
                self.editor = EditorMode(self, self.level_path)
            self.editor.enter(from_play)
        except (InputError, OSError) as e:
            self._recording_failed(f"Cannot open the editor: {str(e).splitlines()[0]}")

    def on_activate(self):
        self.was_active = True

    def on_deactivate(self):
        # Losing focus pauses, as in any game; but a window that never had focus
        # (no window manager, e.g. under Xvfb) keeps running.
        if getattr(self, "was_active", False):
            self.set_paused(True)

    def set_paused(self, paused: bool) -> None:
        """Pause (opening the pause menu) or resume play."""
        if self.game is None or (paused and self.paused and self.menu.screen):
            return  # already paused: losing focus in a sub-menu keeps it open
        if paused != self.paused:
            self.sound.ui("menu_back" if paused else "menu_select")
        self.paused = paused
        if paused:
            self.menu.open("pause")
            self.save_progress()  # quitting from here (closing the window) keeps the level to continue
        else:
            self.menu.close()
        self.set_exclusive_mouse(not paused)
        self.mouse_buttons.clear()
        self.presses.clear()
        self.wheel_held.clear()
        self.look = [0.0, 0.0]

    def on_close(self):
        self.stop_recording()
        if self.game is not None:
            self.save_progress()
        super().on_close()

    # ------------------------------------------------------------------- loop
    def update(self, dt: float) -> None:
        """Advance by ``dt`` wall-clock seconds: as many fixed ticks as fit."""
        if self.game is not None:
            self.waiting_for_level = False
        if not self.waiting_for_level:
            self.wall_time += dt
        if dt > 0:
            self.fps = 0.9 * self.fps + 0.1 / dt if self.fps else 1.0 / dt
        text, left = self.notice
        self.notice = (text, left - dt)
        self.onboarding.wall(dt)
        for name in self.onboarding.take_ui_cues():
            self.sound.ui(name)
        if self.screenshot_after is not None and self.wall_time >= self.screenshot_after:
            self.screenshot_after = None
            self._pending_shot = True
        if self.quit_after is not None and self.wall_time >= self.quit_after:
            pyglet.app.exit()
            return
        if self.warm is not None:
            self.menu.progress_bar = None if self.warm.ready else (self.warm.done, self.warm.total, self.warm.label)
            if self.warm.ready and self.warm.error is not None:
                self.say(f"Kernel warm-up failed: {self.warm.error}", 8.0)
                self.warm.error = None
        self._start_pending()
        if self.paused or self.game is None or self.menu.screen:
            return
        if self.onboarding.before_tick(self.held("w_ana") or self.held("w_kata")):
            self.look = [0.0, 0.0]  # the card is open: the mouse and keys do not reach the game
            self.presses.clear()
            return
        self.accumulator += dt
        steps = 0
        while self.accumulator >= DT and steps < MAX_CATCH_UP:
            actions = self.read_actions()
            self.game.step(actions)
            self.onboarding.ticked(actions, DT)
            self.sound.play(self.sound_director.cues(self.game, DT))
            self.crystals_found += sum(e.kind == "crystal_collected" for e in self.game.events)
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
        checkpoint = checkpoint_of(self.game)
        if checkpoint != self.progress.checkpoint and self.game.outcome != "complete":
            self.progress.checkpoint = checkpoint
            self.save_progress()
        if self.game.outcome == "complete":
            if not self.completed_saved:
                self.completed_saved = True
                self.level_complete()
            if self.recorder:
                self.stop_recording()
            self.finished_for += steps * DT
            if self.finished_for >= NEXT_LEVEL_DELAY:
                self.next_level()

    def level_complete(self) -> None:
        """Save the finished level: best time, crystals, and the next level for Continue."""
        stem = self.level_path.stem
        best = self.progress.finish(stem, self.game.time)
        total = len(getattr(self.game.level, "crystals", ()))
        if total:
            self.progress.found_crystals(stem, self.crystals_found, total)
        entry = next_in_campaign(self.campaign, stem)
        self.progress.current, self.progress.checkpoint = (entry.stem if entry else None), None
        self.save_progress()
        text = f"Level complete in {self.game.time:.1f} s" + (" - best time!" if best else "")
        self.say(text, NEXT_LEVEL_DELAY)

    def current_frame(self):
        """The game's frame with the app's HUD additions (fps, pause, notices)."""
        frame = self.game.frame(alpha=self.accumulator / DT, fov_y_deg=self.settings.fov_deg, pip=self.pip_on)
        hud = frame.hud
        if hud.message:  # the game's prompts name actions ({manipulate}); show the player's keys
            hud.message = self.with_keys(hud.message)
        for label in hud.labels:  # and so do the labels beside things (the manipulation keys)
            label.text = self.with_keys(label.text)
        hud.fps = self.fps if self.show_fps else None
        hud.paused = False  # the pause menu dims the view and says so
        text, left = self.notice
        if left > 0 and text:
            hud.message = text
        self.onboarding.hints_on = self.level_time < 1e8  # the editor's play-from-here skips them
        self.onboarding.decorate(hud, lambda text: fill_keys(text, self.settings))
        if self.recorder and not hud.message:
            hud.message = "REC"
        return frame

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

    def draw(self, dt: float) -> None:
        """pyglet's redraw, skipped (no draw, no buffer swap) while a still menu is on screen."""
        if self.game is None or self.menu.screen:
            self._start_pending()
            if self.warm is not None:
                self.menu.progress_bar = None if self.warm.ready else (self.warm.done, self.warm.total, self.warm.label)
            signature = (repr(self.menu.view()), self.pending is None, self.notice[0])
            now = time.perf_counter()
            fresh = signature != self._drawn_signature
            if not fresh and self._drawn_times >= 2 and now - self._drawn_at < IDLE_REDRAW:
                return  # both buffers already hold this picture
            self._drawn_times = 1 if fresh else self._drawn_times + 1
            self._drawn_signature, self._drawn_at = signature, now
        super().draw(dt)

    def on_draw(self):
        # One update per drawn frame: the wall clock is read here, in the app,
        # and reaches the simulation only as a whole number of fixed ticks.
        now = time.perf_counter()
        self.update(0.0 if self.last_draw is None else min(now - self.last_draw, 0.25))
        self.last_draw = now
        fw, fh = self.get_framebuffer_size()
        self.draw_view(self.ctx.screen, (0, 0, fw, fh))
        if self.game is not None and not self.level_drawn:
            self.level_drawn = True
            _timing("first level frame")
        if getattr(self, "_pending_shot", False):
            self._pending_shot = False
            self.screenshot()

    def draw_view(self, target, viewport) -> None:
        """Draw into ``target`` (the window's screen, or a screenshot's framebuffer): the level (when
        one is loaded or paused) at the render scale, then the HUD, or the menus, at full size; or,
        with no level yet, the loading screen."""
        view = self.menu.view()
        if self.game is not None:
            frame = self.current_frame()
            playing = view is None
            if self.scaled.begin(tuple(viewport[2:])):
                self.renderer.draw(frame, self.scaled.viewport, hud=False)
                if playing:
                    self._debug_draw(frame, self.scaled.viewport)
                    self.renderer.draw_radar(frame, viewport, self.scaled.scale)
                self.scaled.present(target, viewport)
                if playing:
                    self.renderer.draw_overlay(frame, viewport, radar=False)
            else:
                target.use()
                self.renderer.draw(frame, viewport, hud=playing)
                if playing:
                    self._debug_draw(frame, viewport)
            if playing and self.pip_on:
                draw_pip(self.renderer, frame, viewport, self.settings.pip_size)
        else:
            target.use()
            self.ctx.clear(0.02, 0.03, 0.06, 1.0)
        if view is None and self.game is None:  # a level waiting for the kernels: the title's backdrop
            from .menu import MenuView

            w = self.warm
            progress = (w.done, w.total, w.label) if w is not None and not w.ready else (1, 1, "ready")
            view = MenuView("title", "ACROSS DIMENSIONS", [], 0, 0, 0, "Starting...", progress=progress)
        if view is not None:
            target.use()
            self.menu_renderer.draw(view, viewport)

    def _debug_draw(self, frame, viewport) -> None:
        if self.show_debug_draw:
            self.debug_overlay = self.debug_overlay or DebugOverlay(self.ctx)
            self.debug_overlay.draw_game(self.game, frame.camera, viewport)

    def screenshot(self) -> Path | None:
        """Save what the window shows as a PNG in the player's pictures folder (see
        :mod:`.screenshots`); a failure is a notice, never an exit.

        The frame is drawn again into an offscreen framebuffer of the window's
        size (reading the window's own back buffer is not portable in a core
        profile), through the same render scale as the window.
        """
        fw, fh = self.get_framebuffer_size()

        def write(path):
            with Offscreen(self.ctx, fw, fh) as target:
                self.draw_view(target.fbo, target.viewport)
                target.save_png(path)

        try:
            path, message = save_screenshot(write)
        finally:
            self.ctx.screen.use()
        if path is None:
            self._recording_failed(message)
            return None
        print(f"screenshot saved: {path}", flush=True)
        self.say(message, 2.0)
        return path


def _timing(what: str) -> None:
    """With ``ACROSS_DIMENSIONS_TIMING`` set, print when ``what`` happened (Unix time), for the
    start-up measurements in the README."""
    if os.environ.get("ACROSS_DIMENSIONS_TIMING"):
        print(f"timing: {what} at {time.time():.3f}", flush=True)


class _Missing(dict):
    """format_map helper: unknown ``{names}`` stay as written."""

    def __missing__(self, key):
        return "{" + key + "}"


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
    if args.level or args.record or getattr(args, "edit", False):  # a level named, or needed: straight into it
        path = resolve_level(args.level) if args.level else level_files()[0]
        load_level(path)  # a broken level is reported before a window opens
    if args.record:
        check_record_path(args.record)
    editing = getattr(args, "edit", False)
    warm = None
    if editing:  # the editor builds games of its own from its first frame: compile before it opens
        warm_up()
    else:  # started first, so loading the kernels overlaps with opening the window
        warm = BackgroundWarmUp()
        warm.start()
    try:
        # The window opens at once; the kernels compile behind its title (or loading) screen.
        window = GameWindow(
            settings,
            path,
            seed=args.seed,
            record=args.record,
            warnings=[warning_screen_line(warnings, args.settings)] if line else [],
            screenshot_after=args.screenshot_after,
            quit_after=args.quit_after,
            warm_first=path is not None and not editing,
            settings_file=args.settings,
            warm=warm,
        )
        if editing:
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
