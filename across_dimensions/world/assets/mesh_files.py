"""Reading the triangles of a mesh file: OBJ, glTF (``.gltf``/``.glb``) or STL.

The file's bytes are read once, bounded (:mod:`.confine`), checked where a
loader would misbehave on bad input, and handed to trimesh as a stream with a
:class:`~.confine.ConfinedResolver`, so trimesh never opens a path itself.
Materials and textures are skipped: a bake needs only geometry.
"""

from __future__ import annotations

import io
import re
import struct
import warnings
from pathlib import Path

import numpy as np

from .confine import Budget, ConfinedResolver, referenced_files
from .errors import AssetError
from .limits import MAX_ASSET_BYTES, MAX_COORDINATE, MAX_TRIANGLES

SUPPORTED = (".obj", ".glb", ".gltf", ".stl")
_STL_HEADER = 84  # 80-byte header + uint32 triangle count
_STL_TRIANGLE = 50  # normal, three corners (12 float32) + uint16 attribute
_OBJ_FACE = re.compile(rb"^[ \t]*f[ \t]", re.MULTILINE)


def read_triangles(path) -> tuple[np.ndarray, np.ndarray]:
    """The raw triangles of a mesh file.

    A scene (glTF) is flattened: every mesh with its node transform applied.

    Parameters
    ----------
    path : str or Path
        ``.obj``, ``.glb``, ``.gltf`` or ``.stl``, at most
        :data:`~.limits.MAX_ASSET_BYTES` with the files it references.

    Returns
    -------
    vertices : (n, 3) float64
        Finite.
    faces : (f, 3) int64
        At most :data:`~.limits.MAX_TRIANGLES`; not yet repaired.

    Raises
    ------
    AssetError
        Unknown format, unreadable, not a regular file, too large, references
        outside its folder, corrupt, no triangles or too many.
    """
    path = Path(path)
    ext = path.suffix.lower()
    check_format(path)
    budget = Budget(MAX_ASSET_BYTES)
    data = budget.read(path, "mesh asset")
    root = path.resolve().parent
    referenced_files(path, data, root)  # refuse escaping URIs before any loader sees them
    if ext == ".stl":
        _check_stl(path, data)
    elif ext == ".obj":
        data = _obj_as_utf8(data)
    _check_text_face_count(path, ext, data)
    resolver = ConfinedResolver(root, path, budget)
    meshes = _load_meshes(path, ext, data, resolver)
    meshes = [m for m in meshes if len(m.faces)]
    if not meshes:
        raise AssetError(f"{path}: contains no triangles")
    n_faces = sum(len(m.faces) for m in meshes)
    if n_faces > MAX_TRIANGLES:
        raise AssetError(
            f"{path}: {n_faces} triangles is more than the {MAX_TRIANGLES} a mesh asset may have; "
            "simplify it in the modelling tool"
        )
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes])
    vertices = np.concatenate([np.asarray(m.vertices, np.float64) for m in meshes])
    faces = np.concatenate([np.asarray(m.faces, np.int64) + o for m, o in zip(meshes, offsets)])
    if not np.isfinite(vertices).all():
        raise AssetError(f"{path}: has non-finite vertex coordinates")
    if np.abs(vertices).max() > MAX_COORDINATE:
        raise AssetError(
            f"{path}: a vertex lies {np.abs(vertices).max():.3g} from the origin; "
            f"a mesh asset's coordinates must be within {MAX_COORDINATE:g}"
        )
    return vertices, faces


def check_format(path) -> None:
    """Refuse a file whose suffix is not one of :data:`SUPPORTED`, before reading it.

    Raises
    ------
    AssetError
    """
    ext = Path(path).suffix.lower()
    if ext not in SUPPORTED:
        raise AssetError(
            f"{path}: unsupported mesh format {ext or '(no extension)'!r}; expected one of {', '.join(SUPPORTED)}"
        )


def _check_text_face_count(path: Path, ext: str, data: bytes) -> None:
    """Refuse a text mesh with too many faces before trimesh parses them all.

    Every OBJ face line (``f ...``) and every ASCII STL ``endfacet`` is at
    least one triangle, so counting them bounds the parse by the limit, not by
    the file size.
    """
    if ext == ".obj":
        faces = len(_OBJ_FACE.findall(data))
    elif ext == ".stl" and _binary_stl_count(data) is None:
        faces = data.count(b"endfacet")
    else:
        return
    if faces > MAX_TRIANGLES:
        raise AssetError(
            f"{path}: {faces} faces is more than the {MAX_TRIANGLES} triangles a mesh asset may have; "
            "simplify it in the modelling tool"
        )


def _load_meshes(path: Path, ext: str, data: bytes, resolver: ConfinedResolver) -> list:
    import trimesh  # local: only baking needs it

    # load_scene is trimesh 5's name; 4.x spells it load(force="scene").
    load = getattr(trimesh, "load_scene", None) or (lambda *a, **k: trimesh.load(*a, force="scene", **k))
    try:
        # Hostile coordinates (1e308) overflow inside trimesh's merging; the result
        # is checked below (non-finite, or out of range), so its warnings are noise.
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore", RuntimeWarning)
            scene = load(io.BytesIO(data), file_type=ext[1:], resolver=resolver, skip_materials=True)
            return [g for g in scene.dump() if isinstance(g, trimesh.Trimesh)] if scene.geometry else []
    except AssetError:
        raise  # the resolver refused a file: its message already says which and why
    except Exception as e:  # noqa: BLE001 -- loaders raise anything on bad bytes
        raise AssetError(f"{path}: cannot read as {ext[1:].upper()} ({_describe(e)})") from None


def _describe(e: BaseException) -> str:
    """One line about a loader's exception, without leaking its internals."""
    if isinstance(e, ImportError):  # trimesh reaching for an optional package to guess at bad bytes
        return "the file is corrupt or in an unsupported variant"
    text = str(e).strip().splitlines()
    return f"{type(e).__name__}: {text[0][:200]}" if text else type(e).__name__


def _check_stl(path: Path, data: bytes) -> None:
    """Refuse a corrupt STL before trimesh guesses at it.

    A binary STL is exactly ``84 + 50 * count`` bytes. Anything else must be
    ASCII text starting with ``solid``; trimesh would otherwise try to guess
    a text encoding with an optional package and fail with an ImportError.
    """
    count = _binary_stl_count(data)
    if count is not None:
        if count > MAX_TRIANGLES:
            raise AssetError(f"{path}: {count} triangles is more than the {MAX_TRIANGLES} a mesh asset may have")
        return
    count = struct.unpack_from("<I", data, 80)[0] if len(data) >= _STL_HEADER else None
    head = data[:512].lstrip()
    try:
        data.decode("ascii")
        is_text = head[:5].lower() == b"solid"
    except UnicodeDecodeError:
        is_text = False
    if not is_text:
        if count is None:
            raise AssetError(
                f"{path}: not an STL file ({len(data)} bytes: too short for a binary STL "
                "and not ASCII text starting with 'solid')"
            )
        raise AssetError(
            f"{path}: corrupt binary STL: its header says {count} triangles, which needs "
            f"{_STL_HEADER + _STL_TRIANGLE * count} bytes, but the file has {len(data)}"
        )


def _binary_stl_count(data: bytes) -> int | None:
    """The triangle count of a well-formed binary STL, else None."""
    if len(data) < _STL_HEADER:
        return None
    (count,) = struct.unpack_from("<I", data, 80)
    return count if len(data) == _STL_HEADER + _STL_TRIANGLE * count else None


def _obj_as_utf8(data: bytes) -> bytes:
    """The OBJ's bytes as UTF-8.

    trimesh guesses the encoding of non-UTF-8 text with an optional package
    (charset_normalizer) and fails with an ImportError without it. OBJ keywords
    are ASCII, so reading the rest as Latin-1 loses nothing that matters.
    """
    try:
        data.decode("utf-8")
        return data
    except UnicodeDecodeError:
        return data.decode("latin-1").encode("utf-8")
