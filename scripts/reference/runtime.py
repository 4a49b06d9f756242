"""What numerical machinery this process computes with: the BLAS library, the kernel it
picked for this CPU and its thread count (threadpoolctl), and the SIMD paths numpy
dispatches its elementwise functions to (exp, log, arctan, arctan2, tanh differ in the
last bits between them).

Both choices depend on the CPU and on OPENBLAS_CORETYPE / OPENBLAS_NUM_THREADS /
NPY_DISABLE_CPU_FEATURES, so float output of the reference is not byte-identical across
machines. Estimate logs record them (metadata keys ``blas`` and ``numpy_simd``) so a reviewer
can tell a regeneration that is only rounding; comparisons ignore these two keys
(compare.py).
"""

from __future__ import annotations

import numpy as np

RUNTIME_KEYS = ("blas", "numpy_simd")


def _blas_libs() -> list[dict] | None:
    """threadpoolctl's records of the BLAS libraries loaded (None without threadpoolctl)."""
    try:
        import threadpoolctl
    except ImportError:                      # pragma: no cover - pinned in requirements.txt
        return None
    return [i for i in threadpoolctl.threadpool_info() if i.get("user_api") == "blas"]


def blas() -> str:
    """'openblas 0.3.31.188.0 Haswell, 1 thread' (or 'unknown' without threadpoolctl)."""
    libs = _blas_libs()
    if libs is None:                         # pragma: no cover
        return "unknown (threadpoolctl not installed)"
    if not libs:
        return "none found"
    parts = []
    for i in libs:
        n = i.get("num_threads")
        parts.append(f"{i.get('internal_api')} {i.get('version')} {i.get('architecture')}, "
                     f"{n} thread{'' if n == 1 else 's'}")
    return "; ".join(sorted(parts))        # load order varies with the import path


def blas_kernel() -> str:
    """The BLAS kernel name alone (for example 'Haswell'), '' when unknown."""
    libs = _blas_libs()
    return str(libs[0].get("architecture") or "") if libs else ""


def _simd_targets():
    """(baseline, dispatched targets enabled on this CPU), None when numpy hides them."""
    try:
        from numpy._core._multiarray_umath import (__cpu_baseline__, __cpu_dispatch__,
                                                   __cpu_features__)
    except ImportError:                      # pragma: no cover - other numpy layouts
        return None
    return list(__cpu_baseline__), [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]


def numpy_simd() -> str:
    """numpy's SIMD targets in use: the baseline and the dispatched ones enabled on this CPU,
    for example 'X86_V2 + X86_V3 X86_V4 AVX512_ICL'."""
    t = _simd_targets()
    if t is None:                            # pragma: no cover
        return f"numpy {np.__version__}, unknown"
    base, found = t
    return f"{' '.join(base)} + {' '.join(found) if found else 'none'}"


def numpy_dispatched() -> list[str]:
    """The dispatched (non-baseline) SIMD targets numpy enabled here; disabling all of them
    (NPY_DISABLE_CPU_FEATURES) leaves the baseline paths every CPU of the architecture has."""
    t = _simd_targets()
    return t[1] if t else []


def metadata() -> list[tuple[str, str]]:
    """The metadata lines an estimate log carries about its numerical machinery."""
    return [("blas", blas()), ("numpy_simd", numpy_simd())]
