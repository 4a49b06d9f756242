"""Generate the golden trajectories of the velocity observer (docs/OBSERVER.md) with the
float64 reference (scripts/reference/observer.py), for the C tests to compare against.

Usage (from the repository root):

    .venv/bin/python scripts/data/make_observer_goldens.py [--scenarios scenarios ...] \
        [--out scenarios/golden/observer] [--lat-every N] [--only name.csv ...]

For every noisy sensor log <dir>/<name>.csv of each --scenarios folder (not *.nf.csv, not
*.mf.csv, not sub-folders) it writes <out>/<name>.csv: t and the observer's outputs
(reference.observer.OUTPUTS). The configuration is written into the file's metadata:
the friction estimator's default preset for vehicle and tyre, the log's metadata over it,
the observer's defaults, and as friction input the log's truth mu_* columns with sd
MU_SD (no friction input when the log has none). Deterministic: running it twice writes
identical bytes (plain Python floats, no BLAS on the observer's path).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

sys.path[:0] = [os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]
import numpy as np  # noqa: E402

from reference import logs, observer, params  # noqa: E402

MU_SD = 0.05
WHEELS = ("fl", "fr", "rl", "rr")


def logs_in(folder):
    return sorted(os.path.join(folder, f) for f in os.listdir(folder)
                  if f.endswith(".csv") and not f.endswith(".nf.csv") and ".mf." not in f
                  and os.path.isfile(os.path.join(folder, f)))


def golden(path, lat_every=None, out_floor=None):
    """(metadata pairs, column names, rows) of one log's golden, the model's rows every
    lat_every-th step (OBSERVER.md §4.2; None: the observer's default), the reported sd(vy)'s
    floor at obs_vy_out_floor_mu = out_floor (§5; None: the default, 4)."""
    log = logs.read_csv_log(path, required=("t", "delta", "yaw_rate", "ax", "ay")
                            + tuple("omega_" + w for w in WHEELS))
    c = log.columns
    rate = {} if lat_every is None else {"obs_lat_every": float(lat_every)}
    if out_floor is not None:
        rate["obs_vy_out_floor_mu"] = float(out_floor)
    p = observer.params_with_defaults(params.from_metadata(log.meta), **rate)
    truth = all("mu_" + w in c for w in WHEELS)
    mu = ([c["mu_" + w] for w in WHEELS], [np.full(len(c["t"]), MU_SD)] * 4) if truth else None
    out = observer.run(c, p, mu)
    meta = [("source", os.path.basename(path)), ("generator", "scripts/reference/observer.py"),
            ("mu_input", f"truth columns, sd {MU_SD!r}" if truth else "none")]
    meta += [(k, p[k]) for k in sorted(observer.OBS_DEFAULTS)] + [("tyre", p["tyre"])]
    cols = ("t",) + observer.OUTPUTS
    rows = zip(c["t"], *(out[k] for k in observer.OUTPUTS))
    return meta, cols, rows


def write(path, meta, cols, rows):
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        for k, v in meta:
            fh.write(f"# {k} = {v!r}\n" if isinstance(v, float) else f"# {k} = {v}\n")
        fh.write(",".join(cols) + "\n")
        for row in rows:
            fh.write(",".join(repr(float(v)) for v in row) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenarios", action="append", default=None)
    ap.add_argument("--out", default=os.path.join("scenarios", "golden", "observer"))
    ap.add_argument("--lat-every", type=int, default=None,
                    help="obs_lat_every of the goldens (OBSERVER.md §4.2; default: the "
                         "observer's default, OBS_DEFAULTS)")
    ap.add_argument("--vy-out-floor-mu", type=float, default=None,
                    help="obs_vy_out_floor_mu of the goldens (OBSERVER.md §5; default: the "
                         "observer's default, 4; 0 is off)")
    ap.add_argument("--only", nargs="+", default=None,
                    help="only these logs (file names) of the --scenarios folders")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    files = [f for d in (a.scenarios or ["scenarios"]) for f in logs_in(d)
             if a.only is None or os.path.basename(f) in a.only]
    t0 = time.time()
    for i, f in enumerate(files, 1):
        write(os.path.join(a.out, os.path.basename(f)), *golden(f, a.lat_every, a.vy_out_floor_mu))
        print(f"[{i}/{len(files)}] {os.path.basename(f)} ({time.time() - t0:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
