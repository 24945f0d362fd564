"""Across Dimensions: a hybrid 3D/4D first-person game and its 4D projection core.

Packages, lowest first: ``core`` (4D maths and projection; numpy and numba
only), ``physics``, ``world`` (levels, scenes, assets), ``game`` (the
simulation), ``render`` (the only user of moderngl) and ``app`` (the only user
of pyglet: window, input, command line).
"""

from ._blas import pin_kernels

__version__ = "0.1.0"

# Before anything imports numpy: the same BLAS kernels on every machine, so replays agree.
pin_kernels()
