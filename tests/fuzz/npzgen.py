"""Hostile ``.npz`` 4D mesh files: bad arrays, nested zips, zip bombs, lying headers.

The base meshes come from :mod:`across_dimensions.core.shapes` (small regular
polytopes, so a file that survives the mutation still slices in milliseconds).
"""

from __future__ import annotations

import functools
import io
import struct
import zipfile
import zlib

import numpy as np

from .mutate import pick

__all__ = ["base_arrays", "savez", "zip_bomb", "npy_header", "lying_header", "nested_zip", "MUTATIONS"]


@functools.cache
def _base(name: str) -> tuple:
    from across_dimensions.core import shapes

    m = shapes.make_shape(name)
    return m.vertices, m.tets, m.colors


def base_arrays(rng) -> tuple[str, dict]:
    """A small shipped shape as the arrays :meth:`TetMesh4.save` writes (copies)."""
    name = pick(rng, ("tesseract", "5-cell", "16-cell"))
    v, t, c = _base(name)
    arrays = {"vertices": v.copy(), "tets": t.copy()}
    if c is not None:
        arrays["colors"] = c.copy()
    return name, arrays


def savez(arrays: dict, compressed: bool = True) -> bytes:
    """``np.savez[_compressed]`` to bytes; object arrays are pickled, as an attacker's file may be."""
    buf = io.BytesIO()
    (np.savez_compressed if compressed else np.savez)(buf, **arrays)
    return buf.getvalue()


def npy_header(dtype: str, shape: tuple) -> bytes:
    """A version 1.0 ``.npy`` header (padded to 64 bytes) claiming ``dtype`` and ``shape``."""
    d = f"{{'descr': '{dtype}', 'fortran_order': False, 'shape': {shape!r}, }}"
    pad = 64 - (10 + len(d) + 1) % 64
    d = d + " " * pad + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(d)) + d.encode("latin-1")


def _zip_one(name: str, deflated: bytes, crc: int, size: int, extra_members: dict | None = None) -> bytes:
    """A zip archive holding ``name`` (already deflated) and optional plain members."""
    out = io.BytesIO()
    central = []
    fname = name.encode()
    local = struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, 8, 0, 0x21, crc, len(deflated), size, len(fname), 0)
    central.append((fname, 0, crc, len(deflated), size, 8))
    out.write(local + fname + deflated)
    for mname, data in (extra_members or {}).items():
        off = out.tell()
        mb = mname.encode()
        c = zlib.crc32(data)
        out.write(
            struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, 0, 0, 0x21, c, len(data), len(data), len(mb), 0) + mb + data
        )
        central.append((mb, off, c, len(data), len(data), 0))
    cd_start = out.tell()
    for fn, off, c, csize, usize, method in central:
        out.write(
            struct.pack(
                "<IHHHHHHIIIHHHHHII",
                0x02014B50,
                20,
                20,
                0,
                method,
                0,
                0x21,
                c,
                csize,
                usize,
                len(fn),
                0,
                0,
                0,
                0,
                0,
                off,
            )
            + fn
        )
    cd_size = out.tell() - cd_start
    out.write(struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, len(central), len(central), cd_size, cd_start, 0))
    return out.getvalue()


@functools.lru_cache(maxsize=4)
def _zero_stream(header: bytes, n_chunks: int, chunk: int = 1 << 24) -> tuple[bytes, int, int]:
    """Deflate ``header + n_chunks * chunk`` zero bytes cheaply.

    After a full flush the compressor's output for the same input repeats
    byte for byte, so one compressed chunk is copied ``n_chunks - 1`` times.
    """
    zeros = bytes(chunk)
    c = zlib.compressobj(6, zlib.DEFLATED, -15)
    first = c.compress(header + zeros) + c.flush(zlib.Z_FULL_FLUSH)
    again = c.compress(zeros) + c.flush(zlib.Z_FULL_FLUSH)
    assert again == c.compress(zeros) + c.flush(zlib.Z_FULL_FLUSH), "deflate output does not repeat"
    body = first + again * (n_chunks - 1) + c.flush()
    crc = zlib.crc32(header)
    for _ in range(n_chunks):  # the CRC still needs every byte; cheap next to deflate
        crc = zlib.crc32(zeros, crc)
    return body, crc, len(header) + n_chunks * chunk


def zip_bomb(rng, arrays: dict) -> tuple[bytes, str]:
    """One member claims hundreds of MiB of zeros in about a MiB of file."""
    target = pick(rng, ("vertices", "tets"))
    mib = int(pick(rng, (512, 2000)))
    chunk = 1 << 24
    n_chunks = mib * (1 << 20) // chunk
    if target == "vertices":
        header = npy_header("<f8", (n_chunks * chunk // 32, 4))
    else:
        header = npy_header("<u4", (n_chunks * chunk // 16, 4))
    body, crc, size = _zero_stream(header, n_chunks, chunk)
    others = {f"{k}.npy": _npy_bytes(v) for k, v in arrays.items() if k != target}
    data = _zip_one(f"{target}.npy", body, crc, size, others)
    return data, f"zip bomb: {target}.npy is {mib} MiB of zeros in a {len(data) / 2**20:.1f} MiB file"


def _npy_bytes(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, a, allow_pickle=True)
    return buf.getvalue()


def lying_header(rng, arrays: dict) -> tuple[bytes, str]:
    """A member whose header claims a huge shape over a few bytes of data."""
    target = pick(rng, ("vertices", "tets", "colors"))
    shape = pick(rng, ((2**40, 4), (2**31, 2**31), (10**6, 4), (-1, 4), (2**62, 2**62, 4)))
    dtype = "<u4" if target == "tets" else "<f4"
    members = {f"{k}.npy": _npy_bytes(v) for k, v in arrays.items()}
    members[f"{target}.npy"] = npy_header(dtype, shape) + bytes(64)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        for k, v in members.items():
            z.writestr(k, v)
    return buf.getvalue(), f"{target}.npy header claims shape {shape} over 64 bytes"


def nested_zip(rng, arrays: dict) -> tuple[bytes, str]:
    """A member that is itself a zip (an .npz inside the .npz)."""
    inner = savez(arrays)
    target = pick(rng, ("vertices", "tets", "colors", "inner"))
    members = {f"{k}.npy": _npy_bytes(v) for k, v in arrays.items() if k != target}
    depth = int(pick(rng, (1, 2, 50)))
    blob = inner
    for _ in range(depth - 1):
        b = io.BytesIO()
        with zipfile.ZipFile(b, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr(f"{target}.npy", blob)
        blob = b.getvalue()
    members[f"{target}.npy" if target != "inner" else "inner.npz"] = blob
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        for k, v in members.items():
            z.writestr(k, v)
    return buf.getvalue(), f"{target} member is a zip nested {depth} deep"


# ------------------------------------------------------------- array mutations
def _value_extreme(rng, a):
    a = dict(a)
    v = a["vertices"].astype(pick(rng, (np.float32, np.float64)))
    value = pick(rng, (np.nan, np.inf, -np.inf, 3.4e38, -3.4e38, 1e308, 5e-324, 1e-45))
    i, j = int(rng.integers(len(v))), int(rng.integers(4))
    with np.errstate(over="ignore"):
        v[i, j] = value
    a["vertices"] = v
    return a, f"vertices[{i}, {j}] = {value!r} ({v.dtype})", False


def _bad_index(rng, a):
    a = dict(a)
    t = a["tets"].astype(np.int64)
    n = len(a["vertices"])
    value = pick(rng, (n, n + 1, 2**31 - 1, -1, -(2**31), 2**40))
    i, j = int(rng.integers(len(t))), int(rng.integers(4))
    t[i, j] = value
    a["tets"] = t
    return a, f"tets[{i}, {j}] = {value} (int64; {n} vertices)", True


def _uint64_wrap(rng, a):
    a = dict(a)
    k = int(pick(rng, (1, 2**31)))
    a["tets"] = a["tets"].astype(np.uint64) + np.uint64(k) * np.uint64(2**32)
    return a, f"tets as uint64 with {k} * 2**32 added (wraps to valid uint32 indices)", True


def _dtype_swap(rng, a):
    a = dict(a)
    target = pick(rng, [k for k in a])
    kind = pick(rng, ("U8", "S8", "bool", "complex128", "float16", "int8", "object", "structured", "datetime64[s]"))
    x = a[target]
    if kind == "object":
        y = np.empty(x.shape, dtype=object)
        y[...] = [[str(e) for e in row] for row in x.tolist()] if x.ndim == 2 else 0
    elif kind == "structured":
        y = np.zeros(x.shape[:1], dtype=[("a", "f4"), ("b", "u4", (3,))])
    elif kind == "datetime64[s]":
        y = x.astype(np.int64).astype(kind)
    else:
        with np.errstate(all="ignore"):
            y = x.astype(kind)
    a[target] = y
    return a, f"{target} as {kind} {y.shape}", kind not in ("float16", "int8", "bool", "complex128")


def _shape_swap(rng, a):
    a = dict(a)
    target = pick(rng, [k for k in a])
    x = a[target]
    kind = pick(rng, ("scalar", "flat", "transposed", "extra-axis", "empty", "five-columns", "3d-points"))
    y = {
        "scalar": lambda: np.asarray(x.flat[0]),
        "flat": lambda: x.ravel(),
        "transposed": lambda: x.T.copy(),
        "extra-axis": lambda: x[..., None],
        "empty": lambda: x[:0],
        "five-columns": lambda: np.concatenate([x, x[:, :1]], axis=1),
        "3d-points": lambda: x[:, :3].copy(),
    }[kind]()
    a[target] = y
    refused = not (kind == "empty" and target == "colors")
    return a, f"{target} reshaped ({kind}) to {y.shape}", refused


def _scalar_colour(rng, a):
    a = dict(a)
    kind = pick(rng, ("0-d", "one-rgba", "rgb-only", "nan", "wrong-length", "string"))
    n = len(a["vertices"])
    a["colors"] = {
        "0-d": lambda: np.float32(0.5),
        "one-rgba": lambda: np.array([1, 0, 0, 1], np.float32),
        "rgb-only": lambda: np.full((n, 3), 0.5, np.float32),
        "nan": lambda: np.full((n, 4), np.nan, np.float32),
        "wrong-length": lambda: np.ones((n + 3, 4), np.float32),
        "string": lambda: np.array("red"),
    }[kind]()
    return a, f"colors: {kind} {np.shape(a['colors'])}", kind != "rgb-only"


def _missing_or_extra(rng, a):
    a = dict(a)
    kind = pick(rng, ("missing", "extra", "renamed", "many"))
    target = pick(rng, ("vertices", "tets"))
    if kind == "missing":
        del a[target]
    elif kind == "extra":
        a["payload"] = np.arange(10)
    elif kind == "renamed":
        a[target.upper()] = a.pop(target)
    else:
        for i in range(5000):
            a[f"extra{i}"] = np.zeros(1)
    return a, f"{kind} array ({target})", kind in ("missing", "renamed")


def _degenerate(rng, a):
    a = dict(a)
    kind = pick(rng, ("all-same-vertex", "repeated-index", "zero-vertices", "huge-scale"))
    if kind == "all-same-vertex":
        a["vertices"] = np.zeros_like(a["vertices"])
    elif kind == "repeated-index":
        t = a["tets"].copy()
        t[:, 1] = t[:, 0]
        a["tets"] = t
    elif kind == "zero-vertices":
        a["vertices"] = a["vertices"][:0]
    else:
        a["vertices"] = a["vertices"].astype(np.float64) * 1e300
    return a, f"degenerate mesh: {kind}", False


#: name -> function(rng, arrays) returning (arrays, description, must_be_refused)
ARRAY_MUTATIONS = {
    "value_extreme": _value_extreme,
    "bad_index": _bad_index,
    "uint64_wrap": _uint64_wrap,
    "dtype_swap": _dtype_swap,
    "shape_swap": _shape_swap,
    "scalar_colour": _scalar_colour,
    "missing_or_extra": _missing_or_extra,
    "degenerate": _degenerate,
}
#: name -> function(rng, arrays) returning (file bytes, description); all must be refused
FILE_MUTATIONS = {"zip_bomb": zip_bomb, "lying_header": lying_header, "nested_zip": nested_zip}
MUTATIONS = (*ARRAY_MUTATIONS, *FILE_MUTATIONS)
