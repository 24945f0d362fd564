"""Bake 3D mesh assets into 4D solids, with an on-disk cache.

Pipeline (paper section 4.2, "lifting and tetrahedralization")::

    OBJ / GLB / STL --load--> triangles --repair--> closed surface
        --tetrahedralize (pytetwild)--> 3D tets --extrude--> TetMesh4

The slow step is tetrahedralization (seconds), so its result -- the 3D tets --
is what the cache stores, keyed by the file's bytes, the tetrahedralization
parameters and :data:`BAKE_VERSION`. The hyper-depth, ``w`` position and
profile only feed :func:`~across_dimensions.core.lift.extrude`, which takes
milliseconds, so a designer tuning them never waits for a re-bake.

Errors for people: anything wrong with an asset file raises :class:`AssetError`
with one line naming the file and what is wrong, never a traceback from deep
inside a loader.

pytetwild holds the GIL for the whole call and can abort the process on bad
input, so it runs in a child Python process: the caller's threads (the progress
spinner, a game's loading screen) keep running and a crash becomes an
:class:`AssetError`.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

from ..core.lift import extend_solid, orient_tets3
from ..core.mesh import MeshError, TetMesh4

#: Bump when anything changes what a bake produces for the same input.
BAKE_VERSION = 1
#: Ideal tet edge length as a fraction of the bounding-box diagonal.
DEFAULT_EDGE_LENGTH_FAC = 0.1
SUPPORTED = (".obj", ".glb", ".gltf", ".stl")
#: Holes with at most this many edges are filled; bigger ones are modelling errors.
MAX_FILLED_HOLE = 4


class AssetError(ValueError):
    """An asset file that cannot be used; the message names the file and the problem."""


# ------------------------------------------------------------------------ load
def load_surface(path) -> tuple[np.ndarray, np.ndarray]:
    """Read a closed triangle surface, repairing small defects.

    Parameters
    ----------
    path : str or Path
        ``.obj``, ``.glb``, ``.gltf`` or ``.stl``. A scene (glTF) is flattened:
        every mesh with its node transform applied.

    Returns
    -------
    vertices : (n, 3) float64
    faces : (f, 3) int64
        Closed, consistently wound, counter-clockwise seen from outside.

    Raises
    ------
    AssetError
        Unreadable, unknown format, no triangles, or still open after repair.
    """
    v, f = read_triangles(path)
    return repair_surface(v, f, path)


def read_triangles(path) -> tuple[np.ndarray, np.ndarray]:
    """The raw triangles of a mesh file, ``(n, 3) float64`` and ``(f, 3) int64``."""
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in SUPPORTED:
        raise AssetError(f"{path}: unsupported mesh format {ext or '(no extension)'!r}; expected one of {', '.join(SUPPORTED)}")
    if not path.is_file():
        raise AssetError(f"{path}: no such file")
    import trimesh  # local: only baking needs it

    try:
        scene = trimesh.load_scene(_obj_as_utf8(path) if ext == ".obj" else str(path), file_type=ext[1:])
        meshes = [g for g in scene.dump() if isinstance(g, trimesh.Trimesh)] if scene.geometry else []
    except Exception as e:  # noqa: BLE001 -- loaders raise anything on bad bytes
        raise AssetError(f"{path}: cannot read as {ext[1:].upper()} ({type(e).__name__}: {_first_line(e)})") from None
    meshes = [m for m in meshes if len(m.faces)]
    if not meshes:
        raise AssetError(f"{path}: contains no triangles")
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes])
    vertices = np.concatenate([np.asarray(m.vertices, np.float64) for m in meshes])
    faces = np.concatenate([np.asarray(m.faces, np.int64) + o for m, o in zip(meshes, offsets)])
    if not np.isfinite(vertices).all():
        raise AssetError(f"{path}: has non-finite vertex coordinates")
    return vertices, faces


def _obj_as_utf8(path: Path):
    """The path, or for a non-UTF-8 OBJ its bytes re-encoded as UTF-8.

    trimesh guesses the encoding of non-UTF-8 text with an optional package
    (charset_normalizer) and fails with an ImportError without it. OBJ keywords
    are ASCII, so reading the rest as Latin-1 loses nothing that matters.
    """
    data = path.read_bytes()
    try:
        data.decode("utf-8")
        return str(path)
    except UnicodeDecodeError:
        return io.BytesIO(data.decode("latin-1").encode("utf-8"))


def _first_line(e: BaseException) -> str:
    text = str(e).strip().splitlines()
    return text[0][:200] if text else "no details"


# ---------------------------------------------------------------------- repair
def repair_surface(vertices, faces, path="mesh") -> tuple[np.ndarray, np.ndarray]:
    """Merge duplicate vertices, drop degenerate faces, fill small holes, fix winding.

    The same steps as ``trimesh.repair`` (merge_vertices, fill_holes,
    fix_normals), done here in numpy because trimesh's versions need networkx,
    which is not a dependency of this project.

    Parameters
    ----------
    vertices : (n, 3) array_like float
    faces : (f, 3) array_like int
    path : str or Path
        Only for messages.

    Returns
    -------
    vertices : (n', 3) float64
        Only the referenced ones.
    faces : (f', 3) int64

    Raises
    ------
    AssetError
        When the surface is still not closed, is non-orientable or encloses no volume.
    """
    v, f = merge_vertices(np.asarray(vertices, np.float64), np.asarray(faces, np.int64))
    f = _drop_bad_faces(f)
    if len(f) == 0:
        raise AssetError(f"{path}: contains no triangles (all are degenerate)")
    f = fill_small_holes(f)
    open_edges, nonmanifold = _edge_problems(f)
    if open_edges or nonmanifold:
        what = ", ".join(x for x in (
            f"{open_edges} open edges" if open_edges else "",
            f"{nonmanifold} edges shared by more than two triangles" if nonmanifold else "",
        ) if x)
        raise AssetError(f"{path}: surface is not watertight after repair ({what}); close it in the modelling tool")
    f = fix_winding(f, path)
    f = fix_inversion(v, f)
    if signed_volume(v, f) <= 0:
        raise AssetError(f"{path}: surface encloses no volume")
    used = np.unique(f)
    remap = np.full(len(v), -1, np.int64)
    remap[used] = np.arange(len(used))
    return v[used], remap[f]


def merge_vertices(vertices: np.ndarray, faces: np.ndarray, rel_tol: float = 1e-8) -> tuple[np.ndarray, np.ndarray]:
    """Weld vertices closer than ``rel_tol`` times the bounding-box diagonal.

    Exporters split vertices along UV and normal seams; without welding, every
    seam looks like a hole.
    """
    diag = float(np.linalg.norm(np.ptp(vertices, axis=0))) or 1.0
    q = np.round(vertices / (rel_tol * diag)).astype(np.int64)
    _, first, inverse = np.unique(q, axis=0, return_index=True, return_inverse=True)
    return vertices[first], inverse.reshape(-1)[faces]


def _drop_bad_faces(faces: np.ndarray) -> np.ndarray:
    """Remove faces with a repeated vertex and exact duplicates (same three vertices)."""
    f = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])]
    _, first = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
    return f[np.sort(first)]


def _edge_problems(faces: np.ndarray) -> tuple[int, int]:
    """Counts of undirected edges used once (open) and more than twice (non-manifold)."""
    _, counts = np.unique(np.sort(_directed_edges(faces), axis=1), axis=0, return_counts=True)
    return int((counts == 1).sum()), int((counts > 2).sum())


def _directed_edges(faces: np.ndarray) -> np.ndarray:
    """``(3f, 2) int64``: edge ``i`` belongs to face ``i // 3``."""
    return faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)


def fill_small_holes(faces: np.ndarray, max_edges: int = MAX_FILLED_HOLE) -> np.ndarray:
    """Close boundary loops of at most ``max_edges`` edges with a fan.

    Small loops are what exporters drop (a missing quad); a fan over them is
    safe because a triangle or quad loop cannot make the fan fold over. Larger
    holes are left open for :func:`repair_surface` to report.
    """
    loops = boundary_loops(faces)
    new = []
    for loop in loops:
        if 3 <= len(loop) <= max_edges:
            # The loop runs along the existing faces' edges; the new faces must
            # traverse it backwards to be wound like their neighbours.
            back = loop[::-1]
            new += [[back[0], back[i], back[i + 1]] for i in range(1, len(back) - 1)]
    return np.concatenate([faces, np.array(new, np.int64).reshape(-1, 3)]) if new else faces


def boundary_loops(faces: np.ndarray) -> list[list[int]]:
    """Vertex loops along open edges, in the direction the faces traverse them.

    Only simple loops (each boundary vertex starts one open edge) are returned;
    tangled boundaries are not filled.
    """
    e = _directed_edges(faces)
    key = np.sort(e, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    open_e = e[counts[inverse.reshape(-1)] == 1]
    starts, n_out = np.unique(open_e[:, 0], return_counts=True)
    nxt = {int(a): int(b) for a, b in open_e}
    ok = set(starts[n_out == 1].tolist())
    loops, seen = [], set()
    for s in ok:
        if s in seen:
            continue
        loop, cur = [], s
        while cur in ok and cur not in seen:
            seen.add(cur)
            loop.append(cur)
            cur = nxt[cur]
        if cur == s and len(loop) >= 3:
            loops.append(loop)
    return loops


def fix_winding(faces: np.ndarray, path="mesh") -> np.ndarray:
    """Flip faces so neighbours traverse their shared edge in opposite directions.

    Breadth-first over faces joined by an edge of exactly two faces (the mesh is
    closed and manifold by now), one traversal per connected piece.
    """
    e = _directed_edges(faces)
    key = np.sort(e, axis=1)
    _, inverse = np.unique(key, axis=0, return_inverse=True)
    order = np.argsort(inverse.reshape(-1), kind="stable")
    pair = order.reshape(-1, 2)  # closed manifold: every edge twice
    fa, fb = pair[:, 0] // 3, pair[:, 1] // 3
    # Same direction in both faces: one of the two must flip.
    differ = (e[pair[:, 0], 0] == e[pair[:, 1], 0]).astype(np.int8)
    nbrs = [[] for _ in range(len(faces))]
    for a, b, d in zip(fa.tolist(), fb.tolist(), differ.tolist()):
        nbrs[a].append((b, d))
        nbrs[b].append((a, d))
    flip = np.full(len(faces), -1, np.int8)
    for seed in range(len(faces)):
        if flip[seed] >= 0:
            continue
        flip[seed] = 0
        queue = [seed]
        while queue:
            cur = queue.pop()
            for nb, d in nbrs[cur]:
                want = flip[cur] ^ d
                if flip[nb] < 0:
                    flip[nb] = want
                    queue.append(nb)
                elif flip[nb] != want:
                    raise AssetError(f"{path}: surface is non-orientable (like a Moebius strip); it has no inside")
    out = faces.copy()
    out[flip == 1] = out[flip == 1][:, ::-1]
    return out


def fix_inversion(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Reverse every connected piece that encloses negative volume."""
    comp = _face_components(faces)
    p = vertices[faces]
    vol = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])) / 6.0
    piece_vol = np.bincount(comp, weights=vol)
    out = faces.copy()
    inside_out = piece_vol[comp] < 0
    out[inside_out] = out[inside_out][:, ::-1]
    return out


def _face_components(faces: np.ndarray) -> np.ndarray:
    """Connected piece of each face ``(f,) int64`` (sharing a vertex connects), by union-find."""
    parent = np.arange(faces.max() + 1)

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for a, b, c in faces.tolist():
        ra, rb, rc = find(a), find(b), find(c)
        parent[rb] = ra
        parent[rc] = ra
    roots = np.array([find(a) for a in faces[:, 0].tolist()])
    return np.unique(roots, return_inverse=True)[1].reshape(-1)


def signed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    p = vertices[faces]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


# ------------------------------------------------------------- tetrahedralize
_WORKER = r"""
import json, sys
import numpy as np
import pytetwild
src, dst, kw = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
with np.load(src) as d:
    v, f = d["vertices"], d["faces"]
tv, tt = pytetwild.tetrahedralize(v, f.astype(np.int32), quiet=True, **kw)
with open(dst, "wb") as out:
    np.savez(out, vertices=np.asarray(tv, np.float64), tets=np.asarray(tt, np.int64))
"""


def tetrahedralize(vertices, faces, edge_length_fac: float = DEFAULT_EDGE_LENGTH_FAC, *,
                   isolate: bool = True, **tetwild_kw) -> tuple[np.ndarray, np.ndarray]:
    """Fill a closed surface with tetrahedra using pytetwild (fTetWild).

    Parameters
    ----------
    vertices : (n, 3) array_like float
    faces : (f, 3) array_like int
    edge_length_fac : float
        Ideal tet edge length over the bounding-box diagonal; bigger is coarser
        and faster.
    isolate : bool
        Run pytetwild in a child process (default). It holds the GIL for the
        whole call and aborts the process on some inputs; isolated, other
        threads keep running and a crash raises instead of killing the game.
    **tetwild_kw
        More ``pytetwild.tetrahedralize`` options (``epsilon``, ``coarsen``, ...).

    Returns
    -------
    vertices : (n', 3) float64
        Only those the tets use.
    tets : (m, 4) int64
        Positive volume: ``d`` is on the side of ``(b - a) x (c - a)``. fTetWild's
        own convention is the opposite; the orientation is fixed per tet from
        geometry, so either convention (or a mix) comes out right.

    Raises
    ------
    AssetError
        pytetwild failed or produced no tets.
    """
    v = np.ascontiguousarray(vertices, np.float64)
    f = np.ascontiguousarray(faces, np.int64)
    kw = dict(edge_length_fac=float(edge_length_fac), **tetwild_kw)
    tv, tt = _tetwild_child(v, f, kw) if isolate else _tetwild_here(v, f, kw)
    if len(tt) == 0:
        raise AssetError("pytetwild produced no tets (is the surface closed and not flat?)")
    used = np.unique(tt)
    remap = np.full(len(tv), -1, np.int64)
    remap[used] = np.arange(len(used))
    tv, tt = tv[used], remap[tt]
    try:
        return tv, orient_tets3(tv, tt)
    except ValueError as e:
        raise AssetError(f"pytetwild produced an unusable mesh: {e}") from None


def _tetwild_here(v, f, kw):
    import pytetwild  # local: heavy, only bakes need it

    tv, tt = pytetwild.tetrahedralize(v, f.astype(np.int32), quiet=True, **kw)
    return np.asarray(tv, np.float64), np.asarray(tt, np.int64)


def _tetwild_child(v, f, kw):
    with tempfile.TemporaryDirectory(prefix="ad-tetwild-") as tmp:
        src, dst = os.path.join(tmp, "in.npz"), os.path.join(tmp, "out.npz")
        np.savez(src, vertices=v, faces=f)
        proc = subprocess.Popen(
            [sys.executable, "-c", _WORKER, src, dst, json.dumps(kw)],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
            cwd=tmp,  # fTetWild writes __tracked_surface.stl into the working folder
        )
        try:
            _, err = proc.communicate()
        finally:
            if proc.poll() is None:  # interrupted (Ctrl-C): do not leave it running
                proc.kill()
                proc.wait()
        if proc.returncode != 0 or not os.path.exists(dst):
            tail = err.decode(errors="replace").strip().splitlines()
            why = tail[-1] if tail else f"exit status {proc.returncode}"
            raise AssetError(f"pytetwild failed: {why}")
        with np.load(dst) as d:
            return d["vertices"], d["tets"]


# ------------------------------------------------------------------- progress
class _Progress:
    """One status line on stderr: ``bake pillar.obj: tetrahedralize | 2.4 s``.

    A thread redraws the line ten times a second on a terminal, so the elapsed
    time moves during the long silent tetrahedralization. Elsewhere (logs, CI)
    each stage is printed once on its own line.
    """

    SPIN = "|/-\\"

    def __init__(self, label: str, enabled: bool, stream=None):
        self.label, self.enabled = label, enabled
        self.stream = stream if stream is not None else sys.stderr
        self.tty = enabled and getattr(self.stream, "isatty", lambda: False)()
        self.stage_name, self.t0 = "", time.monotonic()
        self.stage_t0 = self.t0
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self._thread = None
        if self.tty:
            self._thread = threading.Thread(target=self._spin, name="bake-progress", daemon=True)
            self._thread.start()

    def stage(self, name: str) -> None:
        if not self.enabled:
            return
        with self._lock:
            self.stage_name, self.stage_t0 = name, time.monotonic()
            if self.tty:
                self._draw(0)
            else:
                self.stream.write(f"bake {self.label}: {name}\n")
                self.stream.flush()

    def _draw(self, tick: int) -> None:
        dt = time.monotonic() - self.stage_t0
        self.stream.write(f"\r\033[Kbake {self.label}: {self.stage_name} {self.SPIN[tick % 4]} {dt:.1f} s")
        self.stream.flush()

    def _spin(self) -> None:
        tick = 0
        while not self._stop.wait(0.1):
            tick += 1
            with self._lock:
                self._draw(tick)

    def done(self, summary: str) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
        if self.enabled:
            total = time.monotonic() - self.t0
            prefix = "\r\033[K" if self.tty else ""
            self.stream.write(f"{prefix}bake {self.label}: {summary} in {total:.1f} s\n")
            self.stream.flush()


# ----------------------------------------------------------------------- cache
def default_cache_dir() -> Path:
    """``platformdirs.user_cache_dir("across-dimensions") / "bake"``."""
    import platformdirs

    return Path(platformdirs.user_cache_dir("across-dimensions")) / "bake"


def cache_key(path, **params) -> str:
    """sha256 hex of :data:`BAKE_VERSION`, the parameters and the file's bytes.

    A ``.gltf`` also hashes the external buffers and images it references, so
    editing its ``.bin`` invalidates the bake too.
    """
    h = hashlib.sha256()
    h.update(json.dumps({"bake_version": BAKE_VERSION, **params}, sort_keys=True).encode())
    for chunk in _source_files(Path(path)):
        h.update(chunk.read_bytes())
    return h.hexdigest()


def _source_files(path: Path) -> list[Path]:
    files = [path]
    if path.suffix.lower() == ".gltf":
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
            uris = [x.get("uri", "") for k in ("buffers", "images") for x in doc.get(k, [])]
            files += [path.parent / u for u in uris if u and not u.startswith("data:") and (path.parent / u).is_file()]
        except (ValueError, OSError, AttributeError):
            pass  # unreadable JSON: the loader will report it
    return files


def _load_cached(file: Path) -> tuple[np.ndarray, np.ndarray] | None:
    """The cached 3D tets, or None when missing or unusable (then it is rebuilt)."""
    try:
        with np.load(file, allow_pickle=False) as d:
            v, t = d["vertices"], d["tets"]
            version = int(d["bake_version"])
    except Exception:  # noqa: BLE001 -- truncated, corrupt, old format: all mean "rebake"
        return None
    if (version != BAKE_VERSION or v.ndim != 2 or v.shape[1] != 3 or t.ndim != 2 or t.shape[1] != 4
            or len(t) == 0 or t.min() < 0 or t.max() >= len(v) or not np.isfinite(v).all()):
        return None
    return v.astype(np.float64), t.astype(np.int64)


def _save_cached(file: Path, vertices: np.ndarray, tets: np.ndarray) -> None:
    """Write atomically: a unique temp file in the same folder, then rename over."""
    file.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=file.name + ".", suffix=".tmp", dir=file.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez_compressed(f, vertices=vertices, tets=tets.astype(np.int32), bake_version=BAKE_VERSION)
        os.chmod(tmp, 0o644)  # mkstemp makes it private; a cache is not a secret
        os.replace(tmp, file)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


# ------------------------------------------------------------------------ bake
def bake_solid(path, edge_length_fac: float = DEFAULT_EDGE_LENGTH_FAC, cache_dir=None,
               progress: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The tetrahedralized 3D solid of a mesh file, from the cache when possible.

    Returns
    -------
    vertices : (n, 3) float64
    tets : (m, 4) int64
        Positively oriented.
    """
    path = Path(path)
    if not path.is_file():
        raise AssetError(f"{path}: no such file")
    key = cache_key(path, edge_length_fac=float(edge_length_fac))
    file = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    file = file / f"{path.stem}-{key[:24]}.npz"
    cached = _load_cached(file) if file.exists() else None
    if cached is not None:
        return cached
    bar = _Progress(path.name, progress)
    try:
        if file.exists():
            bar.stage("cache entry unreadable, rebaking")
        bar.stage("load")
        v, f = read_triangles(path)
        bar.stage("repair")
        v, f = repair_surface(v, f, path)
        bar.stage(f"tetrahedralize {len(f)} triangles")
        try:
            tv, tt = tetrahedralize(v, f, edge_length_fac)
        except AssetError as e:
            raise AssetError(f"{path}: {e}") from None
        bar.stage("save")
        _save_cached(file, tv, tt)
    except BaseException:
        bar.done("failed")
        raise
    bar.done(f"{len(tt)} tets")
    return tv, tt


def lift_asset(path, depth: float, w_center: float = 0.0, profile: str = "prism", cache_dir=None,
               progress: bool = True, *, layers: int = 9, edge_length_fac: float = DEFAULT_EDGE_LENGTH_FAC,
               color=None, center=None) -> TetMesh4:
    """A mesh file extended along ``w`` into a closed 4D solid.

    Parameters
    ----------
    path : str or Path
        ``.obj``, ``.glb``, ``.gltf`` or ``.stl``; must be (repairably) watertight.
    depth : float
        Full extent along ``w`` (> 0).
    w_center : float
    profile : {"prism", "round", "taper"}
        How the cross-section scales along ``w`` (see
        :func:`~across_dimensions.core.lift.profile_scales`).
    cache_dir : str or Path, optional
        Where baked 3D tets are kept; default :func:`default_cache_dir`.
    progress : bool
        A status line on stderr while a bake runs (a cache hit prints nothing).
    layers : int
        Copies along ``w`` for the ``round`` and ``taper`` profiles.
    edge_length_fac : float
        Tetrahedralization resolution (see :func:`tetrahedralize`).
    color : (3,) or (4,) array_like float, optional
        One linear RGB(A) colour for the whole solid.
    center : (3,) array_like float, optional
        Centre the profile scales about (default the bounding-box centre).

    Returns
    -------
    TetMesh4
        Validated; named after the file's stem.

    Raises
    ------
    AssetError
    """
    path = Path(path)
    v, t = bake_solid(path, edge_length_fac, cache_dir, progress)
    try:
        mesh = extend_solid(v, t, w_center, depth, profile, layers, colors=color, center=center, name=path.stem)
        return mesh.validate()
    except (MeshError, ValueError) as e:
        raise AssetError(f"{path}: cannot lift to 4D: {e}") from None


def lift_to_file(mesh_path, depth: float, out_path, **kw) -> Path:
    """Bake ``mesh_path`` with :func:`lift_asset` and write it as ``.npz`` (:meth:`TetMesh4.save`).

    Returns
    -------
    Path
        ``out_path``.
    """
    mesh = lift_asset(mesh_path, depth, **kw)
    out = Path(out_path)
    out.parent.mkdir(parents=True, exist_ok=True)
    mesh.save(out)
    return out
