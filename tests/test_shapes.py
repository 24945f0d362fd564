"""Shapes: closed, oriented meshes with the right combinatorics, measures and sections.

Truth comes from closed forms (volumes, counts, edge lengths), from scipy's
convex hull and from the cross-section oracle. Cells are recovered from the
finished mesh by grouping tets by outward normal, not taken from the builder.
"""

from __future__ import annotations

import math
import zlib

import numpy as np
import pytest
from scipy.spatial import ConvexHull, cKDTree

from across_dimensions.core import cross_section, cross_section_reference, shapes, transform
from across_dimensions.core.mesh import MeshError, TetMesh4, cross4

PHI = (1 + 5**0.5) / 2

# name -> (builder kwargs kept small enough for fast tests)
SMALL = {
    "5-cell": {},
    "tesseract": {},
    "16-cell": {},
    "24-cell": {},
    "120-cell": {},
    "600-cell": {},
    "hypersphere": {"subdivisions": 1},
    "duoprism": {"p": 5, "q": 7, "r1": 1.0, "r2": 0.6},
    "cubinder": {"segments": 12},
    "duocylinder": {"segments": 10},
    "spherinder": {"subdivisions": 1},
}

_CACHE: dict = {}


def build(name: str) -> TetMesh4:
    """Each test shape built once per session (builders validate anyway)."""
    if name not in _CACHE:
        _CACHE[name] = shapes.make_shape(name, **SMALL[name])
    return _CACHE[name]


# ------------------------------------------------------------------ helpers
def cells_by_normal(mesh: TetMesh4) -> tuple[np.ndarray, np.ndarray]:
    """Group tets into flat cells by their unit outward normal (and offset).

    Returns
    -------
    normals : (c, 4) float64
    labels : (m,) int64
    """
    p = mesh.vertices.astype(np.float64)[mesh.tets]
    n = cross4(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    offset = np.einsum("ij,ij->i", n, p[:, 0])
    key = np.round(np.column_stack([n, offset]) * 1e4).astype(np.int64)
    _, first, labels = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return n[first], labels.reshape(-1)


def polytope_edges(mesh: TetMesh4) -> np.ndarray:
    """Edges of the polytope (not the triangulation) via the face lattice."""
    normals, _ = cells_by_normal(mesh)
    return shapes.polytope_lattice(mesh.vertices, normals, tol=1e-5).edges


def random_model(rng, reach: float) -> np.ndarray:
    """Random rotation plus a shift along w of at most ``reach``."""
    angles = dict(zip(transform.PLANES, rng.uniform(0, 2 * np.pi, 6)))
    m = np.eye(5)
    m[:4, :4] = transform.angles_to_rotation(angles)
    return transform.translation((0, 0, 0, rng.uniform(-reach, reach))) @ m


def generic_models(mesh: TetMesh4, count: int, seed: int, reach_frac: float = 0.7):
    """``count`` random hyperplanes that stay clear of every vertex.

    A plane within rounding distance of a vertex makes cut points that
    ``welded`` may merge; those are legitimate but not what these tests probe.
    """
    rng = np.random.default_rng(seed)
    _, r = mesh.bounding_sphere()
    out = []
    while len(out) < count:
        m = random_model(rng, reach_frac * r)
        w = transform.apply(m, mesh.vertices)[:, 3]
        if np.abs(w).min() > 1e-3 * r:
            out.append(m)
    return out


def assert_closed_section(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Every undirected edge in two triangles, every directed edge once; returns volume."""
    assert len(faces) >= 4
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    n = len(vertices)
    key = directed[:, 0] * n + directed[:, 1]
    reverse = directed[:, 1] * n + directed[:, 0]
    assert len(np.unique(key)) == len(key), "a directed edge is used twice (inconsistent winding)"
    assert np.isin(reverse, key).all(), "an edge has no partner with the opposite direction (open)"
    p = vertices[faces]
    volume = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0
    assert volume > 0, f"section volume {volume} should be positive"
    return float(volume)


def match_triangles(fast, slow) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pair each triangle of ``fast`` with the same triangle of ``slow``.

    A triangle may start at any of its three vertices (the winding is what
    matters), so every cyclic rotation of ``fast``'s triangles is tried and
    the nearest match kept; no rounding, so nothing hinges on the last bit.

    Returns
    -------
    dist : (f,) float64
        Distance between matched vertex triples, as 9-vectors.
    idx : (f,) int64
        Index of the matching triangle in ``slow``.
    rot : (f,) int64
        Cyclic shift of ``fast``'s triangle that matches.
    """
    a = fast.vertices.astype(np.float64)[fast.faces]
    b = slow.vertices.astype(np.float64)[slow.faces].reshape(-1, 9)
    tree = cKDTree(b)
    found = [tree.query(np.roll(a, -r, axis=1).reshape(-1, 9)) for r in range(3)]
    dists = np.stack([d for d, _ in found])
    rot = np.argmin(dists, axis=0)
    cols = np.arange(len(a))
    return dists[rot, cols], np.stack([i for _, i in found])[rot, cols], rot


def polygon_area(k: int, r: float) -> float:
    return 0.5 * k * r * r * math.sin(2 * math.pi / k)


# ----------------------------------------------------------- basic contract
@pytest.mark.parametrize("name", list(SMALL))
def test_mesh_contract(name):
    mesh = build(name)
    assert mesh.vertices.dtype == np.float32 and mesh.vertices.shape[1] == 4
    assert mesh.tets.dtype == np.uint32 and mesh.tets.shape[1] == 4
    assert mesh.name == name
    assert mesh.problems() == []
    assert mesh.hypervolume() > 0
    # Centred: the vertex centroid is the origin (all shapes are centrally or
    # rotationally symmetric about it).
    np.testing.assert_allclose(mesh.vertices.mean(axis=0), 0, atol=1e-6)
    # Every vertex is used.
    assert len(np.unique(mesh.tets)) == len(mesh.vertices)
    # Default colours: valid, opaque and not flat.
    c = mesh.colors
    assert c is not None and c.shape == (len(mesh.vertices), 4) and c.dtype == np.float32
    assert (c >= 0).all() and (c <= 1).all() and (c[:, 3] == 1).all()
    assert np.ptp(c[:, :3], axis=0).max() > 0.1


@pytest.mark.parametrize("name", list(SMALL))
def test_color_parameter(name):
    mesh = shapes.make_shape(name, color=(0.2, 0.4, 0.6), **SMALL[name])
    np.testing.assert_allclose(mesh.colors, np.broadcast_to([0.2, 0.4, 0.6, 1.0], mesh.colors.shape), atol=1e-7)


# ------------------------------------------------------------ combinatorics
# name: (vertices, edges, 2-faces, cells, vertices per cell, polygon sides, tets)
POLYCHORA = {
    "5-cell": (5, 10, 10, 5, 4, 3, 5),
    "tesseract": (16, 32, 24, 8, 8, 4, 48),
    "16-cell": (8, 24, 32, 16, 4, 3, 16),
    "24-cell": (24, 96, 96, 24, 6, 3, 96),
    "120-cell": (600, 1200, 720, 120, 20, 5, 3240),
    "600-cell": (120, 720, 1200, 600, 4, 3, 600),
}


@pytest.mark.parametrize("name", list(POLYCHORA))
def test_polychoron_counts(name):
    nv, ne, nf, nc, per_cell, sides, ntets = POLYCHORA[name]
    mesh = build(name)
    assert len(mesh.vertices) == nv
    assert len(mesh.tets) == ntets
    normals, labels = cells_by_normal(mesh)
    assert len(normals) == nc, "cells counted by grouping tets by outward normal"
    lattice = shapes.polytope_lattice(mesh.vertices, normals, tol=1e-5)
    assert lattice.counts == (nv, ne, nf, nc)
    assert nv - ne + nf - nc == 0  # Euler characteristic of the 3-sphere
    assert (lattice.incidence.sum(axis=1) == per_cell).all()
    assert {len(p) for p in lattice.polygons} == {sides}
    # Each cell's tets use exactly that cell's vertices.
    for c in range(0, nc, max(1, nc // 10)):
        used = np.unique(mesh.tets[labels == c])
        assert len(used) == per_cell


@pytest.mark.parametrize("name", list(POLYCHORA))
def test_feature_faces_are_the_polygons(name):
    """Tets inside a cell are coplanar: only the polygons' triangles crease."""
    nv, ne, nf, nc, per_cell, sides, ntets = POLYCHORA[name]
    assert len(build(name).feature_faces()) == nf * (sides - 2)


# name: (circumradius, edge length) at the default size
def _regular_metrics():
    return {
        "5-cell": (1.0, math.sqrt(2.5)),
        "tesseract": (1.0, 1.0),
        "16-cell": (1.0, math.sqrt(2)),
        "24-cell": (1.0, 1.0),
        "120-cell": (1.0, (3 - math.sqrt(5)) / math.sqrt(8)),
        "600-cell": (1.0, 1 / PHI),
    }


@pytest.mark.parametrize("name", list(POLYCHORA))
def test_regular_metrics(name):
    radius, edge = _regular_metrics()[name]
    mesh = build(name)
    v = mesh.vertices.astype(np.float64)
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), radius, rtol=1e-6)
    e = polytope_edges(mesh)
    np.testing.assert_allclose(np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1), edge, rtol=1e-6)
    # The polytope's edges are exactly the shortest vertex distances.
    d = np.linalg.norm(v[:, None] - v[None], axis=2)
    assert np.sum(np.abs(d - edge) < 1e-5) == 2 * len(e)


# --------------------------------------------------------------- measures
def test_tesseract_measures():
    for size in (1.0, 1.7):
        mesh = shapes.tesseract(size)
        assert mesh.hypervolume() == pytest.approx(size**4, rel=1e-6)
        assert mesh.boundary_volume() == pytest.approx(8 * size**3, rel=1e-6)
        np.testing.assert_allclose(np.abs(mesh.vertices), size / 2, rtol=1e-7)


@pytest.mark.parametrize(
    "name, radius, closed_form",
    [
        # Volumes in terms of the edge a.
        ("5-cell", 1.3, lambda a: math.sqrt(5) / 96 * a**4),
        ("16-cell", 1.3, lambda a: a**4 / 6),
        ("24-cell", 1.3, lambda a: 2 * a**4),
        ("120-cell", 1.3, lambda a: 15 / 4 * (105 + 47 * math.sqrt(5)) * a**4),
        ("600-cell", 1.3, lambda a: 25 / 4 * (2 + math.sqrt(5)) * a**4),
    ],
)
def test_regular_hypervolumes(name, radius, closed_form):
    mesh = shapes.make_shape(name, radius=radius)
    edge = _regular_metrics()[name][1] * radius
    assert mesh.hypervolume() == pytest.approx(closed_form(edge), rel=1e-5)


@pytest.mark.parametrize("name", [n for n in SMALL if n != "hypersphere"])
def test_hypervolume_matches_convex_hull(name):
    mesh = build(name)
    hull = ConvexHull(mesh.vertices.astype(np.float64))
    assert mesh.hypervolume() == pytest.approx(hull.volume, rel=1e-5)
    assert mesh.boundary_volume() == pytest.approx(hull.area, rel=1e-5)


def test_boundary_volume_16_cell():
    # 16 regular tetrahedra of edge R*sqrt(2).
    a = 1.1 * math.sqrt(2)
    assert shapes.cell16(1.1).boundary_volume() == pytest.approx(16 * a**3 / (6 * math.sqrt(2)), rel=1e-6)


@pytest.mark.parametrize("p, q, r1, r2", [(3, 3, 1.0, 1.0), (5, 7, 1.0, 0.6), (4, 9, 0.3, 2.0), (12, 4, 0.8, 0.8)])
def test_duoprism(p, q, r1, r2):
    mesh = shapes.duoprism(p, q, r1, r2)
    assert len(mesh.vertices) == p * q
    normals, _ = cells_by_normal(mesh)
    assert len(normals) == p + q  # p q-gonal prisms and q p-gonal prisms
    assert mesh.hypervolume() == pytest.approx(polygon_area(p, r1) * polygon_area(q, r2), rel=1e-5)
    lattice = shapes.polytope_lattice(mesh.vertices, normals, tol=1e-5)
    # 2-faces: q p-gons, p q-gons, p*q squares; edges: 2pq.
    assert lattice.counts == (p * q, 2 * p * q, p * q + p + q, p + q)


def test_cubinder_and_duocylinder():
    mesh = shapes.cubinder(segments=16, radius=0.4, height=1.2)
    assert mesh.hypervolume() == pytest.approx(polygon_area(16, 0.4) * 1.2**2, rel=1e-5)
    lo, hi = mesh.bounds()
    np.testing.assert_allclose(hi[[1, 3]], 0.6, rtol=1e-6)  # square in y and w
    np.testing.assert_allclose(hi[[0, 2]], 0.4, rtol=1e-6)  # disc in x and z
    duo = shapes.duocylinder(segments=20, radius=0.7)
    assert duo.hypervolume() == pytest.approx(polygon_area(20, 0.7) ** 2, rel=1e-5)
    # Both tend to the smooth solids as segments grow.
    fine = shapes.cubinder(segments=64, radius=0.5, height=1.0).hypervolume()
    assert fine < math.pi * 0.25 and fine == pytest.approx(math.pi * 0.25, rel=0.01)


def _icosphere_volume(r: float, subdivisions: int) -> float:
    v, f = shapes.icosphere(r, subdivisions)
    p = v[f]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6)


@pytest.mark.parametrize("subdivisions", [0, 1, 2])
def test_icosphere(subdivisions):
    v, f = shapes.icosphere(0.7, subdivisions)
    assert len(v) == 10 * 4**subdivisions + 2 and len(f) == 20 * 4**subdivisions
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 0.7, rtol=1e-12)
    # Convex with outward winding: every vertex is on or below every face plane.
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    assert (np.einsum("ij,ij->i", n, v[f].mean(axis=1)) > 0).all()
    assert ((v @ n.T) - np.einsum("ij,ij->i", n, v[f[:, 0]]) <= 1e-12).all()


@pytest.mark.parametrize("subdivisions", [1, 2])
def test_spherinder(subdivisions):
    r, h = 0.5, 1.0
    mesh = shapes.spherinder(r, h, subdivisions)
    ball = 4 / 3 * math.pi * r**3
    assert mesh.hypervolume() == pytest.approx(_icosphere_volume(r, subdivisions) * h, rel=1e-5)
    assert mesh.hypervolume() < ball * h
    assert mesh.hypervolume() == pytest.approx(ball * h, rel=[0.15, 0.04][subdivisions - 1])
    normals, _ = cells_by_normal(mesh)
    assert len(normals) == 20 * 4**subdivisions + 2  # triangular prisms and two caps


def test_hypersphere_converges_from_below():
    exact = math.pi**2 / 2 * 0.8**4
    volumes = []
    for s in (0, 1, 2):
        mesh = shapes.hypersphere(radius=0.8, subdivisions=s)
        assert len(mesh.tets) == 600 * 8**s
        np.testing.assert_allclose(np.linalg.norm(mesh.vertices, axis=1), 0.8, rtol=1e-6)
        # No tet inverted by pushing midpoints onto the sphere: each faces outward.
        p = mesh.vertices.astype(np.float64)[mesh.tets]
        n = cross4(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])
        assert (np.einsum("ij,ij->i", n, p.mean(axis=1)) > 0).all()
        volumes.append(mesh.hypervolume())
    assert volumes[0] < volumes[1] < volumes[2] < exact
    assert volumes[2] == pytest.approx(exact, rel=0.02)
    # Error shrinks about 4x per split (second order in edge length).
    err = [exact - v for v in volumes]
    assert err[2] < err[1] / 3 < err[0] / 9


@pytest.mark.slow
def test_hypersphere_subdivisions_3():
    mesh = shapes.hypersphere(subdivisions=3)
    assert len(mesh.tets) == 600 * 8**3
    assert mesh.hypervolume() == pytest.approx(math.pi**2 / 2, rel=0.005)


# ---------------------------------------------------------- cross-sections
@pytest.mark.parametrize("name", list(SMALL))
def test_random_sections_closed(name):
    mesh = build(name)
    cut = 0
    for m in generic_models(mesh, 20, seed=zlib.crc32(name.encode())):
        section = cross_section(mesh, model=m)
        if section.is_empty:
            continue
        cut += 1
        v, f = section.welded()
        assert_closed_section(v, f)
    assert cut >= 15


@pytest.mark.parametrize("name", list(SMALL))
def test_section_matches_reference(name):
    mesh = build(name)
    for m in generic_models(mesh, 3, seed=7):
        fast = cross_section(mesh, model=m)
        slow = cross_section_reference(mesh, model=m)
        assert len(fast) == len(slow)
        if fast.is_empty:
            continue
        dist, idx, rot = match_triangles(fast, slow)
        assert dist.max() < 1e-5
        assert len(np.unique(idx)) == len(idx), "triangle sets are not a bijection"
        # Matching triangles also carry the same normals and colours.
        np.testing.assert_allclose(fast.normals[::3], slow.normals[::3][idx], atol=1e-5)
        ca = fast.colors[fast.faces]  # (f, 3, 4)
        ca = np.take_along_axis(ca, ((np.arange(3)[None, :] + rot[:, None]) % 3)[:, :, None], axis=1)
        np.testing.assert_allclose(ca, slow.colors[slow.faces][idx], atol=1e-5)


def test_axis_aligned_sections():
    # Tesseract at w = 0: the cube [-s/2, s/2]^3.
    v, f = cross_section(shapes.tesseract(1.4)).welded()
    assert assert_closed_section(v, f) == pytest.approx(1.4**3, rel=1e-5)
    np.testing.assert_allclose([v.min(axis=0), v.max(axis=0)], [[-0.7] * 3, [0.7] * 3], rtol=1e-6)
    # 16-cell at w = 0: the octahedron |x|_1 <= R.
    v, f = cross_section(shapes.cell16(1.2)).welded()
    assert assert_closed_section(v, f) == pytest.approx(4 / 3 * 1.2**3, rel=1e-5)
    # 5-cell at w = 0: its top facet (at w = R/4) shrunk by 4/5 towards the -w apex.
    a = math.sqrt(2.5) * 0.8
    v, f = cross_section(shapes.simplex5()).welded()
    assert assert_closed_section(v, f) == pytest.approx(a**3 / (6 * math.sqrt(2)), rel=1e-5)
    # 24-cell at w = 0 passes through 12 vertices (the tie rule): a cuboctahedron of edge R.
    v, f = cross_section(shapes.cell24(1.0)).welded()
    assert assert_closed_section(v, f) == pytest.approx(5 * math.sqrt(2) / 3, rel=1e-5)
    # Spherinder inside its height: the icosphere itself.
    v, f = cross_section(shapes.spherinder(0.5, 1.0, 2), camera_pose=transform.translation((0, 0, 0, 0.2))).welded()
    assert assert_closed_section(v, f) == pytest.approx(_icosphere_volume(0.5, 2), rel=1e-5)
    # Cubinder at w = 0: an upright 24-gon prism (y is the height).
    v, f = cross_section(shapes.cubinder()).welded()
    assert assert_closed_section(v, f) == pytest.approx(polygon_area(24, 0.5) * 1.0, rel=1e-5)
    np.testing.assert_allclose([v[:, 1].min(), v[:, 1].max()], [-0.5, 0.5], rtol=1e-6)


@pytest.mark.parametrize("w", [0.0, 0.31, -0.55, 0.8])
def test_hypersphere_slices(w):
    radius = 1.0
    r = math.sqrt(radius**2 - w**2)
    errors = []
    for s in (1, 2):
        mesh = shapes.hypersphere(radius, s)
        v, f = cross_section(mesh, camera_pose=transform.translation((0, 0, 0, w))).welded()
        volume = assert_closed_section(v, f)
        # Section points lie on chords of the 3-sphere: inside radius r, and no
        # deeper than the chords' sagitta allows.
        vv = mesh.vertices.astype(np.float64)
        e = np.sort(mesh.tets[:, [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]].reshape(-1, 2), axis=1)
        chord = np.linalg.norm(vv[e[:, 0]] - vv[e[:, 1]], axis=1).max()
        deepest = math.sqrt(radius**2 - (chord / 2) ** 2)  # distance of a chord's midpoint
        dist = np.linalg.norm(v, axis=1)
        assert dist.max() <= r * (1 + 1e-6)
        assert dist.min() >= math.sqrt(max(deepest**2 - w**2, 0)) * (1 - 1e-6)
        p = v[f]
        area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum()
        errors.append((4 * math.pi * r**2 - area) / (4 * math.pi * r**2))
        assert volume < 4 / 3 * math.pi * r**3
    assert 0 < errors[1] < errors[0]
    assert errors[1] < 0.06


def test_section_volume_integrates_to_hypervolume():
    # Fubini: integrating section volumes over w gives the hyper-volume.
    mesh = shapes.duoprism(5, 7, 1.0, 0.6)
    rng = np.random.default_rng(3)
    rot = np.eye(5)
    rot[:4, :4] = transform.angles_to_rotation(dict(zip(transform.PLANES, rng.uniform(0, 6.3, 6))))
    turned = mesh.transformed(rot)
    lo, hi = turned.bounds()
    ws = np.linspace(lo[3], hi[3], 401)
    vols = []
    for w in ws:
        s = cross_section(turned, camera_pose=transform.translation((0, 0, 0, w)))
        vols.append(s.volume() if not s.is_empty else 0.0)
    integral = np.trapezoid(vols, ws)
    assert integral == pytest.approx(mesh.hypervolume(), rel=1e-3)


# -------------------------------------------------------------- registry
def test_registry_names():
    for name in (
        "5-cell",
        "simplex",
        "tesseract",
        "16-cell",
        "24-cell",
        "120-cell",
        "600-cell",
        "hypersphere",
        "duoprism",
        "cubinder",
        "spherinder",
    ):
        assert name in shapes.SHAPES
    assert shapes.make_shape("simplex").name == "5-cell"
    assert shapes.make_shape("Tesseract", size=2.0).hypervolume() == pytest.approx(16.0)


def test_make_shape_errors():
    with pytest.raises(ValueError) as err:
        shapes.make_shape("klein-bottle")
    msg = str(err.value)
    assert "\n" not in msg and "klein-bottle" in msg
    for name in shapes.SHAPES:
        assert name in msg
    with pytest.raises(ValueError, match="radius"):
        shapes.make_shape("tesseract", radius=2.0)


@pytest.mark.parametrize(
    "call",
    [
        lambda: shapes.duoprism(2, 5),
        lambda: shapes.duoprism(3.5, 5),
        lambda: shapes.hypersphere(subdivisions=-1),
        lambda: shapes.hypersphere(radius=0.0),
        lambda: shapes.tesseract(-1.0),
        lambda: shapes.spherinder(height=0.0),
        lambda: shapes.cubinder(segments=2),
    ],
)
def test_bad_parameters(call):
    with pytest.raises(ValueError):
        call()


def test_convex_polytope_rejects_bad_normals():
    v = shapes.tesseract().vertices
    with pytest.raises(ValueError):
        shapes.convex_polytope(v, [[1, 1, 0, 0]])  # picks an edge-square, not a cell
    with pytest.raises(ValueError, match="same facet"):
        shapes.convex_polytope(v, np.concatenate([np.eye(4), -np.eye(4), [[2.0, 0, 0, 0]]]))
    # A missing facet leaves the boundary open.
    with pytest.raises(MeshError):
        shapes.convex_polytope(v, np.concatenate([np.eye(4), -np.eye(4)[:3]]))


def test_convex_polytope_generic():
    """An irregular polytope: random points on the 3-sphere, facets from qhull."""
    rng = np.random.default_rng(11)
    pts = rng.normal(size=(40, 4))
    pts /= np.linalg.norm(pts, axis=1, keepdims=True)
    hull = ConvexHull(pts)
    mesh = shapes.convex_polytope(pts, hull.equations[:, :4], name="random")
    assert mesh.name == "random" and mesh.problems() == []
    assert len(mesh.tets) == len(hull.simplices)  # simplicial: one tet per cell
    assert mesh.hypervolume() == pytest.approx(hull.volume, rel=1e-6)
    # Per-vertex colours pass straight through.
    rgb = rng.uniform(size=(40, 3))
    coloured = shapes.convex_polytope(pts, hull.equations[:, :4], color=rgb)
    np.testing.assert_allclose(coloured.colors[:, :3], rgb, atol=1e-7)
    # A box with unequal sides: cells are cuboids, volume the product.
    sides = np.array([0.5, 1.0, 1.5, 2.0])
    box = shapes.convex_polytope(shapes.tesseract(2.0).vertices * sides / 2, np.concatenate([np.eye(4), -np.eye(4)]))
    assert box.hypervolume() == pytest.approx(np.prod(sides), rel=1e-6)
    assert box.boundary_volume() == pytest.approx(2 * sum(np.prod(sides) / s for s in sides), rel=1e-6)
