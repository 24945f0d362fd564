"""Pin numpy's BLAS kernels, so a replay recorded on one machine replays bit for bit on another.

The simulation multiplies small float64 matrices with numpy (poses, transforms, inverses), and
numpy hands them to OpenBLAS, which picks its kernels by CPU at load time. Its AVX-512 kernels
round some sums differently from its AVX2 and AVX ones (measured: the Armory's replay diverges
at tick 600 under ``OPENBLAS_CORETYPE=SkylakeX`` and not under ``Haswell`` or ``Sandybridge``),
so on a newer CPU every shipped replay would report a divergence although the level is still
won. The AVX2 ("Haswell") kernels run on every x86-64 CPU with AVX2; this module asks for them
before numpy is first imported. A player's own ``OPENBLAS_CORETYPE`` is left alone, and a
process that imported numpy before this package keeps what OpenBLAS chose then.

Whether the CPU has AVX2 is read from ``/proc/cpuinfo``; where that cannot be read (a chroot or
container without ``/proc``), LLVM is asked, as numba asks it (measured: in a Debian 11 root
without ``/proc`` on an AVX-512 machine, the kernels were left unpinned and the Tumbling Hall's
replay diverged at tick 880, a push's ``np.linalg.norm`` one unit in the last place apart).
"""

from __future__ import annotations

import os
import platform
import sys

#: The kernels every shipped replay was recorded with.
CORETYPE = "Haswell"


def _has_avx2(cpuinfo: str) -> bool:
    """Does the CPU run AVX2 code? (``cpuinfo``: Linux's /proc/cpuinfo, read by the caller)"""
    for line in cpuinfo.splitlines():
        if line.startswith("flags"):
            return "avx2" in line.split(":", 1)[-1].split()
    return False


def _llvm_has_avx2() -> bool:
    """Does the CPU run AVX2 code, as LLVM sees it? (llvmlite comes with numba and does not
    import numpy.) False when it cannot tell."""
    try:
        import llvmlite.binding as ll

        return bool(ll.get_host_cpu_features().get("avx2", False))
    except Exception:  # no llvmlite, or a platform it cannot read: leave OpenBLAS its choice
        return False


def pin_kernels(environ=os.environ, cpuinfo_path: str = "/proc/cpuinfo", host_avx2=_llvm_has_avx2) -> str | None:
    """Set ``OPENBLAS_CORETYPE`` to :data:`CORETYPE` where that is safe and still matters.

    ``host_avx2()`` answers for the CPU when ``cpuinfo_path`` cannot be read.

    Returns
    -------
    str or None
        The coretype set, or None when nothing was changed (already set by the player, numpy
        already loaded, not an x86-64 Linux machine, or no AVX2).
    """
    if "OPENBLAS_CORETYPE" in environ or "numpy" in sys.modules:
        return None
    if platform.system() != "Linux" or platform.machine().lower() not in ("x86_64", "amd64"):
        return None
    try:
        with open(cpuinfo_path, encoding="ascii", errors="replace") as f:
            avx2 = _has_avx2(f.read(1 << 16))  # the first CPU's entry is enough
    except OSError:
        avx2 = host_avx2()
    if not avx2:
        return None
    environ["OPENBLAS_CORETYPE"] = CORETYPE
    return CORETYPE
