"""Bounds on what a mesh asset may ask of the machine.

A mesh file comes from a modder or a download, so it is treated as hostile:
every step that could grow without bound is capped, and an asset beyond a cap
is refused with one line naming the file, what it asks for and the limit.
"""

from __future__ import annotations

from ...core.fileio import MiB

#: Bytes read for one asset: the mesh file plus every file it references
#: (a ``.gltf``'s buffers and images). An OBJ of the largest accepted mesh is
#: about 8 MiB; data URIs count as part of the ``.gltf`` that holds them.
MAX_ASSET_BYTES = 32 * MiB
#: Triangles a surface may have before tetrahedralization. fTetWild takes
#: seconds for the shipped assets (under 600 triangles); an 82,000-triangle
#: sphere took 72 s on the project's 2-core machine (repair: 1 s).
MAX_TRIANGLES = 100_000
#: Elements all accessors of a glTF may declare together (positions, normals,
#: texture coordinates and indices of the largest accepted mesh fit). The loader
#: allocates ``count`` elements even when no buffer backs them, so a few bytes
#: of JSON could otherwise ask for gigabytes.
MAX_GLTF_ELEMENTS = 8 * MAX_TRIANGLES
#: Tetrahedra a baked 3D solid may have (the shipped assets bake to 500-3,000).
#: Its lifted 4D boundary has about 4 times as many tets as a prism and 11 times
#: with the round or taper profile (9 layers), so this caps one lifted asset at
#: about 2 million 4D tets: some 8 ms of slicing per frame on one core.
MAX_TETS = 200_000

#: Largest vertex coordinate of a mesh asset, in its own units: the level format's
#: positions stay within 10 km, and float32 vertices keep millimetres there.
MAX_COORDINATE = 1e4
