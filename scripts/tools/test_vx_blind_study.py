"""vx_blind_study.py: the vx share, the candidate rule's hook and the counterfactual updates,
on slices of the bundled hard_brake_high_mu.mf log (the reference run over 0.3-1.5 s)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import vx_blind_study as vb  # noqa: E402

LOG = Path(__file__).resolve().parents[2] / "scenarios" / "hard_brake_high_mu.mf.csv"


def _slice(a: int, b: int):
    log = vb.logs.read_csv_log(str(LOG))
    return vb.logs.CsvLog(log.path, dict(log.meta), {k: v[a:b] for k, v in log.columns.items()})


def _braking_step():
    """The filter, inputs and step noise of the first braking sample (2.0 s, ABS slip -0.1)
    after a run over 1.0-2.0 s."""
    log = _slice(100, 201)
    p = vb.preset(log, LOG, 0.27)
    seen = {}

    def spy(pp, f, T, u, sd_u, persistent=None, reuse=None):
        s_r = vb._ORIG_STEP_NOISE(pp, f, T, u, sd_u, persistent, reuse)
        seen.update(p=pp, f=f, T=T, u=u.copy(), sd_u=sd_u.copy(), x=f.x.copy(), s_r=s_r)
        return s_r
    vb.trusted._step_noise = spy
    try:
        vb.trusted.run(log, p)
    finally:
        vb.trusted._step_noise = vb._ORIG_STEP_NOISE
    return seen


def test_vx_share_is_the_vx_columns_part_of_r_ax():
    """Tria keeps R = S_R0 S_R0^T + sum_j g_j g_j^T, so R_ax minus the same without the vx
    column is g_vx,ax^2: the share equals g_vx,ax^2 / R_ax with g from the reference's own
    derivative (_input_columns, which the share does not call). Both are sums of a few squares
    of O(1) numbers: 1e-12 is ~1e4 roundings."""
    s = _braking_step()
    f = s["f"]
    f.x = s["x"]
    share = vb.vx_share(s["p"], f, s["T"], s["u"], s["sd_u"], s["s_r"])
    g = vb.trusted._input_columns(s["p"], s["u"], s["T"] @ s["x"], s["sd_u"], [1])[1]
    r_ax = float(s["s_r"][0] @ s["s_r"][0])
    assert 0.0 < share < 1.0
    assert share == pytest.approx(g[0] ** 2 / r_ax, abs=1e-12)
    sd0 = s["sd_u"].copy()
    sd0[1] = 0.0
    assert vb.vx_share(s["p"], f, s["T"], s["u"], sd0, s["s_r"]) == 0.0


def test_rule_inert_above_every_share_and_holding_below_all():
    """share 1: no step can exceed it (a share is < 1 while r_ax > 0), so the run is the plain
    one bit for bit. share -1: every update is taken with S_R x 1e4 (R x 1e8): the gain
    P H^T (H P H^T + R)^-1 falls by (H P H^T + R) / (1e8 R) <= 1e-8 (1 + H P H^T / R), and
    H P H^T / R <= (sd0 |dh/dmu| / r)^2 ~ (0.32 x 10 / 0.05)^2 ~ 4e3 here, so by < 1e-4: the
    mean's drift from mu0 stays below 1e-3 of the plain run's (a factor 10 of margin); the
    hook puts the step noise back afterwards."""
    log = _slice(30, 150)
    p = vb.preset(log, LOG, 0.27)
    plain = vb.run(log, p)
    with vb.VxBlind(1.0) as rule:
        same = vb.run(log, p, rule)
    assert rule.skipped == 0
    assert np.array_equal(same["mu"], plain["mu"]) and np.array_equal(same["valid"], plain["valid"])
    with vb.VxBlind(-1.0) as rule:
        held = vb.run(log, p, rule)
    assert rule.skipped > 0
    assert vb.trusted._step_noise is vb._ORIG_STEP_NOISE
    plain_drift = np.abs(plain["mu"] - p["mu0"]).max()
    assert plain_drift > 0.05                               # the plain run does move
    assert np.abs(held["mu"] - p["mu0"]).max() < 1e-3 * plain_drift


def test_counterfactual_noise_factors():
    """rows_out scales the chosen rows by 1e3 inside its window only; diag_r keeps each row's
    norm (R's diagonal) and drops the cross-terms."""
    s_r = np.array([[0.4, 0.0, 0.0], [0.1, 0.2, 0.0], [0.3, 0.05, 0.1]])
    t = np.array([4.0, 4.1])
    a = vb.rows_out((1, 2), t, (4.05, 4.2))
    assert np.array_equal(a(0, None, None, None, s_r), s_r)
    out = a(1, None, None, None, s_r)
    assert np.array_equal(out[0], s_r[0]) and np.array_equal(out[1:], 1e3 * s_r[1:])
    d = vb.diag_r(0, None, None, None, s_r)
    assert np.allclose(np.diag(d) ** 2, (s_r ** 2).sum(1), rtol=1e-15, atol=0)
    assert np.count_nonzero(d - np.diag(np.diag(d))) == 0


def test_ax_information_is_the_ax_rows_fisher_information():
    """I_ax,k = J_ax,k^2 / R_ax,ax with J = P_zx (S S^T)^-1, formed here with a general solve
    (the rule uses two triangular solves through trusted._information_of): equal to 1e-9
    relative (a 2x2 solve of a well-conditioned S, sd ~0.1, relative rounding ~1e-15 x its
    condition number, far below 1e-9)."""
    s = _braking_step()
    f = s["f"]
    f.x = s["x"]
    rule = vb.AxAnchor(25.0, 3.0)
    rule.f = f
    pts = f.points()
    hfun = lambda q: vb.trusted.h_points(  # noqa: E731
        s["p"], np.tile(s["u"], (q.shape[1], 1)), (s["T"] @ q).T).T
    z = hfun(pts)
    zc = (z - z.mean(axis=1)[:, None]) / f.sqrt_2n
    xc = (pts - f.x[:, None]) / f.sqrt_2n
    j = np.linalg.solve(f.S @ f.S.T, (zc @ xc.T).T).T          # J (S S^T) = P_zx
    expect = j[0] ** 2 / float(s["s_r"][0] @ s["s_r"][0])
    assert np.allclose(rule.info_ax(zc, s["s_r"]), expect, rtol=1e-9, atol=0)


def test_ax_anchor_acts_only_at_hard_ax():
    """ax_hard above any ax: inert, the plain run bit for bit. ax_hard 0 with an info_min no
    row reaches: every evaluated step held, the mean within 1e-3 of the plain run's drift
    (as in the vx-share test: the gain falls by <1e-4)."""
    log = _slice(30, 150)
    p = vb.preset(log, LOG, 0.27)
    plain = vb.run(log, p)
    with vb.AxAnchor(p["info_min"], 1e9) as rule:
        same = vb.run(log, p, rule)
    assert rule.skipped == 0 and np.array_equal(same["mu"], plain["mu"])
    with vb.AxAnchor(1e300, 0.0) as rule:
        held = vb.run(log, p, rule)
    plain_drift = np.abs(plain["mu"] - p["mu0"]).max()
    assert rule.skipped > 0
    assert np.abs(held["mu"] - p["mu0"]).max() < 1e-3 * plain_drift
