"""Sections one dimension down (core/flat_section.py, core/flat_solids.py) against analytic truth."""

from __future__ import annotations

import math

import numpy as np
import pytest

from across_dimensions.core.flat_section import (
    Solid3,
    section_loops,
    section_segments,
    section_segments_reference,
    signed_area,
    sphere_circle_radius,
)
from across_dimensions.core.flat_solids import (
    box_solid,
    circle_overlaps_box,
    convex_overlaps_box,
    convex_pieces,
    is_convex,
    prism_solid,
    simplified,
    sphere_solid,
    staircase_profile,
    triangulate,
)

#: Coordinates here are metres of order 1; the cut points are one division and one multiply-add
#: from exact inputs, so 1e-12 holds them.
EXACT = 1e-12


def _turned(solid: Solid3, seed: int) -> Solid3:
    """``solid`` rotated by a random rotation about its centroid (QR of a Gaussian matrix)."""
    rng = np.random.default_rng(seed)
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] *= -1
    c = solid.vertices.mean(axis=0)
    return Solid3((solid.vertices - c) @ q.T + c, solid.triangles)


def _volume(solid: Solid3) -> float:
    v = solid.vertices[solid.triangles.astype(np.int64)]
    return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6.0)


# ----------------------------------------------------------------- the box
def test_box_section_is_its_rectangle_inside_its_z_extent():
    box = box_solid((1.0, 2.0, 0.5), (2.0, 3.0, 1.0))  # z from 0 to 1
    for z0 in (0.0, 0.25, 0.5, 0.999):
        (loop,) = section_loops(box, z0)
        assert signed_area(loop) == pytest.approx(6.0, abs=EXACT)
        assert loop.min(axis=0) == pytest.approx([0.0, 0.5], abs=EXACT)
        assert loop.max(axis=0) == pytest.approx([2.0, 3.5], abs=EXACT)


@pytest.mark.parametrize("z0", [-5.0, -1e-9, 1.0, 1.0 + 1e-9, 7.0])
def test_box_vanishes_outside_its_z_extent(z0):
    box = box_solid((1.0, 2.0, 0.5), (2.0, 3.0, 1.0))
    assert section_loops(box, z0) == []
    assert len(section_segments(box, z0).points) == 0


# ----------------------------------------------------------------- the sphere
@pytest.mark.parametrize("z0", np.linspace(-1.4, 1.9, 23))
def test_sphere_section_is_the_circle_of_radius_sqrt_r2_minus_d2(z0):
    center, r = np.array([0.3, -0.2, 0.25]), 1.5
    sphere = sphere_solid(center, r, subdivisions=3)
    expected = sphere_circle_radius(center[2], r, z0)
    assert expected == pytest.approx(math.sqrt(max(0.0, r * r - (z0 - center[2]) ** 2)), abs=EXACT)
    loops = section_loops(sphere, z0)
    if expected == 0.0:
        assert loops == []
        return
    # Every point of the mesh lies between the sphere and the nearest triangle plane (the vertices
    # are on the sphere), so each section corner's distance from the circle's centre is bounded
    # by the same two spheres cut at this z: an exact band, no fitted tolerance.
    v = sphere.vertices[sphere.triangles.astype(np.int64)]
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    inner = np.min(np.abs(np.einsum("ij,ij->i", n, v[:, 0] - center)) / np.linalg.norm(n, axis=1))
    dz2 = (z0 - center[2]) ** 2
    (loop,) = loops
    radii = np.hypot(*(loop - center[:2]).T)
    assert radii.max() <= expected + EXACT
    assert radii.min() >= math.sqrt(max(0.0, inner * inner - dz2)) - EXACT
    assert signed_area(loop) > 0


def test_sphere_circle_radius_grows_and_shrinks_through_the_plane():
    radii = [sphere_circle_radius(k / 10, 1.0, 0.0) for k in range(-15, 16)]  # -c is exactly the mirror of c
    assert radii[0] == radii[-1] == 0.0
    assert max(radii) == 1.0 and radii == radii[::-1]


# ----------------------------------------------------------------- staircases
def test_staircase_climbing_along_z_has_one_height_per_step():
    # Three steps of 1 m run and 0.5 m rise along z, 4 m wide in x: at z0 in step k the plane cuts
    # a 4 m x (k * 0.5 m) rectangle; beyond the last step, nothing.
    profile = staircase_profile(3, 1.0, 0.5)  # (along = z, up = y)
    stairs = prism_solid(profile[::-1, ::-1], -2.0, 2.0, axis="x")  # (y, z) counter-clockwise
    for z0, height in ((0.0, 0.5), (0.5, 0.5), (1.0, 1.0), (1.7, 1.0), (2.0, 1.5), (2.99, 1.5)):
        (loop,) = section_loops(stairs, z0)
        assert loop.min(axis=0) == pytest.approx([-2.0, 0.0], abs=EXACT)
        assert loop.max(axis=0) == pytest.approx([2.0, height], abs=EXACT)
        assert signed_area(loop) == pytest.approx(4.0 * height, abs=EXACT)
    assert section_loops(stairs, 3.0) == [] and section_loops(stairs, -0.01) == []


def test_staircase_climbing_along_x_is_its_profile_inside_its_depth():
    profile = staircase_profile(4, 0.6, 0.35)
    stairs = prism_solid(profile, -1.0, 1.5)
    for z0 in (-1.0, 0.0, 1.2):
        (loop,) = section_loops(stairs, z0)
        assert signed_area(loop) == pytest.approx(signed_area(profile), abs=EXACT)
        assert sorted(map(tuple, np.round(simplified(loop), 12))) == sorted(map(tuple, np.round(profile, 12)))
    assert section_loops(stairs, 1.5) == []


# ----------------------------------------------------------------- rules
@pytest.mark.parametrize("seed", range(6))
def test_kernel_matches_the_reference_bit_for_bit(seed):
    solids = [
        box_solid((0, 0, 0), (1, 2, 3)),
        sphere_solid((0.1, 0, 0), 1.0, 2),
        prism_solid(staircase_profile(3, 1, 1), -1, 1),
    ]
    solid = _turned(solids[seed % 3], seed)
    for z0 in np.random.default_rng(seed).uniform(-1.5, 1.5, 9):
        fast, slow = section_segments(solid, z0), section_segments_reference(solid, z0)
        np.testing.assert_array_equal(fast.points, slow.points)
        np.testing.assert_array_equal(fast.keys, slow.keys)


@pytest.mark.parametrize("seed", range(4))
def test_section_areas_integrate_to_the_volume(seed):
    # Cavalieri: the volume is the integral of the section areas over z. Outer loops count
    # positive, so a wrongly wound or unclosed loop shows here. The areas of a polyhedron are
    # piecewise quadratic in z; 4000 midpoint samples hold the integral to ~1e-6 of the volume.
    solid = _turned([box_solid((0, 0, 0), (1, 2, 3)), prism_solid(staircase_profile(3, 1, 0.7), -1, 1)][seed % 2], seed)
    lo, hi = solid.z_extent()
    zs = lo + (np.arange(4000) + 0.5) * (hi - lo) / 4000
    areas = [sum(signed_area(p) for p in section_loops(solid, z)) for z in zs]
    assert all(a > 0 for a in areas)
    assert np.sum(areas) * (hi - lo) / 4000 == pytest.approx(_volume(solid), rel=1e-4)


def test_a_cut_through_a_vertex_still_closes():
    box = _turned(box_solid((0, 0, 0), (1, 1, 1)), 3)
    for z0 in box.vertices[:, 2]:
        for loop in section_loops(box, z0):
            assert signed_area(loop) > 0


# ----------------------------------------------------------------- 2D pieces
def _inside(q, poly) -> bool:
    x, y = q
    hit = False
    for (x0, y0), (x1, y1) in zip(poly, np.roll(poly, -1, axis=0)):
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            hit = not hit
    return hit


@pytest.mark.parametrize("steps", [1, 2, 3, 6])
def test_convex_pieces_tile_the_polygon(steps):
    poly = staircase_profile(steps, 0.6, 0.35)
    pieces = convex_pieces(poly)
    assert all(is_convex(p) and signed_area(p) > 0 for p in pieces)
    assert sum(signed_area(p) for p in pieces) == pytest.approx(signed_area(poly), abs=1e-12)
    assert len(pieces) <= max(1, 2 * steps - 1)
    rng = np.random.default_rng(steps)
    for q in rng.uniform(poly.min(axis=0), poly.max(axis=0), size=(300, 2)):
        assert sum(_inside(q, p) for p in pieces) == _inside(q, poly)


def test_triangulation_covers_the_polygon():
    poly = staircase_profile(4, 1.0, 1.0)
    tri = triangulate(poly)
    assert len(tri) == len(poly) - 2
    assert sum(signed_area(poly[t]) for t in tri) == pytest.approx(signed_area(poly))


def test_overlaps_count_touching_as_apart():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    assert convex_overlaps_box(square, (0.5, 0.5), (2.0, 2.0))
    assert not convex_overlaps_box(square, (1.0, 0.0), (2.0, 1.0))  # side by side
    assert not convex_overlaps_box(square, (0.0, 1.0), (1.0, 2.0))  # standing on it
    wedge = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    assert not convex_overlaps_box(wedge, (1.2, 1.2), (2.0, 2.0))  # beyond the slope: only its normal says so
    assert convex_overlaps_box(wedge, (0.9, 0.9), (2.0, 2.0))
    assert circle_overlaps_box((0.0, 0.0), 1.0, (0.5, -0.1), (2.0, 0.1))
    assert not circle_overlaps_box((0.0, 0.0), 1.0, (1.0, -1.0), (2.0, 1.0))
    assert not circle_overlaps_box((0.0, 0.0), 1.0, (0.8, 0.8), (2.0, 2.0))  # the corner is outside the circle
