"""Generate the golden estimate logs the C tests compare against (reference estimator).

Usage (from the repository root):

    .venv/bin/python scripts/data/make_goldens.py [--scenarios scenarios] [--out scenarios/golden]

For every sensor log <scenarios>/<name>.csv and <name>.nf.csv (files containing ".mf" are
skipped, as are files in sub-directories) it writes, with stem = file name without ".csv":
    <out>/<stem>.paper.sckf.csv and <out>/<stem>.paper.ckf.csv
and for the noisy <name>.csv (not *.nf.csv) also
    <out>/<stem>.absolute.sckf.csv  (paper preset, absolute tyre)
    <out>/<stem>.default.sckf.csv   (default preset, docs/ESTIMATOR.md)
Parameters: defaults < the log's metadata (scripts/reference/params.py).  Deterministic:
running it twice writes identical bytes.
"""

from __future__ import annotations

import os

# Pin BLAS threading before numpy is imported (determinism; matrices are tiny anyway).
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)
from reference import estimate  # noqa: E402


def jobs_for(name: str):
    """(preset, tyre, filter, file tag) per sensor-log file name, or [] if it is skipped.
    The paper preset with its own tyre and with the absolute tyre; the default preset
    (docs/ESTIMATOR.md) on the noisy logs."""
    if not name.endswith(".csv") or ".mf" in name:
        return []
    jobs = [("paper", "paper", "sckf", "paper.sckf"), ("paper", "paper", "ckf", "paper.ckf")]
    if not name.endswith(".nf.csv"):
        jobs.append(("paper", "absolute", "sckf", "absolute.sckf"))
        jobs.append(("default", None, "sckf", "default.sckf"))
    return jobs


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="write golden estimate logs")
    ap.add_argument("--scenarios", default="scenarios", help="directory of sensor logs")
    ap.add_argument("--out", default=os.path.join("scenarios", "golden"))
    a = ap.parse_args(argv)

    names = sorted(f for f in os.listdir(a.scenarios)
                   if os.path.isfile(os.path.join(a.scenarios, f)) and jobs_for(f))
    if not names:
        print(f"make_goldens: no sensor logs in {a.scenarios}", file=sys.stderr)
        return 1
    os.makedirs(a.out, exist_ok=True)
    t_all = time.perf_counter()
    for name in names:
        stem = name[: -len(".csv")]
        src = os.path.join(a.scenarios, name)
        t0 = time.perf_counter()
        outs = []
        for preset, tyre, kind, tag in jobs_for(name):
            out = os.path.join(a.out, f"{stem}.{tag}.csv")
            estimate.estimate_file(src, out, None, kind, tyre, preset)
            outs.append(os.path.basename(out))
        print(f"{name}: {', '.join(outs)} ({time.perf_counter() - t0:.2f} s)", flush=True)
    print(f"make_goldens: {len(names)} logs in {time.perf_counter() - t_all:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
