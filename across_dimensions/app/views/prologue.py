"""The prologue's play view: the Flatland level (``format = "flatland"``) in the window.

It plays as the play view does (:mod:`.play`): the same fixed-tick accumulator, the same input
(:class:`~across_dimensions.app.input.PlayInput`: the player's own keys, so its w keys move the
flat being's plane along z), the same pause menu (with a row to skip the prologue), recording,
sounds, progress and level-complete view. What differs is the game (:class:`FlatGame`), its
picture (:class:`~across_dimensions.render.flatland.FlatRenderer`: the side view, then the turn to
the 3D world) and its hints, done by the level's state (:class:`StateHints`). After the goal the
view turns for :data:`~across_dimensions.game.flatland.view.REVEAL_SECONDS`, and the next level
(Arrival) starts saying the closing line.
"""

from __future__ import annotations

from pathlib import Path

from ...core import heap
from ...game.flatland import DT, FlatGame
from ...game.flatland.hints import StateHints
from ...game.flatland.view import CLOSING_LINE, REVEAL_SECONDS, flat_frame
from ...render.flatland import FlatRenderer
from ...world.flat_level import load_flat_level
from ..input import PlayInput
from ..onboarding import fill_keys
from ..sound import STRIDE, W_MOVE_PERIOD, Cue
from .base import View
from .complete import LevelCompleteView
from .menus import PauseView
from .play import MAX_CATCH_UP

#: Each prologue event's sound (:mod:`..synth` effects).
EVENT_SOUNDS = {
    "item_taken": "pickup",
    "door_opened": "target",
    "z_blocked": "w_blocked",
    "checkpoint": "arrive",
    "fell": "respawn",
    "complete": "complete",
}


class FlatSounds:
    """The prologue's cues: its events, the being's steps, jumps and landings, and the glide of its
    plane along z (the sounds of the 4D game's player, one dimension down)."""

    def __init__(self):
        self.walked, self.foot, self.z_timer = 0.0, 0, 0.0
        self.last: tuple[float, float, float, bool, float] | None = None  # x, y, z, grounded, vy

    def cues(self, game: FlatGame, dt: float) -> list[Cue]:
        out = [Cue(EVENT_SOUNDS[e.kind]) for e in game.events if e.kind in EVENT_SOUNDS]
        x, y, z = (float(v) for v in game.position)
        vy = float(game.space.being.velocity.y)
        if self.last is not None:
            lx, _, lz, grounded, last_vy = self.last
            if grounded and not game.grounded and vy > 1.0:
                out.append(Cue("jump", 0.8))
            if not grounded and game.grounded and last_vy < -3.0:
                out.append(Cue("land", min(1.0, -last_vy / 8.0)))
            if game.grounded:
                self.walked += abs(x - lx)
                if self.walked >= STRIDE:
                    self.walked, self.foot = 0.0, self.foot ^ 1
                    out.append(Cue("step_alt" if self.foot else "step", 0.7))
            self.z_timer = self.z_timer - dt if z != lz else 0.0
            if z != lz and self.z_timer <= 0.0:
                out.append(Cue("w_move", 0.6))
                self.z_timer = W_MOVE_PERIOD
        self.last = (x, y, z, game.grounded, vy)
        return out


class FlatPlayView(View):
    """The prologue being played.

    Parameters
    ----------
    session : Session
    path : Path
        The prologue's level file.
    """

    shows_level = True
    from_editor = False  # the editor plays 4D levels only
    #: Seconds of play after the goal before the next level: the turn to 3D, then the closing line.
    finish_seconds = REVEAL_SECONDS + 2.5
    #: Said as the next level starts.
    farewell = CLOSING_LINE

    def __init__(self, session, path: Path):
        super().__init__(session)
        self.input = PlayInput(session.bindings, self.window.keys, session.settings)
        if session.flat_renderer is None:
            session.flat_renderer = FlatRenderer(self.window.ctx, session.renderer)
        self.load(path)
        if session.recording.path_given:  # --record FILE: the first level played
            self.start_recording()

    def load(self, path: Path) -> None:
        """Start the prologue at ``path`` from scratch."""
        s = self.session
        self._path = Path(path)
        self.game = FlatGame(load_flat_level(path), seed=s.seed)
        self.accumulator = 0.0
        self.crystals_found = 0
        self.hints = StateHints(self.game.level.hints)
        self.sounds = FlatSounds()
        stems = [e.stem for e in s.campaign]
        self.continues = s.progress.play(self._path.stem, None, stems, s.optional)
        s.save_progress()
        heap.settle()

    @property
    def level_path(self) -> Path:
        return self._path

    def start_recording(self) -> None:
        """Restart the prologue and record it."""
        self.load(self._path)
        self.session.recording.start(self.game, self._path)

    # ---------------------------------------------------------------- life
    def on_show(self) -> None:
        self.window.set_exclusive_mouse(False)  # a side view: the mouse looks nowhere
        self.window.set_caption(f"Across Dimensions - {self.game.level.name}")
        self.input.forget()

    def on_update(self, dt: float) -> None:
        self.run(dt)
        if self.game.outcome == "complete":
            self.session.onboarding.card_allowed = False  # the flat-being card would say it again
            self.window.push_view(LevelCompleteView(self.session, self))

    def run(self, dt: float) -> int:
        """Advance by ``dt`` wall-clock seconds in whole fixed ticks (at most :data:`MAX_CATCH_UP`)."""
        self.accumulator += dt
        steps = 0
        while self.accumulator >= DT and steps < MAX_CATCH_UP:
            self.tick()
            self.accumulator -= DT
            steps += 1
        if steps == MAX_CATCH_UP:
            self.accumulator = 0.0
        return steps

    def tick(self) -> None:
        s = self.session
        actions = self.read_actions()
        self.game.step(actions)
        self.hints.tick(self.game, DT)
        s.sound.play(self.sounds.cues(self.game, DT))
        s.recording.record(actions)

    def read_actions(self):
        """This tick's actions (see :class:`~across_dimensions.app.input.PlayInput`)."""
        return self.input.read()

    def on_close(self) -> bool:
        self.session.save_progress()
        return False

    def on_deactivate(self) -> None:
        self.pause()

    def pause(self) -> None:
        self.window.push_view(PauseView(self.session, self))

    # ---------------------------------------------------------------- drawing
    def on_draw(self, target, viewport) -> None:
        self.draw_scene(target, viewport, playing=True)

    def draw_scene(self, target, viewport, playing: bool) -> None:
        """The side view (or the turn to 3D); the hint, notices and the z bar only while ``playing``."""
        s = self.session
        hint = label = message = ""
        h = self.hints.current()
        if playing and h is not None:
            hint = fill_keys(h.text, s.settings)
            which = f"Hint {self.hints.current_index() + 1}/{len(self.hints.specs)}"
            label = fill_keys(which + " \u00b7 {hints} hides", s.settings)
        if playing:
            message = s.notice_text or ("REC" if s.recording.active else "")
        frame = flat_frame(self.game, self.accumulator / DT, hint, label, message)
        target.use()
        s.flat_renderer.draw(frame, viewport, hud=playing)

    # ---------------------------------------------------------------- input
    def on_key_press(self, symbol, modifiers) -> None:
        s = self.session
        action = s.bindings.action_of("key", symbol)
        self.input.press("key", symbol)
        if self.window_key(action):
            return
        if action == "pause":
            self.pause()
        elif action == "hints":
            self.hints.toggle()
            s.sound.ui("menu_move")
        elif action == "record":
            s.recording.stop() if s.recording.active else self.start_recording()
        elif action == "toggle_mute":
            s.say("Sound muted" if s.sound.toggle_mute() else "Sound on", 1.5)
        elif action == "editor":
            s.say("The level editor edits the 4D levels; the prologue is a file to edit by hand.", 4.0)

    def on_mouse_press(self, x, y, button, modifiers) -> None:
        self.input.mouse_down(button)

    def on_mouse_release(self, x, y, button, modifiers) -> None:
        self.input.mouse_up(button)
