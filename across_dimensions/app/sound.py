"""Sound: the game's events become effects (:mod:`.synth`), played through pyglet's media.

Two parts:

* :class:`SoundDirector` turns each simulated tick into :class:`Cue` records: the tick's
  :mod:`~across_dimensions.game.events` (crystal taken, shot fired, bullet hit, blast, weapon
  refused, grab, seek, level complete, any enemy event ...) plus what the player's own motion
  implies (footsteps every stride on the ground, jumps, landings, gliding along w) and a slow hum
  from each crystal or enemy near enough to hear. A cue from a thing in the 4D world carries that
  thing's w offset from the player, so it is muffled and detuned by
  :func:`~.synth.w_filter` when off the slice: the player hears along w what they cannot see.
  The director only reads the game, never changes it, and uses no clock, so it is tested headless.
* :class:`SoundOut` plays cues with ``pyglet.media``, at the player's volume, unless muted. Where
  no audio device exists (a server, a container, pyglet's silent driver) it stays silent with no
  error, and so does every call on it.
"""

from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass

import numpy as np

from . import synth

#: Metres walked on the ground per footstep.
STRIDE = 1.4
#: Seconds between the glide sounds while moving along w.
W_MOVE_PERIOD = 0.2
#: Seconds between two hums of one crystal or enemy.
HUM_PERIOD = 1.8
#: Metres within which a crystal or enemy hums; and how many hum at most at once.
HUM_RANGE = 14.0
HUM_MAX = 3
#: Metres at which a sound is at half its loudness (3D distance).
HALF_GAIN_METRES = 6.0
#: Most effects playing at once; more are dropped (a burst of contacts must not pile up).
MAX_VOICES = 12
#: Smallest contact impulse that makes a sound, N s: bodies at rest jitter below it.
IMPACT_MIN = 0.4

#: Event kind -> effect. Kinds not here are looked up by :func:`cue_name`.
EVENT_SOUNDS: dict[str, str | None] = {
    "crystal_collected": "pickup",
    "energy_spent": None,  # moving along w already sounds (w_move); a shot's cost is in the shot
    "energy_empty": "energy_empty",
    "w_blocked": "w_blocked",
    "contact": "impact",
    "respawned": "respawn",
    "level_complete": "complete",
    "shot_fired": "shot",
    "bullet_hit": "hit",
    "blast": "blast",
    "field": "field",
    "target_hit": "target",
    "weapon_refused": "refused",
    "weapon_selected": "weapon_select",
    "manipulation_started": "grab",
    "manipulated": "turn",
    "manipulation_ended": "release",
    "seek_started": "seek",
    "seek_arrived": "arrive",
    "seek_blocked": "w_blocked",
    "enemy_hit": "enemy_hit",
    "enemy_defeated": "enemy_die",
    "player_hit": "hurt",
    "player_died": "respawn",
    "loot_released": "pickup",
    "checkpoint_reached": "arrive",
    "camera_switched": "field",
    "slice_aligned": "arrive",
    "object_reset": "respawn",
    "slice_turn_refused": "refused",
    "slice_turn_unpaid": "refused",
    "weapon_acquired": "pickup",
    "secret_found": "complete",
    "slab_knocked": "impact",
    "entered_frustum_object": "arrive",
    "moved_to_safety": "respawn",
}


def cue_name(kind: str) -> str | None:
    """The effect for an event ``kind``, or None for a silent one.

    Known kinds use :data:`EVENT_SOUNDS`; kinds added later are matched by their words, so a new
    enemy or damage event sounds right without editing this table: ``enemy_*`` -> ``enemy``
    (``enemy_hit``, ``enemy_die`` when the kind says hit/hurt/damage or die/death/killed/destroyed),
    ``player_hit``/``*damage*``/``*hurt*`` -> ``hurt``.
    """
    if kind in EVENT_SOUNDS:
        return EVENT_SOUNDS[kind]
    words = kind.lower()
    dies = any(w in words for w in ("die", "death", "dead", "killed", "destroyed"))
    hurt = any(w in words for w in ("hit", "hurt", "damage"))
    if "enemy" in words or "hive" in words or "drone" in words:
        return "enemy_die" if dies else "enemy_hit" if hurt else "enemy"
    if "player" in words and hurt or "damage" in words or "hurt" in words:
        return "hurt"
    return None


@dataclass(frozen=True)
class Cue:
    """One effect to play.

    Attributes
    ----------
    name : str
        An effect of :data:`~.synth.NAMES`.
    gain : float
        0 to 1, before the player's volume.
    dw : float
        The source's w minus the player's (0 for the player's own sounds).
    pan : float
        -1 left to +1 right.
    kind : str
        The event it sounds (``"slice_aligned"``), or "" for the player's motion and the hums:
        captions (:mod:`.captions`) tell apart events that share an effect.
    """

    name: str
    gain: float = 1.0
    dw: float = 0.0
    pan: float = 0.0
    kind: str = ""


class SoundDirector:
    """Turns ticks of a game into cues. Keep one per level (:meth:`reset` on a new one)."""

    def __init__(self):
        self.reset()

    def reset(self) -> None:
        self._walked = 0.0
        self._on_ground = True
        self._vy = 0.0
        self._w = None
        self._w_timer = 0.0
        self._hum_timer = 0.0
        self._foot = 0
        self._last_xz = None

    # ------------------------------------------------------------- placement
    @staticmethod
    def _where(game, entity_id) -> tuple[float, float, float]:
        """``(dw, gain, pan)`` of a sound from entity ``entity_id`` (the player's own when it is gone)."""
        e = game.entities.get(entity_id) if entity_id is not None and entity_id >= 0 else None
        if e is None:
            return 0.0, 1.0, 0.0
        try:
            c = np.asarray(e.center(game), dtype=np.float64)
        except Exception:  # an entity whose motion cannot say where it is: heard as the player's own
            return 0.0, 1.0, 0.0
        return placement(game.player, c)

    # ------------------------------------------------------------------ tick
    def cues(self, game, dt: float) -> list[Cue]:
        """The cues of the tick just simulated (call once after each ``game.step``)."""
        out: list[Cue] = []
        for ev in game.events:
            name = cue_name(ev.kind)
            if name is None:
                continue
            if ev.kind == "contact":
                if ev.impulse < IMPACT_MIN:
                    continue
                dw, gain, pan = self._where(game, ev.entity)
                out.append(Cue(name, gain * min(1.0, ev.impulse / 6.0), dw, pan, ev.kind))
                continue
            entity = getattr(ev, "entity", None)
            if ev.kind in ("shot_fired", "crystal_collected", "seek_started", "seek_arrived"):
                entity = None  # the player's own doing, at the player
            dw, gain, pan = self._where(game, entity)
            out.append(Cue(name, gain, dw, pan, ev.kind))
        out += self._motion(game, dt)
        out += self._hums(game, dt)
        return out

    def _motion(self, game, dt: float) -> list[Cue]:
        p = game.player
        out = []
        pos = np.asarray(p.position, dtype=np.float64)
        vel = np.asarray(p.velocity, dtype=np.float64)
        if self._on_ground and not p.on_ground and vel[1] > 1.0:
            out.append(Cue("jump", 0.8))
        if not self._on_ground and p.on_ground and self._vy < -3.0:
            out.append(Cue("land", min(1.0, -self._vy / 8.0)))
        xz = (float(pos[0]), float(pos[2]))
        if p.on_ground and self._last_xz is not None:
            self._walked += math.hypot(xz[0] - self._last_xz[0], xz[1] - self._last_xz[1])
            if self._walked >= STRIDE:
                self._walked = 0.0 if self._walked > 2 * STRIDE else self._walked - STRIDE  # a teleport is one step
                self._foot ^= 1
                out.append(Cue("step_alt" if self._foot else "step", 0.7))
        self._last_xz = xz
        w = float(pos[3])
        if self._w is not None and abs(w - self._w) > 1e-6:
            self._w_timer -= dt
            if self._w_timer <= 0.0:
                out.append(Cue("w_move", 0.6))
                self._w_timer = W_MOVE_PERIOD
        else:
            self._w_timer = 0.0
        self._w = w
        self._on_ground = bool(p.on_ground)
        self._vy = float(vel[1])
        return out

    def _hums(self, game, dt: float) -> list[Cue]:
        self._hum_timer -= dt
        if self._hum_timer > 0.0:
            return []
        self._hum_timer = HUM_PERIOD
        near = []
        for e in game.entities:
            if e.kind not in ("crystal", "enemy"):
                continue
            try:
                c = np.asarray(e.center(game), dtype=np.float64)
            except Exception:
                continue
            d = float(np.linalg.norm(c[:3] - game.player.eye()[:3]))
            if d <= HUM_RANGE and abs(c[3] - game.player.position[3]) <= synth.W_AUDIBLE:
                near.append((d, e.kind, c))
        near.sort(key=lambda t: t[0])
        out = []
        for _, kind, c in near[:HUM_MAX]:
            dw, gain, pan = placement(game.player, c)
            out.append(Cue("hum" if kind == "crystal" else "enemy", 0.6 * gain, dw, pan))
        return out


def placement(player, center: np.ndarray) -> tuple[float, float, float]:
    """``(dw, gain, pan)`` of a source at 4D ``center`` as heard by ``player``.

    ``dw`` is the source's w minus the player's; ``gain`` halves every
    :data:`HALF_GAIN_METRES` of 3D distance; ``pan`` is the sine of the source's bearing from the
    view direction (+1 straight right).
    """
    eye = np.asarray(player.eye(), dtype=np.float64)
    d = np.asarray(center[:3], dtype=np.float64) - eye[:3]
    dist = float(np.linalg.norm(d))
    gain = 1.0 / (1.0 + dist / HALF_GAIN_METRES)
    yaw = float(player.yaw)
    # Right of the view: yaw 0 looks along +z, so +x is to the right.
    right = np.array([math.cos(yaw), 0.0, -math.sin(yaw)])
    pan = float(np.dot(d, right) / dist) if dist > 1e-6 else 0.0
    return float(center[3] - player.position[3]), gain, max(-1.0, min(1.0, pan))


class SoundOut:
    """Plays cues through ``pyglet.media``; silent, without error, where there is no audio device.

    Parameters
    ----------
    volume : float
        0 to 1.
    muted : bool
    allow_silent : bool
        Play through pyglet's silent driver too (it consumes sources without a device): tests use
        it to run the playing path where there is no sound card.
    defer : bool
        Open the device later, with :meth:`open` (the window does once its first frame is up):
        cues played before then are not heard.
    """

    def __init__(self, volume: float = 0.8, muted: bool = False, allow_silent: bool = False, defer: bool = False):
        self.volume = float(volume)
        self.muted = bool(muted)
        self.available = False
        self.problem = ""
        self._opened = False
        self._allow_silent = allow_silent
        self._voices: list = []
        self._cache: dict = {}
        self._sources: dict = {}
        if not defer:
            self.open()

    def open(self) -> None:
        """Open the audio device (once; what went wrong, if anything, goes to :attr:`problem`)."""
        if self._opened:
            return
        self._opened = True
        if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
            # pyglet's media module opens a (hidden) window when imported: without a display there
            # is no game window either, so stay silent instead of failing inside pyglet.
            self.problem = "no display"
            return
        try:
            import pyglet.media as media
            from pyglet.media.codecs.base import AudioFormat, StaticSource

            driver = media.get_audio_driver()
            if driver is None or (type(driver).__name__ == "SilentDriver" and not self._allow_silent):
                self.problem = "no audio device"
                return
            self._media = media
            fmt = AudioFormat(channels=2, sample_size=16, sample_rate=synth.RATE)

            class _Pcm(StaticSource):
                """Samples already in memory: a static source queued any number of times."""

                def __init__(self, data: bytes):  # noqa: B024 - StaticSource's own init decodes a source
                    self.audio_format = fmt
                    self._data = data
                    self._duration = len(data) / fmt.bytes_per_second

            self._source = _Pcm
            self.available = True
        except Exception as e:  # no driver library, no device, a sandbox: play nothing
            self.problem = f"no audio ({type(e).__name__}: {e})"

    def toggle_mute(self) -> bool:
        """Flip mute; returns the new state."""
        self.muted = not self.muted
        return self.muted

    @staticmethod
    def _key(cue: Cue) -> tuple:
        return (cue.name, round(cue.dw * 8) / 8, round(cue.gain * 10) / 10, round(cue.pan * 10) / 10)

    def buffer(self, cue: Cue) -> bytes:
        """The PCM bytes a cue plays (16-bit stereo at :data:`~.synth.RATE`), cached by rounded
        ``dw`` (eighths of a unit), gain and pan (tenths)."""
        key = self._key(cue)
        data = self._cache.get(key)
        if data is None:
            x = synth.w_filter(synth.effect(cue.name), key[1])
            data = synth.to_pcm16_stereo(x, key[2], key[3])
            if len(self._cache) > 512:
                self._cache.clear()
            self._cache[key] = data
        return data

    def play(self, cues) -> int:
        """Start the cues (at most :data:`MAX_VOICES` at once); returns how many started."""
        if not self.available or self.muted or self.volume <= 0.0:
            return 0
        started = 0
        try:
            self._voices = [v for v in self._voices if v.playing]
            for cue in cues:
                if len(self._voices) >= MAX_VOICES or abs(cue.dw) > synth.W_AUDIBLE:
                    continue
                source = self._sources.get(key := self._key(cue))
                if source is None:
                    source = self._source(self.buffer(cue))
                    if len(self._sources) > 256:
                        self._sources.clear()
                    self._sources[key] = source
                player = self._media.Player()
                player.volume = self.volume
                player.queue(source)
                player.play()
                self._voices.append(player)
                started += 1
        except Exception as e:  # the device went away mid-game: go quiet rather than crash
            self.available = False
            self.problem = f"audio stopped ({type(e).__name__}: {e})"
        return started

    def ui(self, name: str) -> int:
        """Play a menu or card effect (``menu_move``, ``menu_select``, ``menu_back``)."""
        return self.play([Cue(name, 0.8)])
