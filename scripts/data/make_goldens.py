"""Generate the golden estimate logs the C tests compare against (reference estimator).

Usage (from the repository root):

    .venv/bin/python scripts/data/make_goldens.py [--scenarios scenarios] [--out scenarios/golden]

For every sensor log <scenarios>/<name>.csv and <name>.nf.csv (files containing ".mf" are
skipped, as are files in sub-directories) it writes, with stem = file name without ".csv":
    <out>/<stem>.paper.sckf.csv and <out>/<stem>.paper.ckf.csv
and for the noisy <name>.csv (not *.nf.csv) also
    <out>/<stem>.absolute.sckf.csv  (paper preset, absolute tyre)
    <out>/<stem>.default.sckf.csv   (default preset, docs/ESTIMATOR.md, monitor on)
and, for the model-validity monitor (docs/MONITOR.md), for every noisy Magic Formula log
<name>.mf.csv and every fault log <scenarios>/faults/*.csv whose samples the library accepts
(sim/faults.py REFUSED_BY_LIBRARY)
    <out>/monitor/<stem>.monitor.sckf.csv  (default preset, whose mon_enable is 1)
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
from sim import faults as fault_defs  # noqa: E402


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


def monitor_logs(scenarios: str) -> list[str]:
    """The logs of the monitor goldens: the noisy Magic Formula logs and the fault logs."""
    mf = [os.path.join(scenarios, f) for f in sorted(os.listdir(scenarios))
          if f.endswith(".mf.csv") and not f.endswith(".nf.mf.csv") and ".nf." not in f]
    faults = os.path.join(scenarios, "faults")
    fl = ([os.path.join(faults, f) for f in sorted(os.listdir(faults))
           if f.endswith(".csv") and not f.startswith(fault_defs.REFUSED_BY_LIBRARY)]
          if os.path.isdir(faults) else [])
    return mf + fl


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
    mon_out = os.path.join(a.out, "monitor")
    os.makedirs(mon_out, exist_ok=True)
    mon_logs = monitor_logs(a.scenarios)
    for k, src in enumerate(mon_logs, 1):
        stem = os.path.basename(src)[: -len(".csv")]
        t0 = time.perf_counter()
        out = os.path.join(mon_out, f"{stem}.monitor.sckf.csv")
        estimate.estimate_file(src, out, None, "sckf", None, "default")
        print(f"[{k}/{len(mon_logs)}] {os.path.basename(out)} ({time.perf_counter() - t0:.2f} s)",
              flush=True)
    print(f"make_goldens: {len(names)} logs, {len(mon_logs)} monitor logs in "
          f"{time.perf_counter() - t_all:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
