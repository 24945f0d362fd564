"""The radar's meshes: the unit shapes its pins are instanced from, and the static disc.

Built once with numpy when a :class:`~.radar.RadarRenderer` starts (no OpenGL here, so tested
without a context). Pin shapes are triangle soups ``(k, 6) float32`` (position, normal) about
unit size, welded to indexed meshes for the draw (:func:`weld`); the disc is a translucent
triangle list ``(k, 7) float32`` (position, RGBA) in radar space (the unit circle in x-z).
"""

from __future__ import annotations

import numpy as np

DISC_FILL = (0.06, 0.22, 0.32, 0.42)
DISC_RIM_FILL = (0.10, 0.38, 0.52, 0.55)
RING_COLOR = (0.45, 0.85, 1.0, 0.55)
RIM_COLOR = (0.6, 0.95, 1.0, 0.95)
AXIS_COLOR = (0.45, 0.85, 1.0, 0.22)
WEDGE_COLOR = (0.7, 0.95, 1.0, 0.14)
FORWARD_COLOR = (0.85, 1.0, 1.0, 0.95)
PLAYER_COLOR = (1.0, 1.0, 1.0, 1.0)


def _soup(verts, faces) -> np.ndarray:
    """Triangle soup ``(3 f, 6) float32`` (position, flat normal) from indexed triangles."""
    v = np.asarray(verts, np.float64)[np.asarray(faces, np.int64)]  # (f, 3, 3)
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    out = np.empty((len(v), 3, 6), np.float32)
    out[:, :, :3] = v
    out[:, :, 3:] = n[:, None, :]
    return out.reshape(-1, 6)


def _hull_faces(verts) -> list[tuple[int, int, int]]:
    """Triangles of a small convex point set (brute force; winding does not matter here)."""
    v = np.asarray(verts, np.float64)
    faces = []
    m = len(v)
    for i in range(m):
        for j in range(i + 1, m):
            for k in range(j + 1, m):
                n = np.cross(v[j] - v[i], v[k] - v[i])
                if np.linalg.norm(n) < 1e-9:
                    continue
                d = (v - v[i]) @ n
                if (d <= 1e-9).all() or (d >= -1e-9).all():
                    faces.append((i, j, k))
    return faces


def _box(center, half) -> np.ndarray:
    c, h = np.asarray(center, float), np.asarray(half, float)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float) * h + c
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return _soup(corners, [t for a, b, c_, d in quads for t in ((a, b, c_), (a, c_, d))])


def _revolve(profile, axis: int, segments: int) -> np.ndarray:
    """Surface of revolution of ``(r, t)`` profile points round the coordinate ``axis``."""
    ang = np.linspace(0, 2 * np.pi, segments + 1)[:-1]
    p = np.asarray(profile, float)
    a, b = [i for i in range(3) if i != axis]
    verts = np.zeros((len(p) * segments, 3))
    for i, (r, t) in enumerate(p):
        sl = slice(i * segments, (i + 1) * segments)
        verts[sl, axis] = t
        verts[sl, a] = r * np.cos(ang)
        verts[sl, b] = r * np.sin(ang)
    faces = []
    for i in range(len(p) - 1):
        for s in range(segments):
            q0, q1 = i * segments + s, i * segments + (s + 1) % segments
            faces += [(q0, q1, q1 + segments), (q0, q1 + segments, q0 + segments)]
    soup = _soup(verts, faces)
    # Drop degenerate triangles at the tips (radius 0).
    tri = soup.reshape(-1, 3, 6)
    keep = np.abs(tri[:, :, 3:]).sum(axis=(1, 2)) > 0
    return tri[keep].reshape(-1, 6)


def _sphere(subdiv: int = 1) -> np.ndarray:
    t = (1 + 5**0.5) / 2
    v = [
        (-1, t, 0),
        (1, t, 0),
        (-1, -t, 0),
        (1, -t, 0),
        (0, -1, t),
        (0, 1, t),
        (0, -1, -t),
        (0, 1, -t),
        (t, 0, -1),
        (t, 0, 1),
        (-t, 0, -1),
        (-t, 0, 1),
    ]
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    f = _hull_faces(v)
    for _ in range(subdiv):
        nf, cache = [], {}

        def mid(i, j, cache=cache):
            key = (min(i, j), max(i, j))
            if key not in cache:
                m = v[i] + v[j]
                v.append(m / np.linalg.norm(m))
                cache[key] = len(v) - 1
            return cache[key]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return _soup(v, f)


def weld(soup: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Indexed form of a triangle soup: unique ``(k, 6) float32`` rows and ``(3 f,) uint32`` indices.

    Indexed draws let llvmpipe shade each shared vertex once per instance instead of once per
    triangle corner (it runs vertex shaders on the CPU).
    """
    q = np.round(np.asarray(soup, np.float64) * 1e5).astype(np.int64)
    _, first, inverse = np.unique(q, axis=0, return_index=True, return_inverse=True)
    return np.ascontiguousarray(soup[first], np.float32), inverse.reshape(-1).astype(np.uint32)


def unit_shapes() -> dict[str, np.ndarray]:
    """Every instanced shape as a triangle soup ``(k, 6) float32`` (position, normal), about unit size.

    Heads fit in ``[-1, 1]^3``; ``stem`` is the quad ``x in [-0.5, 0.5], y in [0, 1]`` facing -z;
    ``foot`` a flat unit disc and ``seen_ring`` a flat annulus (r 0.75 to 1) in the x-z plane;
    ``arrow`` a cone with its tip at ``y = 1`` and its base at ``y = 0``.
    """
    s: dict[str, np.ndarray] = {}
    octa = [(0.75, 0, 0), (-0.75, 0, 0), (0, 1.25, 0), (0, -1.25, 0), (0, 0, 0.75), (0, 0, -0.75)]
    s["octahedron"] = _soup(octa, _hull_faces(octa))
    s["cube"] = _box((0, 0, 0), (0.75, 0.75, 0.75))
    tet = np.array([(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)], float) * 0.8
    # Stella octangula: two interpenetrating tetrahedra, all spikes.
    s["star"] = np.concatenate([_soup(tet, _hull_faces(tet)), _soup(-tet, _hull_faces(-tet))])
    sphere = _sphere(0)  # an icosahedron with smooth normals: bullets are a few pixels wide
    sphere[:, 3:] = sphere[:, :3]
    s["sphere"] = sphere
    # Torus standing in the x-y plane (a ring facing the radar camera): revolve a circle about z,
    # built as rings of quads.
    # Few segments: llvmpipe transforms every vertex of every instance on the CPU.
    seg, tube, big, small = 10, 4, 0.72, 0.27
    u = np.linspace(0, 2 * np.pi, seg + 1)[:-1]
    w = np.linspace(0, 2 * np.pi, tube + 1)[:-1]
    U, Wt = np.meshgrid(u, w, indexing="ij")
    ring_r = big + small * np.cos(Wt)
    tv = np.stack([ring_r * np.cos(U), ring_r * np.sin(U), small * np.sin(Wt)], -1).reshape(-1, 3)
    tf = []
    for i in range(seg):
        for j in range(tube):
            a, b = i * tube + j, ((i + 1) % seg) * tube + j
            c, d = ((i + 1) % seg) * tube + (j + 1) % tube, i * tube + (j + 1) % tube
            tf += [(a, b, c), (a, c, d)]
    torus = _soup(tv, tf).reshape(-1, 6)
    # Smooth normals (from the tube's centre line), so the welded mesh shares every vertex.
    p = torus[:, :3].astype(np.float64)
    centre = p.copy()
    centre[:, 2] = 0.0
    centre *= big / np.maximum(np.linalg.norm(centre, axis=1, keepdims=True), 1e-12)
    nrm = p - centre
    torus[:, 3:] = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
    s["torus"] = torus
    bar = 0.22
    s["cross"] = np.concatenate([_box((0, 0, 0), half) for half in ((1.0, bar, bar), (bar, 1.0, bar), (bar, bar, 1.0))])
    # Camera eye: a cone lying on its side, tip to the right (reads as a projector or eye beam).
    s["cone"] = _revolve([(0.0, 1.0), (0.7, -0.8), (0.0, -0.8)], axis=0, segments=10)
    # Object: a hollow cube, each face a square frame (eight triangles), so its edges read as an outline.
    e, t = 0.8, 0.55
    frames = []
    for axis in range(3):
        a, b = [i for i in range(3) if i != axis]
        for side in (-e, e):
            outer = [(-e, -e), (e, -e), (e, e), (-e, e)]
            pts = []
            for u, v in outer + [(t * u, t * v) for u, v in outer]:
                p = np.zeros(3)
                p[axis], p[a], p[b] = side, u, v
                pts.append(p)
            tris = [t_ for i in range(4) for t_ in ((i, (i + 1) % 4, 4 + (i + 1) % 4), (i, 4 + (i + 1) % 4, 4 + i))]
            frames.append(_soup(pts, tris))
    s["cube_outline"] = np.concatenate(frames)
    s["stem"] = _soup([(-0.5, 0, 0), (0.5, 0, 0), (0.5, 1, 0), (-0.5, 1, 0)], [(0, 1, 2), (0, 2, 3)])
    k = 8
    ang = np.linspace(0, 2 * np.pi, k + 1)[:-1]
    circle = np.stack([np.cos(ang), 0 * ang, np.sin(ang)], 1)
    s["foot"] = _soup(np.vstack([[0, 0, 0], circle]), [(0, 1 + i, 1 + (i + 1) % k) for i in range(k)])
    k = 12
    ang = np.linspace(0, 2 * np.pi, k + 1)[:-1]
    circle = np.stack([np.cos(ang), 0 * ang, np.sin(ang)], 1)
    ring = np.vstack([circle, 0.72 * circle])
    quads = [((i, (i + 1) % k, k + (i + 1) % k), (i, k + (i + 1) % k, k + i)) for i in range(k)]
    s["seen_ring"] = _soup(ring, [t for q in quads for t in q])
    s["arrow"] = _revolve([(0.0, 1.0), (1.0, 0.0), (0.0, 0.0)], axis=1, segments=8)
    return s


def _annulus(r0, r1, color, segments=64, y=0.0, a0=0.0, a1=2 * np.pi) -> np.ndarray:
    ang = np.linspace(a0, a1, segments + 1)
    c0, s0 = np.cos(ang[:-1]), np.sin(ang[:-1])
    c1, s1 = np.cos(ang[1:]), np.sin(ang[1:])

    # Angle 0 is +x, angles grow towards +z.
    def p(r, c, s):
        return np.stack([r * c, np.full_like(c, y), r * s], -1)

    a, b, c, d = p(r0, c0, s0), p(r1, c0, s0), p(r1, c1, s1), p(r0, c1, s1)
    tris = np.stack([a, b, c, a, c, d], 1).reshape(-1, 3)
    return _colored(tris, color)


def _colored(points, color) -> np.ndarray:
    out = np.empty((len(points), 7), np.float32)
    out[:, :3] = points
    out[:, 3:] = color
    return out


def disc_vertices() -> np.ndarray:
    """The static disc as a translucent triangle list ``(k, 7) float32`` (position, RGBA), back to front layers."""
    parts = [
        _annulus(0.0, 0.66, DISC_FILL),
        _annulus(0.66, 1.0, DISC_RIM_FILL),
    ]
    # The player's view wedge (about a 75 degree field of view, centred on +z).
    half = np.radians(37.5)
    parts.append(_annulus(0.0, 1.0, WEDGE_COLOR, segments=16, a0=np.pi / 2 - half, a1=np.pi / 2 + half))
    for r in (1 / 3, 2 / 3):
        parts.append(_annulus(r - 0.007, r + 0.007, RING_COLOR))
    parts.append(_annulus(0.985, 1.015, RIM_COLOR))
    w = 0.006
    for tri in (((-1, -w), (1, -w), (1, w)), ((-1, -w), (1, w), (-1, w))):
        parts.append(_colored(np.array([(x, 0.0, z) for x, z in tri]), AXIS_COLOR))  # x axis
        parts.append(_colored(np.array([(z, 0.0, x) for x, z in tri]), AXIS_COLOR))  # z axis
    # Forward notch outside the rim, and the player's chevron at the centre, both pointing +z.
    parts.append(_colored(np.array([(-0.09, 0.0, 1.03), (0.09, 0.0, 1.03), (0.0, 0.0, 1.17)]), FORWARD_COLOR))
    chev = np.array(
        [
            (-0.06, 0.0, -0.05),
            (0.0, 0.0, 0.09),
            (0.0, 0.0, -0.01),
            (0.06, 0.0, -0.05),
            (0.0, 0.0, -0.01),
            (0.0, 0.0, 0.09),
        ]
    )
    chev[:, 1] = 0.007
    parts.append(_colored(chev, PLAYER_COLOR))
    return np.concatenate(parts).astype(np.float32)
