"""The level-complete view: the finished level plays on for a moment, then its results and the
way on (Continue, Retry, Time trial, Level select). Nothing moves on by itself.

The results screen is a menu screen (:class:`~.menus.MenuScreen`, screen ``"complete"`` of the
one menu model) over the finished level, dimmed: the run's time, the best time, the crystals
and secrets found, the deaths, and in a time trial the ghost's time; its rows take the keys,
the mouse and the wheel as every menu does.
"""

from __future__ import annotations

from ...game.sim import DT
from ...world.campaign import next_in_campaign
from ..menu import format_time
from ..time_trial import keep_ghost, signed
from .menus import MenuScreen

#: Seconds a finished 4D level plays on under the notice before its results (the prologue's
#: turn to the 3D world takes longer: its view's ``finish_seconds``).
OUTRO_SECONDS = 1.0


class LevelCompleteView(MenuScreen):
    """Over the :class:`~.play.PlayView` (or the prologue's view) whose level was just finished.

    When first shown it saves the run (best time, crystals, the next level for Continue; the run
    as the level's ghost when it is the best from the start), stops a recording and says the
    time. The level keeps running under it, with the player's input (Esc still pauses), for the
    play view's ``finish_seconds``; then the results screen opens, and stays until the player
    chooses. A level the editor started goes back to the editor instead. Continue starts the
    next level of the campaign, with the play view's ``farewell`` said over it when it has one.
    """

    shows_level = True

    def __init__(self, session, play):
        super().__init__(session, "complete", backdrop=play)
        self.play = play
        self.finished_for = 0.0
        self.announced = False
        self.results_shown = False

    def on_show(self) -> None:
        if self.results_shown:  # back from the level select
            super().on_show()
        elif self.announced:  # back from the pause menu
            self.play.on_show()
        else:
            self.announced = True
            self.results = self._save()
            self.session.recording.stop()

    def _save(self) -> tuple:
        """Keep the run in the progress file and as the ghost; the results screen's lines."""
        s, game = self.session, self.play.game
        stem = self.play.level_path.stem
        seconds = (game.completed_tick or game.tick) * game.dt
        new_best = s.progress.finish(stem, seconds)
        total = len(getattr(game.level, "crystals", ()))
        if total:
            s.progress.found_crystals(stem, self.play.crystals_found, total)
        entry = next_in_campaign(s.campaign, stem)
        s.progress.current, s.progress.checkpoint = (entry.stem if entry else None), None
        s.save_progress()
        before, kept = keep_ghost(getattr(self.play, "run_log", None), s.warn)
        s.say(f"Level complete in {seconds:.1f} s" + (" - best time!" if new_best else ""), 3.0)
        counts = getattr(game, "event_counts", {})
        lines = [
            ("Time", format_time(seconds), False),
            ("Best time", format_time(s.progress.finished[stem]) + ("  new best!" if new_best else ""), new_best),
            ("Crystals found", f"{self.play.crystals_found}/{total}" if total else "none here", False),
        ]
        secrets = len(getattr(game.level, "secrets", ()))
        if secrets:
            lines.append(("Secrets found", f"{counts.get('secret_found', 0)}/{secrets}", False))
        lines.append(("Deaths", str(counts.get("player_died", 0)), False))
        if before is not None:
            lines.append(("Ghost", f"{format_time(before.seconds)}  {signed(seconds - before.seconds)} s", kept))
        elif kept:
            lines.append(("Ghost", "this run: race it in a time trial", True))
        return tuple(lines)

    def _open_results(self) -> None:
        s, stem = self.session, self.play.level_path.stem
        entry = next_in_campaign(s.campaign, stem)
        in_campaign = stem in [e.stem for e in s.campaign]
        following = entry.title if entry else ("the title screen" if in_campaign else "the next level")
        s.menu.open_results(self.results, following, time_trial=hasattr(self.play, "race"))  # not the prologue
        self.results_shown = True
        super().on_show()

    def on_update(self, dt: float) -> None:
        if self.results_shown:
            return
        if self.play.game.outcome != "complete":  # the editor put a game of its own in the play view
            self.window.pop_view()
            return
        self.finished_for += self.play.run(dt) * DT
        if self.finished_for >= self.play.finish_seconds and self.play.from_editor:  # back to the level's editor
            self.window.pop_view()
            self.session.open_editor(self.play, from_play=False)
        elif self.finished_for >= self.play.finish_seconds:
            self._open_results()

    def run(self, command: str) -> None:
        s, path = self.session, self.play.level_path
        if command == "next":
            s.next_level(path)
            if self.play.farewell:
                s.say(self.play.farewell, 6.0)
        elif command == "retry":
            s.start_level(path, trial=getattr(self.play, "trial", False))
        elif command == "time_trial":
            s.start_level(path, trial=True)

    # Until the results open the level is still played: everything is the play view's.
    def on_draw(self, target, viewport) -> None:
        if self.results_shown:
            super().on_draw(target, viewport)
        else:
            self.play.on_draw(target, viewport)

    def still_frame(self):
        return super().still_frame() if self.results_shown else None

    def on_key_press(self, symbol, modifiers) -> None:
        (super() if self.results_shown else self.play).on_key_press(symbol, modifiers)

    def on_mouse_motion(self, x, y, dx, dy) -> None:
        (super() if self.results_shown else self.play).on_mouse_motion(x, y, dx, dy)

    def on_mouse_press(self, x, y, button, modifiers) -> None:
        (super() if self.results_shown else self.play).on_mouse_press(x, y, button, modifiers)

    def on_mouse_release(self, x, y, button, modifiers) -> None:
        if not self.results_shown:
            self.play.on_mouse_release(x, y, button, modifiers)

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y) -> None:
        (super() if self.results_shown else self.play).on_mouse_scroll(x, y, scroll_x, scroll_y)

    def on_deactivate(self) -> None:
        if not self.results_shown:
            self.play.on_deactivate()
