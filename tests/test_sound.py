"""Sound: game events -> effects, the w filter on the synthesized buffers, silence without a device."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from across_dimensions.app import synth
from across_dimensions.app.sound import EVENT_SOUNDS, STRIDE, Cue, SoundDirector, SoundOut, cue_name
from across_dimensions.game.actions import Actions
from across_dimensions.game.events import event_kinds
from across_dimensions.game.sim import DT, Game
from across_dimensions.world.level import load_level

DATA = Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def crystal_level():
    return load_level(DATA / "crystals.toml")


def high_fraction(x: np.ndarray, above_hz: float = 2000.0) -> float:
    """Fraction of the power above ``above_hz``: how bright a sound is."""
    p = np.abs(np.fft.rfft(x)) ** 2
    f = np.fft.rfftfreq(len(x), 1.0 / synth.RATE)
    return float(p[f > above_hz].sum() / p.sum())


def peak_hz(x: np.ndarray) -> float:
    n = 1 << 16
    p = np.abs(np.fft.rfft(x * np.hanning(len(x)), n))
    return float(np.fft.rfftfreq(n, 1.0 / synth.RATE)[np.argmax(p)])


def test_every_effect_is_a_short_finite_buffer_in_range():
    for name in synth.NAMES:
        x = synth.effect(name)
        assert x.dtype == np.float32 and 0.02 * synth.RATE <= len(x) <= 2 * synth.RATE, name
        assert np.isfinite(x).all() and 0.1 < np.abs(x).max() <= 1.0, name


def test_every_event_kind_has_a_sound_and_later_enemy_events_are_matched_by_name():
    from across_dimensions.game import events

    today = [c.kind for c in vars(events).values() if isinstance(c, type) and issubclass(c, events.Event)]
    assert set(today) - {"event"} <= set(EVENT_SOUNDS) | {k for k in event_kinds() if cue_name(k)}
    assert {v for v in EVENT_SOUNDS.values() if v} <= set(synth.NAMES)
    assert cue_name("enemy_spawned") == "enemy"
    assert cue_name("enemy_hit") == "enemy_hit" and cue_name("enemy_killed") == "enemy_die"
    assert cue_name("player_hit") == "hurt" and cue_name("something_else") is None


def test_the_w_filter_leaves_the_slice_clear_and_muffles_detunes_and_quiets_off_it():
    tone = np.sin(2 * np.pi * 1000 * np.arange(synth.RATE // 2) / synth.RATE).astype(np.float32)
    assert synth.w_filter(tone, 0.0) is tone  # on the slice: exactly as synthesized
    # Detuned: a source ana sounds higher, kata lower, by DETUNE_SEMITONES at W_AUDIBLE (where it
    # has faded out: measured at 90 % of the way there).
    up, down = synth.w_filter(tone, 0.9 * synth.W_AUDIBLE), synth.w_filter(tone, -0.9 * synth.W_AUDIBLE)
    ratio = 2 ** (0.9 * synth.DETUNE_SEMITONES / 12)
    assert peak_hz(up) == pytest.approx(1000 * ratio, rel=0.01)  # the FFT bin is 0.34 Hz; 1% is the resampling
    assert peak_hz(down) == pytest.approx(1000 / ratio, rel=0.01)
    # Muffled: the brightness of a noisy effect falls steadily with the distance along w.
    shot = synth.effect("shot")
    for sign in (1, -1):
        bright = [high_fraction(synth.w_filter(shot, sign * dw)) for dw in (0.0, 0.3, 0.75, 1.4)]
        assert all(a > b for a, b in zip(bright, bright[1:])), bright
        assert bright[-1] < 0.1 * bright[0], bright
    # Quieter, fading to silence at W_AUDIBLE.
    rms = [float(np.sqrt(np.mean(synth.w_filter(shot, dw) ** 2))) for dw in (0.0, 0.75, 1.4)]
    assert rms[0] > rms[1] > rms[2] > 0
    assert not synth.w_filter(shot, synth.W_AUDIBLE).any()
    assert not synth.w_filter(shot, synth.W_AUDIBLE + 0.01).any()


def test_walking_gives_footsteps_by_stride_and_jumping_a_jump(crystal_level):
    game, director = Game(crystal_level), SoundDirector()
    names = []
    for _ in range(20):  # land and settle
        game.step(Actions())
        names += [c.name for c in director.cues(game, DT)]
    start = game.player.position.copy()
    for _ in range(120):
        game.step(Actions(forward=1.0))
        names += [c.name for c in director.cues(game, DT)]
    walked = float(np.hypot(*(game.player.position - start)[[0, 2]]))
    steps = sum(n in ("step", "step_alt") for n in names)
    assert steps == int(walked // STRIDE) and steps >= 3
    names = []
    for i in range(60):
        game.step(Actions(jump=i < 3))
        names += [c.name for c in director.cues(game, DT)]
    assert names.count("jump") == 1 and "step" not in names


def test_moving_along_w_and_taking_a_crystal_sound_and_the_crystal_hums_muffled_from_off_the_slice(crystal_level):
    game, director = Game(crystal_level), SoundDirector()
    game.energy.gain(10_000)
    ana = game.entities.named("ana")
    dw_crystal = float(ana.center(game)[3] - game.player.position[3])
    assert dw_crystal > 0.5  # it is off the slice at the start
    hums, names = [], []
    for i in range(240):
        game.step(Actions(w=1.0 if i >= 120 else 0.0))
        cues = director.cues(game, DT)
        names += [c.name for c in cues]
        hums += [c for c in cues if c.name == "hum"]
    assert "w_move" in names
    off = [c for c in hums if abs(c.dw - dw_crystal) < 1e-9]  # heard from where it is along w
    assert off and SoundOut._key(off[0])[1] > 0.4  # so its buffer is the muffled, detuned one
    assert any(c.dw == 0.0 for c in hums)  # and one on the slice, clear


def test_events_map_to_cues_with_the_sources_w(crystal_level):
    from across_dimensions.game.events import Contact, CrystalCollected, LevelComplete

    game, director = Game(crystal_level), SoundDirector()
    ana = game.entities.named("ana")
    game.events = [CrystalCollected(ana.id, 1000, 1000), LevelComplete(), Contact(ana.id, None, 3.0)]
    cues = [c for c in director.cues(game, DT) if c.name not in ("hum", "step", "step_alt", "w_move")]
    assert [c.name for c in cues] == ["pickup", "complete", "impact"]
    assert cues[0].dw == 0.0 and cues[1].dw == 0.0  # the player's own doing
    assert cues[2].dw == pytest.approx(float(ana.center(game)[3] - game.player.position[3]))
    assert 0 < cues[2].gain < 1


def test_no_audio_device_means_silence_without_error():
    out = SoundOut(volume=0.8)  # in the test environment there is no sound card (or no display)
    if out.available:
        pytest.skip("this machine has an audio device")
    assert out.play([Cue("shot"), Cue("hum", 0.5, 0.7, -0.3)]) == 0
    assert out.ui("menu_select") == 0 and out.toggle_mute() is True
    pcm = out.buffer(Cue("hum", 0.5, 0.7, -0.3))  # the buffers are still made: they are numpy only
    assert len(pcm) % 4 == 0 and len(pcm) > 0


def test_mute_and_volume_stop_playing():
    out = SoundOut(volume=0.0)
    assert out.play([Cue("shot")]) == 0
    out = SoundOut(muted=True)
    assert out.play([Cue("shot")]) == 0


@pytest.fixture(scope="module")
def xvfb():
    """A virtual X display (pyglet's media module needs one to import); skipped without Xvfb."""
    from conftest import xvfb_display

    with xvfb_display(64, "ACROSS_DIMENSIONS_SOUND_TEST_DISPLAY") as display:
        yield display


def test_pyglet_media_plays_the_cues_or_stays_silent_without_a_device(xvfb):
    """In a fresh process with a display: no sound card here means pyglet's silent driver, so the
    game stays silent without an error; forced onto that driver, the playing path runs."""
    import os
    import subprocess
    import sys

    code = (
        "from across_dimensions.app.sound import SoundOut, Cue\n"
        "o = SoundOut()\n"
        "print(o.available, o.play([Cue('shot')]), repr(o.problem))\n"
        "f = SoundOut(volume=0.5, allow_silent=True)\n"
        "print(f.available, f.play([Cue('shot'), Cue('hum', 0.5, 0.7, -0.3), Cue('step')]), repr(f.problem))\n"
    )
    root = str(Path(__file__).resolve().parents[1])
    env = dict(
        os.environ, DISPLAY=xvfb, PYTHONPATH=os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH")) if p)
    )
    env.pop("WAYLAND_DISPLAY", None)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    plain, forced = r.stdout.splitlines()
    if plain.startswith("True"):
        pytest.skip("this machine has an audio device")
    assert plain == "False 0 'no audio device'"
    assert forced == "True 3 ''"
