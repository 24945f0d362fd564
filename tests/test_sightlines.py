"""Segments against boxes (physics/sightlines.py): analytic cases, and the slab test in numpy."""

from __future__ import annotations

import numpy as np

from across_dimensions.physics.sightlines import segments_cross_boxes, segments_cross_their_boxes

UNIT = np.array([[[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]]])


def _cross(eye, ends, boxes):
    out = np.empty((len(ends), len(boxes)), bool)
    anyone = segments_cross_boxes(np.asarray(eye, float), np.asarray(ends, float), np.asarray(boxes, float), out)
    return out, anyone


def _slabs(eye, ends, boxes):
    """The slab test written with numpy, every segment against every box, ``(m, k) bool``."""
    d = ends[:, None] - eye
    inv = 1.0 / np.where(np.abs(d) < 1e-12, 1e-12, d)
    t0, t1 = (boxes[None, :, 0] - eye) * inv, (boxes[None, :, 1] - eye) * inv
    enter, leave = np.minimum(t0, t1).max(axis=2), np.maximum(t0, t1).min(axis=2)
    return (enter <= leave) & (enter <= 1.0) & (leave >= 0.0)


def test_a_segment_through_a_box_crosses_it_and_one_that_stops_short_does_not():
    eye = [0.0, 0.0, -5.0]
    out, anyone = _cross(eye, [[0.0, 0.0, 5.0], [0.0, 0.0, -2.0], [0.0, 3.0, 5.0], [0.0, 0.0, -1.0]], UNIT)
    assert out[:, 0].tolist() == [True, False, False, True]  # through; short; above; ends on the face
    assert anyone


def test_a_segment_along_a_face_outside_the_box_misses_it():
    out, anyone = _cross([2.0, 0.0, -5.0], [[2.0, 0.0, 5.0]], UNIT)  # parallel to x = 1, beyond it
    assert not out.any() and not anyone


def test_a_segment_starting_inside_a_box_crosses_it():
    out, _ = _cross([0.0, 0.0, 0.0], [[0.0, 0.0, 9.0]], UNIT)
    assert out.all()


def test_random_segments_agree_with_the_slab_test_in_numpy():
    rng = np.random.default_rng(7)
    eye = rng.uniform(-3, 3, 3)
    ends = rng.uniform(-6, 6, (200, 3))
    lo = rng.uniform(-4, 3, (9, 3))
    boxes = np.stack([lo, lo + rng.uniform(0.1, 2.0, (9, 3))], axis=1)
    out, anyone = _cross(eye, ends, boxes)
    expect = _slabs(eye, ends, boxes)
    assert 0 < expect.sum() < expect.size  # some of each
    assert np.array_equal(out, expect) and anyone == expect.any()
    pairs = np.empty(len(ends), bool)
    segments_cross_their_boxes(eye, ends, np.ascontiguousarray(boxes[np.arange(len(ends)) % 9]), pairs)
    assert np.array_equal(pairs, expect[np.arange(len(ends)), np.arange(len(ends)) % 9])
