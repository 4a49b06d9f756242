"""MODEL.md section 6: square-root cubature Kalman filter (SCKF) and the paper's CKF baseline.

Both filters are generic in the measurement function: ``h(X)`` maps the cubature points X,
shape (n, 2n), one point per column, to Z, shape (m, 2n).  The process is the random walk
f(x) = x of MODEL.md section 5, still propagated through the cubature points as section 6
writes it (so the float64 rounding follows the specified algorithm).

Cubature points: xi_j = sqrt(n) e_j, j = 1..n, then -sqrt(n) e_j, weights w = 1/(2n).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import solve_triangular


def cubature_unit_points(n: int) -> np.ndarray:
    """[sqrt(n) e_1 .. sqrt(n) e_n, -sqrt(n) e_1 .. -sqrt(n) e_n], shape (n, 2n) (MODEL.md 6)."""
    eye = np.eye(n)
    return np.sqrt(n) * np.hstack([eye, -eye])


def tria(a: np.ndarray) -> np.ndarray:
    """Tria(A): lower-triangular S with S S^T = A A^T (MODEL.md section 6).

    Householder QR of A^T (numpy.linalg.qr, LAPACK dgeqrf): A^T = Q R, S = R^T; the columns
    of S are then sign-flipped so the diagonal is non-negative (S S^T is unchanged).
    """
    r = np.linalg.qr(a.T, mode="r")
    s = r.T
    signs = np.where(np.diag(s) < 0.0, -1.0, 1.0)
    return s * signs[None, :]


def project(x: np.ndarray, lo: float, hi: float):
    """Projection of the mean onto [mu_min, mu_max] (MODEL.md section 6). Returns (x, clamped)."""
    xp = np.minimum(np.maximum(x, lo), hi)
    return xp, bool(np.any(xp != x))


class SCKF:
    """Square-root CKF state (x, S) with S lower triangular, P = S S^T."""

    def __init__(self, x0, s0, s_q, s_r):
        self.x = np.array(x0, dtype=float)
        self.S = np.array(s0, dtype=float)
        self.s_q = np.array(s_q, dtype=float)
        self.s_r = np.array(s_r, dtype=float)
        self.n = self.x.size
        self.xi = cubature_unit_points(self.n)
        self.sqrt_2n = np.sqrt(2.0 * self.n)
        # h linear in x, h(x) = H x (the paper tyre): the update's exact n-column form
        # (centred; sckf_flt.c rfe_sckf_update_linear)
        self.linear = False

    def points(self):
        """X_j = S xi_j + x, shape (n, 2n)."""
        return self.S @ self.xi + self.x[:, None]

    def time_update(self):
        """X_j = S xi_j + x; X*_j = f(X_j) = X_j; x- = mean X*_j;
        S- = Tria([(X*_1 - x-, ..., X*_2n - x-)/sqrt(2n), S_Q])   (MODEL.md section 6).

        For the random walk this needs no cubature points: they are symmetric about x, so
        x- = x exactly (their average would only add rounding, which walks the mean over many
        held steps), and the centred points +-sqrt(n) S e_j / sqrt(2n) = +-S e_j / sqrt(2)
        contribute exactly S S^T, so S- = Tria([S, S_Q]) (as the C library computes it)."""
        self.x = self.x.copy()
        self.S = tria(np.hstack([self.S, self.s_q]))

    def time_update_steps(self, k: int):
        """k random-walk time updates at once (sckf_flt.c rfe_sckf_predict_steps):
        S- = Tria([S, sqrt(k) S_Q]); k = 0 changes nothing."""
        if k > 0:
            self.S = tria(np.hstack([self.S, np.sqrt(float(k)) * self.s_q]))

    def propagate(self, f):
        """The general cubature time update (MODEL.md section 6 with a nonlinear process, the
        tyre identifier's augmented state, TYRE_ID.md section 15): X_j = S xi_j + x;
        X*_j = f(X)_j (f maps all points at once, shape (n, 2n)); x- = mean X*_j;
        S- = Tria([(X*_1 - x-, ..., X*_2n - x-)/sqrt(2n), S_Q])."""
        x_star = np.asarray(f(self.points()), dtype=float)
        self.x = x_star.mean(axis=1)
        self.S = tria(np.hstack([(x_star - self.x[:, None]) / self.sqrt_2n, self.s_q]))

    def q_diag(self):
        return np.sum(self.s_q ** 2, axis=1)

    def centred(self, h):
        """(z, Xc, Zc) of the measurement update at x-, S-. The cubature rule: X_j = S- xi_j
        + x-, Z_j = h(X_j), z = mean Z_j, Xc = (X_j - x-)/sqrt(2n), Zc = (Z_j - z)/sqrt(2n)
        (2n columns). With self.linear (h(x) = H x, no constant term) the rule is exact and
        the n columns z = h(x-), Xc = S-, Zc = h(S-) = H S- have the same products Xc Xc^T,
        Zc Zc^T, Xc Zc^T as the 2n points' ([S-, -S-]/sqrt(2)): docs/ESTIMATOR.md "The linear
        update", sckf_flt.c centre_linear."""
        if self.linear:
            z_hat = np.asarray(h(self.x[:, None]), dtype=float)[:, 0]
            return z_hat, self.S.copy(), np.asarray(h(self.S), dtype=float)
        pts = self.points()
        z_pts = np.asarray(h(pts), dtype=float)
        z_hat = z_pts.mean(axis=1)
        xc = (pts - self.x[:, None]) / self.sqrt_2n
        zc = (z_pts - z_hat[:, None]) / self.sqrt_2n
        return z_hat, xc, zc

    def measurement_update(self, y, h):
        """MODEL.md section 6 measurement update:
        X_j = S- xi_j + x-; Z_j = h(X_j); z = mean Z_j; Xc = (X_j - x-)/sqrt(2n);
        Zc = (Z_j - z)/sqrt(2n); S_zz = Tria([Zc, S_R]); P_xz = Xc Zc^T;
        K = (P_xz / S_zz^T) / S_zz; x = x- + K (y - z); S = Tria([Xc - K Zc, K S_R]).
        With self.linear the n columns of centred() instead of the 2n points.
        """
        z_hat, xc, zc = self.centred(h)
        s_zz = tria(np.hstack([zc, self.s_r]))
        p_xz = xc @ zc.T
        # K S_zz S_zz^T = P_xz: first W = P_xz S_zz^-T  (S_zz W^T = P_xz^T),
        # then K = W S_zz^-1  (S_zz^T K^T = W^T).  Two triangular solves, no inverse.
        w_t = solve_triangular(s_zz, p_xz.T, lower=True, check_finite=False)
        k_gain = solve_triangular(s_zz, w_t, lower=True, trans="T", check_finite=False).T
        self.x = self.x + k_gain @ (np.asarray(y, dtype=float) - z_hat)
        self.S = tria(np.hstack([xc - k_gain @ zc, k_gain @ self.s_r]))
        return k_gain

    def sd(self):
        """sqrt(diag(S S^T)) = row norms of S."""
        return np.sqrt(np.einsum("ij,ij->i", self.S, self.S))


class CKF:
    """The paper's cubature Kalman filter with the full covariance P (MODEL.md section 6)."""

    def __init__(self, x0, p0, q, r):
        self.x = np.array(x0, dtype=float)
        self.P = np.array(p0, dtype=float)
        self.q = np.array(q, dtype=float)
        self.r = np.array(r, dtype=float)
        self.n = self.x.size
        self.xi = cubature_unit_points(self.n)
        self.w = 1.0 / (2.0 * self.n)

    def points(self):
        """X_j = chol(P) xi_j + x (lower Cholesky factor), shape (n, 2n)."""
        return np.linalg.cholesky(self.P) @ self.xi + self.x[:, None]

    def time_update(self):
        """X*_j = X_j; x- = mean; P- = sum_j w X*_j X*_j^T - x- x-^T + Q."""
        x_star = self.points()
        x_mean = x_star.mean(axis=1)  # the moment formula needs the points' own mean
        self.P = self.w * (x_star @ x_star.T) - np.outer(x_mean, x_mean) + self.q
        self.x = self.x.copy()  # symmetric points: x- = x exactly (see SCKF.time_update)

    def time_update_steps(self, k: int):
        """k random-walk time updates at once (ckf_flt.c rfe_ckf_predict_steps): P + k Q."""
        self.P = self.P + k * self.q

    def q_diag(self):
        return np.diag(self.q).copy()

    def measurement_update(self, y, h):
        """Z_j = h(X_j); z = mean; P_zz = sum w Z Z^T - z z^T + R; P_xz = sum w X Z^T - x- z^T;
        K = P_xz P_zz^-1 (linear solve); x = x- + K (y - z); P = P- - K P_zz K^T."""
        pts = self.points()
        z_pts = np.asarray(h(pts), dtype=float)
        z_hat = z_pts.mean(axis=1)
        p_zz = self.w * (z_pts @ z_pts.T) - np.outer(z_hat, z_hat) + self.r
        p_xz = self.w * (pts @ z_pts.T) - np.outer(self.x, z_hat)
        k_gain = np.linalg.solve(p_zz, p_xz.T).T     # P_zz symmetric: K^T = P_zz^-1 P_xz^T
        self.x = self.x + k_gain @ (np.asarray(y, dtype=float) - z_hat)
        self.P = self.P - k_gain @ p_zz @ k_gain.T
        return k_gain

    def sd(self):
        return np.sqrt(np.diag(self.P))


UINT32_MAX = 2 ** 32 - 1


GAP_PERIODS = 2           # rfe/common.h RFE_GAP_PERIODS: a gap is longer than 2 periods,
GAP_STAMP_REL = 2.0 ** -20  # widened by RFE_GAP_STAMP_SHIFT for the time stamps' own rounding


def gap_periods(period: float, dt: float) -> int:
    """The sample periods a gap misses (src/host/log_timing.c rfe_log_missed): none up to
    2 dt (jitter; one dropped sample is not a gap), else round(period / dt) - 1, at most
    2^32 - 1; none for dt <= 0."""
    if not (dt > 0) or not (period > GAP_PERIODS * dt * (1.0 + GAP_STAMP_REL)):
        return 0
    return int(min(np.floor(period / dt + 0.5) - 1.0, UINT32_MAX))


def gap_steps(f, missed: int, prior_var: float) -> int:
    """The gap's time updates made (friction_flt.c gap_steps, docs/ESTIMATOR.md "Gaps"):
    missed, but at most until some state's variance reaches prior_var."""
    k = missed
    var = f.sd() ** 2
    for v, q in zip(var, f.q_diag()):
        if q > 0:
            room = max(prior_var - v, 0.0) / q
            if room < k:
                k = int(room)
    return k


def gap_time_update(f, t, k: int, p: dict) -> bool:
    """The gap before row k of time stamps t (docs/ESTIMATOR.md "Gaps", mu_replay's
    rfe_friction_skip): its time updates at once, up to the prior's variance. True when there
    was a gap (the caller then bounds the sd and restarts its input filter, as the step does)."""
    missed = gap_periods(t[k] - t[k - 1], p["dt"]) if k > 0 else 0
    if missed == 0:
        return False
    f.time_update_steps(gap_steps(f, missed, p["sd0"] ** 2 + p["sd0_common"] ** 2))
    return True
