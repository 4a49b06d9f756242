#!/usr/bin/env python3
"""Measure what the estimator does on each fault-injection log against its clean twin.

    .venv/bin/python scripts/data/measure_faults.py [--replay build/mu_replay] [--real float]
        [--preset default] [--gate] [--only NAME ...] [--json OUT.json]

For every fault of scripts/sim/faults.py: mu_replay on the fault log and on its clean twin
(scenarios/<base>.csv), rows matched by t, then per log
  dmu      max |mu_fault - mu_clean| over rows and wheels, and the time where it occurs;
  dmu_end  the same over the last second (has it recovered?);
  median   the median over fault events (runs of consecutive faulty rows) of the largest
           |dmu| between the event and the next one;
  t_rec    the longest time, over events, from the event's last row until |dmu| <= REC_TOL
           on every wheel up to the next event; "+Nx": N events after which it never got
           back within REC_TOL before the next event (or the end);
  valid    share of (row, wheel) reported valid, fault / clean;
  bad_val  share of valid (row, wheel) with |mu - truth| > 2 sd, fault / clean (valid but
           inconsistent: the dangerous case);
  err_v    max |mu - truth| where valid, fault / clean;
  status   count of each status in the fault log.
--gate additionally runs the float64 reference estimator (scripts/reference, the default
preset: identical to the C double build to 1e-9) with a chi-square gate on the normalised
innovation d^2 = |S_zz^-1 (y - z_hat)|^2 (3 dof; skip the update when d^2 > threshold) at
the 99.9 % and 99 % points, on the fault log and on the clean twin, and reports the same
dmu (against the ungated clean run, so what the gate costs on clean data shows too) and
the number of rejected updates.  The gate is a measurement only: it is not in the library.
--gate-clean counts what the 99.9 % gate rejects on every bundled log (scenarios/*.csv: no
fault at all, so every rejection throws away a real measurement) and exits.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))       # scripts/: sim

from sim import faults  # noqa: E402

REC_TOL = 0.01
CHI2_3 = {"99.9%": 16.266, "99%": 11.345}  # chi-square quantiles, 3 dof
WHEELS = ("fl", "fr", "rl", "rr")


def read_est(path):
    with open(path, encoding="utf-8") as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    h, d = rows[0], np.array(rows[1:], dtype=float)
    col = {n: d[:, i] for i, n in enumerate(h)}
    return dict(t=col["t"], mu=np.stack([col["mu_" + w] for w in WHEELS], 1),
                sd=np.stack([col["sd_" + w] for w in WHEELS], 1),
                valid=np.stack([col["valid_" + w] for w in WHEELS], 1).astype(int),
                status=col["status"].astype(int))


def read_sensor(path):
    with open(path, encoding="utf-8") as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    h, d = rows[0], np.array(rows[1:], dtype=float)
    col = {n: d[:, i] for i, n in enumerate(h)}
    return dict(t=col["t"], truth=np.stack([col["mu_" + w] for w in WHEELS], 1),
                fault=col.get("fault", np.zeros(len(d))))


def replay(replay_bin, sensor, preset, real, out):
    subprocess.run([replay_bin, "--in", sensor, "--out", out, "--preset", preset, "--real", real,
                    "--quiet"], check=True)
    return read_est(out)


def compare(f, est_f, est_c, sen_f, sen_c):
    """The figures of the module docstring for one fault log against its clean twin."""
    key_c = {round(t, 6): i for i, t in enumerate(est_c["t"])}
    idx_f = np.array([i for i, t in enumerate(est_f["t"]) if round(t, 6) in key_c])
    idx_c = np.array([key_c[round(est_f["t"][i], 6)] for i in idx_f])
    t = est_f["t"][idx_f]
    d = np.abs(est_f["mu"][idx_f] - est_c["mu"][idx_c])
    dmax = d.max(axis=1)
    k = int(np.argmax(dmax))
    # events: runs of consecutive fault rows; each is judged up to the next event (or the end)
    frow = np.flatnonzero(sen_f["fault"] > 0)
    events = []
    for i in frow:
        if events and i == events[-1][1] + 1:
            events[-1][1] = i
        else:
            events.append([i, i])
    peaks, recs, never = [], [], 0
    for e, (i0, i1) in enumerate(events):
        t0, t1 = sen_f["t"][i0], sen_f["t"][i1]
        t_next = sen_f["t"][events[e + 1][0]] if e + 1 < len(events) else np.inf
        seg = (t >= t0 - 1e-9) & (t < t_next - 1e-9)
        if not seg.any():
            continue
        peaks.append(float(dmax[seg].max()))
        after = seg & (t > t1 + 1e-9)
        over = np.flatnonzero(after & (dmax > REC_TOL))
        if over.size and over[-1] == np.flatnonzero(after)[-1]:
            never += 1
        elif over.size:
            recs.append(float(t[over[-1]] - t1) + 0.01)
        else:
            recs.append(0.0)
    end = t >= t[-1] - 1.0

    def valid_stats(est, sen):
        v = est["valid"] > 0
        err = np.abs(est["mu"] - sen["truth"])
        incons = v & (err > 2.0 * est["sd"])
        return (float(v.mean()), float(incons.sum() / max(v.sum(), 1)),
                float(err[v].max()) if v.any() else 0.0)

    vf, bf, ef = valid_stats(est_f, sen_f)
    vc, bc, ec = valid_stats(est_c, sen_c)
    st = {str(s): int((est_f["status"] == s).sum()) for s in sorted(set(est_f["status"]))}
    return dict(fault=f.name, base=f.base, file=faults.file_name(f), dmu=float(dmax[k]),
                t_dmu=float(t[k]), dmu_end=float(dmax[end].max()), n_events=len(events),
                peak_median=float(np.median(peaks)) if peaks else 0.0,
                t_rec=max(recs) if recs else 0.0, n_never=never,
                valid=(vf, vc), bad_valid=(bf, bc), err_valid=(ef, ec), status=st)


# ---- chi-square innovation gate on the float64 reference (measurement only) -------------

def gated_run(sensor_path, threshold):
    """The reference default estimator with an innovation gate; returns (est dict, rejected)."""
    from reference import filters, logs, params, trusted

    class GatedSCKF(filters.SCKF):
        rejected = 0

        def measurement_update(self, y, h):
            pts = self.points()
            z_pts = np.asarray(h(pts), dtype=float)
            z_hat = z_pts.mean(axis=1)
            zc = (z_pts - z_hat[:, None]) / self.sqrt_2n
            s_zz = filters.tria(np.hstack([zc, self.s_r]))
            nu = np.linalg.solve(s_zz, np.asarray(y, dtype=float) - z_hat)
            if threshold is not None and float(nu @ nu) > threshold:
                GatedSCKF.rejected += 1
                return None
            return super().measurement_update(y, h)

    log = logs.read_csv_log(sensor_path)
    p = params.resolve(log.meta, None, source=sensor_path, preset="default")
    saved = filters.SCKF
    filters.SCKF = GatedSCKF
    try:
        GatedSCKF.rejected = 0
        res = trusted.run(log, p)
    finally:
        filters.SCKF = saved
    return dict(t=res["t"], mu=res["mu"], sd=res["sd"], valid=res["valid"],
                status=res["status"]), GatedSCKF.rejected


def gate_clean(scenarios):
    """Rejections of the 99.9 % gate on each bundled log (none has a fault)."""
    thr = CHI2_3["99.9%"]
    total = 0
    logs = sorted(f for f in os.listdir(scenarios) if f.endswith(".csv"))
    for i, name in enumerate(logs):
        _, n = gated_run(os.path.join(scenarios, name), thr)
        total += n
        print(f"[{i + 1}/{len(logs)}] {name:36s} rejected {n:4d}", flush=True)
    print(f"99.9 % gate (d^2 > {thr}) on {len(logs)} clean logs: {total} rejected updates")
    return 0


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(HERE))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--replay", default=os.path.join(repo, "build", "mu_replay"))
    ap.add_argument("--scenarios", default=os.path.join(repo, "scenarios"))
    ap.add_argument("--real", default="float", choices=("float", "double"))
    ap.add_argument("--preset", default="default", choices=("default", "paper"))
    ap.add_argument("--gate", action="store_true", help="also measure a chi-square gate")
    ap.add_argument("--gate-clean", action="store_true",
                    help="count the 99.9 %% gate's rejections on every bundled (clean) log")
    ap.add_argument("--only", nargs="+", help="fault file names (or prefixes)")
    ap.add_argument("--json", help="write the results as JSON")
    a = ap.parse_args(argv)
    if a.gate_clean:
        return gate_clean(a.scenarios)
    out = []
    tmp = tempfile.mkdtemp(prefix="faults_")
    sel = [f for f in faults.FAULTS
           if not a.only or any(faults.file_name(f).startswith(o) for o in a.only)]
    print(f"{'fault log':48s} {'dmu':>6s} {'at t':>6s} {'median':>6s} {'dmu_end':>7s} {'t_rec':>8s} "
          f"{'valid f/c':>11s} {'bad_val f/c':>11s} {'err_v f/c':>11s}  statuses")
    for f in sel:
        fpath = os.path.join(a.scenarios, "faults", faults.file_name(f))
        cpath = os.path.join(a.scenarios, f.base + ".csv")
        ef = replay(a.replay, fpath, a.preset, a.real, os.path.join(tmp, "f.csv"))
        ec = replay(a.replay, cpath, a.preset, a.real, os.path.join(tmp, "c.csv"))
        r = compare(f, ef, ec, read_sensor(fpath), read_sensor(cpath))
        rec = f"{r['t_rec']:.2f}" + (f"+{r['n_never']}x" if r["n_never"] else "")
        print(f"{r['file']:48s} {r['dmu']:6.3f} {r['t_dmu']:6.2f} {r['peak_median']:6.3f} {r['dmu_end']:7.3f} {rec:>8s} "
              f"{r['valid'][0]:5.0%}/{r['valid'][1]:4.0%} {r['bad_valid'][0]:5.1%}/{r['bad_valid'][1]:4.1%} "
              f"{r['err_valid'][0]:5.2f}/{r['err_valid'][1]:4.2f}  {r['status']}", flush=True)
        if a.gate:
            r["gate"] = {}
            clean0, _ = gated_run(cpath, None)
            for name, thr in [("off", None)] + list(CHI2_3.items()):
                gf, nf = gated_run(fpath, thr)
                gc, nc = gated_run(cpath, thr)
                sf, sc = read_sensor(fpath), read_sensor(cpath)
                rf = compare(f, gf, clean0, sf, sc)
                rc = compare(f, gc, clean0, sc, sc)
                r["gate"][name] = dict(dmu=rf["dmu"], dmu_end=rf["dmu_end"], t_rec=rf["t_rec"],
                                       rejected_fault=nf, rejected_clean=nc,
                                       clean_dmu=rc["dmu"], valid=rf["valid"],
                                       bad_valid=rf["bad_valid"], err_valid=rf["err_valid"])
                print(f"    gate {name:6s} dmu {rf['dmu']:6.3f} end {rf['dmu_end']:6.3f} "
                      f"t_rec {rf['t_rec']:5.2f}  rejected {nf:4d} (clean twin {nc:3d}, "
                      f"its dmu {rc['dmu']:.3f})  valid {rf['valid'][0]:.0%} "
                      f"bad_val {rf['bad_valid'][0]:.1%} err_v {rf['err_valid'][0]:.2f}", flush=True)
        out.append(r)
    if a.json:
        with open(a.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
