"""Sounds made visible: captions for the important sounds, with their direction and w side.

With the ``captions`` setting on, every important cue the sound director gives (a crystal's hum,
an enemy, being hit, a refusal, the bar running dry...) becomes a caption such as
``"crystal hum, ana, left"``: what it is, which side of the slice along w it comes from (``ana``
for +w, ``kata`` for -w, nothing on the slice) and where it is (``left``, ``right``, or
nothing ahead). A caption stays :data:`CAPTION_SECONDS` and fades; the same sound heard again
refreshes its caption instead of adding a line. A sound heard along w also puts a mark at the
screen's edge (drawn by :mod:`across_dimensions.render.captions`). Footsteps, the jump, the
menus and the player's own shots are not captioned: they are what the player just did.
"""

from __future__ import annotations

from ..game.frame import Caption
from .sound import Cue

#: Words for the events that share an effect with others (the rest go by :data:`WORDS`).
EVENT_WORDS = {
    "slice_aligned": "slice aligned",
    "checkpoint_reached": "checkpoint",
    "camera_switched": "camera switched",
    "seek_blocked": "seek stopped",
    "player_died": "you died",
    "loot_released": "loot released",
    "object_reset": "object put back",
    "slice_turn_refused": "slice turn refused",
    "slice_turn_unpaid": "no energy to turn the slice",
    "weapon_acquired": "weapon taken",
    "secret_found": "secret found",
    "slab_knocked": "slab knocked",
    "entered_frustum_object": "stepped onto the image",
    "moved_to_safety": "moved to safety",
}
#: Words for each captioned effect (effects not here are not captioned).
WORDS = {
    "hum": "crystal hum",
    "enemy": "enemy",
    "enemy_hit": "enemy hit",
    "enemy_die": "enemy destroyed",
    "hurt": "you are hit",
    "refused": "refused",
    "w_blocked": "blocked along w",
    "energy_empty": "energy empty",
    "pickup": "crystal taken",
    "target": "target hit",
    "blast": "blast",
    "field": "field",
    "impact": "thud",
    "respawn": "respawned",
    "arrive": "seek arrived",
    "complete": "level complete",
}
#: Seconds a caption stays on screen.
CAPTION_SECONDS = 2.5
#: Most captions shown at once (the newest).
MAX_CAPTIONS = 4
#: |dw| below which a sound counts as on the slice, and |pan| below which as ahead.
ON_SLICE = 0.05
AHEAD = 0.35


def caption_text(cue: Cue) -> str | None:
    """The caption of ``cue`` (``"crystal hum, ana, left"``), or None when it is not captioned."""
    words = EVENT_WORDS.get(cue.kind) or WORDS.get(cue.name)
    if words is None:
        return None
    parts = [words]
    if abs(cue.dw) > ON_SLICE:
        parts.append("ana" if cue.dw > 0 else "kata")
    if abs(cue.pan) > AHEAD:
        parts.append("right" if cue.pan > 0 else "left")
    return ", ".join(parts)


class CaptionBoard:
    """The captions on screen: :meth:`heard` each tick's cues, :meth:`shown` what to draw."""

    def __init__(self):
        self._live: dict[str, list] = {}  # text -> [seconds left, side, pan], oldest first

    def heard(self, cues, dt: float) -> None:
        """Age the captions by ``dt`` seconds and add (or refresh) those of ``cues``."""
        for text in list(self._live):
            self._live[text][0] -= dt
            if self._live[text][0] <= 0.0:
                del self._live[text]
        for cue in cues:
            text = caption_text(cue)
            if text is None:
                continue
            self._live.pop(text, None)  # refreshed: it moves to the newest line
            side = 0 if abs(cue.dw) <= ON_SLICE else (1 if cue.dw > 0 else -1)
            self._live[text] = [CAPTION_SECONDS, side, float(cue.pan)]

    def shown(self, on: bool = True) -> list[Caption]:
        """The newest :data:`MAX_CAPTIONS` captions, oldest first (none when not ``on``: the
        player's ``captions`` setting)."""
        if not on:
            return []
        live = list(self._live.items())[-MAX_CAPTIONS:]
        return [Caption(text, side, pan, min(1.0, left / 0.5)) for text, (left, side, pan) in live]

    def clear(self) -> None:
        self._live.clear()


__all__ = [
    "EVENT_WORDS",
    "AHEAD",
    "CAPTION_SECONDS",
    "CaptionBoard",
    "MAX_CAPTIONS",
    "ON_SLICE",
    "WORDS",
    "caption_text",
]
