#!/usr/bin/env python3
"""What the tyre identifier's lateral curve does to the friction estimator when the replay feeds
it (tid_feed_sd_rel, docs/TYRE_ID.md section 14), on every steering scenario.

    .venv/bin/python scripts/tools/tyre_id_feed_results.py [--page docs/TYRE_ID_RESULTS.md]
                     [--mu-replay build/mu_replay] [--jobs 2]

Every steering log (the scenarios whose driver steers: brake in turn, double lane change, ramp
steer, sine steer, the wrong tyre data, each with the Dugoff truth, the Magic Formula truth .mf
and the noise-free .nf; and the tyre identification logs scenarios/tyre_id/) is replayed by the
C library (`mu_replay`, float, the default preset) without the identifier and with each
identifier of FILTERS (`--tyre-id apf`, the auxiliary particle filter, and `--tyre-id sckf`,
the sigma-point filter of docs/TYRE_ID.md section 15) feeding at each (tid_feed_sd_rel,
tid_feed_evidence) of FEEDS: from the start, and only after 0.25 s of the friction
estimator's own evidence that its curve is wrong (time at a mu bound or in model mismatch).
Both filters feed by the same rule (the relative sd of the summed cornering stiffness, the
particles' spread for the APF, the row norms of the square-root covariance for the SCKF).
Per run, from the --metrics JSON, the figures pooled over the four wheels as the README's
trust table pools them (scripts/tools/wheel_figures.py):
    RMSE when valid         over the settled samples reported valid
    consistency when valid  the share of those with |error| <= 2 sd
    valid                   the share of the settled samples reported valid
    fed                     the share of samples whose curve the estimator took
A run "helps" when its RMSE when valid is lower and its consistency when valid no lower than
without the feed, and its valid share no more than 5 points lower (a feed that only silences
the estimate does not help). It "hurts" when its RMSE when valid is higher by more than 0.02
(issue 16's threshold for "no worse") or its consistency when valid lower by more than 0.05.
A run "meets" issue 20's targets when its RMSE when valid is <= 0.08 and its consistency when
valid >= 0.9 (no verdict without a valid sample); the count of logs that meet them is given
per column, "off" included.
Every fed run of that table has tid_feed_ax_max at its default (0.5 m/s^2: no curve fed after
a sample whose |ax| exceeds it, braking or driving). A second table, "before -> after", sets
each filter's ungated feeds of HOLD_FEEDS once with tid_feed_ax_max = 0 (no hold: before) and
once at the default (after), with the same rules and, per log, the verdict of the hold against
the run without it ("helps" / "hurts" as above with the unheld run as the base).
A third table, the friction ellipse (docs/TYRE_ID.md section 3.5), sets tid_ellipse = 1 on
each filter's ungated feeds of HOLD_FEEDS, once with the hold at its default and once without
it (tid_feed_ax_max 0), against the same feed without the ellipse (before -> after), with the
same rules, and per log the verdict of the ellipse against the run without it. Those runs
set tid_ell_ax_min = 0: the ellipse as first built, without its dead band.
A fourth table does the same with the ellipse's dead band at its default (tid_ell_ax_min
BAND: below that |ax| the ellipse takes ax as 0, TYRE_ID.md section 3.5).
With --page the tables go between <!-- tyre-feed:begin/end -->,
<!-- tyre-feed-hold:begin/end -->, <!-- tyre-feed-ellipse:begin/end --> and
<!-- tyre-feed-band:begin/end --> of the page.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from md_tables import replace_region  # noqa: E402
from wheel_figures import pooled  # noqa: E402

STEERING = ("brake_in_turn", "brake_in_turn_low_mu", "double_lane_change_high_mu",
            "double_lane_change_low_mu", "ramp_steer_high_mu", "ramp_steer_low_mu",
            "sine_steer_high_mu", "sine_steer_low_mu", "wrong_tyre_data")
VARIANTS = ("", ".mf", ".nf")
FEEDS = ((0.05, 0.0), (0.1, 0.0), (0.05, 0.25), (0.1, 0.25))  # (tid_feed_sd_rel, tid_feed_evidence)
VALID_DROP = 0.05  # the largest fall of the valid share a run that helps may have
RMSE_WORSE = 0.02  # a rise of the RMSE when valid that hurts (issue 16's "no worse")
CONS_WORSE = 0.05  # a fall of the consistency when valid that hurts
FILTERS = (("apf", "A"), ("sckf", "S"))  # (--tyre-id FILTER, its letter in the column labels)
RMSE_TARGET = 0.08  # issue 20: RMSE when valid with identified parameters at most this
CONS_TARGET = 0.9  # issue 20: consistency when valid at least this
HOLD_FEEDS = ((0.05, 0.0), (0.1, 0.0))  # the feeds of the before -> after table
HOLD_OFF = 0.0  # tid_feed_ax_max of the "before" runs: no hold
ELLIPSE_ON = 1.0  # tid_ellipse of the ellipse table's "after" runs (TYRE_ID.md section 3.5)
NO_BAND = 0.0  # tid_ell_ax_min of the third table's runs: the ellipse without its dead band
BAND = 0.6  # tid_ell_ax_min of the fourth table's runs: the key's default (TYRE_ID.md section 2)


def label(feed, letter=""):
    """The column label of a feed: the filter's letter, its tid_feed_sd_rel, the evidence
    asked for, tid_feed_ax_max when the feed sets it (a third entry not None; else the
    default), " E" when it sets tid_ellipse (a fourth entry), and "bX" after it when it sets
    the ellipse's dead band tid_ell_ax_min X > 0 (a fifth entry)."""
    return (f"{letter}{feed[0]:g}" + (f" e{feed[1]:g}" if feed[1] > 0 else "")
            + (f" a{feed[2]:g}" if len(feed) > 2 and feed[2] is not None else "")
            + (" E" if len(feed) > 3 and feed[3] else "")
            + (f"b{feed[4]:g}" if len(feed) > 4 and feed[4] else ""))


def columns():
    """The fed runs of a log, in column order: (filter, letter, feed), every feed of FEEDS for
    each filter of FILTERS in turn."""
    return [(flt, letter, feed) for flt, letter in FILTERS for feed in FEEDS]


def logs():
    out = [f"scenarios/{s}{v}.csv" for s in STEERING for v in VARIANTS]
    out += sorted(f"scenarios/tyre_id/{f}" for f in os.listdir(os.path.join(ROOT, "scenarios",
                                                                             "tyre_id"))
                  if f.endswith(".csv"))
    return out


def run(exe, log, flt, feed):
    """(RMSE when valid, consistency when valid, valid share, share fed) of one run; flt the
    --tyre-id filter, feed (tid_feed_sd_rel, tid_feed_evidence[, tid_feed_ax_max[,
    tid_ellipse[, tid_ell_ax_min]]]; without the third, or None, the key's default; without
    the fourth the ellipse's default, off; without the fifth the dead band's default), None:
    without the identifier."""
    with tempfile.TemporaryDirectory() as tmp:
        js = os.path.join(tmp, "m.json")
        args = [exe, "--in", os.path.join(ROOT, log), "--out", os.path.join(tmp, "e.csv"),
                "--metrics", js, "--quiet"]
        if feed is not None:
            par = os.path.join(tmp, "feed.params")
            with open(par, "w", encoding="utf-8") as fh:
                fh.write(f"tid_feed_sd_rel = {feed[0]!r}\ntid_feed_evidence = {feed[1]!r}\n")
                if len(feed) > 2 and feed[2] is not None:
                    fh.write(f"tid_feed_ax_max = {feed[2]!r}\n")
                if len(feed) > 3:
                    fh.write(f"tid_ellipse = {feed[3]!r}\n")
                if len(feed) > 4:
                    fh.write(f"tid_ell_ax_min = {feed[4]!r}\n")
            args += ["--tyre-id", flt, "--params", par]
        r = subprocess.run(args, capture_output=True, text=True, check=False)
        if r.returncode != 0:
            raise SystemExit(f"tyre_id_feed_results: {log} {flt} feed {feed}: "
                             f"exit {r.returncode}: {r.stderr.strip()}")
        with open(js, encoding="utf-8") as fh:
            j = json.load(fh)
    m = j["metrics"]
    fed = (j["tyre_id"]["feed"]["n_fed"] / j["steps"]) if feed is not None else 0.0
    return (pooled(m, "rmse_valid", "n_valid", square=True),
            pooled(m, "consistency_valid", "n_valid"), pooled(m, "frac_valid", "n_settled"), fed)


def helps(base, fed):
    """The rule of the docstring; None when either run has no valid sample."""
    if base[0] is None or fed[0] is None:
        return None
    return fed[0] < base[0] and fed[1] >= base[1] and fed[2] >= base[2] - VALID_DROP


def hurts(base, fed):
    """The rule of the docstring; None when either run has no valid sample."""
    if base[0] is None or fed[0] is None:
        return None
    return fed[0] > base[0] + RMSE_WORSE or fed[1] < base[1] - CONS_WORSE


def meets(r):
    """Issue 20's targets on one run; None when it has no valid sample."""
    if r[0] is None:
        return None
    return r[0] <= RMSE_TARGET and r[1] >= CONS_TARGET


def hold_columns():
    """The before -> after pairs: (filter, letter, feed without the hold, feed at the default),
    each filter of FILTERS with each feed of HOLD_FEEDS."""
    return [(flt, letter, (f[0], f[1], HOLD_OFF), f) for flt, letter in FILTERS
            for f in HOLD_FEEDS]


def ellipse_columns(band=NO_BAND):
    """The ellipse table's pairs: (filter, letter, feed without the ellipse, the same feed with
    tid_ellipse on and the dead band @p band), each filter of FILTERS with each feed of
    HOLD_FEEDS, held at the default (the main table's run the base) and without the hold."""
    out = []
    for flt, letter in FILTERS:
        for f in HOLD_FEEDS:
            out.append((flt, letter, f, (f[0], f[1], None, ELLIPSE_ON, band)))
            out.append((flt, letter, (f[0], f[1], HOLD_OFF),
                        (f[0], f[1], HOLD_OFF, ELLIPSE_ON, band)))
    return out


HOLD_WORDS = (f"tid_feed_ax_max {HOLD_OFF:g} (no hold, aX: its value) → the default",
              "the hold", "no hold")  # the hold table's: before -> after, the change, its base
ELLIPSE_WORDS = ("the feed without the friction ellipse (tid_ellipse 0) → with it (E: "
                 "tid_ellipse 1, tid_ell_ax_min 0: no dead band), held at the default or not "
                 "(aX: tid_feed_ax_max X)", "the ellipse", "no ellipse")
BAND_WORDS = ("the feed without the friction ellipse (tid_ellipse 0) → with it and its dead "
              f"band (EbX: tid_ellipse 1, tid_ell_ax_min X, the default {BAND:g} m/s²), held at "
              "the default or not (aX: tid_feed_ax_max X)", "the ellipse with its band",
              "no ellipse")


def hold_table(names, res, pairs=None, words=HOLD_WORDS):
    """The before -> after table's lines (the docstring's second table; with @p pairs and
    @p words, the third) from the runs @p res."""
    pairs = hold_columns() if pairs is None else pairs
    heads = " / ".join(f"{label(b, letter)} → {label(f, letter)}" for _, letter, b, f in pairs)
    rows = [f"| log | RMSE when valid: off / {heads} | consistency when valid: off / {heads} "
            f"| valid: off / {heads} | fed: {heads} | {words[1]} helps / hurts against "
            f"{words[2]} |",
            "|---|---|---|---|---|---|"]
    vs_off = {p: [[0, 0], [0, 0]] for p in pairs}  # per pair, before and after: helps, hurts
    met = {p: [0, 0] for p in pairs}
    hold = {p: [0, 0] for p in pairs}
    for log in names:
        base = res[(log, None, None)]
        cells = [[cell(base[0], ".3f")], [cell(base[1], ".2f")], [cell(base[2], ".0%")], [], []]
        for p in pairs:
            b, a = res[(log, p[0], p[2])], res[(log, p[0], p[3])]
            cells[0].append(f"{cell(b[0], '.3f')} → {cell(a[0], '.3f')}")
            cells[1].append(f"{cell(b[1], '.2f')} → {cell(a[1], '.2f')}")
            cells[2].append(f"{cell(b[2], '.0%')} → {cell(a[2], '.0%')}")
            cells[3].append(f"{b[3]:.0%} → {a[3]:.0%}")
            h, u = helps(b, a), hurts(b, a)
            hold[p][0] += 1 if h else 0
            hold[p][1] += 1 if u else 0
            cells[4].append("–" if h is None else ("helps" if h else ("hurts" if u else "=")))
            for k, r in enumerate((b, a)):
                vs_off[p][k][0] += 1 if helps(base, r) else 0
                vs_off[p][k][1] += 1 if hurts(base, r) else 0
                met[p][k] += 1 if meets(r) else 0
        name = log[len("scenarios/"):-len(".csv")]
        rows.append(f"| {name} | " + " | ".join(" / ".join(c) for c in cells) + " |")
    rows.append("")
    rows.append(f"Before → after: {words[0]}. Helps / hurts against off: "
                + "; ".join(f"{label(p[3], p[1])}: {vs_off[p][0][0]} / {vs_off[p][0][1]} → "
                            f"{vs_off[p][1][0]} / {vs_off[p][1][1]}" for p in pairs)
                + ". Meets issue 20's targets: "
                + "; ".join(f"{label(p[3], p[1])}: {met[p][0]} → {met[p][1]}" for p in pairs)
                + f". {words[1][0].upper()}{words[1][1:]} against {words[2]}, helps / hurts: "
                + "; ".join(f"{label(p[3], p[1])}: {hold[p][0]} / {hold[p][1]}" for p in pairs)
                + ".")
    return rows


def cell(x, fmt):
    return "–" if x is None else format(x, fmt)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mu-replay", default=os.path.join(ROOT, "build", "mu_replay"))
    ap.add_argument("--page", default="")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    if not os.access(a.mu_replay, os.X_OK):
        raise SystemExit(f"tyre_id_feed_results: {a.mu_replay} not found: run make first")
    names = logs()
    cols = columns()
    jobs = [(log, None, None) for log in names] + [(log, c[0], c[2]) for log in names
                                                   for c in cols]
    jobs += [(log, p[0], p[2]) for log in names for p in hold_columns()]
    jobs += [(log, p[0], p[3]) for log in names for p in ellipse_columns()]
    jobs += [(log, p[0], p[3]) for log in names for p in ellipse_columns(BAND)]
    done = [0]

    def one(job):
        out = run(a.mu_replay, *job)
        done[0] += 1
        if done[0] % 20 == 0 or done[0] == len(jobs):
            print(f"tyre_id_feed_results: {done[0]} / {len(jobs)} runs", file=sys.stderr,
                  flush=True)
        return out

    with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        res = dict(zip(jobs, ex.map(one, jobs)))
    labels = [label(c[2], c[1]) for c in cols]
    feeds = " / ".join(labels)
    rows = [f"| log | RMSE when valid: off / {feeds} | consistency when valid: off / {feeds} "
            f"| valid: off / {feeds} | fed: {feeds} | helps: {feeds} |",
            "|---|---|---|---|---|---|"]
    count = {c: [0, 0, 0] for c in cols}
    met = [[0, 0] for _ in range(len(cols) + 1)]
    for log in names:
        runs = [res[(log, None, None)]] + [res[(log, c[0], c[2])] for c in cols]
        h = [helps(runs[0], r) for r in runs[1:]]
        for c, x, r in zip(cols, h, runs[1:]):
            count[c][0] += 1 if x else 0
            count[c][1] += 1 if x is not None else 0
            count[c][2] += 1 if hurts(runs[0], r) else 0
        for k, r in enumerate(runs):
            m = meets(r)
            met[k][0] += 1 if m else 0
            met[k][1] += 1 if m is not None else 0
        name = log[len("scenarios/"):-len(".csv")]
        rows.append(f"| {name} | " + " / ".join(cell(r[0], ".3f") for r in runs) + " | "
                    + " / ".join(cell(r[1], ".2f") for r in runs) + " | "
                    + " / ".join(cell(r[2], ".0%") for r in runs) + " | "
                    + " / ".join(f"{r[3]:.0%}" for r in runs[1:]) + " | "
                    + " / ".join("–" if x is None else ("yes" if x else "no") for x in h) + " |")
    rows.append("")
    rows.append("Columns: A the APF's curve fed, S the SCKF's; the number its tid_feed_sd_rel, "
                "eX: after X s of evidence.")
    rows.append("")
    rows.append("Helps / hurts (of the logs with valid samples both ways): "
                + "; ".join(f"{lab}: {count[c][0]} / {count[c][2]} of {count[c][1]}"
                            for lab, c in zip(labels, cols)) + ".")
    rows.append("")
    rows.append(f"Meets issue 20's targets (RMSE when valid <= {RMSE_TARGET:g}, consistency "
                f"when valid >= {CONS_TARGET:g}; of the logs with valid samples): "
                + "; ".join(f"{lab}: {m[0]} of {m[1]}" for lab, m in zip(["off"] + labels, met))
                + ".")
    text = "\n".join(rows)
    print(text)
    held = hold_table(names, res)
    print("\n".join(held))
    ell = hold_table(names, res, ellipse_columns(), ELLIPSE_WORDS)
    print("\n".join(ell))
    band = hold_table(names, res, ellipse_columns(BAND), BAND_WORDS)
    print("\n".join(band))
    if a.page:
        replace_region(Path(a.page), "<!-- tyre-feed:begin -->", "<!-- tyre-feed:end -->",
                       text.splitlines(), "tyre_id_feed_results")
        replace_region(Path(a.page), "<!-- tyre-feed-hold:begin -->",
                       "<!-- tyre-feed-hold:end -->", held, "tyre_id_feed_results")
        replace_region(Path(a.page), "<!-- tyre-feed-ellipse:begin -->",
                       "<!-- tyre-feed-ellipse:end -->", ell, "tyre_id_feed_results")
        replace_region(Path(a.page), "<!-- tyre-feed-band:begin -->",
                       "<!-- tyre-feed-band:end -->", band, "tyre_id_feed_results")


if __name__ == "__main__":
    main()
