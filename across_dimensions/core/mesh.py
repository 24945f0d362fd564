"""Tetrahedral 4D meshes and the 3D triangle meshes projections produce.

A :class:`TetMesh4` is the boundary of a 4D solid: a closed 3-manifold made of
tetrahedra, the way a triangle mesh is the boundary of a 3D solid.

Orientation
-----------
For a tet ``(a, b, c, d)`` let ``u, v, t = b - a, c - a, d - a`` and let
``N = cross4(u, v, t)`` be the vector with ``det[u, v, t, N] = |N|**2 > 0``
(the 4D analogue of ``(b - a) x (c - a)``). A tet is *positively oriented* when
``N`` points out of the solid. The hyper-volume enclosed is then
``sum(det[a, b, c, d]) / 24`` and is positive. Each tet's boundary is
``[b, c, d] - [a, c, d] + [a, b, d] - [a, b, c]``; in a closed, consistently
oriented mesh every triangle appears exactly twice, once with each orientation.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import MeshError
from .fileio import FileProblem, atomic_writer, read_bytes
from .npz import NPZ_MAX_BYTES, NPZ_MAX_COORD, NPZ_MAX_TETS, NPZ_MAX_VERTICES, read_npz

__all__ = [
    "NPZ_MAX_BYTES",
    "NPZ_MAX_COORD",
    "NPZ_MAX_TETS",
    "NPZ_MAX_VERTICES",
    "TET_FACES",
    "MeshError",
    "TetMesh4",
    "TriMesh3",
    "concatenate",
    "cross4",
]

_UINT32_MAX = 2**32 - 1


def cross4(u, v, t) -> np.ndarray:
    """Generalized cross product of three 4-vectors.

    Parameters
    ----------
    u, v, t : (..., 4) array_like

    Returns
    -------
    (..., 4) float64
        Orthogonal to all three, with ``det[u, v, t, N] = |N|**2`` and ``|N|``
        the 3-volume of the parallelepiped they span.
    """
    u = np.asarray(u, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)
    # Cofactor expansion of det[u, v, t, e_i] along the last row.
    m = np.stack([u, v, t], axis=-2)  # (..., 3, 4)
    out = np.empty(m.shape[:-2] + (4,))
    cols = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]]
    for i in range(4):
        out[..., i] = (-1) ** (i + 3) * np.linalg.det(m[..., cols[i]])
    return out


def _face_keys(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """One integer per triangle, equal for the same three vertices in any order.

    Sorting ``(f,)`` integers is several times faster than ``np.unique(axis=0)``
    on rows; meshes too large to pack into 63 bits fall back to byte rows.
    """
    key = np.sort(faces, axis=1).astype(np.int64)
    n = max(int(n_vertices), 1)
    if n**3 < 2**62:
        return (key[:, 0] * n + key[:, 1]) * n + key[:, 2]
    return np.ascontiguousarray(key).view(np.dtype((np.void, 24))).ravel()


# Faces of tet (0, 1, 2, 3) with the orientation the tet induces on them.
TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]], dtype=np.intp)


def _frozen(a: np.ndarray, given) -> np.ndarray:
    """``a`` (converted from ``given``) as an array nobody can write into.

    Copied only when it is writeable memory the caller also holds: a fresh
    array from a dtype conversion is just marked read-only.
    """
    if a.flags.writeable:
        if isinstance(given, np.ndarray) and np.may_share_memory(a, given):
            a = a.copy()
        a.flags.writeable = False
    return a


@dataclass(eq=False)
class TetMesh4:
    """The closed boundary of a 4D solid as tetrahedra.

    The arrays are read-only (``flags.writeable`` is False): derived data such
    as the face table and the slicer's cluster layout is cached on the mesh, and
    an in-place edit would leave that cache describing another mesh. Arrays
    passed in are copied unless they are already read-only, so the caller's own
    arrays stay writeable. To change a mesh, build a new one (for example with
    :meth:`transformed`); assigning a new array to an attribute also works and
    clears the cache.

    Parameters
    ----------
    vertices : (n, 4) float32
    tets : (m, 4) uint32
        Positively oriented (see the module docstring).
    colors : (n, 4) float32, optional
        Linear RGBA per vertex.
    name : str
    """

    vertices: np.ndarray
    tets: np.ndarray
    colors: np.ndarray | None = None
    name: str = ""
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def __setattr__(self, key, value):
        if key == "vertices":
            value = _frozen(np.ascontiguousarray(value, dtype=np.float32).reshape(-1, 4), value)
        elif key == "tets":
            value = _frozen(self._checked_tets(value), value)
        elif key == "colors" and value is not None and "vertices" in self.__dict__:
            value = _frozen(self._checked_colors(value), value)
        if key in ("vertices", "tets", "colors") and "_cache" in self.__dict__:
            self._cache.clear()  # derived data described the old arrays
        object.__setattr__(self, key, value)

    def _checked_tets(self, tets) -> np.ndarray:
        tets = np.asarray(tets)
        if tets.size and np.issubdtype(tets.dtype, np.integer):
            # Range first: casting a negative or >= 2**32 index to uint32 would wrap silently.
            lo, hi = int(tets.min()), int(tets.max())
            if lo < 0:
                raise MeshError(f"{self.label}: negative vertex index {lo} in tets")
            if hi > _UINT32_MAX:
                raise MeshError(f"{self.label}: vertex index {hi} in tets is past the uint32 range")
        return np.ascontiguousarray(tets, dtype=np.uint32).reshape(-1, 4)

    def _checked_colors(self, colors) -> np.ndarray:
        c = np.asarray(colors, dtype=np.float32)
        if c.ndim == 1:
            c = np.broadcast_to(c, (len(self.vertices), c.shape[0]))
        if c.ndim == 2 and c.shape[-1] == 3:
            c = np.concatenate([c, np.ones(c.shape[:-1] + (1,), np.float32)], axis=-1)
        if c.shape != (len(self.vertices), 4):
            raise MeshError(f"{self.label}: colors must be (n, 3) or (n, 4) for n={len(self.vertices)}, got {c.shape}")
        return np.ascontiguousarray(c)

    @property
    def label(self) -> str:
        return getattr(self, "name", "") or "mesh"  # "name" is set after the arrays in __init__

    def __len__(self) -> int:
        return len(self.tets)

    # ------------------------------------------------------------------ measures
    def tet_normals(self) -> np.ndarray:
        """Outward normals of each tet, ``(m, 4) float64``, length = tet 3-volume * 6."""
        p = self.vertices.astype(np.float64)[self.tets]
        return cross4(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])

    def boundary_volume(self) -> float:
        """Total 3-volume of the tets (the "surface area" of the 4D solid)."""
        return float(np.linalg.norm(self.tet_normals(), axis=1).sum() / 6.0)

    def hypervolume(self) -> float:
        """Signed 4-volume enclosed, by the divergence theorem (positive when outward)."""
        p = self.vertices.astype(np.float64)[self.tets]
        return float(-np.linalg.det(p).sum() / 24.0)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Axis-aligned bounds ``((4,), (4,))`` float64."""
        return self.vertices.min(axis=0).astype(np.float64), self.vertices.max(axis=0).astype(np.float64)

    def bounding_sphere(self) -> tuple[np.ndarray, float]:
        """A bounding hypersphere: centre ``(4,) float64`` (bounds centre) and radius."""
        lo, hi = self.bounds()
        c = 0.5 * (lo + hi)
        r = float(np.sqrt(((self.vertices - c) ** 2).sum(axis=1)).max()) if len(self.vertices) else 0.0
        return c, r

    # ------------------------------------------------------------------- topology
    def oriented_faces(self) -> np.ndarray:
        """Every tet's four faces with induced orientation, ``(4m, 3) uint32``."""
        return self.tets[:, TET_FACES].reshape(-1, 3)

    def unique_faces(self) -> tuple[np.ndarray, np.ndarray]:
        """Each triangle once, with the tets on either side.

        Returns
        -------
        faces : (f, 3) uint32
            Orientation as induced by the first tet listing it.
        owners : (f, 2) int64
            Tet indices on either side; -1 where a face has only one tet.
        """
        if "unique_faces" not in self._cache:
            of = self.oriented_faces()
            key = _face_keys(of, len(self.vertices))
            _, first, inverse, counts = np.unique(key, return_index=True, return_inverse=True, return_counts=True)
            inverse = inverse.reshape(-1)
            owners = np.full((len(first), 2), -1, dtype=np.int64)
            tet_of = np.arange(len(of)) // 4
            order = np.argsort(inverse, kind="stable")
            starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
            owners[:, 0] = tet_of[order[starts]]
            two = counts >= 2
            owners[two, 1] = tet_of[order[starts[two] + 1]]
            self._cache["unique_faces"] = (of[first], owners)
        return self._cache["unique_faces"]

    def feature_faces(self, angle_tol: float = 1e-4) -> np.ndarray:
        """Faces where the surface creases: edges of the solid's real 2-faces.

        Triangles inside a flat cell (a tesseract's cube split into tets) are not
        features. Frustum projection draws only these. Affine maps keep
        coplanarity, so the answer holds under any transform.

        Returns
        -------
        (f', 3) uint32
        """
        key = ("feature_faces", angle_tol)
        if key not in self._cache:
            faces, owners = self.unique_faces()
            n = self.tet_normals()
            n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
            a, b = owners[:, 0], owners[:, 1]
            cos = np.where(b >= 0, np.einsum("ij,ij->i", n[a], n[np.maximum(b, 0)]), -1.0)
            self._cache[key] = np.ascontiguousarray(faces[cos < np.cos(angle_tol)])
        return self._cache[key]

    # ----------------------------------------------------------------- validation
    def problems(self, max_report: int = 5, check_closed: bool = True) -> list[str]:
        """Everything wrong with the mesh, as one message per kind of problem."""
        out: list[str] = []
        n = len(self.vertices)
        if self.tets.size == 0:
            return [f"{self.label}: has no tets"]
        if not np.isfinite(self.vertices).all():
            bad = np.flatnonzero(~np.isfinite(self.vertices).all(axis=1))
            # Nothing geometric can be checked on NaN or infinite coordinates.
            return [f"{self.label}: vertices {bad[:max_report].tolist()} are not finite"]
        if self.tets.max() >= n:
            bad = np.flatnonzero((self.tets >= n).any(axis=1))
            out.append(
                f"{self.label}: tets {bad[:max_report].tolist()} index vertices past the end "
                f"(there are {n} vertices, found index {int(self.tets.max())})"
            )
            return out
        repeated = (np.sort(self.tets, axis=1)[:, 1:] == np.sort(self.tets, axis=1)[:, :-1]).any(axis=1)
        vol = np.linalg.norm(self.tet_normals(), axis=1) / 6.0
        # Relative to each tet's own size, so small tets in a large world pass:
        # a regular tet has vol / edge**3 = 0.118; a sliver far below 1e-9 is flat.
        p = self.vertices.astype(np.float64)[self.tets]
        edges = p[:, [1, 2, 3, 2, 3, 3]] - p[:, [0, 0, 0, 1, 1, 2]]
        longest = np.sqrt((edges**2).sum(axis=2).max(axis=1))
        degenerate = repeated | (vol <= 1e-9 * longest**3) | (longest == 0)
        if degenerate.any():
            bad = np.flatnonzero(degenerate)
            out.append(
                f"{self.label}: {len(bad)} degenerate tets (zero volume or repeated vertex), "
                f"e.g. {bad[:max_report].tolist()}"
            )
        if check_closed:
            of = self.oriented_faces()
            key = _face_keys(of, len(self.vertices))
            _, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
            inverse = inverse.reshape(-1)
            if (counts != 2).any():
                bad_faces = np.flatnonzero(counts != 2)
                tets_bad = np.unique(np.flatnonzero(np.isin(inverse, bad_faces)) // 4)
                out.append(
                    f"{self.label}: {len(bad_faces)} faces are not shared by exactly two tets "
                    f"(open or non-manifold), in tets {tets_bad[:max_report].tolist()}"
                )
            else:
                # Parity of the permutation sorting each face: opposite orientations
                # of the same triangle have opposite parity.
                parity = _permutation_parity(of)
                sums = np.bincount(inverse, weights=parity, minlength=len(counts))
                inconsistent = np.flatnonzero(sums != 0)
                if len(inconsistent):
                    tets_bad = np.unique(np.flatnonzero(np.isin(inverse, inconsistent)) // 4)
                    out.append(
                        f"{self.label}: {len(inconsistent)} faces are used with the same orientation by both "
                        f"their tets (inverted tets), in tets {tets_bad[:max_report].tolist()}"
                    )
                elif self.hypervolume() <= 0:
                    out.append(
                        f"{self.label}: the mesh is inside out (enclosed hyper-volume {self.hypervolume():.3g} <= 0)"
                    )
        return out

    def validate(self, check_closed: bool = True) -> TetMesh4:
        """Raise :class:`MeshError` listing every problem, or return ``self``."""
        problems = self.problems(check_closed=check_closed)
        if problems:
            raise MeshError("; ".join(problems))
        return self

    # ------------------------------------------------------------- transformation
    def transformed(self, m) -> TetMesh4:
        """A copy with vertices mapped by the 5x5 transform ``m``.

        A reflection (negative determinant) reverses tets to keep them outward.
        """
        m = np.asarray(m, dtype=np.float64)
        v = self.vertices.astype(np.float64) @ m[:4, :4].T + m[:4, 4]
        tets = self.tets if np.linalg.det(m[:4, :4]) > 0 else self.tets[:, [0, 2, 1, 3]]
        return TetMesh4(v, tets, self.colors, self.name)

    def with_color(self, rgba) -> TetMesh4:
        """A copy with every vertex coloured ``rgba`` (3 or 4 floats)."""
        # Geometry caches stay valid for the copy; copy the dict so they are not shared.
        cache = {k: v for k, v in self._cache.items() if k != "white"}
        return TetMesh4(self.vertices, self.tets, np.asarray(rgba, np.float32), self.name, cache)

    def vertex_colors(self) -> np.ndarray:
        """``(n, 4) float32`` colours, white where the mesh has none (cached)."""
        if self.colors is not None:
            return self.colors
        if "white" not in self._cache:
            self._cache["white"] = np.ones((len(self.vertices), 4), np.float32)
        return self._cache["white"]

    # ------------------------------------------------------------------------ I/O
    def save(self, path) -> None:
        """Write ``.npz`` with arrays ``vertices``, ``tets`` and optionally ``colors``.

        Written whole or not at all (:func:`~.fileio.atomic_writer`): two
        writers to one path, a crash or a kill never leave a half file or a
        temporary file behind.

        Raises
        ------
        FileProblem
            The folder is missing or the file cannot be written.
        """
        arrays = {"vertices": self.vertices, "tets": self.tets}
        if self.colors is not None:
            arrays["colors"] = self.colors
        try:
            with atomic_writer(path, "wb") as f:
                np.savez_compressed(f, **arrays)
        except OSError as e:
            raise FileProblem(f"{path}: cannot write it ({e.strerror or e})") from None

    @classmethod
    def load(cls, path, validate: bool = True) -> TetMesh4:
        """Read a mesh written by :meth:`save`, treating the file as hostile.

        The file is read whole through :func:`~.fileio.read_bytes` (regular
        files only, at most :data:`NPZ_MAX_BYTES`). Each array's size is then
        checked twice before anything is decompressed or allocated: the size
        the zip directory declares for its member, and the shape in the
        ``.npy`` header. Limits: at most :data:`NPZ_MAX_BYTES` (256 MiB) of
        file, :data:`NPZ_MAX_VERTICES` (1,000,000) vertices and
        :data:`NPZ_MAX_TETS` (2,000,000) tets, so a zip bomb of a few
        kilobytes is refused rather than expanded.

        Accepted arrays (``allow_pickle`` is never used):

        - ``vertices``: ``(n, 4)`` real numbers, finite and within
          :data:`NPZ_MAX_COORD` (1e6) in magnitude.
        - ``tets``: ``(m, 4)`` integers in ``[0, n)``; the range is checked
          before the cast to ``uint32`` so large indices cannot wrap.
        - ``colors`` (optional): ``(n, 3)`` or ``(n, 4)`` finite real numbers
          (linear RGB(A), usually 0 to 1).

        Parameters
        ----------
        path : str or Path
        validate : bool
            Also check the mesh is closed and outward (:meth:`validate`).

        Raises
        ------
        MeshError
            One line naming the file, the array and what was expected.
        FileProblem
            Missing, not a regular file, or too large.
        """
        path = Path(path)
        raw = read_bytes(path, limit=NPZ_MAX_BYTES, what=".npz mesh")
        arrays = read_npz(path, raw)
        n = len(arrays["vertices"])
        t = arrays["tets"]
        if t.size and int(t.max()) >= n:
            raise MeshError(f"{path}: 'tets' indexes vertex {int(t.max())}, past the end (there are {n} vertices)")
        mesh = cls(arrays["vertices"], t, arrays.get("colors"), name=str(path))
        return mesh.validate() if validate else mesh


def _permutation_parity(faces: np.ndarray) -> np.ndarray:
    """+1 for even, -1 for odd permutations sorting each row of ``(f, 3)``."""
    a, b, c = faces[:, 0], faces[:, 1], faces[:, 2]
    inversions = (a > b).astype(np.int8) + (a > c) + (b > c)
    return np.where(inversions % 2 == 0, 1.0, -1.0)


@dataclass(eq=False)
class TriMesh3:
    """A 3D triangle soup with per-vertex attributes, as projections produce.

    Parameters
    ----------
    vertices : (k, 3) float32
    faces : (f, 3) uint32
        Counter-clockwise seen from outside (normals by the right-hand rule).
    normals : (k, 3) float32
    colors : (k, 4) float32
    depth : (k,) float32, optional
        Distance along the 4D camera's viewing axis (frustum projection only).
    """

    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    colors: np.ndarray
    depth: np.ndarray | None = None

    @classmethod
    def empty(cls, with_depth: bool = False) -> TriMesh3:
        return cls(
            np.zeros((0, 3), np.float32),
            np.zeros((0, 3), np.uint32),
            np.zeros((0, 3), np.float32),
            np.zeros((0, 4), np.float32),
            np.zeros((0,), np.float32) if with_depth else None,
        )

    def __len__(self) -> int:
        return len(self.faces)

    @property
    def is_empty(self) -> bool:
        return len(self.faces) == 0

    def welded(self, tol: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Merge coincident vertices and drop collapsed triangles.

        With ``tol = 0`` only bit-identical positions merge: the slicer computes
        a shared edge's point identically in every tet, so this is exact.

        Returns
        -------
        vertices : (k', 3) float64
        faces : (f', 3) int64
        """
        if self.is_empty:
            return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
        if tol > 0:
            q = np.round(self.vertices.astype(np.float64) / tol).astype(np.int64)
        else:
            q = np.ascontiguousarray(self.vertices + np.float32(0.0))  # folds -0.0 into 0.0
        _, first, inverse = np.unique(q, axis=0, return_index=True, return_inverse=True)
        faces = inverse.reshape(-1)[self.faces]
        keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
        return self.vertices[first].astype(np.float64), faces[keep]

    def area(self) -> float:
        """Total triangle area."""
        p = self.vertices.astype(np.float64)[self.faces]
        return float(0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum())

    def volume(self) -> float:
        """Signed enclosed volume (positive for a closed, outward-wound mesh)."""
        p = self.vertices.astype(np.float64)[self.faces]
        return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def save(self, path) -> tuple[int, int]:
        """Write ``.obj``, ``.ply`` (ASCII) or ``.glb`` (binary glTF), welded and indexed, with numpy alone.

        Returns
        -------
        (int, int)
            The vertices and triangles written (see :func:`~.meshio.indexed_mesh`).
        """
        from .meshio import save_trimesh3  # local: keeps file formats out of the hot path

        return save_trimesh3(self, path)


def concatenate(meshes, name: str = "") -> TetMesh4:
    """One mesh holding several (a union of disjoint solids).

    Parameters
    ----------
    meshes : sequence of TetMesh4
        Colours are kept where given and white elsewhere.

    Returns
    -------
    TetMesh4
    """
    meshes = list(meshes)
    if not meshes:
        raise MeshError("concatenate needs at least one mesh")
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
    verts = np.concatenate([m.vertices for m in meshes])
    tets = np.concatenate([m.tets.astype(np.int64) + o for m, o in zip(meshes, offsets)])
    colors = None
    if any(m.colors is not None for m in meshes):
        colors = np.concatenate(
            [m.colors if m.colors is not None else np.ones((len(m.vertices), 4), np.float32) for m in meshes]
        )
    return TetMesh4(verts, tets, colors, name or "+".join(m.name for m in meshes if m.name))
