"""What the views of one window share, and the moves between them.

A :class:`Session` lives as long as the window. It holds the player's settings and progress,
the campaign, the menus' model, the renderer, the sound, notices, the hints, the recording and
the kernel warm-up; and it moves the window between views: :meth:`Session.start_level`,
:meth:`Session.to_title`, :meth:`Session.next_level`, :meth:`Session.open_editor`. Views reach
each other only through it and through their own methods.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from ..core.errors import InputError
from ..core.fileio import FileProblem
from ..render.menu import MenuRenderer
from ..render.palette import settings_palette
from ..render.renderer import Renderer
from ..render.scale import ScaledTarget, resolve_render_scale
from ..render.text_layout import set_text_size
from ..world.campaign import CampaignEntry, CampaignError, load_campaign, next_in_campaign
from ..world.resources import is_prologue_file, level_files
from .captions import CaptionBoard
from .editor import missing_message
from .input import Bindings
from .menu import Menu
from .onboarding import Onboarding
from .play_options import play_options
from .recording import Recording
from .saves import load_progress, save_progress
from .settings import Settings, save_settings
from .sound import SoundDirector, SoundOut
from .views.menus import TitleView
from .views.play import PlayView
from .views.prologue import FlatPlayView
from .views.startup import StartupView
from .warmup import BackgroundWarmUp


@dataclass
class Start:
    """How the window starts: the command line's choices.

    Attributes
    ----------
    level_path : Path or None
        A level to play at once; None opens the title screen.
    seed : int
    record : str or None
        ``--record FILE``: record the first level played to FILE.
    warnings : list of str
        Settings warnings, shown as one line at the bottom.
    screenshot_after, quit_after : float or None
        Seconds, from the level's first frame when a level was named, else from the window's.
    warm_first : bool
        Compile the kernels behind a loading screen before ``level_path`` starts.
    settings_file : path or None
        Where menu changes are saved (``--settings``); the default settings file otherwise.
    warm : BackgroundWarmUp or None
        The warm-up to use (tests give a stand-in); one is made when needed and not given.
        Either starts once the window's first frame is up (:meth:`Session.after_first_frame`).
    edit : bool
        Open ``level_path`` in the level editor.
    """

    level_path: Path | None = None
    seed: int = 0
    record: str | None = None
    warnings: list[str] = field(default_factory=list)
    screenshot_after: float | None = None
    quit_after: float | None = None
    warm_first: bool = False
    settings_file: str | os.PathLike | None = None
    warm: BackgroundWarmUp | None = None
    edit: bool = False


class Session:
    """The shared state of one window's views.

    Parameters
    ----------
    window : GameWindow
    settings : Settings
    start : Start
    """

    def __init__(self, window, settings: Settings, start: Start):
        self.window = window
        self.settings, self.settings_file, self.seed = settings, start.settings_file, start.seed
        self.bindings = Bindings(settings)
        self.renderer = Renderer(window.ctx)
        # The scene at a fraction of the window (settings.render_scale), upscaled; HUD at full size.
        self.scaled = ScaledTarget(window.ctx, resolve_render_scale(settings.render_scale, window.ctx))
        self.menu_renderer = MenuRenderer(self.renderer.hud)
        self.sound = SoundOut(settings.volume, settings.mute, defer=True)  # opened after the first frame
        self.sound_director = SoundDirector()
        self.options = play_options(settings)
        self.debug_overlay = None  # the physics overlay's GL objects (render/debug_draw.py), made on first use
        self.flat_renderer = None  # the prologue's renderer (render/flatland.py), made on first use
        self.notice = ("", 0.0)  # (text, seconds left)
        self.progress, progress_warnings = load_progress()
        self.save_problem_said = False
        for w in progress_warnings:
            print(f"warning: {w}", file=sys.stderr, flush=True)
        self.campaign = _campaign()
        #: Levels the campaign lets a player skip (the prologue): the next one is open without them.
        self.optional = frozenset(e.stem for e in self.campaign if e.optional)
        # The flat-being card teaches what the prologue did: not again after it.
        played = any(stem in self.progress.finished for stem in self.optional)
        # Settings and save warnings: one line at the bottom (details in the log and on the
        # terminal), never over a hint.
        warning = " ".join([*start.warnings, *progress_warnings])
        self.onboarding = Onboarding(warning, card=not start.record and not played)
        self.menu = Menu(settings, self.progress, self.campaign, on_change=self.setting_changed)
        self.recording = Recording(start.record, self.say, self.warn)
        self.warm = start.warm
        if (start.level_path is None or start.warm_first) and self.warm is None:
            self.warm = BackgroundWarmUp()
        self.editor = None  # the level editor's view (app/editor), made on first use
        if settings.colour_blind or settings.high_contrast:
            self.apply_palette()
        set_text_size(settings.text_size)
        self.captions = CaptionBoard()  # sounds made visible, shown when the setting is on

    def after_first_frame(self) -> None:
        """Start what the first frame does not need, once it is on screen: the kernel warm-up and
        the audio device.

        Both would delay it: the warm-up's thread takes the interpreter's lock from the window's
        imports and set-up (about 0.3 s of a 2 s start on two cores), and opening the audio device
        (pyglet's media drivers and codecs, which look for libraries with ``ldconfig``) about
        0.25 s. The title or the loading view then shows the warm-up's progress.
        """
        if self.warm is not None:
            self.warm.start_once()
        self.sound.open()

    # ---------------------------------------------------------------- moves
    def first_view(self, start: Start) -> None:
        """Show the title screen, or the level named on the command line (in the editor with ``edit``)."""
        if start.level_path is None:
            self.window.show_view(TitleView(self))
            return
        if start.edit and self.warm is not None and not self.warm.ready:  # the window shows the compile
            self.window.show_view(StartupView(self, Path(start.level_path), edit=True))
            return
        self.start_level(start.level_path)
        if start.edit:
            self.open_editor(self.window.current_view, from_play=False)

    def start_level(self, path: Path, checkpoint: int | None = None, trial: bool = False) -> None:
        """Play ``path`` from ``checkpoint`` (or as a time ``trial`` against its ghost, from its
        start), once the kernels are ready (a loading view until then). The Flatland prologue
        needs none of them: it starts at once, while they compile, and has no time trial."""
        self.menu.close()
        if is_prologue_file(path):
            self.window.show_view(FlatPlayView(self, Path(path)))
            return
        if self.warm is not None and not self.warm.ready:
            self.window.show_view(StartupView(self, Path(path), checkpoint, trial=trial))
            return
        if self.warm is not None and self.warm.seconds is not None:
            timing(f"kernels ready after {self.warm.seconds:.1f} s of warm-up")
        self.window.show_view(PlayView(self, Path(path), checkpoint, trial))

    def to_title(self, message: str = "") -> None:
        """Leave the level (its place is saved for Continue) for the title screen."""
        self.recording.stop()
        self.save_progress()
        self.menu.message = message
        self.window.show_view(TitleView(self))

    def next_level(self, after: Path) -> None:
        """The level after ``after`` in the campaign (in the shipped files, for a level outside it);
        after the last one, the title screen."""
        stem = after.stem
        if stem in [e.stem for e in self.campaign]:
            entry = next_in_campaign(self.campaign, stem)
            following = entry.path if entry else None
        else:
            files = level_files()
            names = [f.resolve() for f in files]
            i = names.index(after.resolve()) if after.resolve() in names else len(files)
            following = files[i + 1] if i + 1 < len(files) else None
        if following is not None:
            self.start_level(following)
            return
        self.progress.current, self.progress.checkpoint = None, None
        self.to_title("Campaign complete - thanks for playing!")

    def open_editor(self, play, from_play: bool = True) -> None:
        """Open the level editor (an optional extra) over ``play``; its own key brings the game back."""
        problem = missing_message()
        if problem:
            self.say(problem, 8.0)
            return
        from .editor.mode import EditorView  # the optional extra's GUI libraries: only when asked for

        try:  # the file may have broken on disk since the level was loaded: the game goes on
            if self.editor is None:
                self.editor = EditorView(self, play.level_path)
            self.editor.enter(play, from_play)
        except (InputError, OSError) as e:
            self.warn(f"Cannot open the editor: {str(e).splitlines()[0]}")

    # ---------------------------------------------------------------- services
    def tick(self, dt: float) -> None:
        """``dt`` wall-clock seconds passed: notices, the hints' animations, the warm-up's failure."""
        text, left = self.notice
        self.notice = (text, left - dt)
        self.onboarding.wall(dt)
        for name in self.onboarding.take_ui_cues():
            self.sound.ui(name)
        if self.warm is not None and self.warm.ready and self.warm.error is not None:
            self.say(f"Kernel warm-up failed: {self.warm.error}", 8.0)
            self.warm.error = None

    @property
    def notice_text(self) -> str:
        """The notice on screen now, or ``""``."""
        text, left = self.notice
        return text if left > 0 else ""

    def say(self, text: str, seconds: float = 4.0) -> None:
        """Show ``text`` for ``seconds`` (over the level's prompts)."""
        self.notice = (text, seconds)

    def warn(self, message: str) -> None:
        """A problem the player should know of: on screen, and on the terminal."""
        self.say(message, 8.0)
        print(f"warning: {message}", file=sys.stderr, flush=True)

    def save_progress(self) -> None:
        try:
            save_progress(self.progress)
        except (FileProblem, OSError) as e:
            if not self.save_problem_said:  # once: a read-only folder must not flood the screen
                self.save_problem_said = True
                self.warn(f"Progress not saved: {e}")

    def setting_changed(self, name: str) -> None:
        """A menu changed a setting: apply it now and save the settings file atomically."""
        s = self.settings
        if name == "bindings":
            self.bindings.update(s)
        if name in ("colour_blind", "high_contrast"):
            self.apply_palette()
        if name == "text_size":
            set_text_size(s.text_size)
        if name == "render_scale":
            self.scaled.scale = resolve_render_scale(s.render_scale, self.window.ctx)
        try:
            save_settings(s, self.settings_file)
        except (OSError, InputError, ValueError) as e:
            self.say(f"Settings not saved: {e}", 6.0)

    def apply_palette(self) -> None:
        """Switch the renderer's palette, through its hook when it has one (``set_palette(name)``)."""
        set_palette = getattr(self.renderer, "set_palette", None)
        if set_palette is not None:
            set_palette(settings_palette(self.settings.colour_blind, self.settings.high_contrast))


def _campaign() -> list[CampaignEntry]:
    try:
        return load_campaign()
    except CampaignError as e:  # still playable: every shipped level, in file order
        print(f"warning: {e}", file=sys.stderr, flush=True)
        return [CampaignEntry(p.stem, p.stem, "", p) for p in level_files()]


def timing(what: str) -> None:
    """With ``ACROSS_DIMENSIONS_TIMING`` set, print when ``what`` happened, in seconds from the
    command's start (the process's), for the start-up measurements in the README."""
    if os.environ.get("ACROSS_DIMENSIONS_TIMING"):
        print(f"timing: {what} at {time.time() - _started():.2f} s", flush=True)


_IMPORTED = time.time()  # the fallback start: where the process's own start cannot be read


def _started() -> float:
    """When this process started (Unix time): from ``/proc`` on Linux, else when this module loaded."""
    try:
        fields = Path("/proc/self/stat").read_text().rsplit(")", 1)[1].split()
        ticks = int(fields[19])  # field 22 of stat(5), counted after the ") " that ends the name
        boot = next(int(ln.split()[1]) for ln in Path("/proc/stat").read_text().splitlines() if ln.startswith("btime"))
        return boot + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, StopIteration):
        return _IMPORTED
