"""Reading and writing files a player or modder hands us: bounded and atomic.

Every file the game reads (levels, replays, settings, meshes, assets) goes
through :func:`read_bytes`, and every file it writes goes through
:func:`atomic_write` or :func:`atomic_writer`. One reader and one writer means
one place where the rules hold:

- **Read only regular files, never more than a limit.** A FIFO would block
  ``open`` forever and ``/dev/zero`` never ends, so the file is opened
  non-blocking and checked with ``fstat`` on the open descriptor (no race
  between a check and the open), then read up to ``limit + 1`` bytes.
- **Write whole files or nothing.** Data goes to a uniquely named temporary file
  in the target's own folder (so two writers never share one), is flushed to
  disk with ``fsync``, then renamed over the target with ``os.replace``, which
  is atomic on POSIX and Windows. On any error, ``KeyboardInterrupt``
  included, the temporary file is removed.
- **Never create folders the user did not ask for.** A missing target folder is
  an error naming it.

Errors are :class:`FileProblem`, an :class:`~.errors.InputError` (a ``ValueError``) whose message names the file
and says what was expected, ready to show a player as one line.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from pathlib import Path

from .errors import InputError

__all__ = ["FileProblem", "MiB", "read_bytes", "read_text", "atomic_write", "atomic_writer", "check_folder"]

MiB = 1 << 20
# Read once at import: os.umask can only be read by setting it, which is not
# safe to do later while other threads may be creating files.
_UMASK = os.umask(0o022)
os.umask(_UMASK)


class FileProblem(InputError):
    """A file that cannot be read or written as asked; the message names it."""


def _kind(mode: int) -> str:
    for test, name in (
        (stat.S_ISDIR, "a folder"),
        (stat.S_ISFIFO, "a pipe (FIFO)"),
        (stat.S_ISCHR, "a device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return name
    return "not a regular file"


def _size(n: int) -> str:
    return f"{n / MiB:.3g} MiB" if n >= MiB else f"{n} bytes"


def read_bytes(path, *, limit: int, what: str = "file") -> bytes:
    """Read a whole regular file of at most ``limit`` bytes.

    Parameters
    ----------
    path : str or Path
    limit : int
        Largest accepted size in bytes; a larger file is refused, not truncated.
    what : str
        What the file should be ("level", "replay"), used in messages.

    Raises
    ------
    FileProblem
        The file is missing, unreadable, not a regular file (a folder, FIFO,
        device, socket, or a symlink to one) or larger than ``limit``.
    """
    path = Path(path)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise FileProblem(f"{path}: no such file (expected a {what})") from None
    except IsADirectoryError:
        raise FileProblem(f"{path}: is a folder (expected a {what} file)") from None
    except OSError as e:
        raise FileProblem(f"{path}: cannot open it ({e.strerror or e})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise FileProblem(f"{path}: is {_kind(st.st_mode)} (expected a regular {what} file)")
        if st.st_size > limit:
            raise FileProblem(f"{path}: {_size(st.st_size)} is larger than the {_size(limit)} a {what} may be")
        chunks, total = [], 0
        while True:  # the size can change after fstat: read no more than limit + 1
            chunk = os.read(fd, min(limit + 1 - total, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
            if total > limit:
                raise FileProblem(f"{path}: larger than the {_size(limit)} a {what} may be")
        return b"".join(chunks)
    except OSError as e:
        raise FileProblem(f"{path}: cannot read it ({e.strerror or e})") from None
    finally:
        os.close(fd)


def read_text(path, *, limit: int, what: str = "file") -> str:
    """:func:`read_bytes` decoded as UTF-8 (a leading byte-order mark is skipped).

    Raises
    ------
    FileProblem
        As :func:`read_bytes`, or when the bytes are not UTF-8 text.
    """
    raw = read_bytes(path, limit=limit, what=what)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise FileProblem(f"{path}: not a text file (byte {e.start} is not UTF-8; expected a {what})") from None


def check_folder(path) -> Path:
    """``path`` as a Path, after checking that its folder exists.

    Raises
    ------
    FileProblem
        When the folder is missing or is not a folder, or ``path`` is there and
        is not a regular file (a folder, a FIFO, a device such as ``/dev/null``,
        a socket, or a link to one): writing replaces the target, and only a
        regular file or a new name may be replaced. Folders are never created
        here: a typo must not scatter directories over the disk.
    """
    path = Path(path)
    folder = path.parent
    try:
        if not folder.is_dir():
            what = "is not a folder" if folder.exists() else "does not exist"
            raise FileProblem(f"{path}: the folder {folder} {what}")
        mode = os.stat(path).st_mode  # follows a link: a link to /dev/null is a device
    except FileNotFoundError:
        return path  # a new file (or a dangling link, replaced by the file)
    except OSError as e:
        raise FileProblem(f"{path}: cannot write it ({e.strerror or e})") from None
    if stat.S_ISDIR(mode):
        raise FileProblem(f"{path}: is a folder (expected a file name to write)")
    if not stat.S_ISREG(mode):
        raise FileProblem(f"{path}: is {_kind(mode)}, not a regular file (expected a new file or one to replace)")
    return path


@contextlib.contextmanager
def atomic_writer(path, mode: str = "wb", *, encoding: str | None = None):
    """Open a temporary file that replaces ``path`` only when the block succeeds.

    Parameters
    ----------
    path : str or Path
        The target. Its folder must exist (see :func:`check_folder`).
    mode : {"wb", "w"}
        Binary or text.
    encoding : str, optional
        For text mode; UTF-8 by default.

    Yields
    ------
    file
        Write to it; it is flushed, synced and renamed over ``path`` on exit.
        If the block raises, the target is untouched and the temporary file
        is removed.

    Examples
    --------
    >>> with atomic_writer("out.obj", "w") as f:   # doctest: +SKIP
    ...     f.write("v 0 0 0\\n")
    """
    if mode not in ("wb", "w"):
        raise ValueError(f"atomic_writer: mode must be 'wb' or 'w', got {mode!r}")
    path = check_folder(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as e:
        raise FileProblem(f"{path}: cannot write in {path.parent} ({e.strerror or e})") from None
    try:
        kw = {"encoding": encoding or "utf-8", "newline": ""} if mode == "w" else {}
        with os.fdopen(fd, mode, **kw) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        # mkstemp makes the file private (0600); give it the permissions a
        # plain open() would have, so outputs are readable as users expect.
        os.chmod(tmp, 0o666 & ~_UMASK)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def atomic_write(path, data: bytes | str, *, encoding: str = "utf-8") -> Path:
    """Write ``data`` to ``path`` whole or not at all (see :func:`atomic_writer`).

    Returns
    -------
    Path
        The file written.
    """
    binary = isinstance(data, (bytes, bytearray, memoryview))
    try:
        with atomic_writer(path, "wb" if binary else "w", encoding=encoding) as f:
            f.write(data)
    except OSError as e:
        raise FileProblem(f"{path}: cannot write it ({e.strerror or e})") from None
    return Path(path)
