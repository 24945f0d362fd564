"""Throughput of the projection kernels, next to a memory-copy baseline.

Each figure is the median of several runs after a warm-up (compilation is not
timed), in CPU time of the measuring thread (``time.thread_time``): on a
machine shared with other jobs, wall time mostly measures the other jobs. The
baseline copies the same bytes the kernel must read (tets and vertices) with
``numpy.copyto`` in the same run, so the ratio says how close a kernel is to
the machine's memory speed whatever else the machine is doing.
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


def _median_ms(fn, repeat: int) -> float:
    fn()  # warm-up: compilation and caches
    times = []
    for _ in range(repeat):
        t0 = time.thread_time()
        fn()
        times.append(time.thread_time() - t0)
    return 1e3 * float(np.median(times))


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


def _copy_ms(mesh: TetMesh4, repeat: int) -> float:
    src = np.concatenate([mesh.tets.view(np.uint8).ravel(), mesh.vertices.view(np.uint8).ravel()])
    dst = np.empty_like(src)
    return _median_ms(lambda: np.copyto(dst, src), repeat)


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

    def report(name, mesh, ms):
        copy = _copy_ms(mesh, repeat)
        row = dict(name=name, tets=len(mesh), ms=ms, mtets_per_s=len(mesh) / ms / 1e3, copy_ms=copy, ratio=ms / copy)
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
            _median_ms(lambda scene=scene: cross_section(scene, hyperplane, cull=False), repeat),
        )
        if n == 1_000_000:
            report(
                "section, same scene with cluster culling",
                scene,
                _median_ms(lambda scene=scene: cross_section(scene, hyperplane), repeat),
            )
    dense = tiled_scene(base, sizes[0])
    mesh_clusters(dense)
    report(
        "section, dense worst case (every copy cut)",
        dense,
        _median_ms(lambda: cross_section(dense, hyperplane), repeat),
    )
    camera = translation((0, 0, 0, -4.0))
    dense.feature_faces()
    report("frustum projection (every face in view)", dense, _median_ms(lambda: frustum_project(dense, camera), repeat))
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
