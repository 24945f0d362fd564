"""Reading a ``.npz`` mesh file as hostile input (:meth:`~.mesh.TetMesh4.load`).

Each array's size is checked twice before anything is decompressed or
allocated: the size the zip directory declares for its member, and the shape
in the ``.npy`` header. Every problem is one :class:`~.errors.MeshError` line
naming the file, the array and what was expected.
"""

from __future__ import annotations

import io
import zipfile
import zlib
from pathlib import Path

import numpy as np

from .errors import MeshError
from .fileio import MiB

#: Limits on what a ``.npz`` mesh file may ask for (see :meth:`TetMesh4.load`).
#: A 4D mesh the game can slice at 60 Hz is far below these; they exist so a
#: small hostile file cannot make the loader allocate gigabytes.
NPZ_MAX_BYTES = 256 * MiB
NPZ_MAX_VERTICES = 1_000_000
NPZ_MAX_TETS = 2_000_000
#: Largest vertex coordinate (and colour channel) magnitude: far beyond any
#: level, and far enough from float32's 3.4e38 that no product overflows.
NPZ_MAX_COORD = 1e6


# What each array of a .npz mesh may be: element counts per row and the dtype
# kinds accepted (f float, i signed, u unsigned integer).
_NPZ_ARRAYS = {"vertices": ((4,), "fiu"), "tets": ((4,), "iu"), "colors": ((3, 4), "fiu")}


def read_npz(path: Path, raw: bytes) -> dict:
    """The arrays of a ``.npz`` held in ``raw``, each checked before it is decompressed.

    Returns
    -------
    dict of str to ndarray
        ``vertices (n, 4)``, ``tets (m, 4)`` and maybe ``colors (n, 3|4)``,
        with the dtypes stored in the file.
    """
    if not raw.startswith(b"PK"):
        raise MeshError(f"{path}: not a .npz file (expected a zip archive of numpy arrays)")
    try:
        zf = zipfile.ZipFile(io.BytesIO(raw))
        members = {info.filename.removesuffix(".npy"): info for info in zf.infolist()}
    except (zipfile.BadZipFile, ValueError, OSError, EOFError) as e:
        raise MeshError(f"{path}: not a readable .npz file ({e})") from None
    missing = [k for k in ("vertices", "tets") if k not in members]
    if missing:
        raise MeshError(f"{path}: missing array(s) {', '.join(missing)}; expected 'vertices' (n, 4) and 'tets' (m, 4)")
    out = {}
    for name, (widths, kinds) in _NPZ_ARRAYS.items():
        if name not in members:
            continue
        limit = NPZ_MAX_TETS if name == "tets" else NPZ_MAX_VERTICES
        info = members[name]
        # 8-byte elements at most, plus the .npy header (bounded by numpy at 10 kB + alignment).
        most = limit * max(widths) * 8 + 16_384
        if info.file_size > most:
            raise MeshError(
                f"{path}: '{name}' would unpack to {info.file_size} bytes, more than the "
                f"{limit} rows a mesh may have ({most} bytes)"
            )
        try:
            data = zf.read(info)
        except (zipfile.BadZipFile, zlib.error, ValueError, OSError, EOFError, NotImplementedError, RuntimeError) as e:
            raise MeshError(f"{path}: cannot unpack '{name}' ({e})") from None
        out[name] = _read_npy(path, name, data, widths, kinds, limit)
    if "colors" in out and len(out["colors"]) != len(out["vertices"]):
        raise MeshError(
            f"{path}: 'colors' has {len(out['colors'])} rows for {len(out['vertices'])} vertices; "
            f"expected one colour per vertex"
        )
    return out


def _read_npy(path: Path, name: str, data: bytes, widths: tuple, kinds: str, limit: int) -> np.ndarray:
    """One ``.npy`` member, its header checked before the array is made."""
    where = f"{path}: '{name}'"
    if data.startswith(b"PK"):
        raise MeshError(f"{where} is a zip archive inside the .npz (nested zip); expected a numpy array")
    f = io.BytesIO(data)
    try:
        version = np.lib.format.read_magic(f)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(f)
        elif version == (2, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(f)
        else:
            raise ValueError(f"unsupported .npy version {version}")
    except (ValueError, EOFError, SyntaxError, TypeError) as e:
        raise MeshError(f"{where} is not a numpy array ({e})") from None
    if dtype.hasobject or dtype.kind not in kinds or dtype.itemsize > 8 or dtype.fields is not None:
        expected = "integers" if kinds == "iu" else "real numbers"
        raise MeshError(f"{where} holds {dtype} values; expected {expected}")
    row = widths[0]
    expected_shape = f"(n, {row})" if len(widths) == 1 else "(n, 3) or (n, 4)"
    if len(shape) != 2 or shape[1] not in widths:
        raise MeshError(f"{where} has shape {shape}; expected {expected_shape}")
    if shape[0] > limit:
        raise MeshError(f"{where} has {shape[0]} rows; a mesh may have at most {limit}")
    offset = f.tell()
    count = shape[0] * shape[1]
    if len(data) - offset != count * dtype.itemsize:
        raise MeshError(
            f"{where} holds {len(data) - offset} bytes of data; its header promises {count * dtype.itemsize}"
        )
    a = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
    a = a.reshape(shape[::-1]).T if fortran else a.reshape(shape)
    if name != "tets":
        with np.errstate(invalid="ignore"):  # NaN compares False: it is reported, not warned about
            # Both bounds, not abs(): abs of the most negative integer is still negative.
            bad = np.flatnonzero(~((a >= -NPZ_MAX_COORD) & (a <= NPZ_MAX_COORD)).all(axis=1))
        if len(bad):
            kind = "are not finite" if not np.isfinite(a[bad]).all() else f"exceed {NPZ_MAX_COORD:g} in magnitude"
            raise MeshError(
                f"{where} rows {bad[:5].tolist()} {kind}; expected finite numbers within +-{NPZ_MAX_COORD:g}"
            )
    if dtype.kind in "iu" and name == "tets" and a.size and int(a.min()) < 0:
        raise MeshError(f"{where} holds the negative vertex index {int(a.min())}")
    return a
