"""Sound effects synthesized with numpy, and the w filter that lets a player hear along w.

Every effect is made here from oscillators, noise and envelopes (nothing is shipped or
downloaded): mono ``float32`` buffers in [-1, 1] at :data:`RATE` samples per second.

The w filter (:func:`w_filter`) is what makes sound four-dimensional: a sound whose source is
``dw`` away from the player's slice along w is

* **muffled**: a two-pole low-pass filter whose cut-off falls from :data:`CLEAR_HZ` on the slice to
  :data:`MUFFLED_HZ` at :data:`W_AUDIBLE` away (geometric in between, as pitch is heard);
* **detuned**: resampled up to :data:`DETUNE_SEMITONES` semitones, *up* for a source ana (+w)
  and *down* for one kata (-w), so the ear tells the two sides apart;
* **quieter**: the gain falls smoothly (``1 - smoothstep``, flat at both ends) from 1 on the slice
  to exactly 0 at :data:`W_AUDIBLE`, so a source drifting away along w fades out instead of
  stopping.

On the slice (``dw = 0``) a sound is left exactly as synthesized.

No effect clicks: every note starts and ends with a short raised-cosine fade (:data:`FADE_IN`,
:data:`FADE_OUT`), so each effect starts and ends at zero and no note of a sequence is cut
above a few percent of its peak.
"""

from __future__ import annotations

import functools

import numpy as np

#: Samples per second: plenty for effects, and small buffers.
RATE = 22050
#: w distance at which a sound is fully muffled and detuned, and beyond which it is not heard
#: (units of w). About the reach of the ghosts: what the player cannot see yet but can hear.
W_AUDIBLE = 1.5
#: Low-pass cut-off on the slice and at W_AUDIBLE, Hz.
CLEAR_HZ = 9000.0
MUFFLED_HZ = 300.0
#: Detune at W_AUDIBLE, semitones (a minor third: clearly "off", still the same sound).
DETUNE_SEMITONES = 3.0
#: Fades at the start and the end of every note and effect, seconds: short enough not to
#: soften an attack, long enough that nothing clicks.
FADE_IN = 0.002
FADE_OUT = 0.012


def _t(seconds: float) -> np.ndarray:
    return np.arange(int(RATE * seconds), dtype=np.float64) / RATE


def _env(n: int, attack: float, decay: float) -> np.ndarray:
    """Attack-then-exponential-decay envelope over ``n`` samples (times in seconds)."""
    t = np.arange(n) / RATE
    a = np.clip(t / max(attack, 1e-4), 0.0, 1.0)
    return a * np.exp(-np.maximum(t - attack, 0.0) / max(decay, 1e-4))


def _sweep(f0: float, f1: float, seconds: float, shape: str = "sine") -> np.ndarray:
    """A tone gliding exponentially from ``f0`` to ``f1`` Hz."""
    t = _t(seconds)
    f = f0 * (f1 / f0) ** (t / seconds)
    phase = 2 * np.pi * np.cumsum(f) / RATE
    if shape == "square":
        return np.sign(np.sin(phase)) * 0.6
    if shape == "saw":
        return ((phase / (2 * np.pi)) % 1.0) * 2 - 1
    return np.sin(phase)


def _noise(seconds: float, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-1.0, 1.0, int(RATE * seconds))


def lowpass(x: np.ndarray, cutoff_hz: float) -> np.ndarray:
    """Two-pole low-pass magnitude response (12 dB per octave) applied in the frequency domain (zero phase).

    Parameters
    ----------
    x : (n,) float
    cutoff_hz : float
        -3 dB frequency.
    """
    if len(x) == 0:
        return x.astype(np.float32)
    n = 1 << int(np.ceil(np.log2(len(x) * 2)))  # padded: no wrap-around of the tail
    spec = np.fft.rfft(x, n)
    f = np.fft.rfftfreq(n, 1.0 / RATE)
    spec *= 1.0 / (1.0 + (f / cutoff_hz) ** 2)
    return np.fft.irfft(spec, n)[: len(x)].astype(np.float32)


def _tone(freqs, seconds, decay, attack=0.004, partial_decay=1.0) -> np.ndarray:
    t = _t(seconds)
    out = np.zeros_like(t)
    for i, f in enumerate(freqs):
        out += np.sin(2 * np.pi * f * t) * np.exp(-t / (decay * partial_decay**i))
    return out * _env(len(t), attack, 10.0)


def faded(x: np.ndarray, fade_in: float = FADE_IN, fade_out: float = FADE_OUT) -> np.ndarray:
    """``x`` (a copy, float64) with raised-cosine fades: its first and last samples are 0."""
    y = np.array(x, dtype=np.float64)
    for seconds, ends in ((fade_in, slice(None)), (fade_out, slice(None, None, -1))):
        n = min(len(y), max(2, int(seconds * RATE)))
        if len(y):
            ramp = np.sin(0.5 * np.pi * np.arange(n) / (n - 1)) ** 2 if n > 1 else np.zeros(1)
            y[ends][:n] *= ramp
    return y


def _seq(*parts, gap: float = 0.0) -> np.ndarray:
    """The notes one after the other (``gap`` seconds apart), each faded in and out: a note
    that has not decayed by its end fades rather than being cut."""
    pad = np.zeros(int(RATE * gap))
    out = []
    for p in parts:
        out += [faded(p), pad]
    return np.concatenate(out[:-1]) if out else np.zeros(0)


def _norm(x: np.ndarray, peak: float = 0.8) -> np.ndarray:
    m = float(np.max(np.abs(x))) if len(x) else 0.0
    y = x * (peak / m) if m > 0 else x
    return faded(y).astype(np.float32)  # no click at either end


def _step(seed: int) -> np.ndarray:
    n = _noise(0.09, seed) * _env(int(RATE * 0.09), 0.002, 0.018)
    thump = np.sin(2 * np.pi * 85 * _t(0.09)) * _env(int(RATE * 0.09), 0.002, 0.03)
    return _norm(lowpass(n, 1800) + 0.8 * thump, 0.45)


_RECIPES = {
    # the player
    "step": lambda: _step(1),
    "step_alt": lambda: _step(2),
    "jump": lambda: _norm(
        _sweep(180, 420, 0.14) * _env(int(RATE * 0.14), 0.01, 0.08) + 0.2 * lowpass(_noise(0.14, 3), 900), 0.5
    ),
    "land": lambda: _norm(
        lowpass(_noise(0.15, 4), 500) * _env(int(RATE * 0.15), 0.002, 0.04)
        + np.sin(2 * np.pi * 60 * _t(0.15)) * _env(int(RATE * 0.15), 0.002, 0.05),
        0.6,
    ),
    "w_move": lambda: _norm(
        (
            np.sin(2 * np.pi * 330 * _t(0.22))
            + 0.6 * np.sin(2 * np.pi * 495 * _t(0.22))
            + 0.4 * np.sin(2 * np.pi * 662 * _t(0.22))
        )
        * (0.6 + 0.4 * np.sin(2 * np.pi * 18 * _t(0.22)))
        * np.sin(np.pi * _t(0.22) / 0.22),
        0.25,
    ),
    "w_blocked": lambda: _norm(_sweep(140, 110, 0.16, "square") * _env(int(RATE * 0.16), 0.005, 0.08), 0.4),
    "respawn": lambda: _norm(_sweep(900, 120, 0.6) * _env(int(RATE * 0.6), 0.01, 0.3), 0.6),
    "complete": lambda: _norm(_seq(*(_tone([f, 2 * f], 0.25, 0.2) for f in (523.3, 659.3, 784.0, 1046.5))), 0.7),
    # energy and crystals
    "pickup": lambda: _norm(
        _seq(*(_tone([f, 2.01 * f, 3.02 * f], 0.18, 0.12, partial_decay=0.6) for f in (880, 1318.5, 1760))), 0.6
    ),
    "energy_empty": lambda: _norm(_seq(_tone([440], 0.15, 0.1), _tone([330], 0.15, 0.1), _tone([220], 0.3, 0.2)), 0.5),
    "hum": lambda: _norm(
        (
            np.sin(2 * np.pi * 220 * _t(0.7))
            + 0.5 * np.sin(2 * np.pi * 331 * _t(0.7))
            + 0.3 * np.sin(2 * np.pi * 1320 * _t(0.7))
        )
        * np.sin(np.pi * _t(0.7) / 0.7) ** 2,
        0.35,
    ),
    # weapons
    "shot": lambda: _norm(
        _sweep(1400, 260, 0.16) * _env(int(RATE * 0.16), 0.002, 0.07)
        + 0.3 * lowpass(_noise(0.16, 5), 3000) * _env(int(RATE * 0.16), 0.001, 0.02),
        0.6,
    ),
    "blast": lambda: _norm(
        lowpass(_noise(0.7, 6), 400) * _env(int(RATE * 0.7), 0.005, 0.25)
        + np.sin(2 * np.pi * 48 * _t(0.7)) * _env(int(RATE * 0.7), 0.005, 0.3),
        0.8,
    ),
    "field": lambda: _norm(
        sum(np.sin(2 * np.pi * f * _t(0.6) + 3 * np.sin(2 * np.pi * 5 * _t(0.6))) for f in (600, 757, 901))
        * np.sin(np.pi * _t(0.6) / 0.6),
        0.4,
    ),
    "hit": lambda: _norm(
        lowpass(_noise(0.07, 7), 4000) * _env(int(RATE * 0.07), 0.001, 0.015) + 0.5 * _tone([1900], 0.07, 0.02), 0.5
    ),
    "target": lambda: _norm(_seq(_tone([1568, 3136], 0.2, 0.15), _tone([2093, 4186], 0.35, 0.25)), 0.6),
    "impact": lambda: _norm(
        lowpass(_noise(0.2, 8), 700) * _env(int(RATE * 0.2), 0.001, 0.05) + _tone([95, 190], 0.2, 0.06), 0.6
    ),
    "refused": lambda: _norm(_seq(_tone([180], 0.07, 0.05), _tone([150], 0.09, 0.06), gap=0.03), 0.4),
    "weapon_select": lambda: _norm(
        _seq(
            lowpass(_noise(0.03, 9), 5000) * _env(int(RATE * 0.03), 0.001, 0.008),
            lowpass(_noise(0.05, 10), 2500) * _env(int(RATE * 0.05), 0.001, 0.012),
            gap=0.05,
        ),
        0.45,
    ),
    # manipulation and seek
    "grab": lambda: _norm(
        _tone([220, 440, 660], 0.2, 0.08) + 0.3 * lowpass(_noise(0.2, 11), 1500) * _env(int(RATE * 0.2), 0.001, 0.03),
        0.5,
    ),
    "turn": lambda: _norm(_sweep(300, 480, 0.25, "saw") * np.sin(np.pi * _t(0.25) / 0.25), 0.25),
    "release": lambda: _norm(_tone([660, 440], 0.2, 0.07), 0.4),
    "seek": lambda: _norm(
        lowpass(_noise(0.45, 12), 2500) * np.sin(np.pi * _t(0.45) / 0.45) ** 2
        + 0.3 * _sweep(300, 900, 0.45) * np.sin(np.pi * _t(0.45) / 0.45),
        0.4,
    ),
    "arrive": lambda: _norm(_tone([988, 1976], 0.25, 0.12), 0.4),
    # enemies (whatever the enemy events are called, see sound.cue_name)
    "enemy": lambda: _norm(
        _sweep(95, 80, 0.5, "saw") * (0.7 + 0.3 * np.sin(2 * np.pi * 9 * _t(0.5))) * _env(int(RATE * 0.5), 0.04, 0.25),
        0.5,
    ),
    "enemy_hit": lambda: _norm(_sweep(420, 200, 0.18, "saw") * _env(int(RATE * 0.18), 0.002, 0.07), 0.5),
    "enemy_die": lambda: _norm(
        _sweep(380, 40, 0.8, "saw") * _env(int(RATE * 0.8), 0.005, 0.35)
        + 0.3 * lowpass(_noise(0.8, 13), 800) * _env(int(RATE * 0.8), 0.005, 0.3),
        0.7,
    ),
    "hurt": lambda: _norm(_sweep(300, 150, 0.25, "square") * _env(int(RATE * 0.25), 0.002, 0.1), 0.5),
    # menus and cards
    "menu_move": lambda: _norm(_tone([1800], 0.04, 0.012), 0.25),
    "menu_select": lambda: _norm(_seq(_tone([880], 0.06, 0.03), _tone([1320], 0.1, 0.05)), 0.35),
    "menu_back": lambda: _norm(_seq(_tone([1320], 0.06, 0.03), _tone([880], 0.1, 0.05)), 0.35),
}

#: Every effect's name.
NAMES: tuple[str, ...] = tuple(_RECIPES)


@functools.cache
def effect(name: str) -> np.ndarray:
    """The effect ``name`` (one of :data:`NAMES`) as ``(n,) float32`` in [-1, 1] at :data:`RATE`.

    Made once and cached; the array is read-only (it is shared).
    """
    x = _RECIPES[name]()
    x = np.asarray(x, np.float32)
    x.setflags(write=False)
    return x


def w_amount(dw: float) -> float:
    """How far off the slice a source is, 0 on it to 1 at :data:`W_AUDIBLE` (clamped)."""
    return min(abs(float(dw)) / W_AUDIBLE, 1.0)


def w_filter(x: np.ndarray, dw: float) -> np.ndarray:
    """``x`` as heard from ``dw`` along w: muffled, detuned and quieter the farther it is.

    Parameters
    ----------
    x : (n,) float32
        A sound on the slice.
    dw : float
        Source w minus listener w. Positive (ana) detunes up, negative (kata) down.

    Returns
    -------
    (m,) float32
        ``x`` itself when ``dw == 0``; silence (zeros) from :data:`W_AUDIBLE` on. Detuning
        resamples, so the length changes by the pitch ratio.
    """
    if dw == 0.0:
        return x
    if abs(dw) >= W_AUDIBLE:
        return np.zeros_like(x)
    k = w_amount(dw)
    ratio = 2.0 ** (np.sign(dw) * DETUNE_SEMITONES * k / 12.0)  # > 1 plays faster: higher
    m = max(1, int(round(len(x) / ratio)))
    detuned = np.interp(np.arange(m) * ratio, np.arange(len(x)), x).astype(np.float32)
    cutoff = CLEAR_HZ * (MUFFLED_HZ / CLEAR_HZ) ** k
    # The zero-phase low-pass rings a little before the start: fade again so it starts at 0.
    return (faded(lowpass(detuned, cutoff)) * w_gain(dw)).astype(np.float32)


def w_gain(dw: float) -> float:
    """Loudness of a source ``dw`` away along w: 1 on the slice, falling smoothly (flat at both
    ends) to exactly 0 at :data:`W_AUDIBLE`, so a sound drifting out of hearing fades away."""
    k = w_amount(dw)
    return 1.0 - k * k * (3.0 - 2.0 * k)


def to_pcm16_stereo(x: np.ndarray, gain: float, pan: float) -> bytes:
    """Mono float samples to interleaved 16-bit stereo bytes, with ``gain`` and ``pan`` in [-1, 1]
    (equal-power: -1 all left, +1 all right)."""
    a = (np.clip(pan, -1.0, 1.0) + 1.0) * np.pi / 4.0
    left, right = np.cos(a) * gain, np.sin(a) * gain
    st = np.empty((len(x), 2), np.float32)
    st[:, 0] = x * left
    st[:, 1] = x * right
    return (np.clip(st, -1.0, 1.0) * 32767).astype("<i2").tobytes()
