"""Generate the small watertight OBJ assets in this folder.

Run ``python assets/meshes/make_assets.py`` to rewrite them; the output is
deterministic, so a diff shows real changes only. numpy only. Axes: x right,
y up, z forward; every asset stands on ``y = 0`` centred on the y axis; metres.

Each asset is a single closed, outward-wound surface (no overlapping parts), so
its volume is well defined and tetrahedralization sees one solid.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


# ------------------------------------------------------------------- builders
def lathe(profile, segments: int) -> tuple[np.ndarray, np.ndarray]:
    """Surface of revolution about the y axis.

    Parameters
    ----------
    profile : (p, 2) array_like float
        ``(radius, y)`` from bottom to top; the first and last must have radius 0
        (the poles), the others radius > 0.
    segments : int

    Returns
    -------
    vertices : (v, 3) float64
    faces : (f, 3) int64
        Counter-clockwise seen from outside.
    """
    prof = np.asarray(profile, dtype=np.float64)
    assert prof[0, 0] == 0 and prof[-1, 0] == 0 and (prof[1:-1, 0] > 0).all()
    ring = prof[1:-1]
    ang = 2 * np.pi * np.arange(segments) / segments
    # Ring i, segment j -> vertex 1 + i * segments + j; poles are 0 and last.
    rings = np.stack([np.c_[r * np.cos(ang), np.full(segments, y), r * np.sin(ang)] for r, y in ring])
    vertices = np.concatenate([[[0.0, prof[0, 1], 0.0]], rings.reshape(-1, 3), [[0.0, prof[-1, 1], 0.0]]])
    top = len(vertices) - 1
    j = np.arange(segments)
    jn = (j + 1) % segments
    faces = [np.c_[np.zeros(segments, int), 1 + j, 1 + jn]]
    for i in range(len(ring) - 1):
        a, b = 1 + i * segments + j, 1 + i * segments + jn
        c, d = a + segments, b + segments
        faces += [np.c_[a, c, b], np.c_[b, c, d]]
    last = 1 + (len(ring) - 1) * segments
    faces.append(np.c_[np.full(segments, top), last + jn, last + j])
    return vertices, _outward(vertices, np.concatenate(faces))


def extrude_strip(inner, outer, depth: float) -> tuple[np.ndarray, np.ndarray]:
    """A band between two open 2D curves, extruded along z: an arch or a U.

    Parameters
    ----------
    inner, outer : (p, 2) array_like float
        ``(x, y)`` points; point ``i`` of each is joined, so the band is ``p - 1``
        quads long, and its two ends are closed by the end quads.
    depth : float
        Extent in z, centred on ``z = 0``.

    Returns
    -------
    vertices : (4p, 3) float64
    faces : (f, 3) int64
    """
    inner, outer = np.asarray(inner, np.float64), np.asarray(outer, np.float64)
    p = len(inner)
    z = depth / 2
    # Blocks: inner front, outer front, inner back, outer back.
    vertices = np.concatenate([np.c_[c, np.full(p, zz)] for zz in (z, -z) for c in (inner, outer)])
    inf, outf, inb, outb = (np.arange(p) + k * p for k in range(4))
    quads = []
    for u, v in ((inf, outf), (outb, inb), (outf, outb), (inb, inf)):  # front, back, outer, inner
        quads.append(np.c_[u[:-1], u[1:], v[1:], v[:-1]])
    quads.append([[outf[0], outb[0], inb[0], inf[0]], [inb[-1], outb[-1], outf[-1], inf[-1]]])  # feet
    q = np.concatenate([np.asarray(x) for x in quads])
    faces = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
    return vertices, _outward(vertices, faces)


def _outward(vertices, faces) -> np.ndarray:
    """Flip every face when the surface is wound inside out (consistency is by construction)."""
    p = vertices[faces]
    vol = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6
    return faces if vol > 0 else faces[:, ::-1]


def chamfered_box(size, chamfer: float) -> tuple[np.ndarray, np.ndarray]:
    """A box with bevelled edges and corners: 26 planar patches, 44 triangles.

    The 24 vertices are the box corners pulled in by ``chamfer`` along two axes
    each; the patches are the 6 faces (quads), 12 edge bevels (quads) and 8
    corner triangles. The shape is convex, so each face is wound to point away
    from the centre.
    """
    h = np.asarray(size, np.float64) / 2
    c = chamfer
    # Points: for each corner sign (sx, sy, sz) and each axis k, the corner
    # pulled in by c along the two other axes.
    pts, key = [], {}
    for sx in (-1, 1):
        for sy in (-1, 1):
            for sz in (-1, 1):
                s = np.array([sx, sy, sz])
                for k in range(3):
                    q = s * h - s * c
                    q[k] = s[k] * h[k]
                    key[(sx, sy, sz, k)] = len(pts)
                    pts.append(q)
    vertices = np.array(pts)
    faces = []

    def poly(idx):  # fan a convex polygon, orientation fixed later
        for i in range(1, len(idx) - 1):
            faces.append([idx[0], idx[i], idx[i + 1]])

    for k in range(3):  # the 6 main faces: 4 points each
        a, b = [i for i in range(3) if i != k]
        for sk in (-1, 1):
            ring = []
            for sa, sb in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                s = [0, 0, 0]
                s[k], s[a], s[b] = sk, sa, sb
                ring.append(key[(*s, k)])
            poly(ring)
    for k in range(3):  # the 12 edge bevels: quads along axis k
        a, b = [i for i in range(3) if i != k]
        for sa in (-1, 1):
            for sb in (-1, 1):
                ring = []
                for sk, pa in ((-1, a), (-1, b), (1, b), (1, a)):
                    s = [0, 0, 0]
                    s[k], s[a], s[b] = sk, sa, sb
                    ring.append(key[(*s, pa)])
                poly(ring)
    for sx in (-1, 1):  # the 8 corner triangles
        for sy in (-1, 1):
            for sz in (-1, 1):
                poly([key[(sx, sy, sz, k)] for k in range(3)])
    faces = np.array(faces)
    # Orient each face away from the (convex) box's centre.
    p = vertices[faces]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    inward = np.einsum("ij,ij->i", n, p.mean(axis=1)) < 0
    faces[inward] = faces[inward][:, ::-1]
    vertices[:, 1] += h[1]  # stand on the floor
    return vertices, faces


# --------------------------------------------------------------------- assets
def pillar():
    """A round column 0.8 m wide, 3 m tall: plinth, tapering shaft, capital."""
    profile = [
        (0.0, 0.0),
        (0.40, 0.0),
        (0.40, 0.20),
        (0.30, 0.28),
        (0.25, 0.40),
        (0.22, 2.55),
        (0.26, 2.68),
        (0.38, 2.80),
        (0.40, 3.00),
        (0.0, 3.00),
    ]
    return lathe(profile, 24)


def arch():
    """A doorway arch: 3 m wide, 3.5 m tall, 0.5 m deep, opening 2 m x 2.75 m."""
    n_arc = 16
    t = np.linspace(np.pi, 0.0, n_arc + 1)  # left to right over the top
    ri, ro, spring = 1.0, 1.5, 2.0
    inner_arc = np.c_[ri * np.cos(t), spring + 0.75 * ri * np.sin(t)]
    outer_arc = np.c_[ro * np.cos(t), spring + ro * np.sin(t)]
    # Legs: from the floor up to the springing line, then the arc, then down.
    legs = np.linspace(0.0, spring, 5)[:-1]
    inner = np.concatenate([np.c_[np.full(4, -ri), legs], inner_arc, np.c_[np.full(4, ri), legs[::-1]]])
    outer = np.concatenate([np.c_[np.full(4, -ro), legs], outer_arc, np.c_[np.full(4, ro), legs[::-1]]])
    return extrude_strip(inner, outer, 0.5)


def tree():
    """A stylised conifer 1.8 m wide, 3.4 m tall: trunk and a two-tier crown, one surface."""
    profile = [
        (0.0, 0.0),
        (0.22, 0.0),
        (0.16, 0.15),
        (0.14, 1.00),
        (0.90, 1.10),
        (0.80, 1.35),
        (0.45, 2.00),  # lower tier
        (0.65, 2.00),
        (0.55, 2.30),
        (0.25, 3.00),
        (0.08, 3.30),
        (0.0, 3.40),  # upper tier
    ]
    return lathe(profile, 18)


def crate():
    """A 1 m cube crate with 4 cm bevels."""
    return chamfered_box([1.0, 1.0, 1.0], 0.04)


def extrude_convex(profile, width: float) -> tuple[np.ndarray, np.ndarray]:
    """A convex polygon in the z-y plane, extruded along x and capped: a prism.

    Parameters
    ----------
    profile : (p, 2) array_like float
        ``(z, y)`` corners of a convex polygon, in order.
    width : float
        Extent in x, centred on ``x = 0``.

    Returns
    -------
    vertices : (2p, 3) float64
    faces : (f, 3) int64
    """
    prof = np.asarray(profile, np.float64)
    p = len(prof)
    x = width / 2
    vertices = np.concatenate([np.c_[np.full(p, sx), prof[:, 1], prof[:, 0]] for sx in (-x, x)])
    j = np.arange(p)
    jn = (j + 1) % p
    sides = np.concatenate([np.c_[j, jn, jn + p], np.c_[j, jn + p, j + p]])
    caps = [[0, i, i + 1] for i in range(1, p - 1)] + [[p, p + i + 1, p + i] for i in range(1, p - 1)]
    faces = np.concatenate([sides, np.asarray(caps)])
    # Orient each face away from the (convex) prism's centre.
    tri = vertices[faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    inward = np.einsum("ij,ij->i", n, tri.mean(axis=1) - vertices.mean(axis=0)) < 0
    faces[inward] = faces[inward][:, ::-1]
    return vertices, faces


def console():
    """A control console 0.9 m wide: a block whose desk slopes toward the user (-z)."""
    profile = [(-0.30, 0.0), (0.30, 0.0), (0.30, 1.15), (0.12, 1.2), (-0.40, 0.92), (-0.40, 0.80)]
    return extrude_convex(profile, 0.9)


def door():
    """A bulkhead door frame 2.8 m wide, 3.0 m tall, 0.4 m deep; opening 1.8 m x 2.4 m, chamfered corners."""
    hi, ho = 2.4, 3.0  # inner and outer heights
    wi, wo = 0.9, 1.4  # inner and outer half widths
    c = 0.35  # chamfer of the opening's upper corners
    legs = np.linspace(0.0, hi - c, 4)
    inner = np.concatenate(
        [np.c_[np.full(4, -wi), legs], [[-wi + c, hi], [wi - c, hi]], np.c_[np.full(4, wi), legs[::-1]]]
    )
    outer = np.concatenate(
        [np.c_[np.full(4, -wo), legs], [[-wo + c, ho], [wo - c, ho]], np.c_[np.full(4, wo), legs[::-1]]]
    )
    return extrude_strip(inner, outer, 0.4)


def plant():
    """An alien plant in a pot, 0.8 m wide, 1.7 m tall: flared pot, thin stem, a bulb with a spike."""
    profile = [
        (0.0, 0.0),
        (0.24, 0.0),
        (0.34, 0.55),  # pot
        (0.30, 0.60),
        (0.05, 0.62),  # soil, stem
        (0.05, 0.85),
        (0.26, 0.95),
        (0.40, 1.18),  # bulb
        (0.34, 1.38),
        (0.16, 1.50),
        (0.04, 1.56),
        (0.0, 1.70),  # spike
    ]
    return lathe(profile, 16)


ASSETS = {
    "pillar": pillar,
    "arch": arch,
    "tree": tree,
    "crate": crate,
    "console": console,
    "door": door,
    "plant": plant,
}


# ------------------------------------------------------------------------- io
def write_obj(path: Path, vertices, faces, comment: str) -> None:
    lines = [f"# {line}" for line in comment.strip().splitlines()]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


def check(vertices, faces) -> float:
    """Closed, consistently wound, positive volume; returns the volume."""
    e = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    assert (counts == 2).all(), "not closed"
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    assert len(np.unique(directed, axis=0)) == len(directed), "inconsistent winding"
    p = vertices[faces]
    vol = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6
    assert vol > 0, "inside out"
    return vol


def main() -> None:
    for name, make in ASSETS.items():
        v, f = make()
        vol = check(v, f)
        lo, hi = v.min(axis=0), v.max(axis=0)
        size = " x ".join(f"{d:.2f}" for d in hi - lo)
        doc = (make.__doc__ or name).strip()
        write_obj(
            HERE / f"{name}.obj",
            v,
            f,
            f"{name}: {doc}\nsize {size} m (x y z), volume {vol:.4f} m^3; generated by make_assets.py",
        )
        print(f"{name}.obj: {len(v)} vertices, {len(f)} triangles, {size} m, volume {vol:.4f} m^3")


if __name__ == "__main__":
    main()
