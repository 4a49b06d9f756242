"""mu_replay's per-wheel metrics (src/host/metrics.c, its JSON) pooled over the four wheels:
one code path for the demo's tables, the observer results and the trust invariant."""
from __future__ import annotations

WHEELS = ("fl", "fr", "rl", "rr")


def pooled(m: dict, key: str, weight: str, square: bool = False):
    """A per-wheel figure pooled over the four wheels, weighted by each wheel's sample count
    (RMS figures pooled as RMS). None when no wheel has samples."""
    num = den = 0.0
    for w in WHEELS:
        x, n = m[w].get(key), m[w].get(weight) or 0
        if x is None or n == 0:
            continue
        num += n * (x * x if square else x)
        den += n
    if den == 0:
        return None
    return (num / den) ** 0.5 if square else num / den


def worst_valid(m: dict):
    """The worst case when valid: the largest |error| of any wheel over its settled samples
    reported valid (None when no wheel has one)."""
    xs = [m[w]["max_abs_err_valid"] for w in WHEELS
          if (m[w].get("n_valid") or 0) > 0 and m[w].get("max_abs_err_valid") is not None]
    return max(xs) if xs else None
