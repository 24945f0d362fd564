"""Wireframe feature edges (core.edges): pure geometry, no OpenGL needed."""

from __future__ import annotations

import numpy as np

from across_dimensions.core.edges import feature_edges
from across_dimensions.core.lift import box_solid


def box_surface():
    v, _ = box_solid([0.0, 0.0, 0.0], 1.0)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    f = [(a, b, c) for a, b, c, d in quads] + [(a, c, d) for a, b, c, d in quads]
    return v.astype(np.float32), np.array(f, np.uint32)


def test_box_keeps_its_twelve_edges_and_drops_the_diagonals():
    v, f = box_surface()
    e = feature_edges(v, f)
    assert e.shape == (12, 2) and e.dtype == np.uint32
    # Every kept edge is axis-aligned: its ends differ in exactly one coordinate.
    assert (np.count_nonzero(v[e[:, 0]] != v[e[:, 1]], axis=1) == 1).all()


def test_triangle_soup_is_welded_before_edges_are_found():
    v, f = box_surface()
    soup_v = v[f.reshape(-1)]
    soup_f = np.arange(len(soup_v), dtype=np.uint32).reshape(-1, 3)
    e = feature_edges(soup_v, soup_f)
    assert len(e) == 12
    assert (np.count_nonzero(soup_v[e[:, 0]] != soup_v[e[:, 1]], axis=1) == 1).all()


def test_a_fold_is_kept_and_an_empty_mesh_has_no_edges():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    flat = feature_edges(
        np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], np.float32), np.array([[0, 1, 2], [2, 1, 3]], np.uint32)
    )
    assert len(flat) == 4  # the shared diagonal of a flat quad is dropped
    folded = feature_edges(v, np.array([[0, 1, 2], [0, 3, 1]], np.uint32))
    assert len(folded) == 5  # a 90 degree fold keeps the shared edge
    assert feature_edges(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32)).shape == (0, 2)
