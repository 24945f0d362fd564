"""Physics benchmark: a pile of mixed 4D bodies in a walled arena.

Run ``python -m across_dimensions.physics.bench`` (or ``across-dimensions
bench``) to print the figures. The targets, per 60 Hz tick on one core
(process CPU time, which other load on a shared machine disturbs less than the
wall clock): 200 bodies in contact within 3 ms, 1000 within 8 ms.

A last line times bodies resting on a floor of tiles given as one tet mesh (the
collider of non-convex solid objects, :mod:`.tet_mesh`) next to the same bodies on
the same tiles given as solid 4D boxes, in the same run.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from .body_def import BodyDef
from .world import PhysicsWorld
from .world_def import WorldDef


def build_pile(n_bodies: int = 200, seed: int = 0, allow_sleep: bool = False, arena: float = 1.5) -> PhysicsWorld:
    """Hyperspheres and hypercubes (alternating) on a jittered 4D grid over a walled floor.

    The arena is ``|x|, |z| <= arena`` (3D world boxes, extending over all w)
    and ``|w| <= arena`` (two half-spaces), so the bodies fall into a pile a few
    layers deep.
    """
    rng = np.random.default_rng(seed)
    world = PhysicsWorld(WorldDef(allow_sleep=allow_sleep))
    t = 0.5
    a = arena
    world.set_static_boxes(
        [
            ((a + t, 2.0, 0.0), (t, 2.0, a + 2 * t)),
            ((-a - t, 2.0, 0.0), (t, 2.0, a + 2 * t)),
            ((0.0, 2.0, a + t), (a + 2 * t, 2.0, t)),
            ((0.0, 2.0, -a - t), (a + 2 * t, 2.0, t)),
        ]
    )
    # Solid beyond |w| = a: {-w <= -a} and {w <= -a}.
    world.add_half_space((0, 0, 0, -1), -a)
    world.add_half_space((0, 0, 0, 1), -a)
    per = max(2, int(np.ceil((2 * a - 0.6) / 0.6)) + 1)
    coords = np.linspace(-a + 0.35, a - 0.35, per)
    i = 0
    layer = 0
    while i < n_bodies:
        for x in coords:
            for z in coords:
                for w in coords:
                    if i >= n_bodies:
                        break
                    p = np.array([x, 0.4 + 0.65 * layer, z, w]) + rng.uniform(-0.05, 0.05, 4)
                    if i % 2 == 0:
                        world.add_body(
                            BodyDef(
                                "hypersphere",
                                radius=0.25,
                                position=p,
                                velocity=rng.uniform(-0.5, 0.5, 4) * [1, 0, 1, 1],
                            )
                        )
                    else:
                        ang = {pl: float(v) for pl, v in zip(("xy", "xz", "xw", "yw"), rng.uniform(-0.6, 0.6, 4))}
                        world.add_body(BodyDef("hypercube", size=0.45, position=p, angles=ang))
                    i += 1
        layer += 1
    return world


def bench_physics(
    n_bodies: int = 200, ticks: int = 300, settle_ticks: int = 120, dt: float = 1.0 / 60.0, seed: int = 0
) -> dict:
    """Time ``ticks`` 60 Hz ticks of a settling pile of ``n_bodies`` mixed bodies.

    Sleeping is off so every body stays in the solver (the worst case).

    Returns
    -------
    dict
        ``mean_ms``, ``median_ms``, ``p95_ms`` and ``max_ms`` per tick (wall
        clock), ``cpu_median_ms`` (process CPU time, less sensitive to other
        load on the machine),
        ``contacts`` (mean solved contact points per tick), the
        baselines ``empty_step_ms`` (a tick of a world without bodies) and
        ``numpy_ms`` (one vectorised numpy update of same-sized body arrays),
        plus the settings.
    """
    world = build_pile(n_bodies, seed)
    for _ in range(settle_ticks):
        world.step(dt)
    times = np.empty(ticks)
    cpu = np.empty(ticks)
    contacts = np.empty(ticks)
    for k in range(ticks):
        c0 = time.process_time()
        t0 = time.perf_counter()
        world.step(dt)
        times[k] = time.perf_counter() - t0
        cpu[k] = time.process_time() - c0
        contacts[k] = world.last_contact_count
    empty = PhysicsWorld()
    empty.step(dt)
    et = np.empty(200)
    for k in range(et.shape[0]):
        t0 = time.perf_counter()
        empty.step(dt)
        et[k] = time.perf_counter() - t0
    pos = np.zeros((n_bodies, 4))
    vel = np.ones((n_bodies, 4))
    rot = np.tile(np.eye(4), (n_bodies, 1, 1))
    nt = np.empty(200)
    for k in range(nt.shape[0]):
        t0 = time.perf_counter()
        vel += dt * np.array([0.0, -9.81, 0.0, 0.0])
        pos += dt * vel
        rot = rot @ rot
        nt[k] = time.perf_counter() - t0
    return {
        "n_bodies": n_bodies,
        "ticks": ticks,
        "substeps_per_tick": world.substeps,
        "mean_ms": 1e3 * float(times.mean()),
        "median_ms": 1e3 * float(np.median(times)),
        "p95_ms": 1e3 * float(np.percentile(times, 95)),
        "max_ms": 1e3 * float(times.max()),
        "cpu_median_ms": 1e3 * float(np.median(cpu)),
        "contacts": float(contacts.mean()),
        "empty_step_ms": 1e3 * float(np.median(et)),
        "numpy_ms": 1e3 * float(np.median(nt)),
    }


def _tiles(k: int, size: float = 1.0) -> list[tuple[np.ndarray, np.ndarray]]:
    """A ``k x k`` floor of square tiles (top at y = 0, 1 m deep in w): ``(lo, hi)`` each."""
    out = []
    for i in range(k):
        for j in range(k):
            lo = np.array([(i - k / 2) * size, -0.2, (j - k / 2) * size, -0.5])
            out.append((lo, lo + [size, 0.2, size, 1.0]))
    return out


def bench_tet_mesh(n_bodies: int = 50, tiles: int = 8, ticks: int = 60, dt: float = 1.0 / 60.0) -> dict:
    """CPU time per tick of ``n_bodies`` bodies resting on ``tiles x tiles`` tiles given as one
    tet mesh (each tile a lifted box, 48 tets), and on the same tiles given as solid boxes.

    Sleeping is off, so every body is tested against the floor every tick.

    Returns
    -------
    dict
        ``tets``, ``tet_cpu_ms`` and ``box_cpu_ms`` (median process CPU per tick),
        ``tet_contacts`` and ``box_contacts`` (mean contact points per tick).
    """
    from across_dimensions.core import lift

    boxes = _tiles(tiles)
    tets = []
    for lo, hi in boxes:
        mesh = lift.extrude(*lift.box_solid(0.5 * (lo[:3] + hi[:3]), hi[:3] - lo[:3]), [lo[3], hi[3]])
        tets.append(np.asarray(mesh.vertices, np.float64)[np.asarray(mesh.tets, np.int64)])
    floor = np.concatenate(tets)
    out = {"tets": len(floor), "n_bodies": n_bodies}
    for kind in ("tet", "box"):
        world = PhysicsWorld(WorldDef(ground=False, allow_sleep=False))
        if kind == "tet":
            world.set_static_tets([floor])
        else:
            world.set_static_solids([(0.5 * (lo + hi), 0.5 * (hi - lo), np.eye(4)) for lo, hi in boxes])
        rng = np.random.default_rng(1)
        span = 0.5 * tiles - 0.5
        for i in range(n_bodies):
            p = np.array([rng.uniform(-span, span), 0.3 + 0.6 * (i % 3), rng.uniform(-span, span), 0.0])
            if i % 2:
                world.add_body(BodyDef("hypercube", size=0.4, position=p, angles={"xz": float(rng.uniform(0, 1))}))
            else:
                world.add_body(BodyDef("hypersphere", radius=0.2, position=p))
        for _ in range(60):
            world.step(dt)
        cpu = np.empty(ticks)
        contacts = np.empty(ticks)
        for k in range(ticks):
            c0 = time.process_time()
            world.step(dt)
            cpu[k] = time.process_time() - c0
            contacts[k] = world.last_contact_count
        out[f"{kind}_cpu_ms"] = 1e3 * float(np.median(cpu))
        out[f"{kind}_contacts"] = float(contacts.mean())
    return out


#: Process CPU milliseconds per tick the pile of ``n`` bodies should stay within.
TARGETS_MS = {200: 3.0, 1000: 8.0}


def report(out=print, sizes=(200, 1000), ticks: int = 200) -> list[dict]:
    """Print one line per pile size: CPU and wall time per tick against its target, the
    contacts solved, and the baselines of the same run (an empty world's tick, a numpy
    update of same-sized arrays). Returns the :func:`bench_physics` results."""
    rows = []
    for n in sizes:
        r = bench_physics(n, ticks=max(20, ticks * 200 // max(n, 200)))
        target = TARGETS_MS.get(n)
        goal = f" (target <= {target:.0f} ms: {'met' if r['cpu_median_ms'] <= target else 'NOT met'})" if target else ""
        out(
            f"  {n:5d} bodies, {r['contacts']:6.0f} contact points: {r['cpu_median_ms']:6.2f} ms CPU per tick"
            f"{goal}; wall median {r['median_ms']:.2f} ms, p95 {r['p95_ms']:.2f} ms"
        )
        rows.append(r)
    r = rows[-1]
    out(
        f"  baselines of this run: empty world tick {r['empty_step_ms']:.3f} ms, "
        f"numpy update of {r['n_bodies']} bodies' arrays {r['numpy_ms']:.3f} ms"
    )
    t = bench_tet_mesh()
    out(
        f"  {t['n_bodies']} bodies on a floor of {t['tets']} tets (a tet mesh): {t['tet_cpu_ms']:.2f} ms CPU per tick, "
        f"{t['tet_contacts']:.0f} contact points; on the same tiles as solid boxes: {t['box_cpu_ms']:.2f} ms, "
        f"{t['box_contacts']:.0f} contact points"
    )
    rows.append(t)
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bodies", type=int, nargs="+", default=[200, 1000])
    ap.add_argument("--ticks", type=int, default=200, help="ticks timed for 200 bodies (fewer for more)")
    args = ap.parse_args(argv)
    report(print, sizes=tuple(args.bodies), ticks=args.ticks)


if __name__ == "__main__":
    main()
