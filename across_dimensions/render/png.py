"""Minimal PNG writer and reader (zlib + struct only).

Screenshots and golden-image tests need PNG files, and PIL may not be
installed, so this module handles the small subset we produce: 8-bit
greyscale, grey+alpha, RGB and RGBA, non-interlaced. The reader undoes all five
scanline filters, so it also reads PNGs written by other tools in those
formats (e.g. an artist touching up a golden image).
"""

from __future__ import annotations

import struct
import zlib

import numpy as np

from ..core.errors import InputError
from ..core.fileio import MiB, atomic_write, read_bytes

#: Largest PNG file :func:`read_png` reads, and most pixels it decodes
#: (a 8192 x 8192 RGBA image): a small file must not inflate to gigabytes.
PNG_MAX_BYTES = 256 * MiB
PNG_MAX_PIXELS = 8192 * 8192

_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# PNG colour type -> channels (8-bit depth only).
_CHANNELS = {0: 1, 4: 2, 2: 3, 6: 4}
_COLOR_TYPE = {v: k for k, v in _CHANNELS.items()}


class PngError(InputError):
    """A PNG this module cannot read (bad file, or an unsupported variant)."""


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def encode_png(image: np.ndarray, compress_level: int = 6) -> bytes:
    """Encode an image as PNG bytes.

    Parameters
    ----------
    image : (h, w) or (h, w, c) uint8, c in {1, 2, 3, 4}
        Top row first. Other integer/float dtypes are not converted silently:
        pass uint8.
    compress_level : int
        zlib level 0-9.

    Returns
    -------
    bytes
    """
    a = np.asarray(image)
    if a.dtype != np.uint8:
        raise TypeError(f"encode_png needs uint8 pixels, got {a.dtype}")
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] not in _COLOR_TYPE or a.shape[0] == 0 or a.shape[1] == 0:
        raise ValueError(f"encode_png needs (h, w) or (h, w, 1|2|3|4) with h, w > 0, got {a.shape}")
    h, w, c = a.shape
    # Filter type 0 (None) on every row: simplest, and zlib still compresses the
    # flat areas of a game frame (sky, HUD) well.
    raw = np.zeros((h, 1 + w * c), np.uint8)
    raw[:, 1:] = np.ascontiguousarray(a).reshape(h, w * c)
    header = struct.pack(">IIBBBBB", w, h, 8, _COLOR_TYPE[c], 0, 0, 0)
    idat = zlib.compress(raw.tobytes(), compress_level)
    return _SIGNATURE + _chunk(b"IHDR", header) + _chunk(b"IDAT", idat) + _chunk(b"IEND", b"")


def write_png(path, image: np.ndarray, compress_level: int = 6) -> None:
    """Write ``image`` (see :func:`encode_png`) to ``path``.

    Written whole or not at all (:func:`~across_dimensions.core.fileio.atomic_write`),
    so a crash never leaves half a golden image or a temporary file behind.

    Raises
    ------
    FileProblem
        The folder is missing or the file cannot be written.
    """
    atomic_write(path, encode_png(image, compress_level))


def decode_png(data: bytes) -> np.ndarray:
    """Decode PNG bytes.

    Returns
    -------
    (h, w, c) uint8
        Top row first; ``c`` is 1 (grey), 2 (grey+alpha), 3 (RGB) or 4 (RGBA).

    Raises
    ------
    PngError
        Not a PNG, corrupt, or not an 8-bit non-interlaced grey/RGB(A) image.
    """
    if not data.startswith(_SIGNATURE):
        raise PngError("not a PNG file (bad signature)")
    header, idat = _chunks(data)
    if header is None:
        raise PngError("no IHDR chunk")
    w, h, depth, ctype, _, _, interlace = header
    if w * h > PNG_MAX_PIXELS:
        raise PngError(f"{w}x{h} pixels is more than the {PNG_MAX_PIXELS} an image may have")
    if depth != 8 or ctype not in _CHANNELS or interlace != 0:
        raise PngError(
            f"unsupported PNG variant (bit depth {depth}, colour type {ctype}, interlace {interlace}); "
            f"need 8-bit non-interlaced grey/RGB/RGBA"
        )
    c = _CHANNELS[ctype]
    try:
        # Never inflate past what the header promises, plus one byte to notice more.
        inflater = zlib.decompressobj()
        raw = np.frombuffer(inflater.decompress(b"".join(idat), h * (w * _CHANNELS[ctype] + 1) + 1), np.uint8)
    except zlib.error as e:
        raise PngError(f"corrupt image data ({e})") from None
    stride = w * c
    if raw.size != h * (stride + 1):
        raise PngError(f"image data has {raw.size} bytes, expected {h * (stride + 1)} for {w}x{h}x{c}")
    return _unfilter(raw.reshape(h, stride + 1), c).reshape(h, w, c)


def _chunks(data: bytes) -> tuple[tuple | None, list[bytes]]:
    """The unpacked IHDR fields (None if there is none) and the IDAT chunks' bodies, in order."""
    pos = len(_SIGNATURE)
    header = None
    idat = []
    while pos + 8 <= len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if len(body) != length:
            raise PngError(f"truncated {kind!r} chunk")
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    return header, idat


def _unfilter(rows: np.ndarray, c: int) -> np.ndarray:
    """Undo the PNG row filters: ``rows (h, 1 + stride) uint8`` (each row's filter type first) to
    the ``(h, stride) uint8`` pixel bytes; ``c`` bytes a pixel."""
    h, stride = rows.shape[0], rows.shape[1] - 1
    out = np.zeros((h, stride), np.uint8)
    prev = np.zeros(stride, np.int32)
    for y in range(h):
        f, line = rows[y, 0], rows[y, 1:].astype(np.int32)
        if f == 0:
            cur = line
        elif f == 1:  # Sub: depends on the reconstructed pixel to the left -> sequential per pixel
            cur = line.copy()
            for x in range(c, stride):
                cur[x] = (cur[x] + cur[x - c]) & 0xFF
        elif f == 2:  # Up
            cur = (line + prev) & 0xFF
        elif f == 3:  # Average
            cur = line.copy()
            for x in range(stride):
                left = cur[x - c] if x >= c else 0
                cur[x] = (cur[x] + ((left + prev[x]) >> 1)) & 0xFF
        elif f == 4:  # Paeth
            cur = _paeth(line, prev, c)
        else:
            raise PngError(f"bad filter type {int(f)} on row {y}")
        out[y] = cur
        prev = cur
    return out


def _paeth(line: np.ndarray, prev: np.ndarray, c: int) -> np.ndarray:
    """A row under the Paeth filter, reconstructed left to right: ``line`` and ``prev`` (the row
    above, already reconstructed) are ``(stride,) int32``."""
    cur = line.copy()
    for x in range(len(cur)):
        a = cur[x - c] if x >= c else 0
        b = prev[x]
        cc = prev[x - c] if x >= c else 0
        p = a + b - cc
        pa, pb, pc = abs(p - a), abs(p - b), abs(p - cc)
        pred = a if (pa <= pb and pa <= pc) else (b if pb <= pc else cc)
        cur[x] = (cur[x] + pred) & 0xFF
    return cur


def read_png(path) -> np.ndarray:
    """Read a PNG file of at most :data:`PNG_MAX_BYTES`; see :func:`decode_png` for the result.

    Raises
    ------
    FileProblem
        Missing, not a regular file, or too large.
    PngError
        Not a PNG this module reads; the message names the file.
    """
    data = read_bytes(path, limit=PNG_MAX_BYTES, what="PNG image")
    try:
        return decode_png(data)
    except PngError as e:
        raise PngError(f"{path}: {e}") from None
