"""Numba's on-disk cache of a package's kernels is dropped when any of its kernel sources changes,
not only the file that defines a kernel (a kernel compiles other files' helpers into itself)."""

from __future__ import annotations

from across_dimensions.core import stale_kernels


def test_cached_kernels_go_when_a_helper_they_compile_in_changes(tmp_path, monkeypatch):
    monkeypatch.setattr(stale_kernels.config, "CACHE_DIR", "")  # numba's default: __pycache__ beside them
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    kernel, helper = pkg / "kernel.py", pkg / "helper.py"
    kernel.write_text("@njit(cache=True)\ndef f(x):\n    return g(x)\n")
    helper.write_text("@njit(inline='always')\ndef g(x):\n    return x\n")
    cached = stale_kernels.cache_dir(kernel)
    cached.mkdir()
    entry = cached / "kernel.f-1.py311.nbi"

    def drop():
        return stale_kernels.drop_stale_kernels(kernel, stale_kernels.sources_digest(pkg.glob("*.py")), "s.sha256")

    entry.write_text("compiled")
    assert drop() and not entry.exists()  # no digest kept yet: they go
    entry.write_text("compiled")
    assert not drop() and entry.exists()  # the same sources: they stay
    (pkg / "plain.py").write_text("X = 1\n")
    assert not drop() and entry.exists()  # a module without kernels is no matter
    helper.write_text("@njit(inline='always')\ndef g(x):\n    return 2 * x\n")
    assert drop() and not entry.exists()  # only the helper changed: they go all the same


def test_the_core_and_the_physics_keep_their_digests_beside_their_caches():
    import across_dimensions.physics  # noqa: F401  (checks its cache on import)

    core = stale_kernels.Path(stale_kernels.__file__).parent
    digests = {
        "core-sources.sha256": stale_kernels.cache_dir(core / "section.py"),
        "physics-sources.sha256": stale_kernels.cache_dir(core.parent / "physics" / "world.py"),
    }
    for name, folder in digests.items():
        assert len((folder / name).read_text()) == 64, name  # written on importing the package
