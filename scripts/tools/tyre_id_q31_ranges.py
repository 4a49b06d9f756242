#!/usr/bin/env python3
"""What a fixed-point (Q31) twin of the tyre identifier would have to hold, measured with the
float64 reference (scripts/reference/tyre_id.py, docs/TYRE_ID.md) on the bundled logs.

    .venv/bin/python scripts/tools/tyre_id_q31_ranges.py [--n 256] [--filter apf]
        [--only NAME ...] [--page docs/FIXED_POINT.md]

The reference runs unchanged; an instrumented subclass records, at every step of every log
(scenarios/tyre_id/*.csv, seed 1, the defaults): the per-particle log-likelihoods and the
log weights entering each log-sum-exp normalisation (their spread max - min within the step,
and how many particles fall below what exp rounds to zero in Q31, ln 2^-31 = -21.49); the
weights of the parents each draw picks (the smallest one that survives) and the decision
margins of each draw (the distance of each draw position to the nearest cumulative-weight
boundary, relative to the sum; N_eff's distance to the threshold N/3 and to the nearest
integer, which fix how many particles are kept); the range of each state and parameter over
the particles (B = K/(C D) included); the model's intermediates (the RK4 stages' states and
derivatives, the axle forces, x = B tan(alpha) under the Magic Formula's atan, and the
likelihood's residuals and variance). Prints the table and, with --page, writes it between
<!-- tyre-id-q31:begin/end --> of the page.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(ROOT / "scripts" / "tools"))
from md_tables import replace_region  # noqa: E402
from reference import tyre_id as T  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402

# every tyre identification log, read from the folder (a log added there is measured too)
LOGS = tuple(sorted(p.stem for p in (ROOT / "scenarios" / "tyre_id").glob("*.csv")))
LN_Q31 = -31.0 * math.log(2.0)    # exp(l - M) below this rounds to 0 in Q31 (2^-31 = 1 LSB)
BEGIN, END = "<!-- tyre-id-q31:begin -->", "<!-- tyre-id-q31:end -->"


class Ranges:
    """min and max of named quantities (finite values only), and counters."""

    def __init__(self):
        self.lo, self.hi = {}, {}

    def add(self, name, v):
        v = np.asarray(v, dtype=float).ravel()
        v = v[np.isfinite(v)]
        if v.size == 0:
            return
        lo, hi = float(v.min()), float(v.max())
        self.lo[name] = min(self.lo.get(name, lo), lo)
        self.hi[name] = max(self.hi.get(name, hi), hi)

    def merge(self, other):
        for k in other.lo:
            self.add(k, [other.lo[k], other.hi[k]])


class Probe(T.TyreId):
    """The reference identifier with its intermediates recorded (nothing it computes changes)."""

    def __init__(self, params, seed=None):
        super().__init__(params, seed)
        self.rg = Ranges()
        self.stats = {"steps": 0, "norms": 0, "below_q31": 0, "norms_with_below": 0,
                      "particles": 0, "neg_inf": 0, "draws": 0, "positions": 0,
                      "min_parent_w": math.inf, "min_gap": math.inf,
                      "min_neff_thr_gap": math.inf, "min_neff_int_gap": math.inf,
                      "max_spread": 0.0, "gaps_below_2^-23": 0, "gaps_below_2^-14": 0,
                      "neff_int_below_1e-3": 0}
        rg, model = self.rg, self.model
        forces, rhs = model.forces, model.rhs

        def rec_forces(vy, r, th, delta, vx, ax=0.0):
            t_f, t_r = model.slips(vy, r, delta, vx)
            rg.add("tan alpha (per axle)", np.concatenate([t_f, t_r]))
            rg.add("x = B tan alpha",
                   np.concatenate([T.b_of(th, 0) * t_f, T.b_of(th, 4) * t_r]))
            f, rr = forces(vy, r, th, delta, vx, ax)
            rg.add("Fy_f, Fy_r (N)", np.concatenate([f, rr]))
            return f, rr

        def rec_rhs(vy, r, th, delta, cd, vx, ax=0.0):
            rg.add("RK4 stage vy (m/s)", vy)
            rg.add("RK4 stage r (rad/s)", r)
            dvy, dr = rhs(vy, r, th, delta, cd, vx, ax)
            rg.add("RK4 k: vy' (m/s^2)", dvy)
            rg.add("RK4 k: r' (rad/s^2)", dr)
            return dvy, dr

        model.forces, model.rhs = rec_forces, rec_rhs

    def _loglik(self, vy, r, th, s, cd, sd_):
        ll = super()._loglik(vy, r, th, s, cd, sd_)
        p = self.p
        self.rg.add("log-likelihood l (per particle)", ll)
        self.rg.add("e1 = (r_m - r)/sd_r", (s["yaw_rate"] - r) / p["tid_sd_r"])
        f, rr = self.model.forces(vy, r, th, s["delta"], s["vx"], s["ax"])
        self.rg.add("e2 = ay_m - ay_p (m/s^2)", s["ay"] - ((f * cd) + rr) / p["m"])
        self.stats["particles"] += ll.size
        self.stats["neg_inf"] += int(np.sum(~np.isfinite(ll)))
        return ll

    def note_norm(self, logw):
        """One log-sum-exp normalisation's input."""
        fin = logw[np.isfinite(logw)]
        if fin.size == 0:
            return
        d = fin - fin.max()
        self.rg.add("log weight minus max (l - M)", d)
        st = self.stats
        st["norms"] += 1
        st["max_spread"] = max(st["max_spread"], float(-d.min()))
        below = int(np.sum(d < LN_Q31))
        st["below_q31"] += below
        st["norms_with_below"] += below > 0

    def _draw(self, w, purpose, m, scheme):
        idx = super()._draw(w, purpose, m, scheme)
        st = self.stats
        cum = np.cumsum(w)
        s = cum[-1]
        # the positions the draw compared, recomputed from the same uniforms (§5.3)
        if scheme == "systematic":
            u0 = self.stream.uniforms(self.k, purpose, 1)[0]
            x = (np.arange(m, dtype=np.float64) + u0) * (s / m)
        else:
            x = self.stream.uniforms(self.k, purpose, m) * s
        gaps = np.abs(x[:, None] - np.concatenate([[0.0], cum])[None, :]).min(axis=1) / s
        st["draws"] += 1
        st["positions"] += m
        st["min_gap"] = min(st["min_gap"], float(gaps.min()))
        st["gaps_below_2^-23"] += int(np.sum(gaps < 2.0 ** -23))
        st["gaps_below_2^-14"] += int(np.sum(gaps < 2.0 ** -14))
        st["min_parent_w"] = min(st["min_parent_w"], float((w[idx] / s).min()))
        n_eff = 1.0 / np.cumsum((w / s) * (w / s))[-1]
        st["min_neff_thr_gap"] = min(st["min_neff_thr_gap"],
                                     abs(n_eff - self.p["tid_neff_frac"] * self.n))
        st["min_neff_int_gap"] = min(st["min_neff_int_gap"], abs(n_eff - round(n_eff)))
        st["neff_int_below_1e-3"] += abs(n_eff - round(n_eff)) < 1e-3
        return idx

    def step(self, s):
        e = super().step(s)
        self.stats["steps"] += 1
        rg = self.rg
        rg.add("vy (m/s)", self.x[:, 0])
        rg.add("r (rad/s)", self.x[:, 1])
        for j, k in enumerate(T.PARAM_NAMES):
            rg.add(k, self.th[:, j])
        rg.add("B_f (1/rad)", T.b_of(self.th, 0))
        rg.add("B_r (1/rad)", T.b_of(self.th, 4))
        return e


def measure(log, n=256, filt="apf", n_steps=None, seed=1):
    """Run the instrumented reference on one log; (Ranges, stats, run output)."""
    c = read_csv_log(str(ROOT / "scenarios" / "tyre_id" / f"{log}.csv")).columns
    params = {"tid_n": float(n), "tid_filter": filt}
    probe = Probe(params, seed)
    norm = T.normalise_log

    def rec_norm(logw, fn=T.NUMPY):
        probe.note_norm(logw)
        return norm(logw, fn)

    T.normalise_log = rec_norm      # _update looks it up in the module: restored below
    try:
        k = len(c["t"]) if n_steps is None else n_steps
        cols = [np.asarray(c[key], dtype=float) for key in T.SAMPLE_KEYS]
        est = [probe.step({key: float(col[i]) for key, col in zip(T.SAMPLE_KEYS, cols)})
               for i in range(k)]
    finally:
        T.normalise_log = norm
    return probe.rg, probe.stats, est


def int_bits(lo, hi):
    """Integer bits (sign excluded) an int32 needs to hold [lo, hi]: ceil(log2 max|v|)."""
    m = max(abs(lo), abs(hi))
    return max(0, math.ceil(math.log2(m))) if m > 0 else 0


def table(rg, stats, n, filt, logs):
    out = [f"Measured by `scripts/tools/tyre_id_q31_ranges.py` (the float64 reference, "
           f"{filt.upper()}, {n} particles, seed 1, the defaults; every sample of "
           f"{len(logs)} logs: "
           f"{', '.join('`' + g + '`' for g in logs)}). Integer bits: what an int32 needs "
           "above the binary point for the range (sign excluded); the fraction bits left are "
           "31 minus that.", "",
           "| quantity | min | max | integer bits | resolution of int32 at that range |",
           "|---|---|---|---|---|"]
    for k in rg.lo:
        b = int_bits(rg.lo[k], rg.hi[k])
        out.append(f"| {k} | {rg.lo[k]:.4g} | {rg.hi[k]:.4g} | {b} | {2.0 ** (b - 31):.2g} |")
    st = stats
    out += ["",
            "| weights and resampling | value |", "|---|---|",
            f"| steps; log-sum-exp normalisations | {st['steps']}; {st['norms']} |",
            f"| largest spread max − min of the log weights in one normalisation | "
            f"{st['max_spread']:.4g} (Q31's exp resolves {-LN_Q31:.2f}) |",
            f"| normalisations with a particle below exp's Q31 range; such particles | "
            f"{st['norms_with_below']} "
            f"({100.0 * st['norms_with_below'] / max(st['norms'], 1):.1f} %); "
            f"{st['below_q31']} |",
            f"| particle likelihoods −∞ (non-finite) | {st['neg_inf']} of {st['particles']} |",
            f"| draws; positions drawn | {st['draws']}; {st['positions']} |",
            f"| smallest normalised weight of a drawn parent | {st['min_parent_w']:.3g} "
            f"(2^{math.log2(st['min_parent_w']):.1f}) |",
            f"| smallest distance of a draw position to a cumulative-weight boundary, / S | "
            f"{st['min_gap']:.3g} (2^{math.log2(st['min_gap']):.1f}) |",
            f"| draw positions within 2^-23 (N·2^-31 at N = 256) of a boundary; within 2^-14 | "
            f"{st['gaps_below_2^-23']}; {st['gaps_below_2^-14']} |",
            f"| smallest distance of N_eff to the threshold N/3 at a draw | "
            f"{st['min_neff_thr_gap']:.3g} |",
            f"| smallest distance of N_eff to an integer at a draw (fixes how many are kept) | "
            f"{st['min_neff_int_gap']:.3g} (draws within 1e-3: {st['neff_int_below_1e-3']}) |"]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--filter", default="apf", choices=("apf", "sir"))
    ap.add_argument("--only", nargs="*", default=None)
    ap.add_argument("--page", type=Path, default=None)
    a = ap.parse_args(argv)
    logs = tuple(a.only) if a.only else LOGS
    rg, stats = Ranges(), None
    for log in logs:
        r, s, _ = measure(log, a.n, a.filter)
        rg.merge(r)
        if stats is None:
            stats = dict(s)
        else:
            for k, v in s.items():
                stats[k] = (min(stats[k], v) if k.startswith("min_") else
                            max(stats[k], v) if k.startswith("max_") else stats[k] + v)
        print(f"{log}: spread {s['max_spread']:.1f}, min parent w {s['min_parent_w']:.3g}, "
              f"min gap {s['min_gap']:.3g}", file=sys.stderr)
    lines = table(rg, stats, a.n, a.filter, logs)
    print("\n".join(lines))
    if a.page:
        replace_region(a.page, BEGIN, END, lines, "tyre_id_q31_ranges.py")


if __name__ == "__main__":
    main()
