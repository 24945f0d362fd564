"""The 4D projection core: transforms, tetrahedral meshes, cross-section and
frustum projection, shapes. Depends on numpy and numba only.

>>> from across_dimensions.core import shapes, cross_section, transform
>>> cube = cross_section(shapes.tesseract())          # the unit cube at w = 0
"""

from .stale_kernels import drop_stale_core_kernels

# Before any kernel is loaded from the on-disk cache (see stale_kernels for why).
drop_stale_core_kernels()

from .frustum import frustum_project, frustum_project_reference  # noqa: E402
from .mesh import MeshError, TetMesh4, TriMesh3, cross4  # noqa: E402
from .section import cross_section, cross_section_reference  # noqa: E402

__all__ = [
    "MeshError",
    "TetMesh4",
    "TriMesh3",
    "cross4",
    "cross_section",
    "cross_section_reference",
    "frustum_project",
    "frustum_project_reference",
]
