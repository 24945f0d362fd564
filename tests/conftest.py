"""Shared fixtures: one offscreen OpenGL context, golden-image comparison."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

GOLDEN_DIR = Path(__file__).parent / "golden"


@pytest.fixture(scope="session")
def gl_ctx():
    """One standalone EGL context for the session (skips when EGL is unavailable)."""
    from across_dimensions.render.context import RenderError, create_offscreen_context

    try:
        ctx = create_offscreen_context()
    except RenderError as e:
        pytest.skip(f"no OpenGL context through EGL: {e}")
    yield ctx
    ctx.release()


@pytest.fixture
def compare_golden(tmp_path):
    """``compare_golden(name, image)`` against ``tests/golden/<name>.png``.

    Tolerant to llvmpipe rounding: fails when the mean absolute difference is
    2/255 or more, or 1% of pixels differ by more than 32/255. With
    ``REGENERATE_GOLDEN=1`` (or when the file is missing) it writes the image
    and skips, asking for a look before committing.
    """
    from across_dimensions.render.png import read_png, write_png

    def compare(name: str, img: np.ndarray) -> None:
        path = GOLDEN_DIR / f"{name}.png"
        if os.environ.get("REGENERATE_GOLDEN") == "1" or not path.exists():
            GOLDEN_DIR.mkdir(parents=True, exist_ok=True)
            write_png(path, img)
            pytest.skip(f"wrote golden image {path}; check it by eye and commit it")
        want = read_png(path)
        assert want.shape == img.shape, f"golden {path} is {want.shape}, rendered {img.shape}"
        diff = np.abs(want.astype(int) - img.astype(int))
        mean = diff.mean()
        bad = (diff.max(axis=2) > 32).mean()
        if mean >= 2.0 or bad >= 0.01:
            write_png(tmp_path / f"{name}_actual.png", img)
            write_png(tmp_path / f"{name}_diff.png", np.clip(diff * 4, 0, 255).astype(np.uint8))
            pytest.fail(
                f"{name}: mean abs diff {mean:.2f}/255 (limit 2), {bad:.2%} pixels off by > 32 (limit 1%); "
                f"actual and diff images in {tmp_path}; if the change is intended rerun with REGENERATE_GOLDEN=1"
            )

    return compare
