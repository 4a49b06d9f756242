#!/usr/bin/env python3
"""Identify the absolute-mode tyre stiffnesses cx, cy from sensor logs, without knowing mu.

    .venv/bin/python scripts/tools/fit_tyre_stiffness.py LOG.csv [LOG.csv ...] [--max-acc G]
        [--only cx|cy] [--params FILE] [--out params.par]  (--help: all thresholds)

MODEL.md section 4, "absolute Dugoff": Cx = cx*Fz, Cy = cy*Fz, and at low utilisation the
tyre is linear and friction-free:
    Fx_i = cx * Fz_i * kappa_i/(1 - |kappa_i|),   Fy_i = cy * Fz_i * tan(alpha_i)/(1 - |kappa_i|)
(for absolute Dugoff this holds exactly while L >= 1; for a real or Magic-Formula tyre it is
the slope at zero slip).  Through MODEL.md section 5's geometry (front wheels rotated by
delta) the measurement is then linear in (cx, cy):
    [ax, ay, yaw_acc] = cx * sum_i body(Fz_i kappa_i/(1-|kappa_i|), 0)
                      + cy * sum_i body(0, Fz_i tan(alpha_i)/(1-|kappa_i|))
with body(Fx, Fy) = [Fbx/m, Fby/m, (x_i Fby - y_i Fbx)/J], and cx, cy follow by weighted
least squares (with an instrument, step 4).  Kinematics, slips and loads are MODEL.md section 3 (scripts/reference/model.py).

Steps, per log (parameters: MODEL.md defaults < the log's `# key = value` metadata < --params):
 1. Low-pass every logged signal (delta, vx, vy, yaw_rate, yaw_acc, ax, ay, omega_*) with a
    zero-phase Butterworth filter (order 2, forward-backward, --cutoff, default 5 Hz) and
    compute slips, loads and the two regressor columns from the filtered signals.
    Measurement and regressors go through the same filter, so the vehicle's own (slower)
    dynamics are attenuated alike and cancel.
 2. Select low-utilisation samples from measured quantities only (all must hold, on the
    filtered signals, for the sample and every sample within --guard = 0.05 s of it, the
    filter's support): vx >= --min-speed (5 m/s); |ax|, |ay| <= G*g with G = --max-acc
    (0.2); and the same bound per wheel, through the linear model with the parameter
    stiffnesses: on every wheel cx*|kappa| <= G and cy*|tan(alpha)| <= G (|kappa| <= 0.01,
    |alpha| <= 0.0133 rad with cx = 20, cy = 15; --max-kappa / --max-alpha override).
    That keeps any tyre linear without knowing mu as long as mu is well above G: the
    utilisation is then about G/mu (0.24 on mu 0.85; the absolute Dugoff tyre is exactly
    linear up to 0.5).  The per-wheel bound catches wheels that work harder than the
    vehicle's acceleration suggests (one driven axle, split mu).  On a very slippery
    road lower --max-acc: on mu 0.3 the mf tyre at utilisation 0.67 is ~13 % below its
    slope.  The first and last second of each log (1/(excitation filter cutoff), at least
    the instrument lag) are not used.
 3. A selected sample "excites" cx if some wheel has |kappa| >= --kappa-excite (0.002) and
    cy if some wheel has |alpha| >= --alpha-excite (0.002 rad), judged on slips filtered at
    1 Hz (noise sd ~0.0003, so noise alone does not count as excitation).  A stiffness is
    only fitted when at least --min-samples (100, 1 s at 100 Hz) selected samples excite
    it; otherwise the script refuses (exit status 2, no --out file) and says why (e.g.
    straight driving has no slip angles, so no cy).  --only fits one stiffness and holds
    the other at its parameter value (its predicted forces are subtracted; on logs that
    do not excite it they are ~0 anyway).
 4. Least squares with an instrument (instrumental variables, IV):
        (sum_k w^2 z_k^T x_k) c = sum_k w^2 z_k^T y_k
    x_k the regressors of sample k, y_k the filtered [ax, ay, yaw_acc], z_k the regressors
    at k - lag and k + lag averaged (--lag 0.3 s, beyond the filter's correlation length),
    w the channel weight 1/(noise sd) from the log's noise_* metadata (r_ax, r_ay,
    r_yaw_acc of the parameters when absent or 0).  Why not plain least squares: the slips
    are ratios of noisy speeds (0.05 m/s of vx noise gives ~0.0025 of kappa noise per
    sample, about the slip of mild braking), and noise in a regressor biases least squares
    towards zero by noise^2/(noise^2 + signal^2) -- measured on the noisy mf braking logs:
    cx -38 % from raw signals, -8 % after the 5 Hz filter; a 1 Hz filter lowers that bias
    but smears the nonlinear samples next to the selected ones into them (cy -6 to -8 %).  The instrument's noise is independent of
    the noise at k, so the IV estimate has no such bias; on noise-free logs it equals the
    least-squares one.
Standard error: Newey-West (Bartlett) sandwich covariance of the IV estimate, with the
scores z_k*u_k (u the residual) summed over 2*lag + 1/cutoff samples, since the filter and
the instrument correlate them.  It covers measurement and regressor noise and the model
mismatch seen in the residual; it does not cover a systematic tyre nonlinearity inside
the selection (for the Magic-Formula truth about -1 % on cx at mild braking).

Output: a line per log with its number of selected samples, then one line per stiffness,
"cx = 19.87 +- 0.21 (N samples excite cx)"; with --out a DATA.md parameter file with `cx = ...`
and `cy = ...` lines (only what was fitted; --only), ready to pass to the estimator.
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass

import numpy as np
from scipy.signal import butter, filtfilt

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)
from reference import logs, model, params  # noqa: E402

AXES = ("cx", "cy")
CHANNELS = ("ax", "ay", "yaw_acc")
SIGNALS = ("delta", "vx", "vy", "yaw_rate", "yaw_acc", "ax", "ay") + tuple(
    "omega_" + w for w in model.WHEELS)
NOISE_DEFAULT_KEYS = {"ax": "r_ax", "ay": "r_ay", "yaw_acc": "r_yaw_acc"}


class FitError(RuntimeError):
    """Not enough excitation (or no usable samples) to identify a stiffness."""


@dataclass
class Settings:
    max_acc: float = 0.2          # g
    min_speed: float = 5.0        # m/s
    max_kappa: float | None = None   # None: max_acc / cx (parameter value)
    max_alpha: float | None = None   # rad; None: atan(max_acc / cy)
    kappa_excite: float = 0.002
    alpha_excite: float = 0.002   # rad
    min_samples: int = 100
    cutoff: float = 5.0           # Hz, fit filter
    excite_cutoff: float = 1.0    # Hz, filter of the excitation classification
    lag: float = 0.3              # s, instrument lag
    guard: float = 0.05           # s, selection erosion
    order: int = 2


@dataclass
class LogRows:
    """Per-log fitting material, selected samples only."""
    path: str
    n_total: int
    index: np.ndarray        # (n_sel,) sample numbers of the selected samples
    design: np.ndarray       # (n_sel, 3, 2): [cx column, cy column] per channel
    instrument: np.ndarray   # (n_sel, 3, 2): the design at k - lag and k + lag, averaged
    y: np.ndarray            # (n_sel, 3) filtered measurement
    weights: np.ndarray      # (3,) 1/sd per channel
    excite: np.ndarray       # (n_sel, 2) bool: sample excites cx / cy
    hac_lag: int             # samples over which the fit's scores are correlated
    p: dict


def regressors(p, cols):
    """Design per sample, shape (N, 3, 2), from (filtered) log columns (MODEL.md 3-5)."""
    omega = np.stack([cols["omega_" + w] for w in model.WHEELS], axis=-1)
    ti = model.tyre_inputs(p, cols["delta"], cols["vx"], cols["vy"], cols["yaw_rate"],
                           cols["ax"], cols["ay"], omega)
    lin = ti.fz / np.maximum(1.0 - np.abs(ti.kappa), 1e-9)   # locked wheels: never selected
    ux = lin * ti.kappa           # Fx per unit cx
    uy = lin * np.tan(ti.alpha)   # Fy per unit cy
    zero = np.zeros_like(ux)
    col_x = model.body_effects(p, ux, zero, ti.delta_i).sum(axis=-1)   # (N, 3)
    col_y = model.body_effects(p, zero, uy, ti.delta_i).sum(axis=-1)
    return np.stack([col_x, col_y], axis=-1), ti


def _lowpass(raw, cutoff, fs, order):
    b, a = butter(order, cutoff / (0.5 * fs))
    return {c: filtfilt(b, a, v) for c, v in raw.items()}


def prepare(path, st: Settings, param_file=None) -> LogRows:
    log = logs.read_csv_log(path)
    p = params.resolve(log.meta, param_file, source=path)
    n = len(log)
    if n < 2:
        raise FitError(f"{path}: only {n} samples")
    dt = float(np.median(np.diff(log.col("t"))))
    fs = 1.0 / dt
    for name, fc in (("--cutoff", st.cutoff), ("excitation cutoff", st.excite_cutoff)):
        if not 0.0 < fc < 0.5 * fs:
            raise SystemExit(f"{name} must be between 0 and {0.5 * fs:g} Hz")
    lag = max(1, int(round(st.lag * fs)))
    guard = max(0, int(round(st.guard * fs)))
    edge = max(lag, int(np.ceil(fs / st.excite_cutoff)))
    if n <= 2 * edge + 1:
        raise FitError(f"{path}: only {n} samples")
    raw = {c: log.col(c) for c in SIGNALS}
    filt = _lowpass(raw, st.cutoff, fs, st.order)
    design, ti = regressors(p, filt)
    _, ti_ex = regressors(p, _lowpass(raw, st.excite_cutoff, fs, st.order))

    g = p["g"]
    max_kappa = st.max_kappa if st.max_kappa is not None else st.max_acc / p["cx"]
    max_alpha = st.max_alpha if st.max_alpha is not None else np.arctan(st.max_acc / p["cy"])
    ok = ((filt["vx"] >= st.min_speed)
          & (np.abs(filt["ax"]) <= st.max_acc * g) & (np.abs(filt["ay"]) <= st.max_acc * g)
          & np.all(np.abs(ti.kappa) <= max_kappa, axis=-1)
          & np.all(np.abs(ti.alpha) <= max_alpha, axis=-1))
    # erosion: the whole filter support around a sample must pass
    sel = ok.copy()
    for d in range(1, guard + 1):
        sel[d:] &= ok[:-d]
        sel[:-d] &= ok[d:]
    sel[:edge] = False
    sel[n - edge:] = False
    index = np.flatnonzero(sel)
    instrument = 0.5 * (design[index - lag] + design[index + lag])
    excite = np.stack([np.max(np.abs(ti_ex.kappa), axis=-1) >= st.kappa_excite,
                       np.max(np.abs(ti_ex.alpha), axis=-1) >= st.alpha_excite], axis=-1)
    sd = []
    for c in CHANNELS:
        v = float(log.meta.get("noise_" + c, "0") or 0.0)
        sd.append(v if v > 0.0 else p[NOISE_DEFAULT_KEYS[c]])
    y = np.stack([filt[c] for c in CHANNELS], axis=-1)
    memory = int(np.ceil(fs / st.cutoff))   # the fit filter's correlation length
    return LogRows(path, n, index, design[index], instrument, y[index],
                   1.0 / np.array(sd), excite[index], 2 * lag + memory, p)


@dataclass
class FitResult:
    value: dict          # axis -> fitted stiffness (only fitted axes)
    stderr: dict         # axis -> standard error
    n_excite: dict       # axis -> selected samples exciting it (all axes)
    n_selected: int
    per_log: list        # (path, selected, total)


def fit(paths, st: Settings = Settings(), only=None, param_file=None) -> FitResult:
    """Fit cx and cy (or only one of them) from the logs; raises FitError when an axis to be
    fitted is not excited by enough selected samples."""
    rows = [prepare(path, st, param_file) for path in paths]
    n_sel = sum(len(r.index) for r in rows)
    n_excite = {ax: sum(int(r.excite[:, k].sum()) for r in rows) for k, ax in enumerate(AXES)}
    axes = [only] if only else list(AXES)
    problems = []
    for ax in axes:
        if n_excite[ax] < st.min_samples:
            what = "|kappa|" if ax == "cx" else "|alpha|"
            thr = st.kappa_excite if ax == "cx" else st.alpha_excite
            hint = ("braking or driving (longitudinal slip)" if ax == "cx"
                    else "steering / cornering (slip angles); straight driving gives no cy")
            problems.append(
                f"{ax}: not identifiable: {n_excite[ax]} of {n_sel} low-utilisation samples "
                f"have some wheel with {what} >= {thr:g} (need >= {st.min_samples}); "
                f"the logs need {hint} at |ax|, |ay| <= {st.max_acc:g} g")
    if problems:
        raise FitError("\n".join(problems))
    k_fit = [AXES.index(ax) for ax in axes]
    k_fix = [k for k in range(2) if k not in k_fit]

    # Instrumental-variable normal equations  (sum w^2 Z^T X) c = sum w^2 Z^T y
    def parts(r):
        fixed = sum((r.design[:, :, k] * r.p[AXES[k]] for k in k_fix),
                    np.zeros(r.y.shape))
        w = r.weights[None, :, None]
        return (r.design[:, :, k_fit] * w, r.instrument[:, :, k_fit] * w,
                (r.y - fixed) * r.weights[None, :])
    A = np.zeros((len(k_fit), len(k_fit)))
    rhs = np.zeros(len(k_fit))
    for r in rows:
        X, Z, y = parts(r)
        A += np.einsum("kci,kcj->ij", Z, X)
        rhs += np.einsum("kci,kc->i", Z, y)
    c = np.linalg.solve(A, rhs)

    # HAC (Newey-West, Bartlett) sandwich: the scores z_k u_k are correlated over the filter
    # memory and the instrument lag, so sum their cross-products up to that distance.
    meat = np.zeros_like(A)
    for r in rows:
        X, Z, y = parts(r)
        u = y - X @ c
        score = np.einsum("kci,kc->ki", Z, u)          # (n_sel, n_fit)
        full = np.zeros((r.n_total, len(k_fit)))
        full[r.index] = score
        L = r.hac_lag
        meat += full.T @ full
        for l in range(1, L + 1):
            wgt = 1.0 - l / (L + 1.0)
            cross = full[l:].T @ full[:-l]
            meat += wgt * (cross + cross.T)
    Ainv = np.linalg.inv(A)
    cov = Ainv @ meat @ Ainv.T
    value = {AXES[k]: float(c[j]) for j, k in enumerate(k_fit)}
    stderr = {AXES[k]: float(np.sqrt(cov[j, j])) for j, k in enumerate(k_fit)}
    per_log = [(r.path, len(r.index), r.n_total) for r in rows]
    return FitResult(value, stderr, n_excite, n_sel, per_log)


def param_text(res: FitResult, paths):
    lines = ["# absolute-mode tyre stiffness per unit Fz (MODEL.md section 4), fitted by",
             "# scripts/tools/fit_tyre_stiffness.py from " + ", ".join(os.path.basename(p) for p in paths)]
    for ax in AXES:
        if ax in res.value:
            lines.append(f"# {ax}: standard error {res.stderr[ax]:.3g}, "
                         f"{res.n_excite[ax]} exciting samples")
            lines.append(f"{ax} = {res.value[ax]:.6g}")
    return "\n".join(lines) + "\n"


def main(argv=None):
    st = Settings()
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("logs", nargs="+", metavar="LOG.csv", help="sensor logs (DATA.md)")
    ap.add_argument("--max-acc", type=float, default=st.max_acc, metavar="G",
                    help=f"select |ax|, |ay| <= G * g (default {st.max_acc:g})")
    ap.add_argument("--min-speed", type=float, default=st.min_speed, metavar="M/S",
                    help=f"select vx >= this (default {st.min_speed:g})")
    ap.add_argument("--max-kappa", type=float,
                    help="select |kappa| <= this on every wheel (default: G / cx, with cx "
                         "the parameter value, i.e. 0.01)")
    ap.add_argument("--max-alpha", type=float, metavar="RAD",
                    help="select |alpha| <= this on every wheel (default: atan(G / cy), "
                         "i.e. 0.0133)")
    ap.add_argument("--kappa-excite", type=float, default=st.kappa_excite,
                    help=f"a sample excites cx when some |kappa| >= this "
                         f"(default {st.kappa_excite:g})")
    ap.add_argument("--alpha-excite", type=float, default=st.alpha_excite, metavar="RAD",
                    help=f"a sample excites cy when some |alpha| >= this "
                         f"(default {st.alpha_excite:g})")
    ap.add_argument("--min-samples", type=int, default=st.min_samples,
                    help=f"exciting samples needed per stiffness (default {st.min_samples})")
    ap.add_argument("--cutoff", type=float, default=st.cutoff, metavar="HZ",
                    help=f"zero-phase low-pass cutoff (default {st.cutoff:g} Hz)")
    ap.add_argument("--lag", type=float, default=st.lag, metavar="S",
                    help=f"instrument lag (default {st.lag:g} s)")
    ap.add_argument("--guard", type=float, default=st.guard, metavar="S",
                    help=f"selection guard band (default {st.guard:g} s)")
    ap.add_argument("--only", choices=AXES,
                    help="fit only this stiffness; the other keeps its parameter value")
    ap.add_argument("--params", metavar="FILE",
                    help="parameter file overriding defaults and log metadata")
    ap.add_argument("--out", metavar="FILE", help="write cx / cy as a parameter file")
    a = ap.parse_args(argv)
    st = Settings(max_acc=a.max_acc, min_speed=a.min_speed, max_kappa=a.max_kappa,
                  max_alpha=a.max_alpha, kappa_excite=a.kappa_excite,
                  alpha_excite=a.alpha_excite, min_samples=a.min_samples, cutoff=a.cutoff,
                  lag=a.lag, guard=a.guard)
    try:
        res = fit(a.logs, st, a.only, a.params)
    except FitError as exc:
        print(f"fit_tyre_stiffness: refused:\n{exc}", file=sys.stderr)
        return 2
    except (logs.LogError, params.ParamError, OSError) as exc:
        print(f"fit_tyre_stiffness: {exc}", file=sys.stderr)
        return 1
    for path, n_sel, n in res.per_log:
        print(f"{path}: {n_sel} of {n} samples selected")
    for ax in AXES:
        if ax in res.value:
            print(f"{ax} = {res.value[ax]:.4f} +- {res.stderr[ax]:.4f}  "
                  f"({res.n_excite[ax]} samples excite {ax})")
        else:
            print(f"{ax}: held at its parameter value ({res.n_excite[ax]} samples excite it)")
    if a.out:
        with open(a.out, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(param_text(res, a.logs))
        print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
