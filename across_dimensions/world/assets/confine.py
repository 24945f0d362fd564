"""Which files an asset may reference, and reading them within bounds.

A ``.gltf`` names its buffers and images by URI, and a ``.glb`` may too. Those
URIs are data from whoever made the file: an absolute path or ``../..`` would
make the game read (and hash) anything on the disk, a 3 GB file or a device.
So every referenced file must lie in the asset's own folder tree: the folder
of the mesh file and its subfolders, after symbolic links are resolved. Data
URIs (``data:...;base64,...``) are part of the file that holds them and so
bounded by its size. Everything, the mesh file included, is read with
:func:`~across_dimensions.core.fileio.read_bytes`, which reads only regular
files, within one budget of :data:`~.limits.MAX_ASSET_BYTES` per asset.

:class:`ConfinedResolver` is what trimesh's loaders get as their ``resolver``
(trimesh 4.x and 5.x call ``resolver[name]``, ``get``, ``namespaced`` and
``keys``), so the loader itself can reach nothing the rules above refuse.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path
from urllib.parse import unquote

from ...core.fileio import FileProblem, MiB, read_bytes
from .errors import AssetError
from .limits import MAX_ASSET_BYTES, MAX_GLTF_ELEMENTS

#: Suffixes whose files may reference other files.
REFERENCING = (".gltf", ".glb")
_GLB_MAGIC = b"glTF"
_GLB_JSON = 0x4E4F534A  # chunk type "JSON"


class Budget:
    """Bytes still allowed for one asset; every read of it takes from here."""

    def __init__(self, limit: int = MAX_ASSET_BYTES):
        self.limit = limit
        self.left = limit

    def read(self, path: Path, what: str) -> bytes:
        """Read a whole regular file within the remaining budget.

        Raises
        ------
        AssetError
            Missing, not a regular file, or more than the budget allows.
        """
        try:
            data = read_bytes(path, limit=self.left, what=what)
        except FileProblem as e:
            if self.left < self.limit and "larger than" in str(e):  # the budget, not the file, ran out
                raise AssetError(
                    f"{path}: more than the {self.left} bytes left of the {_size(self.limit)} "
                    f"a {what} and the files it references may take together"
                ) from None
            raise AssetError(str(e)) from None
        self.left -= len(data)
        return data


def _size(n: int) -> str:
    return f"{n / MiB:.3g} MiB" if n >= MiB else f"{n} bytes"


def confined_path(root: Path, uri: str, owner: Path, what: str = "URI") -> Path:
    """The file a relative URI names, inside ``root`` or refused.

    Parameters
    ----------
    root : Path
        The asset's folder; resolved (symbolic links followed).
    uri : str
        As written in the file: relative, ``/``-separated, percent-encoded.
    owner : Path
        The file holding the URI, for the message.
    what : str
        What the URI is ("buffer 0 URI"), for the message.

    Raises
    ------
    AssetError
        The URI is not a string, is absolute, has a scheme or drive (``file:``,
        ``http:``, ``C:``), contains a NUL, or resolves outside ``root``.
    """
    if not isinstance(uri, str) or not uri:
        raise AssetError(f"{owner}: {what} {uri!r} is not a file name; expected a path relative to {root}")
    name = unquote(uri)
    why = None
    if "\x00" in name:
        why = "contains a NUL character"
    elif name.startswith(("/", "\\")) or ":" in name:
        why = "is absolute or has a scheme"
    else:
        full = (root / name).resolve()
        if not full.is_relative_to(root):
            why = "leaves the asset's folder"
    if why:
        raise AssetError(f"{owner}: {what} {uri!r} {why}; expected a file inside {root}")
    return full


def _gltf_json(path: Path, data: bytes) -> dict:
    """The JSON document of a ``.gltf`` or of a ``.glb``'s first chunk."""
    if path.suffix.lower() == ".glb":
        if len(data) < 20 or data[:4] != _GLB_MAGIC:
            raise AssetError(f"{path}: not a binary glTF (expected the 'glTF' header)")
        length, kind = struct.unpack_from("<II", data, 12)
        if kind != _GLB_JSON or 20 + length > len(data):
            raise AssetError(f"{path}: binary glTF has no complete JSON chunk after its header")
        data = data[20 : 20 + length]
    try:
        doc = json.loads(data.decode("utf-8-sig"))
    except (UnicodeDecodeError, ValueError) as e:
        raise AssetError(f"{path}: not valid glTF JSON ({str(e).splitlines()[0][:120]})") from None
    if not isinstance(doc, dict):
        raise AssetError(f"{path}: glTF JSON must be an object, got {type(doc).__name__}")
    return doc


def _entries(doc: dict, key: str, path: Path) -> list:
    items = doc.get(key, [])
    if not isinstance(items, list) or not all(isinstance(x, dict) for x in items):
        raise AssetError(f"{path}: glTF '{key}' must be a list of objects")
    return items


def referenced_files(path: Path, data: bytes, root: Path) -> list[Path]:
    """The files a glTF asset references, each checked by :func:`confined_path`.

    Also refuses accessors that declare more than
    :data:`~.limits.MAX_GLTF_ELEMENTS` elements together: the loader
    allocates them whether or not a buffer holds them.

    Parameters
    ----------
    path : Path
        The mesh file; other formats reference nothing (materials of an OBJ
        are never loaded).
    data : bytes
        Its contents.
    root : Path
        The folder the references must stay in (resolved).

    Returns
    -------
    list of Path
        Buffers, then images, in the order the file lists them; data URIs
        are not files and are left out.
    """
    if path.suffix.lower() not in REFERENCING:
        return []
    doc = _gltf_json(path, data)
    total = 0
    for i, acc in enumerate(_entries(doc, "accessors", path)):
        count = acc.get("count", 0)
        if not isinstance(count, int) or isinstance(count, bool) or count < 0:
            raise AssetError(f"{path}: accessor {i} has count {count!r}; expected a whole number")
        total += count
        if total > MAX_GLTF_ELEMENTS:
            raise AssetError(
                f"{path}: accessor {i} brings the elements its accessors declare to {total}, "
                f"more than the {MAX_GLTF_ELEMENTS} a mesh asset may have"
            )
    files = []
    for key, what in (("buffers", "buffer"), ("images", "image")):
        for i, entry in enumerate(_entries(doc, key, path)):
            uri = entry.get("uri")
            if uri is None or (isinstance(uri, str) and uri.startswith("data:")):
                continue
            files.append(confined_path(root, uri, path, f"{what} {i} URI"))
    return files


class ConfinedResolver:
    """A trimesh resolver serving files from one folder tree, within a byte budget.

    Parameters
    ----------
    root : Path
        The asset's folder (resolved).
    owner : Path
        The mesh file, named in messages.
    budget : Budget
        Shared with the read of the mesh file itself.
    namespace : str
        Sub-folder that relative names start from (trimesh's ``namespaced``);
        confinement is always to ``root``.
    """

    def __init__(self, root: Path, owner: Path, budget: Budget, namespace: str = ""):
        self.root, self.owner, self.budget, self.namespace = root, owner, budget, namespace

    def get(self, name: str) -> bytes:
        base = f"{self.namespace}/{name}" if self.namespace else name
        return self.budget.read(confined_path(self.root, base, self.owner), "mesh asset")

    def __getitem__(self, name: str) -> bytes:
        return self.get(name)

    def __contains__(self, name: str) -> bool:
        try:
            return confined_path(self.root, name, self.owner).is_file()
        except AssetError:
            return False

    def namespaced(self, namespace: str) -> ConfinedResolver:
        joined = f"{self.namespace}/{namespace}" if self.namespace else namespace
        return ConfinedResolver(self.root, self.owner, self.budget, joined)

    def keys(self):
        """Nothing is listed: a loader gets only the files it names."""
        return iter(())

    def write(self, name: str, data) -> None:
        raise AssetError(f"{self.owner}: loading an asset never writes files (asked to write {name!r})")
