"""Issue 17 (docs/MONITOR.md section 23): what makes the measurement's residual at the TRUE mu
large at a log's first updates, in the float64 reference only.

Usage (from the repository root; CLEAN holds the noise-free twins, made by
`scripts/data/make_scenarios.py --out CLEAN --only NAME... --tyre mf --noise none`):

    .venv/bin/python scripts/tools/first_update_noise.py --clean CLEAN [--updates 2] LOG ...

Runs LOG as exact_update.py does (the default preset, the library's three trust rules,
relin_steps 1: today's update bit for bit) and, at each of its first --updates updates, takes
the step's inputs u (after the yaw check and the input conditioner), y and step 4's S_R. With
the truth's mu per wheel (mu_*) and the noise-free twin's inputs and measurement at the same
sample it prints, per row (ax, ay, yaw acc):
  - e = y - h(u, mu_true), and e with each input replaced by its noise-free value one at a
    time (delta, vx, vy, r, ax and ay as load inputs, the four omegas) and with y replaced by
    the twin's (the sensor's noise); "shape": y_clean - h(u_clean, mu_true), the model's own
    error at the truth (E_y 0 against the truth's -1, section 20);
  - the NIS |S_R^-1 e|^2 of each;
  - R's terms (sd per row): the sensor's r, r_model_rel |h(T x-)|, the input columns g_j at
    x- (step 4's), and the realised error of each term: the sensor's y - y_clean, the input's
    h(u) - h(u with u_j clean) at x-, the model's shape error; the inputs' realised error in
    their own sd (u_j - u_j,clean) / sd_in_j;
  - the conditioner: vx, vy used, noise-free, raw measured, the steps since it started.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.linalg import solve_triangular

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # scripts: reference
from reference import logs, trusted  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))        # tools
import trust_rules_study as trs  # noqa: E402
import exact_update  # noqa: E402

INPUTS = ("delta", "vx", "vy", "r", "ax_in", "ay_in", "w_fl", "w_fr", "w_rl", "w_rr")
COLS = ("delta", "vx", "vy", "yaw_rate", "ax", "ay")


def conditioner_sd(k: int, tau: float, dt: float, sd_v: float, sd_a: float) -> float:
    """The sd of the input conditioner's vx (or vy) error k steps after its start, from its
    recursion alone: e_0 = n_v (the first raw sample), e_k = (1 - b)(e_{k-1} + dt n_a) + b n_v
    with b = dt / (tau + dt), n_v ~ N(0, sd_v^2) the speed's and n_a ~ N(0, sd_a^2) the
    accelerometer's white noise (the r-coupling term neglected)."""
    b = dt / (tau + dt) if tau > 0 else 1.0
    var = sd_v ** 2
    for _ in range(k):
        var = (1.0 - b) ** 2 * (var + (dt * sd_a) ** 2) + (b * sd_v) ** 2
    return float(np.sqrt(var))


def clean_name(name: str) -> str:
    return name + ".nf"     # make_scenarios.file_name: NAME.mf.nf.csv


def breakdown(p, u, u_c, y, y_c, mu_t, x_w, s_r, sd_u):
    """The per-row residual at mu_t and its parts (see the module doc); arrays (3,)."""
    h = lambda uu, mu: trusted.h_point(p, uu, mu)   # noqa: E731
    e = y - h(u, mu_t)
    nis = lambda v: float(np.sum(solve_triangular(s_r, v, lower=True) ** 2))  # noqa: E731
    rows = {"e": (e, nis(e))}
    for j, lab in enumerate(INPUTS):
        uj = u.copy()
        uj[j] = u_c[j]
        ej = y - h(uj, mu_t)
        rows[f"clean {lab}"] = (ej, nis(ej))
    rows["clean omega"] = (y - h(np.r_[u[:6], u_c[6:]], mu_t),
                           nis(y - h(np.r_[u[:6], u_c[6:]], mu_t)))
    uv = u.copy()
    uv[1:3] = u_c[1:3]
    rows["clean vx, vy"] = (y - h(uv, mu_t), nis(y - h(uv, mu_t)))
    rows["clean y"] = (y_c - h(u, mu_t), nis(y_c - h(u, mu_t)))
    rows["all clean (shape)"] = (y_c - h(u_c, mu_t), nis(y_c - h(u_c, mu_t)))
    # R's terms at x- (step 4's), and their realised errors
    terms = {"sensor": (np.array([p["r_ax"], p["r_ay"], p["r_yaw_acc"]]), y - y_c),
             "model": (p["r_model_rel"] * np.abs(h(u, x_w)), y_c - h(u_c, mu_t))}
    for j, lab in enumerate(INPUTS):
        if sd_u[j] > 0:
            g = trusted._input_columns(p, u, x_w, sd_u, [j])[j]
            uj = u.copy()
            uj[j] = u_c[j]
            terms[lab] = (np.abs(g), h(u, x_w) - h(uj, x_w), (u[j] - u_c[j]) / sd_u[j])
    return rows, terms


def T_of(p):
    return trusted.WHEELS_OF_SIDES if p["structure"] == "sides" else np.eye(4)


def first_updates(path: Path, clean: Path, n_first: int) -> list[dict]:
    log = logs.read_csv_log(str(path))
    lc = logs.read_csv_log(str(clean))
    truth = np.stack([log.col(f"mu_{w}") for w in trs.WHEELS], 1)
    t = log.col("t")
    cols_c = [lc.col(c) for c in COLS]
    om_c = lc.omega()
    raw = [log.col(c) for c in COLS]
    ys = np.stack([log.col("ax"), log.col("ay"), log.col("yaw_acc")], -1)
    ys_c = np.stack([lc.col("ax"), lc.col("ay"), lc.col("yaw_acc")], -1)
    rec, state = [], {"k": -1, "noise": None, "start": 0}
    g = np.arange(0.05, 1.2 + 0.0025, 0.005)     # the presets' [mu_min, mu_max], as exact_update
    pts = np.stack([c.ravel() for c in np.meshgrid(g, g, indexing="ij")])
    orig_up, orig_cond, orig_noise = (trusted.recursive_update, trusted.Conditioner.step,
                                      trusted._step_noise)

    def noise(p, f, T, u, sd_u, *a, **kw):
        s_r = orig_noise(p, f, T, u, sd_u, *a, **kw)
        state["noise"] = (p, u.copy(), sd_u.copy(), T @ f.x, s_r.copy(), f.x.copy(), f.sd())
        return s_r

    def spy(f, y, hfun, n, s_r):
        if len(rec) < n_first:
            k = state["k"]
            p, u, sd_u, x_w, s_r4, x, sd = state["noise"]
            u_c = np.array([c[k] for c in cols_c] + list(om_c[k]))
            rows, terms = breakdown(p, u, u_c, ys[k], ys_c[k], truth[k], x_w, s_r4, sd_u)
            sd_v = conditioner_sd(k - state["start"], p["tau_v"], p["dt"],
                                  float(log.meta.get("noise_vx", 0.05)),
                                  float(log.meta.get("noise_ax", 0.05)))
            sd_c = sd_u.copy()      # the corrected claim: the start-up sd where it is larger
            sd_c[1] = max(sd_u[1], sd_v)
            sd_c[2] = max(sd_u[2], sd_v)
            s_rc = orig_noise(p, type("F", (), dict(
                x=f.x, s_r=np.diag([p["r_ax"], p["r_ay"], p["r_yaw_acc"]])))(), T_of(p), u, sd_c)
            exact = {}
            for lab, sr in (("today", s_r4), ("start-up sd", s_rc)):
                w, mean, psd, _, ll = exact_update.grid_posterior(f.x, f.S, sr, ys[k],
                                                                  hfun(pts), pts)
                i_t = int(np.argmin(np.abs(pts - truth[k][[0, 1]][:, None]).sum(0)))
                exact[lab] = (mean, psd, pts[:, int(np.argmax(ll))], -2 * ll[i_t],
                              -2 * ll.max(), [float(w[pts[j] < exact_update.LOW].sum())
                                              for j in range(2)])
            rec.append(dict(t=t[k], k=k, x=x, sd=sd, rows=rows, terms=terms, sd_v=sd_v,
                            exact=exact,
                            cond=dict(vx=(u[1], u_c[1], raw[1][k]), vy=(u[2], u_c[2], raw[2][k]),
                                      steps=k - state["start"], tau=p["tau_v"]),
                            r_diag=np.sqrt(np.sum(s_r4 ** 2, 1))))
        return orig_up(f, y, hfun, n, s_r)

    def counting(self, *a):
        state["k"] += 1
        if self.vx is None:
            state["start"] = state["k"]
        return orig_cond(self, *a)
    trusted.recursive_update, trusted.Conditioner.step, trusted._step_noise = spy, counting, noise
    try:
        trs.reference_run(path, library_rules=True, extra=dict(relin_steps=1.0))
    finally:
        trusted.recursive_update, trusted.Conditioner.step, trusted._step_noise = (
            orig_up, orig_cond, orig_noise)
    return rec


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="issue 17: the residual at the truth, by cause")
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--scenarios", default="scenarios", type=Path)
    ap.add_argument("--clean", required=True, type=Path)
    ap.add_argument("--updates", default=2, type=int)
    a = ap.parse_args(argv)
    tri = lambda v: "/".join(f"{x:+.3f}" for x in v)   # noqa: E731
    for name in a.logs:
        for i, r in enumerate(first_updates(a.scenarios / f"{name}.csv",
                                            a.clean / f"{clean_name(name)}.csv", a.updates)):
            c = r["cond"]
            print(f"## {name} update {i + 1} at {r['t']:.2f} s (x- {r['x'][0]:.3f}/{r['x'][1]:.3f}"
                  f", sd {r['sd'][0]:.3f}/{r['sd'][1]:.3f}); S_R diag sd {tri(r['r_diag'])}")
            print(f"conditioner: {c['steps']} steps since start (tau {c['tau']}); vx used-clean "
                  f"{c['vx'][0] - c['vx'][1]:+.4f} (raw {c['vx'][2] - c['vx'][1]:+.4f}), vy "
                  f"used-clean {c['vy'][0] - c['vy'][1]:+.4f} (raw {c['vy'][2] - c['vy'][1]:+.4f})")
            print(f"conditioner start-up sd (recursion) {r['sd_v']:.4f}")
            for lab, (m, psd, ml, nt, nm, low) in r["exact"].items():
                print(f"exact update, S_R {lab}: mean {m[0]:.2f}/{m[1]:.2f} (sd {psd[0]:.2f}/"
                      f"{psd[1]:.2f}), likelihood max {ml[0]:.2f}/{ml[1]:.2f}, NIS at truth "
                      f"{nt:.1f}, at max {nm:.1f}, P(mu < 0.3) {low[0]:.2f}/{low[1]:.2f}")
            print("| residual at truth | e ax/ay/yaw | NIS |")
            for lab, (e, nis) in r["rows"].items():
                print(f"| {lab} | {tri(e)} | {nis:.2f} |")
            print("| R term | claimed sd ax/ay/yaw | realised ax/ay/yaw | input error / sd_in |")
            for lab, v in r["terms"].items():
                print(f"| {lab} | {tri(v[0])} | {tri(v[1])} | "
                      + (f"{v[2]:+.2f}" if len(v) > 2 else "") + " |")
            print(flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
