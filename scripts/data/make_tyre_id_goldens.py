"""Generate the goldens of the tyre identifier (docs/TYRE_ID.md) with the float64 reference
(scripts/reference/tyre_id.py, backend libm: the platform's C library, element by element,
so that the C library's double build reproduces it bit for bit), for the C tests.

Usage (from the repository root):

    .venv/bin/python scripts/data/make_tyre_id_goldens.py [--n 256] \
        [--out scenarios/golden/tyre_id]

Writes <out>/<case>.csv for each case of CASES: a few samples of one log of
scenarios/ (the tyre-id logs, and brake_in_turn.mf for the friction ellipse) from row
`start` on (the first of them initialises the filter), with one
filter and one resampling scheme, the reference's defaults otherwise (params.DEFAULTS and
TID_DEFAULTS: the C library's rfe_params_default and rfe_tyre_id_params_default), tid_n =
--n (the C build's RFE_TID_N), seed SEED. Columns: t, status, n_eff and each output's mean
(name) and sd (sd_name). The configuration is in the file's metadata.

And <out>/<case>.csv for each case of SCKF_CASES: the sigma-point filter of §15
(scripts/reference/tyre_id_sckf.py, backend libm), the same columns (n_eff NaN).

And <out>/stream.csv: words, uniforms and normals of the random stream (§6) at a few
(seed, c1, c2) and word indices, the words split in 32-bit halves (exact in a double).

Deterministic: running it twice writes identical bytes (plain Python floats; the libm
backend has no SIMD kernel on its path). The sigma-point filter's goldens go through NumPy's
BLAS and LAPACK (its QR, products), whose kernels depend on the CPU (OPENBLAS_CORETYPE): on
another machine their last bits may change, within the bound test_tyre_id_golden_flt.c derives
(never compare them byte for byte across CPUs).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

sys.path[:0] = [os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]
import numpy as np  # noqa: E402

from reference import philox, tyre_id, tyre_id_sckf  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402

SEED = 7
# tid_delta_q of the steering-angle filter's goldens (TYRE_ID.md §4.4; TYRE_ID_RESULTS.md "The
# steering-angle filter": the value measured there)
DELTA_Q = 0.05
# tid_delta_state_q of the sigma-point filter's golden with the steering angle as its state
# (TYRE_ID.md §15.7; TYRE_ID_RESULTS.md "The steering angle as a state of the SCKF": the value
# recommended there)
DELTA_STATE_Q = 0.04
# (case, log under scenarios/, filter, resample, first row, samples[, tid_ellipse,
# tid_ell_ax_min]): both filters and both schemes, the start of a log (the prior, the first
# draws) and the middle of a manoeuvre at the limit; and the friction ellipse (TYRE_ID.md
# §3.5) on brake in turn with the Magic Formula truth, from just before its braking (t = 2 s)
# into it, without the dead band (0: the ellipse as first built, bit for bit) and with the
# default's (|ax| crosses it about 0.05 s into the braking)
CASES = (
    ("sine_apf_multinomial", "tyre_id/tid_sine_steer", "apf", "multinomial", 0, 25),
    ("ramp_apf_systematic", "tyre_id/tid_ramp_steer_high_mu", "apf", "systematic", 650, 25),
    ("dlc_sir_multinomial", "tyre_id/tid_dlc_high_mu", "sir", "multinomial", 150, 25),
    ("change_sir_systematic", "tyre_id/tid_tyre_change", "sir", "systematic", 790, 25),
    ("brake_apf_ellipse", "brake_in_turn.mf", "apf", "multinomial", 190, 25, 1, 0.0),
    ("brake_apf_ellipse_band", "brake_in_turn.mf", "apf", "multinomial", 190, 25, 1,
     tyre_id.TID_DEFAULTS["tid_ell_ax_min"]),
    # the steering-angle filter of TYRE_ID.md §4.4 (tid_delta_q, last) from the log's start
    ("sine_apf_delta_filter", "tyre_id/tid_sine_steer", "apf", "multinomial", 0, 25, 0, 0.0,
     DELTA_Q),
)
# The sigma-point filter of §15 (tyre_id_sckf.py; deterministic, no seed): (case, log, first
# row, samples[, tid_ellipse, tid_ell_ax_min]): the start of the sine steer (the prior, the
# stiffness found), the ramp steer from its straight run into the limit (the peak found, the
# bounds reached), and brake in turn with the friction ellipse (no dead band) from its steady
# turn through the braking's start
SCKF_CASES = (
    ("sine_sckf", "tyre_id/tid_sine_steer", 0, 200),
    ("ramp_sckf", "tyre_id/tid_ramp_steer_high_mu", 500, 200),
    ("brake_sckf_ellipse", "brake_in_turn.mf", 100, 200, 1, 0.0),
    # the steering-angle filter (§4.4) on the low-mu ramp steer, from its straight start
    ("ramp_low_sckf_delta_filter", "tyre_id/tid_ramp_steer_low_mu", 0, 200, 0, 0.0, DELTA_Q),
    # the steering angle as the filter's eleventh state (§15.7) on the same log and rows
    ("ramp_low_sckf_delta_state", "tyre_id/tid_ramp_steer_low_mu", 0, 200, 0, 0.0, 0.0,
     DELTA_STATE_Q),
)
# (seed, c1, c2, first word, words) of the stream check
STREAM = ((1, 0, 0, 0, 16), (7, 3, 1, 40, 12), (2 ** 64 - 1, 2 ** 40 + 5, 4, 1000, 8))


def samples(log, start, count):
    """The identifier's input columns: rows start .. start + count - 1 of the log (its path
    under scenarios/ without .csv)."""
    c = read_csv_log(os.path.join("scenarios", log + ".csv")).columns
    return {k: np.asarray(c[k][start:start + count], dtype=float) for k in tyre_id.SAMPLE_KEYS}


def table(out):
    """The golden's column names (t, status, n_eff, then each output and its sd) and rows."""
    names = ["t", "status", "n_eff"]
    for k in tyre_id.OUTPUT_NAMES:
        names += [k, "sd_" + k]
    return names, zip(*(out[k] for k in names))


def ellipse_keys(ellipse, ax_min=0.0, delta_q=0.0, delta_state_q=0.0):
    """The keys a case sets beyond the defaults (tid_ellipse and its dead band
    tid_ell_ax_min when on; tid_delta_q, tid_delta_state_q when not 0), and their metadata."""
    keys, meta = {}, []
    if ellipse:
        keys = {"tid_ellipse": 1.0, "tid_ell_ax_min": float(ax_min)}
        meta = [("tid_ellipse", 1), ("tid_ell_ax_min", f"{ax_min:g}")]
    if delta_q:
        keys["tid_delta_q"] = float(delta_q)
        meta.append(("tid_delta_q", f"{delta_q:g}"))
    if delta_state_q:
        keys["tid_delta_state_q"] = float(delta_state_q)
        meta.append(("tid_delta_state_q", f"{delta_state_q:g}"))
    return keys, meta


def golden(log, filt, scheme, start, count, n, ellipse=0, ax_min=0.0, delta_q=0.0):
    cols = samples(log, start, count)
    extra, extra_meta = ellipse_keys(ellipse, ax_min, delta_q)
    params = {"tid_n": float(n), "tid_filter": filt, "tid_resample": scheme, **extra}
    out = tyre_id.run(cols, params, seed=SEED, backend="libm")
    meta = [("source", f"scenarios/{log}.csv"), ("generator", "scripts/reference/tyre_id.py"),
            ("backend", "libm"), ("first_row", start), ("samples", count), ("seed", SEED),
            ("tid_n", n), ("tid_filter", filt), ("tid_resample", scheme)] + extra_meta + [
            ("params", "params.DEFAULTS and TID_DEFAULTS")]
    return (meta,) + table(out)


def golden_sckf(log, start, count, ellipse=0, ax_min=0.0, delta_q=0.0, delta_state_q=0.0):
    cols = samples(log, start, count)
    extra, extra_meta = ellipse_keys(ellipse, ax_min, delta_q, delta_state_q)
    out = tyre_id_sckf.run(cols, extra, backend="libm")  # tid_filter does not apply (§15.1)
    meta = [("source", f"scenarios/{log}.csv"),
            ("generator", "scripts/reference/tyre_id_sckf.py"), ("backend", "libm"),
            ("first_row", start), ("samples", count), ("tid_filter", "sckf")] + extra_meta + [
            ("params", "params.DEFAULTS and TID_DEFAULTS")]
    return (meta,) + table(out)


def stream_rows():
    names = ["seed_hi", "seed_lo", "c1_hi", "c1_lo", "c2", "n", "w_hi", "w_lo", "uniform",
             "normal"]
    rows = []
    for seed, c1, c2, first, count in STREAM:
        m = first + count
        w = philox.words((seed, 0), c1, c2, 0, m)
        u = philox.uniforms_from_words(w)
        z = philox.normals_from_words(w, tyre_id.LIBM)
        for i in range(first, m):
            wi = int(w[i])
            rows.append((seed >> 32, seed & 0xFFFFFFFF, c1 >> 32, c1 & 0xFFFFFFFF, c2, i,
                         wi >> 32, wi & 0xFFFFFFFF, float(u[i]), float(z[i])))
    meta = [("generator", "scripts/reference/philox.py"), ("backend", "libm"),
            ("what", "word n of key (seed, 0), counter (n // 4, c1, c2, 0); uniform n; normal n")]
    return meta, names, rows


def write(path, meta, cols, rows):
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        for k, v in meta:
            fh.write(f"# {k} = {v}\n")
        fh.write(",".join(cols) + "\n")
        for row in rows:
            fh.write(",".join(repr(float(v)) for v in row) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=256, help="particles (the C build's RFE_TID_N)")
    ap.add_argument("--out", default=os.path.join("scenarios", "golden", "tyre_id"))
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    t0 = time.time()
    write(os.path.join(a.out, "stream.csv"), *stream_rows())
    for i, (case, *spec) in enumerate(CASES, 1):
        write(os.path.join(a.out, case + ".csv"), *golden(*spec[:5], a.n, *spec[5:]))
        print(f"[{i}/{len(CASES)}] {case} ({time.time() - t0:.0f} s)", flush=True)
    for case, *spec in SCKF_CASES:
        write(os.path.join(a.out, case + ".csv"), *golden_sckf(*spec))
        print(f"[sckf] {case} ({time.time() - t0:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
