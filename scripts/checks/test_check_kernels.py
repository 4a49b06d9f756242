"""Tests of the plan of scripts/checks/check_kernels.py: which configurations run on a CPU
with given flags and architecture, and which are skipped with a reason. The probes run for
real (a short python process each); the CPU's flags and architecture are made up, so a
kernel this CPU has can still be shown skipped."""

import os
import sys

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__))]

import check_kernels  # noqa: E402

SUBSET = ["brake_in_turn.csv", "paper_mu_step.nf.csv"]


def _names(runs):
    return [r["name"] for r in runs]


# REQ-REF-004
def test_a_cpu_without_avx_skips_the_newer_kernels():
    """Only SSE3: the generic Prescott run happens (it differs from as-is in numpy's paths at
    least), Haswell and SkylakeX are skipped for the missing instructions, never forced."""
    runs, skipped = check_kernels.plan(dict(os.environ), {"pni"}, "x86_64", SUBSET)
    assert _names(runs)[0] == "as-is" and "generic" in _names(runs)
    # one walk over every golden, the generic one; as-is runs the subset
    assert runs[0]["logs"] == SUBSET and [r["logs"] for r in runs if r["name"] == "generic"] == ["all"]
    assert "Haswell" not in _names(runs) and "SkylakeX" not in _names(runs)
    why = dict(skipped)
    assert why["Haswell"] == "the CPU lacks avx2, fma"
    assert why["SkylakeX"].startswith("the CPU lacks avx512bw")
    assert runs[-1]["name"] == "threads" and runs[-1]["logs"] == SUBSET[:1]
    assert runs[-1]["env"]["OPENBLAS_THREAD_TIMEOUT"] == "4"     # sleeps, does not spin


# REQ-REF-004
def test_an_unknown_architecture_still_varies_numpy():
    runs, skipped = check_kernels.plan(dict(os.environ), set(), "riscv64", SUBSET)
    why = dict(skipped)
    assert "no OpenBLAS kernel list for architecture 'riscv64'" in why["BLAS kernels"]
    assert _names(runs)[0] == "as-is"
    generic = [r for r in runs if r["name"] == "generic"]
    if runs[0]["probe"]["dispatched"]:      # numpy has SIMD paths to turn off here
        assert generic and generic[0]["env"]["NPY_DISABLE_CPU_FEATURES"]
        assert runs[0]["logs"] == SUBSET and generic[0]["logs"] == "all"
    else:
        # no second configuration: as-is is then the walk over every golden
        assert "generic" in why and runs[0]["logs"] == "all"


# REQ-REF-004
def test_env_for_forces_only_what_it_is_asked():
    base = {"OPENBLAS_CORETYPE": "Haswell", "OPENBLAS_NUM_THREADS": "8", "X": "1"}
    e = check_kernels.env_for(base, None, "1", None)
    assert e["OPENBLAS_CORETYPE"] == "Haswell" and e["OPENBLAS_NUM_THREADS"] == "1" and e["X"] == "1"
    e = check_kernels.env_for(base, "Prescott", "2", ["X86_V3"])
    assert e["OPENBLAS_CORETYPE"] == "Prescott" and e["OMP_NUM_THREADS"] == "2"
    assert e["NPY_DISABLE_CPU_FEATURES"] == "X86_V3"
    assert "NPY_DISABLE_CPU_FEATURES" not in check_kernels.env_for(
        {"NPY_DISABLE_CPU_FEATURES": "AVX512F"}, None, "1", [])
