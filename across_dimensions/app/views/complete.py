"""The level-complete view: the finished level goes on under a notice, then the next one starts."""

from __future__ import annotations

from ...game.sim import DT
from ...world.campaign import next_in_campaign
from .base import View

#: Seconds between reaching the goal and the next level.
NEXT_LEVEL_DELAY = 3.0


class LevelCompleteView(View):
    """Over a :class:`~.play.PlayView` whose level was just finished.

    When first shown it saves the run (best time, crystals, the next level for Continue), stops
    a recording and says the time; the level keeps running under it, with the player's input
    (Esc still pauses), for the play view's ``finish_seconds`` of play (:data:`NEXT_LEVEL_DELAY`
    for a 4D level; the prologue's turn to the 3D world takes longer), and then the next level of
    the campaign starts, with the play view's ``farewell`` said over it when it has one.
    """

    shows_level = True

    def __init__(self, session, play):
        super().__init__(session)
        self.play = play
        self.finished_for = 0.0
        self.announced = False

    def on_show(self) -> None:
        if self.announced:  # back from the pause menu
            self.play.on_show()
            return
        self.announced = True
        self._save()
        self.session.recording.stop()

    def _save(self) -> None:
        s, game = self.session, self.play.game
        stem = self.play.level_path.stem
        best = s.progress.finish(stem, game.time)
        total = len(getattr(game.level, "crystals", ()))
        if total:
            s.progress.found_crystals(stem, self.play.crystals_found, total)
        entry = next_in_campaign(s.campaign, stem)
        s.progress.current, s.progress.checkpoint = (entry.stem if entry else None), None
        s.save_progress()
        s.say(f"Level complete in {game.time:.1f} s" + (" - best time!" if best else ""), NEXT_LEVEL_DELAY)

    def on_update(self, dt: float) -> None:
        if self.play.game.outcome != "complete":  # the editor put a game of its own in the play view
            self.window.pop_view()
            return
        self.finished_for += self.play.run(dt) * DT
        if self.finished_for >= self.play.finish_seconds and self.play.from_editor:  # back to the level's editor
            self.window.pop_view()
            self.session.open_editor(self.play, from_play=False)
        elif self.finished_for >= self.play.finish_seconds:
            self.session.next_level(self.play.level_path)
            if self.play.farewell:
                self.session.say(self.play.farewell, 6.0)

    # The level is still played: everything else is the play view's.
    def on_draw(self, target, viewport) -> None:
        self.play.on_draw(target, viewport)

    def on_key_press(self, symbol, modifiers) -> None:
        self.play.on_key_press(symbol, modifiers)

    def on_mouse_motion(self, x, y, dx, dy) -> None:
        self.play.on_mouse_motion(x, y, dx, dy)

    def on_mouse_press(self, x, y, button, modifiers) -> None:
        self.play.on_mouse_press(x, y, button, modifiers)

    def on_mouse_release(self, x, y, button, modifiers) -> None:
        self.play.on_mouse_release(x, y, button, modifiers)

    def on_mouse_scroll(self, x, y, scroll_x, scroll_y) -> None:
        self.play.on_mouse_scroll(x, y, scroll_x, scroll_y)

    def on_deactivate(self) -> None:
        self.play.on_deactivate()
