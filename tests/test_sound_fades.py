"""No sound clicks (issue 35, point 3): every effect starts and ends at zero, no note of a
sequence is cut above a few percent of its peak, and the w fade reaches zero smoothly."""

from __future__ import annotations

import numpy as np
import pytest

from across_dimensions.app import synth

#: Most of its peak a note (or an effect) may have in its first quarter millisecond and its last
#: millisecond: a cut leaves a step there (the "refused" notes used to end at 28 %), a fade
#: does not (attacks are short: FADE_IN is 2 ms).
EDGE_SHARE = 0.05
START = synth.RATE // 4000
END = synth.RATE // 1000


def _edges_quiet(x: np.ndarray, what: str) -> None:
    peak = float(np.abs(x).max())
    assert x[0] == 0.0 and x[-1] == 0.0, what
    assert np.abs(x[:START]).max() <= EDGE_SHARE * peak, f"{what}: starts at {np.abs(x[:START]).max() / peak:.0%}"
    assert np.abs(x[-END:]).max() <= EDGE_SHARE * peak, f"{what}: ends at {np.abs(x[-END:]).max() / peak:.0%}"


@pytest.mark.parametrize("name", synth.NAMES)
def test_every_effect_starts_and_ends_at_zero_and_no_note_is_cut(name, monkeypatch):
    notes = []
    seq = synth._seq

    def recording_seq(*parts, gap=0.0):
        out = seq(*parts, gap=gap)
        at, pad = 0, int(synth.RATE * gap)
        for p in parts:  # each note's span in what _seq gives
            notes.append(out[at : at + len(p)])
            at += len(p) + pad
        return out

    monkeypatch.setattr(synth, "_seq", recording_seq)
    x = synth._RECIPES[name]()  # rendered afresh (effect() caches)
    _edges_quiet(x, name)
    for i, note in enumerate(notes):
        _edges_quiet(note, f"{name} note {i + 1} of {len(notes)}")


@pytest.mark.parametrize("dw", [0.2, -0.7, 1.2, -1.45])
def test_effects_heard_along_w_start_and_end_at_zero(dw):
    for name in ("hum", "jump", "enemy", "refused", "shot"):
        _edges_quiet(synth.w_filter(synth.effect(name), dw), f"{name} at dw {dw}")


def test_the_w_fade_reaches_zero_smoothly_at_the_edge_of_hearing():
    dws = np.linspace(0.0, synth.W_AUDIBLE, 301)
    gains = np.array([synth.w_gain(d) for d in dws])
    assert gains[0] == 1.0 and gains[-1] == 0.0
    assert np.all(np.diff(gains) < 0)
    # No step anywhere: the largest change between neighbours (0.005 of w apart) is small,
    # and the gain just inside the edge is all but gone (it used to be 0.35, then nothing).
    assert np.abs(np.diff(gains)).max() < 0.01
    assert synth.w_gain(0.99 * synth.W_AUDIBLE) < 0.001
    # What is played follows the gain: the hum's loudness just inside the edge is near zero.
    hum = synth.effect("hum")
    loud = [float(np.abs(synth.w_filter(hum, d)).max()) for d in (1.0, 1.4, 1.49, 1.5)]
    assert loud[0] > loud[1] > loud[2] > loud[3] == 0.0
    assert loud[2] < 0.002
