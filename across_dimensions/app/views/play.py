"""The play view: a level being played, its input, its fixed-tick loop and its picture.

The loop is a fixed-tick accumulator: wall-clock time (measured by the window, never by the
simulation) fills an accumulator that is drained in steps of ``1 / TICK_RATE``, at most
``MAX_CATCH_UP`` per frame so a long stall does not spiral; the frame is drawn interpolated by
the remainder. Each tick reads :class:`~across_dimensions.app.input.PlayInput`, so a tap shorter
than a frame still reaches the game. Progress (:mod:`..saves`) is saved when the level starts,
reaches a checkpoint, is finished or left. Esc pushes the pause menu; the level's end pushes
the level-complete view; the editor key pushes the level editor, which talks to this view only
through its methods (:meth:`PlayView.eye`, :meth:`PlayView.play_game`, :attr:`PlayView.level_path`).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pyglet

from ...core import heap
from ...game.sim import DT, Game, RadarView
from ...game.stranded import RESTART_ACTION, stranded
from ...render.debug_draw import DebugOverlay
from ...render.pip import draw_pip, warm_views
from ...world.level import load_level
from ..energy_trail import EnergyTrail
from ..input import PlayInput, with_keys
from ..onboarding import fill_keys
from ..saves import checkpoint_of, resume_at_checkpoint
from ..settings import look_delta
from ..time_trial import Race, RunLog
from .base import View
from .complete import OUTRO_SECONDS, LevelCompleteView
from .menus import PauseView

#: Most ticks run in one frame: a machine that falls further behind drops time instead.
MAX_CATCH_UP = 5


class PlayView(View):
    """A level being played.

    Parameters
    ----------
    session : Session
    path : Path
        The level file.
    checkpoint : int or None
        Where to start: the level's start (None) or the index of a checkpoint reached before.
    trial : bool
        A time trial: the level from its start against its ghost (:class:`~..time_trial.Race`).
    """

    shows_level = True
    #: Seconds of play after the goal before the level's results.
    finish_seconds = OUTRO_SECONDS
    #: Said as the next level starts ("": nothing).
    farewell = ""
    #: The game was started by the level editor: finishing it goes back there, not to the next level.
    from_editor = False

    def __init__(self, session, path: Path, checkpoint: int | None = None, trial: bool = False):
        super().__init__(session)
        self.input = PlayInput(session.bindings, self.window.keys, session.settings)
        self.trial = trial
        self.load(path, None if trial else checkpoint)
        if session.recording.path_given:  # --record FILE: the first level played
            self.start_recording()

    # ---------------------------------------------------------------- the level
    def load(self, path: Path, checkpoint: int | None = None) -> None:
        """Start the level at ``path`` (at ``checkpoint``), from scratch."""
        s = self.session
        self._path = Path(path)
        self.from_editor = False
        self.game = Game(load_level(path), seed=s.seed)
        self.accumulator = 0.0
        self.crystals_found = 0
        self.hints = True
        self.energy_trail, self._drawn_at = EnergyTrail(), time.perf_counter()
        resume_at_checkpoint(self.game, checkpoint)
        # A run from the start may become the level's ghost; a time trial races the one kept.
        self.run_log = RunLog(self.game, self._path.stem) if checkpoint_of(self.game) is None else None
        self.race = None
        if self.trial and self.run_log is not None:
            self.race, line = Race.of_level(self._path.stem, self.run_log.level_hash, s.warn)
            s.say(line, 4.0)
        # A level is where Continue resumes only when it is open in the campaign.
        stems = [e.stem for e in s.campaign]
        self.continues = s.progress.play(self._path.stem, checkpoint_of(self.game), stems, s.optional)
        if self.game.level.secrets:  # the level select can say how many there are to find
            s.progress.found_secrets(self._path.stem, (), len(self.game.level.secrets))
        s.save_progress()
        s.renderer.forget_meshes()  # a new world: its meshes reuse the old one's keys and revisions
        st = s.settings
        self.game.radar_view = RadarView(st.radar, st.radar_range_scale, st.radar_height_scale)
        self.game.show_ghosts = st.ghosts  # a view option: not part of the simulation's state
        self.game.ghost_view = s.options.ghosts  # drawing only: never part of a replay
        s.onboarding.level_started(self.game.level.hints)
        self.game.entity_sections.prepare(self.game.entities, self.game.states)  # no first-sight stalls either
        self._warm_views = self.game.level.camera.frustum
        heap.settle()  # no collector stalls mid-level (see core/heap.py)
        s.sound_director.reset()
        s.captions.clear()

    @property
    def level_path(self) -> Path:
        """The level file played."""
        return self._path

    def eye(self) -> tuple[np.ndarray, float, float, float]:
        """The player's eye ``(3,) float64``, yaw and pitch (radians) and w."""
        p = self.game.player
        return p.eye().copy(), float(p.yaw), float(p.pitch), float(p.position[3])

    def play_game(self, game: Game, notice: str, path: Path | None = None) -> None:
        """Play ``game`` (of this level, edited, or of the level file ``path`` the editor made) in place
        of the one running, without the level's hints (they were read when it started), saying ``notice``."""
        self._path = Path(path) if path is not None else self._path
        self.from_editor = True
        self.game = game
        game.entity_sections.prepare(game.entities, game.states)
        self._warm_views = game.level.camera.frustum
        self.run_log = self.race = None  # the editor's game: neither a run to keep nor a race
        self.hints = False
        self.accumulator = 0.0
        self.input.forget()
        self.session.say(notice, 4.0)

    def start_recording(self) -> None:
        """Restart the level and record it (a replay always starts at the spawn)."""
        self.load(self._path)
        self.session.recording.start(self.game, self._path)

    def restart_if_lost(self) -> bool:
        """Restart from the last checkpoint (as Continue would), but only once the level can no
        longer be won (the HUD says so and names the key); True when it restarted."""
        if stranded(self.game) is None:
            return False
        checkpoint = checkpoint_of(self.game)
        self.session.recording.stop()  # a replay runs from the spawn to the end, never across a restart
        self.load(self._path, checkpoint)
        self.session.say("Restarted from the last checkpoint" if checkpoint is not None else "Restarted", 3.0)
        return True

    # ---------------------------------------------------------------- life
    def on_show(self) -> None:
        self.window.set_exclusive_mouse(True)
        self.window.set_caption(f"Across Dimensions - {self.game.level.name}")
        self.input.forget()  # presses and buttons from before a pause or the editor are not this tick's
        self.input.use(self.session.settings)  # changed in the pause menu's settings, maybe

    def on_update(self, dt: float) -> None:
        self.run(dt)
        if self.game.outcome == "complete":
            self.window.push_view(LevelCompleteView(self.session, self))
            return
        checkpoint = checkpoint_of(self.game)
        progress = self.session.progress
        if self.continues and checkpoint != progress.checkpoint:
            progress.checkpoint = checkpoint
            self.session.save_progress()

    def run(self, dt: float) -> int:
        """Advance by ``dt`` wall-clock seconds: as many fixed ticks as fit (none while the
        teaching card is open). Returns the number of ticks."""
        input_ = self.input
        if self.session.onboarding.before_tick(input_.held("w_ana") or input_.held("w_kata")):
            input_.drop_pending()  # the card is open: the mouse and keys do not reach the game
            input_.latched.clear()  # nor a toggle switched on by the key that opened it
            return 0
        self.accumulator += dt
        steps = 0
        while self.accumulator >= DT and steps < MAX_CATCH_UP:
            self.tick()
            self.accumulator -= DT
            steps += 1
        if steps == MAX_CATCH_UP:
            self.accumulator = 0.0  # too far behind: drop time rather than spiral
        return steps

    def tick(self) -> None:
        """One fixed tick of the game with the player's input."""
        s = self.session
        actions = self.read_actions()
        self.game.step(actions)
        s.onboarding.ticked(actions, DT, self.game)
        cues = s.sound_director.cues(self.game, DT)
        s.sound.play(cues)
        s.captions.heard(cues, DT)
        self.crystals_found += sum(e.kind == "crystal_collected" for e in self.game.events)
        found = {e.weapon for e in self.game.events if e.kind == "weapon_acquired"}
        if found - s.progress.arsenal:  # a weapon is the campaign's progress as soon as it is found
            s.progress.arsenal |= found
            s.save_progress()
        self._keep_secrets()
        if any(e.kind == "respawned" for e in self.game.events):  # a fall is never silent
            where = "the last checkpoint" if checkpoint_of(self.game) is not None else "the start"
            s.say(f"You fell out of the level: back at {where}.", 3.0)
        s.recording.record(actions)
        reached = self.run_log.record(self.game, actions) if self.run_log is not None else None
        if reached is not None and self.race is not None:
            s.say(self.race.split(reached, self.game.tick, self.game.level.checkpoints[reached].name), 3.0)

    def _keep_secrets(self) -> None:
        """Save each secret as it is found (not at the level's end): leaving the level keeps it."""
        found = [e for e in self.game.events if e.kind == "secret_found"]
        if found and not self.from_editor:
            self.session.progress.found_secrets(self._path.stem, [e.name for e in found], found[0].total)
            self.session.save_progress()

    def read_actions(self):
        """This tick's actions (see :class:`~across_dimensions.app.input.PlayInput`)."""
        return self.input.read()

    def on_close(self) -> bool:
        self.session.save_progress()
        return False

    def on_deactivate(self) -> None:
        self.pause()  # losing focus pauses, as in any game

    def pause(self) -> None:
        self.window.push_view(PauseView(self.session, self))

    # ---------------------------------------------------------------- drawing
    def on_draw(self, target, viewport) -> None:
        self.draw_scene(target, viewport, playing=True)

    def draw_scene(self, target, viewport, playing: bool) -> None:
        """Draw the level into ``target``: at the render scale, then the HUD (only while
        ``playing``: a menu over a paused level shows the scene alone) at full size."""
        s = self.session
        frame = self.current_frame()
        # A level with the frustum switch: its first frame is drawn over the switch's view, so
        # the switch finds its programs compiled (see render.pip.warm_views).
        views = self.game.frame(pip=True) if playing and self._warm_views else None
        self._warm_views = self._warm_views and not playing
        if s.scaled.begin(tuple(viewport[2:])):
            if views is not None:
                warm_views(s.renderer, views, s.scaled.viewport)
            s.renderer.draw(frame, s.scaled.viewport, hud=False)
            if playing:
                self._debug_draw(frame, s.scaled.viewport)
                s.renderer.draw_radar(frame, viewport, s.scaled.scale)
            s.scaled.present(target, viewport)
            if playing:
                s.renderer.draw_overlay(frame, viewport, radar=False)
        else:
            target.use()
            if views is not None:
                warm_views(s.renderer, views, viewport)
            s.renderer.draw(frame, viewport, hud=playing)
            if playing:
                self._debug_draw(frame, viewport)
        if playing and s.options.pip:
            draw_pip(s.renderer, frame, viewport, s.settings.pip_size)

    def _debug_draw(self, frame, viewport) -> None:
        s = self.session
        if s.options.debug_draw:
            s.debug_overlay = s.debug_overlay or DebugOverlay(self.window.ctx)
            s.debug_overlay.draw_game(self.game, frame.camera, viewport)

    def current_frame(self):
        """The game's frame with the app's HUD additions (fps, notices, hints)."""
        s = self.session
        frame = self.game.frame(alpha=self.accumulator / DT, fov_y_deg=s.settings.fov_deg, pip=s.options.pip)
        hud = frame.hud
        if hud.message:  # the game's prompts name actions ({manipulate}); show the player's keys
            hud.message = with_keys(hud.message, s.settings)
        for label in hud.labels:  # and so do the labels beside things (the manipulation keys)
            label.text = with_keys(label.text, s.settings)
        now = time.perf_counter()
        hud.energy = self.energy_trail.update(hud.energy, now - self._drawn_at)
        self._drawn_at = now
        hud.fps = self.window.fps if s.options.show_fps else None
        hud.captions = s.captions.shown(s.settings.captions)
        if self.input.latched:  # toggled actions stay on until pressed again: say which
            label = self.input.latched_label()
            label.text = with_keys(label.text, s.settings)
            hud.labels.append(label)
        hud.paused = False  # the pause menu dims the view and says so
        if s.notice_text:
            hud.message = s.notice_text
        s.onboarding.hints_on = self.hints
        s.onboarding.decorate(hud, lambda text: fill_keys(text, s.settings))
        if s.recording.active and not hud.message:
            hud.message = "REC"
        if self.race is not None:
            hud.message = hud.message or self.race.clock(self.game.completed_tick or self.game.tick)
            self.race.figure(self.game, frame, self.accumulator / DT)
        return frame

    # ---------------------------------------------------------------- input
    def on_key_press(self, symbol, modifiers) -> None:
        s = self.session
        action = s.bindings.action_of("key", symbol)
        if s.onboarding.key(action, pyglet.window.key.symbol_string(symbol)):
            return  # the card took it, or the hints key
        self.input.press("key", symbol)
        if self.window_key(action):
            return
        if action == "pause":
            self.pause()
        elif action == "editor":
            s.open_editor(self)
        elif action == "record":
            s.recording.stop() if s.recording.active else self.start_recording()
        elif action == RESTART_ACTION:
            self.restart_if_lost()
        else:
            self._toggle(action)

    def _toggle(self, action: str | None) -> None:
        """The on/off keys: sound, FPS counter, inset, ghosts, physics overlay."""
        s, o = self.session, self.session.options
        if action == "toggle_mute":
            s.say("Sound muted" if s.sound.toggle_mute() else "Sound on", 1.5)
        elif action == "toggle_fps":
            o.show_fps = not o.show_fps
        elif action == "toggle_pip":
            o.pip = not o.pip
            s.say("Picture in picture on" if o.pip else "Picture in picture off", 1.5)
        elif action == "toggle_ghosts":
            o.ghosts.enabled = not o.ghosts.enabled
            s.say("Ghosts on" if o.ghosts.enabled else "Ghosts off", 1.5)
        elif action == "debug_draw":
            o.debug_draw = not o.debug_draw

    def on_mouse_motion(self, x, y, dx, dy) -> None:
        self.input.turn(*look_delta(self.session.settings, dx, dy))

    def on_mouse_press(self, x, y, button, modifiers) -> None:
        if self.session.onboarding.click():
            return
        self.input.mouse_down(button)

    def on_mouse_release(self, x, y, button, modifiers) -> None:
        self.input.mouse_up(button)

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y) -> None:
        if scroll_y:
            notches = max(1, round(abs(scroll_y)))
            self.input.press("wheel", 1 if scroll_y > 0 else -1, notches)
