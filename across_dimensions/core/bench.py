"""Throughput of the projection kernels, next to a memory-copy baseline.

Each figure is the median of several runs after a warm-up (compilation is not
timed), in CPU time of the measuring thread (``time.thread_time``): on a
machine shared with other jobs, wall time mostly measures the other jobs. The
baseline copies the bytes the kernel must read, the arrays its scan walks
through (the slicing layout's tets, four uint32 each, and its vertices, four
float32 each), with ``numpy.copyto``. Kernel and copy run alternately, pair
after pair, and the ratio is the median of the pairs' ratios: whatever else
the machine is doing slows both members of a pair alike, so the ratio says how
close a kernel is to the machine's memory speed.
"""

from __future__ import annotations

import time

import numpy as np

from .frustum import frustum_project
from .mesh import TetMesh4, concatenate
from .section import cross_section, mesh_clusters
from .transform import translation

#: Targets of the kernels: a full scan within this factor of the copy of its bytes,
#: and the dense worst case within this many ms per 1e5 tets (half of the 2.2 ms before).
TARGET_SCAN_RATIO = 2.0
TARGET_WORST_MS_PER_1E5 = 1.1


def tiled_scene(base: TetMesh4, target_tets: int, spread_w: float = 0.0, seed: int = 0) -> TetMesh4:
    """Copies of ``base`` on a grid until about ``target_tets`` tets.

    Parameters
    ----------
    spread_w : float
        0 puts every copy across ``w = 0`` (every tet near the hyperplane, the
        worst case); a large value spreads copies along w so most are far from
        it (a level where most 4D content is at other w).
    """
    rng = np.random.default_rng(seed)
    copies = max(1, round(target_tets / len(base)))
    side = int(np.ceil(copies ** (1 / 3)))
    meshes = []
    for i in range(copies):
        x, y, z = i % side, (i // side) % side, i // (side * side)
        w = rng.uniform(-spread_w, spread_w) if spread_w else 0.0
        meshes.append(base.transformed(translation((2.5 * x, 2.5 * y, 2.5 * z, w))))
    return concatenate(meshes, name=f"{copies} x {base.name}")


#: Kernel and copy pairs timed for each ratio (at least).
PAIRS = 15


def _copy_of_scan_bytes(mesh: TetMesh4):
    """A function copying as many bytes as a full scan of ``mesh`` reads (see the module docstring)."""
    layout = mesh_clusters(mesh)
    src = np.concatenate([layout.tets.view(np.uint8).ravel(), layout.vertices.view(np.uint8).ravel()])
    dst = np.empty_like(src)
    return lambda: np.copyto(dst, src)


def _paired_ms(fn, copy, repeat: int) -> tuple[float, float, float]:
    """Median ms of ``fn`` and of ``copy`` run alternately, and the median of their ratios.

    The order within a pair alternates too, so neither always runs on the
    other's cache leftovers.
    """
    fn()  # warm-up: compilation and caches
    copy()
    a, b = [], []
    for i in range(max(repeat, PAIRS)):
        for first in (fn, copy) if i % 2 == 0 else (copy, fn):
            t0 = time.thread_time()
            first()
            (a if first is fn else b).append(time.thread_time() - t0)
    ratios = np.array(a) / np.maximum(np.array(b), 1e-9)
    return 1e3 * float(np.median(a)), 1e3 * float(np.median(b)), float(np.median(ratios))


def run(sizes=(100_000, 1_000_000, 4_000_000), repeat: int = 7, out=print) -> list[dict]:
    """Measure and print cross-section and frustum throughput.

    Returns
    -------
    list of dict
        One row per measurement: ``name``, ``tets``, ``ms``, ``mtets_per_s``,
        ``copy_ms``, ``ratio`` (kernel time / copy time).
    """
    from .shapes import cell600

    base = cell600()
    rows = []
    out(f"{'measurement':46s} {'tets':>9s} {'ms':>8s} {'Mtets/s':>8s} {'copy ms':>8s} {'ratio':>6s}")

    def report(name, mesh, fn):
        ms, copy, ratio = _paired_ms(fn, _copy_of_scan_bytes(mesh), repeat)
        row = dict(name=name, tets=len(mesh), ms=ms, mtets_per_s=len(mesh) / ms / 1e3, copy_ms=copy, ratio=ratio)
        rows.append(row)
        out(f"{name:46s} {len(mesh):9d} {ms:8.2f} {row['mtets_per_s']:8.0f} {copy:8.2f} {row['ratio']:6.1f}")

    hyperplane = translation((0, 0, 0, 0.013))  # off any vertex
    # Copies spread over w in [-30, 30]: the hyperplane cuts about 1 in 50, like
    # a level whose 4D content sits at many w. Scanned without culling, every tet
    # is classified: the full-scan figure.
    for n in sizes:
        scene = tiled_scene(base, n, spread_w=30.0)
        mesh_clusters(scene)  # built once per mesh, like a loaded level
        report(
            "section, full scan (no culling)",
            scene,
            lambda scene=scene: cross_section(scene, hyperplane, cull=False),
        )
        if n == 1_000_000:
            report(
                "section, same scene with cluster culling",
                scene,
                lambda scene=scene: cross_section(scene, hyperplane),
            )
    dense = tiled_scene(base, sizes[0])
    mesh_clusters(dense)
    report("section, dense worst case (every copy cut)", dense, lambda: cross_section(dense, hyperplane))
    camera = translation((0, 0, 0, -4.0))
    dense.feature_faces()
    report("frustum projection (every face in view)", dense, lambda: frustum_project(dense, camera))
    cut = cross_section(dense, hyperplane)
    out(f"  (the dense worst case makes {len(cut):,} triangles; copies: the tets and vertices each scan reads)")
    out("Targets:")
    for r in rows:
        if r["name"].startswith("section, full scan") and r["tets"] >= 1_000_000:  # the sizes
            ok = r["ratio"] <= TARGET_SCAN_RATIO
            out(
                f"  [{'PASS' if ok else 'FAIL'}] full scan of {r['tets']:,} tets within {TARGET_SCAN_RATIO:g}x of the "
                f"copy of its bytes: {r['ratio']:.2f}x"
            )
        if r["name"].startswith("section, dense worst case"):
            per = r["ms"] / r["tets"] * 1e5
            ok = per <= TARGET_WORST_MS_PER_1E5
            out(
                f"  [{'PASS' if ok else 'FAIL'}] dense worst case within {TARGET_WORST_MS_PER_1E5} ms per 1e5 tets: "
                f"{per:.2f} ms"
            )
    return rows
