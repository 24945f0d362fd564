"""Matrices as OpenGL takes them, and the view frustum's planes (shared by the scene and the radar)."""

from __future__ import annotations

import numpy as np


def mat4_bytes(m: np.ndarray) -> bytes:
    """A ``(4, 4)`` matrix as the 64 bytes of a GLSL ``mat4`` uniform."""
    # GLSL matrices are column-major; numpy's are row-major.
    return np.ascontiguousarray(np.asarray(m, np.float64).T, np.float32).tobytes()


def frustum_planes(view_proj: np.ndarray) -> np.ndarray:
    """The six clip planes of ``view_proj`` as ``(6, 4) float64`` rows ``(n, d)``, |n| = 1.

    A point ``p`` is inside when ``n . p + d >= 0`` for all six (Gribb & Hartmann).
    """
    m = np.asarray(view_proj, np.float64)
    planes = np.array([m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2], m[3] - m[2]])
    return planes / np.maximum(np.linalg.norm(planes[:, :3], axis=1, keepdims=True), 1e-300)
