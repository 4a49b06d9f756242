"""Operation-count lower bound of one estimator step (issue 8, docs/BENCHMARKS.md).

Counts the arithmetic one step of the paper's filter needs at minimum for n states and m
measurements: every +, -, *, /, sqrt and every transcendental call (sin, cos, tan, atan2)
counts as one operation; comparisons, clamps, copies, loads and stores count nothing. Each
stage is counted as the dense formula MODEL.md section 6 writes, done once, with only the
structure that is there for free exploited (S is lower-triangular, the cubature points are
x +- sqrt(n) S e_j, so the centred state points are +-S/sqrt(2)); no algebraic re-design
(e.g. no Kalman filter on the linear paper model) is assumed. The random walk's time update
needs no cubature points at all: SCKF S- = Tria([S, S_Q]) (n x 2n), CKF P- = P + Q.

For the fixed-point build the same count is a count of integer multiply-accumulates and
divisions/square roots (each one operation), so the same bound applies.

Householder Tria() of an r x c matrix (r <= c), per row k (tail length L = c - k): the norm,
2L + 1 (sqrt); the reflection of each of the r - k - 1 rows below: a dot product (2L), the
scale (2) and the update (2L).
"""

from __future__ import annotations


def tria_ops(r: int, c: int) -> int:
    ops = 0
    for k in range(r):
        tail = c - k
        ops += 2 * tail + 1
        ops += (r - k - 1) * (4 * tail + 2)
    return ops


def chol_ops(n: int) -> int:
    """Cholesky of an n x n SPD matrix: diagonal 2j + 1 (sqrt), each below 2j + 1 (divide)."""
    ops = 0
    for j in range(n):
        ops += 2 * j + 1
        ops += (n - j - 1) * (2 * j + 1)
    return ops


def tri_solve_ops(m: int, ncols: int) -> int:
    """One triangular solve L X = B, L m x m, B m x ncols: per column m^2 (mult-adds, divides)."""
    return ncols * m * m


# Tyre model per step, four wheels (counted from MODEL.md sections 3-5):
#   kinematics per wheel: body velocity at the wheel 4, rotation into wheel axes 6 (front
#   wheels only), omega R 1, slip kappa 2, atan2 1; loads 11 for all four; sin, cos of delta 2;
#   Dugoff (paper, normalised) per wheel: tan 1, S 6, slip norm 4, E 3, L 4, g 3, F0x, F0y 6;
#   H(u) column per wheel: rotation 6 (front only), three entries 6.
KIN_PER_WHEEL_FRONT = 4 + 6 + 1 + 2 + 1
KIN_PER_WHEEL_REAR = 4 + 1 + 2 + 1
KIN_COMMON = 11 + 2
DUGOFF_NORM = 1 + 6 + 4 + 3 + 4 + 3 + 6
H_FRONT = 6 + 6
H_REAR = 6
#   absolute (load-scaled) Dugoff: the mu-independent part per wheel once per step (tan 1,
#   S 6, slip 4, E 3, (1-|k|) E / (2S) 3, F directions 4) and per cubature point and wheel
#   L = mu c 1, g 3, Fx, Fy 2, rotation 6 (front) and three body sums 6.
ABS_WHEEL_SETUP = 1 + 6 + 4 + 3 + 3 + 4
ABS_POINT_FRONT = 1 + 3 + 2 + 6 + 6
ABS_POINT_REAR = 1 + 3 + 2 + 6


def tyre_ops(tyre: str, n_points: int) -> dict:
    kin = 2 * KIN_PER_WHEEL_FRONT + 2 * KIN_PER_WHEEL_REAR + KIN_COMMON
    if tyre == "paper":
        return {"tyre: kinematics, loads": kin,
                "tyre: Dugoff (once per step)": 4 * DUGOFF_NORM,
                "tyre: H(u)": 2 * H_FRONT + 2 * H_REAR}
    return {"tyre: kinematics, loads": kin,
            "tyre: Dugoff, mu-independent part": 4 * ABS_WHEEL_SETUP,
            "tyre: Dugoff at each cubature point": n_points * (2 * ABS_POINT_FRONT
                                                               + 2 * ABS_POINT_REAR)}


def step_ops(filt: str, tyre: str, n: int = 4, m: int = 3) -> dict:
    """Itemised minimum operations of one step with a measurement update."""
    npts = 2 * n
    tri = n * (n + 1) // 2
    items: dict[str, int] = {}
    items.update(tyre_ops(tyre, npts))
    if filt == "sckf":
        items["time update: Tria([S, S_Q]) n x 2n"] = tria_ops(n, 2 * n)
    else:
        items["time update: P + Q"] = tri
        items["Cholesky of P-"] = chol_ops(n)
    items["cubature points x +- sqrt(n) S e_j"] = tri + 2 * tri
    if tyre == "paper":
        items["propagation Z_j = H X_j"] = npts * m * (2 * n - 1)
    items["predicted measurement z"] = m * (npts - 1) + m
    if filt == "sckf":
        items["centring Zc, Xc = +-S/sqrt(2)"] = 2 * npts * m + tri
        items["Tria([Zc, S_R]) m x (2n+m)"] = tria_ops(m, npts + m)
        items["P_xz = Xc Zc^T"] = n * m * (2 * npts - 1)
        items["gain: two triangular solves"] = 2 * tri_solve_ops(m, n)
        items["x = x- + K (y - z)"] = m + 2 * n * m
        items["[Xc - K Zc, K S_R]"] = n * npts * 2 * m + n * m * (m + 1)
        items["Tria(posterior) n x (2n+m)"] = tria_ops(n, npts + m)
        items["sd = row norms of S"] = 2 * tri + n
    else:
        items["P_zz = w sum Z Z^T - z z^T + R"] = (m * (m + 1) // 2) * (2 * npts + 3)
        items["P_xz = w sum X Z^T - x z^T"] = n * m * (2 * npts + 3)
        items["Cholesky of P_zz"] = chol_ops(m)
        items["gain: two triangular solves"] = 2 * tri_solve_ops(m, n)
        items["x = x- + K (y - z)"] = m + 2 * n * m
        items["P = P- - K P_zz K^T"] = n * m * (2 * m - 1) + tri * (2 * m)
        items["sd = sqrt(diag P)"] = n
    return items


def step_total(filt: str, tyre: str, n: int = 4, m: int = 3) -> int:
    return sum(step_ops(filt, tyre, n, m).values())


if __name__ == "__main__":
    for f in ("sckf", "ckf"):
        for t in ("paper", "absolute"):
            items = step_ops(f, t)
            print(f"{f} {t}: {sum(items.values())} operations")
            for k, v in items.items():
                print(f"  {v:5d}  {k}")
