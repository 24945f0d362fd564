"""Turning 3D mesh files into tetrahedralized solids, one job per module.

The pipeline that :mod:`across_dimensions.world.bake` runs::

    mesh_files   read the file's bytes (bounded, confined) and parse its triangles
    repair       weld, fill small holes, orient outward (trimesh's own repair)
    tetwild      fill the closed surface with tetrahedra (pytetwild, in a child process)
    bake_cache   keep the result on disk, keyed by the bytes it came from
    progress     one status line on a terminal while a bake runs

:mod:`.confine` says which files an asset may reference (its own folder tree
only) and serves them to the loader; :mod:`.limits` holds every bound in one
place; :mod:`.errors` the one exception all of them raise.
"""

from .errors import AssetError
from .limits import MAX_ASSET_BYTES, MAX_TETS, MAX_TRIANGLES

__all__ = ["AssetError", "MAX_ASSET_BYTES", "MAX_TETS", "MAX_TRIANGLES"]
