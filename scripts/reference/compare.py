"""Compare two estimate logs (DATA.md) as numbers, not bytes.

The reference runs on numpy: its QR, Cholesky and products go to the BLAS, whose kernel
depends on the CPU (OPENBLAS_CORETYPE, thread count), and its elementwise exp, log, arctan,
arctan2 and tanh to SIMD paths numpy picks per CPU. Each choice sums and rounds in its own
order, so the same log gives estimates that differ in the last bits from machine to machine
(measured: at most 9.6e-12 on mu and sd over every golden; scripts/checks/check_kernels.py measures
it again on each machine). A golden check must therefore compare with a tolerance:

* mu and sd: |a - b| <= TOL_MU / TOL_SD = 1e-9. The same bound the C double build is held
  to against the reference (test/golden/test_golden_flt.c TOL_MU): both differences come from
  summation order and rounding only (~1e-16 per operation), and the filter is contractive,
  so over 1 000 steps they stay ~1e-11; 1e-9 leaves two orders of magnitude of margin and
  is still six orders below anything the estimator's accuracy figures (>= 1e-3) can see.
* t, valid flags and status: exactly. A flag or status that differs means a decision flipped
  (a quantity sat within rounding of its threshold); the message then names the row and how
  far the deciding quantity stood from its threshold (``diagnostics`` of a fresh run).
* Metadata: every key exactly, except the machinery keys (runtime.RUNTIME_KEYS: which BLAS
  kernel and numpy SIMD paths wrote the file), which record the machine, not the result.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import logs
from .runtime import RUNTIME_KEYS

TOL_MU = 1e-9
TOL_SD = 1e-9
WHEELS = ("fl", "fr", "rl", "rr")
MAX_LISTED = 5          # decision mismatches listed per file (the count is always given)


@dataclass
class Result:
    """Outcome of one comparison: problems (empty when the logs agree) and the largest
    differences seen (for the report)."""
    expected: str
    actual: str
    problems: list = field(default_factory=list)
    max_dmu: float = 0.0
    max_dsd: float = 0.0
    rows: int = 0

    @property
    def ok(self) -> bool:
        return not self.problems


def diagnostics(res: dict) -> dict:
    """The deciding quantities of a run (estimate.run / trusted.run output): the speed the
    low-speed gate compared (v_gate), the largest information (info_max, default preset),
    and the mean before projection (mu_unprojected)."""
    d = {}
    for key in ("v_gate", "mu_unprojected"):
        if key in res:
            d[key] = np.asarray(res[key], dtype=float)
    if "info" in res:
        d["info_max"] = np.asarray(res["info"], dtype=float).max(axis=1)
    return d


def _r(x) -> str:
    """A number as its shortest round-trip decimal."""
    return repr(float(x))


def _param(meta: dict, key: str) -> float | None:
    try:
        return float(meta[key])
    except (KeyError, ValueError):
        return None


def _status_reason(k: int, s_exp: int, s_act: int, meta: dict, diag: list) -> str:
    """How far the quantity that decides between the two statuses stood from its threshold,
    from each side's diagnostics when there are any."""
    pair = {s_exp, s_act}
    parts = []
    if 2 in pair:
        thr = _param(meta, "v_est_min")
        for name, d in diag:
            if d and "v_gate" in d:
                v = d["v_gate"][k]
                parts.append(f"{name}: vx = {_r(v)} vs v_est_min = {thr} (margin {v - thr:+.3g} m/s)")
        what = "low-speed gate"
    elif 3 in pair:
        thr = _param(meta, "info_min")
        for name, d in diag:
            if d and "info_max" in d:
                v = d["info_max"][k]
                parts.append(f"{name}: max information = {_r(v)} vs info_min = {thr} "
                             f"(margin {v - thr:+.3g})")
        what = "information gate"
    else:
        lo, hi = _param(meta, "mu_min"), _param(meta, "mu_max")
        for name, d in diag:
            if d and "mu_unprojected" in d:
                m = d["mu_unprojected"][k]
                margin = np.minimum(m - lo, hi - m)
                i = int(np.argmin(margin))
                parts.append(f"{name}: mu_{WHEELS[i]} before projection = {_r(m[i])} vs "
                             f"[{lo}, {hi}] (margin {margin[i]:+.3g})")
        what = "projection"
    if not parts:
        parts.append("no diagnostics for this file (rerun the reference to see the margin)")
    return f"{what}: " + "; ".join(parts)


def compare_logs(expected_path: str, actual_path: str, expected_diag: dict | None = None,
                 actual_diag: dict | None = None) -> Result:
    """Compare estimate log actual_path with expected_path (see the module doc)."""
    res = Result(expected_path, actual_path)
    try:
        e = logs.read_csv_log(expected_path, required=logs.ESTIMATE_COLUMNS)
        a = logs.read_csv_log(actual_path, required=logs.ESTIMATE_COLUMNS)
    except logs.LogError as exc:
        res.problems.append(str(exc))
        return res
    me = {k: v for k, v in e.meta.items() if k not in RUNTIME_KEYS}
    ma = {k: v for k, v in a.meta.items() if k not in RUNTIME_KEYS}
    for key in sorted(set(me) | set(ma)):
        if me.get(key) != ma.get(key):
            res.problems.append(f"metadata {key}: expected {me.get(key)!r}, got {ma.get(key)!r}")
    if list(e.columns) != list(a.columns):
        res.problems.append(f"columns: expected {list(e.columns)}, got {list(a.columns)}")
        return res
    if len(e) != len(a):
        res.problems.append(f"rows: expected {len(e)}, got {len(a)}")
        return res
    res.rows = len(e)
    if not np.array_equal(e.col("t"), a.col("t")):
        k = int(np.argmax(e.col("t") != a.col("t")))
        res.problems.append(f"row {k}: t expected {_r(e.col('t')[k])}, got {_r(a.col('t')[k])}")
    for prefix, tol, attr in (("mu_", TOL_MU, "max_dmu"), ("sd_", TOL_SD, "max_dsd")):
        d = np.stack([np.abs(a.col(prefix + w) - e.col(prefix + w)) for w in WHEELS], axis=1)
        bad = ~(d <= tol)                       # NaN counts as a difference
        setattr(res, attr, float(np.nanmax(d)) if d.size else 0.0)
        if bad.any():
            k, i = np.argwhere(bad)[0]
            res.problems.append(
                f"{prefix}*: {int(bad.sum())} values beyond {tol:g}, first row {k} "
                f"(t = {_r(e.col('t')[k])}) {prefix}{WHEELS[i]}: expected {_r(e.col(prefix + WHEELS[i])[k])},"
                f" got {_r(a.col(prefix + WHEELS[i])[k])}; largest |difference| {getattr(res, attr):.3g}")
    diag = [("expected", expected_diag), ("actual", actual_diag)]
    sd_valid = _param(e.meta, "sd_valid") or 0.0
    listed = 0
    status_e, status_a = e.col("status").astype(int), a.col("status").astype(int)
    rows = np.flatnonzero(status_e != status_a)
    for k in rows:
        if listed < MAX_LISTED:
            res.problems.append(f"row {k} (t = {_r(e.col('t')[k])}): status expected {status_e[k]}, "
                                f"got {status_a[k]}; "
                                f"{_status_reason(k, status_e[k], status_a[k], e.meta, diag)}")
            listed += 1
    n_flags = 0
    for i, w in enumerate(WHEELS):
        ve, va = e.col("valid_" + w).astype(int), a.col("valid_" + w).astype(int)
        for k in np.flatnonzero(ve != va):
            n_flags += 1
            if listed >= MAX_LISTED:
                continue
            listed += 1
            if sd_valid > 0:
                se, sa = e.col("sd_" + w)[k], a.col("sd_" + w)[k]
                me, ma = e.col("mu_" + w)[k], a.col("mu_" + w)[k]
                why = (f"sd gate: sd_{w} = {_r(se)} (expected) / {_r(sa)} (actual) vs sd_valid = "
                       f"{sd_valid} (margins {se - sd_valid:+.3g} / {sa - sd_valid:+.3g}); "
                       f"never on a bound: mu_{w} = {_r(me)} / {_r(ma)} vs [mu_min, mu_max] = "
                       f"[{_param(e.meta, 'mu_min')}, {_param(e.meta, 'mu_max')}]")
            else:
                why = "valid follows the status: " + _status_reason(
                    k, status_e[k], status_a[k], e.meta, diag)
            res.problems.append(f"row {k} (t = {_r(e.col('t')[k])}): valid_{w} expected {ve[k]}, "
                                f"got {va[k]}; {why}")
    if len(rows) + n_flags > listed:
        res.problems.append(f"decisions that differ: {len(rows)} statuses, {n_flags} valid flags "
                            f"({listed} listed)")
    return res


def report(res: Result) -> str:
    """The problems of a comparison, one per line, for an assertion message."""
    head = f"{res.actual} differs from {res.expected}:"
    return "\n  ".join([head] + res.problems)
