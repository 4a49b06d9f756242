"""Issue 17, docs/MONITOR.md section 18: why a larger vx input sd makes the friction estimate
more wrong on hard_brake_high_mu.mf's ABS release, and one candidate rule, measured with the
float64 reference (scripts/reference/trusted.py, equal to the C double build to 1e-9).

Usage (from the repository root):

    .venv/bin/python scripts/tools/vx_blind_study.py sweep [--log scenarios/hard_brake_high_mu.mf.csv]
    .venv/bin/python scripts/tools/vx_blind_study.py trust [--rule vx-share|ax-anchor]
        [--share 0.5] [--sd-in-vx S] [--jobs 2]

sweep: per sd_in_vx (constant, the parameter file's key) the mean mu error's change over the
release ramp (4.0 -> 4.2 s), the last valid sample, RMSE when valid and valid share (t >= 1 s),
for the preset as it is, three counterfactual updates in 4.065-4.125 s (without the ay and
yaw_acc rows, without the ax row; diag(R) everywhere) and the two candidate rules.
trust: one candidate rule over every bundled log, with the library's trust rules on (as make
trust-invariant), against the preset as it is, as trust_rules_study.verdict.

The candidate rule ("vx-blind ax", reference only): on a step where the vx input's column
g_vx = sd_in_vx dh/dvx holds more than `share` of the ax row's step noise variance
(1 - R0_ax / R_ax, R0 the step noise without that column), the update is skipped: the
longitudinal channel that anchors mu while braking is blinded by the input's uncertainty, and
the ay and yaw-rate rows alone pull mu on a brake's release transient. Skipped = the update
taken with S_R x 1e4 (its gain 1e-8 of the normal one) through trusted.run's adapt hook;
trusted.py is untouched.

Candidate B ("ax-anchored braking update", AxAnchor): on a step with |ax| >= 0.3 g, skip the
update when the ax row alone gives less than info_min of information on every side.
"""
from __future__ import annotations

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # scripts: reference
from reference import logs, monitor, params, trusted  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))
import trust_rules_study as trs  # noqa: E402

SKIP_SCALE = 1e4                    # S_R factor of a skipped update (gain ~1e-8)
SWEEP = (0.01, 0.05, 0.1, 0.15, 0.2, 0.27)
RELEASE = (3.995, 4.195)            # samples 4.00 and 4.20 s: the release ramp
ABLATE = (4.065, 4.125)             # the steps that update during the release (4.07-4.12 s)


def vx_share(p, f, T, u, sd_u, s_r):
    """1 - R0_ax / R_ax: the vx column's share of the ax row's step-noise variance."""
    if sd_u[1] <= 0:
        return 0.0
    sd0 = sd_u.copy()
    sd0[1] = 0.0
    s_r0 = _ORIG_STEP_NOISE(p, f, T, u, sd0)
    r_ax, r0_ax = float(s_r[0] @ s_r[0]), float(s_r0[0] @ s_r0[0])
    return 1.0 - r0_ax / r_ax


_ORIG_STEP_NOISE = trusted._step_noise


class VxBlind:
    """The candidate rule as an adapt hook: installs a step-noise wrapper that records the
    step's vx share; the update's S_R is scaled by SKIP_SCALE where the share > share.
    skipped counts the evaluated steps over the share (the hook runs before the information
    gate, so it includes steps the gate holds anyway)."""

    def __init__(self, share: float):
        self.share, self.last, self.skipped = share, 0.0, 0

    def __enter__(self):
        def wrapped(p, f, T, u, sd_u, persistent=None, reuse=None):
            s_r = _ORIG_STEP_NOISE(p, f, T, u, sd_u, persistent, reuse)
            self.last = vx_share(p, f, T, u, sd_u, s_r)
            return s_r
        trusted._step_noise = wrapped
        return self

    def __exit__(self, *exc):
        trusted._step_noise = _ORIG_STEP_NOISE

    def __call__(self, k, nu, s_zz, zc, s_r, c_pers=None):
        if self.last > self.share:
            self.skipped += 1
            return SKIP_SCALE * s_r
        return s_r


class AxAnchor:
    """Candidate B ("ax-anchored braking update", written before it was measured): on a step
    with |ax| >= AX_HARD (measured ax), skip the update when the ax row alone gives less than
    info_min on every side: I_ax,k = J_ax,k^2 / R_ax,ax, J step 5's statistical linearisation
    at x- (J = P_zx (S S^T)^-1 from the predicted points), R_ax,ax the ax row's step-noise
    variance (its marginal). Same hook as VxBlind; skipped counts the skipped updates' steps
    (where the rule held; the gate may hold some of them anyway)."""

    def __init__(self, info_min: float, ax_hard: float):
        self.info_min, self.ax_hard, self.skipped = info_min, ax_hard, 0
        self.f = self.u = None

    def __enter__(self):
        def wrapped(p, f, T, u, sd_u, persistent=None, reuse=None):
            self.f, self.u = f, np.array(u, copy=True)
            return _ORIG_STEP_NOISE(p, f, T, u, sd_u, persistent, reuse)
        trusted._step_noise = wrapped
        return self

    def __exit__(self, *exc):
        trusted._step_noise = _ORIG_STEP_NOISE

    def info_ax(self, zc, s_r) -> np.ndarray:
        """I_ax per state from the predicted filter (the hook runs before the update)."""
        f = self.f
        xc = (f.points() - f.x[:, None]) / f.sqrt_2n
        r_ax = np.sqrt(np.array([[float(s_r[0] @ s_r[0])]]))
        return trusted._information_of(f, xc, zc[:1], r_ax)

    def __call__(self, k, nu, s_zz, zc, s_r, c_pers=None):
        if abs(self.u[4]) >= self.ax_hard and self.info_ax(zc, s_r).max() < self.info_min:
            self.skipped += 1
            return SKIP_SCALE * s_r
        return s_r


AX_HARD_G = 0.3     # candidate B's hard longitudinal manoeuvre, in g
RULES = ("vx-share", "ax-anchor")


def make_rule(name: str, share: float, p: dict):
    return VxBlind(share) if name == "vx-share" else AxAnchor(p["info_min"], AX_HARD_G * p["g"])


def rows_out(rows, t, window):
    """Counterfactual: the update without the given rows of y (S_R rows x 1e3) in window."""
    def adapt(k, nu, s_zz, zc, s_r, c_pers=None):
        if not window[0] <= t[k] <= window[1]:
            return s_r
        s = s_r.copy()
        s[list(rows), :] *= 1e3
        return s
    return adapt


def diag_r(k, nu, s_zz, zc, s_r, c_pers=None):
    """Counterfactual: the update with diag(R) (no cross-terms between the rows)."""
    return np.diag(np.sqrt(np.einsum("ij,ij->i", s_r, s_r)))


def preset(log, path, sd_in_vx=None, library_rules=True) -> dict:
    p = params.resolve(log.meta, None, source=str(path), preset="default")
    if sd_in_vx is not None:
        p["sd_in_vx"] = sd_in_vx
    if not library_rules:
        p["stale_omega"] = p["valid_bound_k"] = p["yaw_check"] = 0.0
    return p


def run(log, p, adapt=None):
    res = trusted.run(log, p, adapt=adapt)
    return monitor.apply(res, p, p["dt"])


def release_figures(t, truth, res) -> dict:
    """Drop of the mean error over the release, the last valid time after it, RMSE when valid
    and valid share from 1 s on (pooled over the wheels)."""
    e = res["mu"] - truth
    i0, i1 = np.searchsorted(t, RELEASE[0]), np.searchsorted(t, RELEASE[1])
    after, m1 = t >= RELEASE[1], t >= 1.0
    v_after = res["valid"][after].astype(bool).any(axis=1)
    vv = res["valid"][m1].astype(bool)
    return {"drop": float(e[i1].mean() - e[i0].mean()), "err": float(e[i1].mean()),
            "sd": float(res["sd"][i1].mean()),
            "last": float(t[after][v_after].max()) if v_after.any() else float("nan"),
            "rmse": float(np.sqrt(np.mean(e[m1][vv] ** 2))) if vv.any() else float("nan"),
            "valid": float(vv.mean())}


def sweep(path: Path, share: float, sds=SWEEP, rules=("vx-share",)) -> list[str]:
    log = logs.read_csv_log(str(path))
    t = log.col("t")
    truth = np.stack([log.col(f"mu_{w}") for w in trs.WHEELS], 1)
    lines = ["| sd_in_vx [m/s] | variant | μ error change 4.0→4.2 s | error / sd at 4.2 s "
             "| last valid [s] | RMSE when valid (t ≥ 1 s) | valid | steps over the share |",
             "|---|---|---|---|---|---|---|---|"]
    for sd in sds:
        p = preset(log, path, sd)
        variants = [("as is", None), ("no ay, yaw_acc rows 4.07–4.12 s", rows_out((1, 2), t, ABLATE)),
                    ("no ax row 4.07–4.12 s", rows_out((0,), t, ABLATE)),
                    ("diag(R) everywhere", diag_r)]
        for name, adapt in variants:
            lines.append(row(sd, name, release_figures(t, truth, run(log, p, adapt)), None))
        for name in rules:
            with make_rule(name, share, p) as rule:
                fig = release_figures(t, truth, run(log, p, rule))
            label = (f"rule: skip at vx share > {share}" if name == "vx-share"
                     else f"rule B: skip at |ax| >= {AX_HARD_G} g without ax information")
            lines.append(row(sd, label, fig, rule.skipped))
    return lines


def row(sd, name, f, skipped) -> str:
    return (f"| {sd} | {name} | {f['drop']:+.3f} | {f['err']:+.3f} / {f['sd']:.3f} | {f['last']:.2f} "
            f"| {f['rmse']:.4f} | {100 * f['valid']:.1f} % | {'–' if skipped is None else skipped} |")


def _trust_one(args):
    scen, name, share, sd, rule_name = args
    path = scen / f"{name}.csv"
    log = logs.read_csv_log(str(path))
    p = preset(log, path, sd)
    with make_rule(rule_name, share, p) as rule:
        new = run(log, p, rule)
    base = new if rule.skipped == 0 else run(log, p)   # an inert rule leaves the run bit for bit
    keep = ("t", "mu", "sd", "valid", "status")
    return name, {k: base[k] for k in keep}, {k: new[k] for k in keep}, rule.skipped


def trust(scen: Path, share: float, sd, jobs: int, rule: str = "vx-share") -> list[str]:
    names = trs.bundled(scen)
    with ProcessPoolExecutor(jobs) as ex:
        out = list(ex.map(_trust_one, [(scen, n, share, sd, rule) for n in names]))
    base, new, acted = {}, {}, []
    for name, b, r, skipped in out:
        log = logs.read_csv_log(str(scen / f"{name}.csv"))
        truth = np.stack([log.col(f"mu_{w}") for w in trs.WHEELS], 1)
        util = (np.stack([log.col(f"util_{w}") for w in trs.WHEELS], 1)
                if "util_fl" in log.columns else None)
        s = trs.settled(b["t"], truth)
        for dst, rr in ((base, b), (new, r)):
            dst[name] = trs.figures(rr["mu"], rr["sd"], rr["valid"].astype(bool), truth, util, s)
            dst[name]["mismatch"] = float(np.mean(rr["status"] == monitor.STATUS_MISMATCH))
        if skipped:
            acted.append(f"{name} ({skipped})")
    label = (f"vx-blind ax, share > {share}" if rule == "vx-share"
             else f"ax-anchored braking update, |ax| >= {AX_HARD_G} g")
    lines = trs.report(f"{label}, sd_in_vx {sd or 'preset'}", base, new)
    falls = sorted(((base[n]["exc"] - new[n]["exc"], n) for n in base if base[n]["meets"]
                    and base[n]["exc"] is not None and new[n]["exc"] is not None), reverse=True)
    for fall, n in falls:
        if fall > trs.NO_LOSS_MAX:
            lines.append(f"    excited-valid {100 * base[n]['exc']:.1f} -> {100 * new[n]['exc']:.1f} % "
                         f"(RMSE when valid {trs.fmt(base[n]['rmse'])} -> {trs.fmt(new[n]['rmse'])}): {n}")
    lines.append(f"    the rule skipped updates on {len(acted)} of {len(names)} logs: "
                 f"{', '.join(acted) or 'none'}")
    for n in names:
        b, f = base[n], new[n]
        if any(b[k] != f[k] for k in ("valid", "rmse", "worst", "exc")):
            lines.append(f"    {n}: valid {100 * b['valid']:.1f} -> {100 * f['valid']:.1f} %, "
                         f"RMSE {trs.fmt(b['rmse'])} -> {trs.fmt(f['rmse'])}, worst "
                         f"{trs.fmt(b['worst'])} -> {trs.fmt(f['worst'])}, excited-valid "
                         f"{trs.fmt(b['exc'] and 100 * b['exc'], '.1f')} -> "
                         f"{trs.fmt(f['exc'] and 100 * f['exc'], '.1f')}, meets "
                         f"{b['meets']} -> {f['meets']}")
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="issue 17: the vx input sd on a brake's release")
    ap.add_argument("what", choices=("sweep", "trust"))
    ap.add_argument("--log", default="scenarios/hard_brake_high_mu.mf.csv", type=Path)
    ap.add_argument("--scenarios", default="scenarios", type=Path)
    ap.add_argument("--share", default=0.5, type=float)
    ap.add_argument("--sd-in-vx", default=None, type=float, help="trust: default the preset's")
    ap.add_argument("--jobs", default=2, type=int)
    ap.add_argument("--rule", default="vx-share", choices=RULES,
                    help="trust: the rule measured (sweep: both)")
    a = ap.parse_args(argv)
    lines = (sweep(a.log, a.share, rules=RULES) if a.what == "sweep"
             else trust(a.scenarios, a.share, a.sd_in_vx, a.jobs, a.rule))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
