#!/usr/bin/env python3
"""What the tyre identifier's lateral curve does to the friction estimator when the replay feeds
it (tid_feed_sd_rel, docs/TYRE_ID.md section 14), on every steering scenario.

    .venv/bin/python scripts/tools/tyre_id_feed_results.py [--page docs/TYRE_ID_RESULTS.md]
                     [--mu-replay build/mu_replay] [--jobs 2]

Every steering log (the scenarios whose driver steers: brake in turn, double lane change, ramp
steer, sine steer, the wrong tyre data, each with the Dugoff truth, the Magic Formula truth .mf
and the noise-free .nf; and the tyre identification logs scenarios/tyre_id/) is replayed by the
C library (`mu_replay`, float, the default preset) without the identifier and with each
identifier of FEED_FILTERS (`--tyre-id apf`, the auxiliary particle filter, `--tyre-id sir`,
the bootstrap (SIR) particle filter, and `--tyre-id sckf`, the sigma-point filter of
docs/TYRE_ID.md section 15) feeding at each (tid_feed_sd_rel, tid_feed_evidence) of FEEDS:
from the start, and only after 0.25 s of the friction estimator's own evidence that its curve
is wrong (time at a mu bound or in model mismatch). Every filter feeds by the same rule (the
relative sd of the summed cornering stiffness, the particles' spread for the APF and SIR, the
row norms of the square-root covariance for the SCKF). The bootstrap filter is in the first
table only (issue 20's three-way comparison on the feed's effect); the other three tables
compare changes of the feed on the filters of FILTERS (the APF, the SCKF).
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
The APF and SIR draw from a seeded random stream, and a change of the float32 arithmetic moves
their draws, so one seed's figure carries that draw's noise: in the first table each APF and
SIR column is run once per tid_seed of SEEDS (the first the preset's default) and its cells
give the median over the seeds and [min-max] where the seeds differ; its helps (hurts) cell
counts the seeds on which the feed helps (hurts); the counts (helps, hurts, meets) are counted
per seed and given as the median and [min-max] over the seeds. The SCKF is deterministic: one
run.
Every fed run of that table has tid_feed_ax_max at its default (0.5 m/s^2: no curve fed after
a sample whose |ax| exceeds it, braking or driving). The other three tables run their APF
pairs over the same seeds, each seed's "before" and "after" from the same seed: their cells
give the median and [min-max] over the seeds, their verdict cells the number of seeds on
which the change helps (hurts) against the "before" of the same seed, their counts per seed
as the median and [min-max]. A second table, "before -> after", sets each filter's ungated feeds of HOLD_FEEDS once
with tid_feed_ax_max = 0 (no hold: before) and
once at the default (after), with the same rules and, per log, the verdict of the hold against
the run without it ("helps" / "hurts" as above with the unheld run as the base).
A third table, the friction ellipse (docs/TYRE_ID.md section 3.5), sets tid_ellipse = 1 on
each filter's ungated feeds of HOLD_FEEDS, once with the hold at its default and once without
it (tid_feed_ax_max 0), against the same feed without the ellipse (before -> after), with the
same rules, and per log the verdict of the ellipse against the run without it. Those runs
set tid_ell_ax_min = 0: the ellipse as first built, without its dead band.
A fourth table does the same with the ellipse's dead band at its default (tid_ell_ax_min
BAND: below that |ax| the ellipse takes ax as 0, TYRE_ID.md section 3.5).
A fifth table, the SCKF's steering angle as a state (docs/TYRE_ID.md section 15.7), sets
tid_delta_state_q DSTATE_Q on the SCKF at each feed of FEEDS (the first table's S columns,
the hold at its default), against the same feed without it (the first table's S run: before
-> after), with the same rules, and per log the verdict of the delta state against the run
without it. The SCKF is deterministic: one run per pair.
With --page the tables go between <!-- tyre-feed:begin/end -->,
<!-- tyre-feed-hold:begin/end -->, <!-- tyre-feed-ellipse:begin/end -->,
<!-- tyre-feed-band:begin/end --> and <!-- tyre-feed-dstate:begin/end --> of the page.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
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
# The first table's filters: FILTERS with the bootstrap filter (B) between the two, so the
# particle filters stand side by side (issue 20 deliverable 3's APF / SIR / SCKF comparison)
FEED_FILTERS = (("apf", "A"), ("sir", "B"), ("sckf", "S"))
RMSE_TARGET = 0.08  # issue 20: RMSE when valid with identified parameters at most this
CONS_TARGET = 0.9  # issue 20: consistency when valid at least this
HOLD_FEEDS = ((0.05, 0.0), (0.1, 0.0))  # the feeds of the before -> after table
HOLD_OFF = 0.0  # tid_feed_ax_max of the "before" runs: no hold
ELLIPSE_ON = 1.0  # tid_ellipse of the ellipse table's "after" runs (TYRE_ID.md section 3.5)
NO_BAND = 0.0  # tid_ell_ax_min of the third table's runs: the ellipse without its dead band
BAND = 0.6  # tid_ell_ax_min of the fourth table's runs: the key's default (TYRE_ID.md section 2)
# tid_delta_state_q of the fifth table's "after" runs: the SCKF's delta as a state (TYRE_ID.md
# section 15.7), the density docs/TYRE_ID_RESULTS.md recommends for the SCKF's curve
DSTATE_Q = 0.04
DSTATE_FILTER = ("sckf", "S")  # the one filter with the delta state
SEEDS = (1, 2, 3, 4, 5)  # tid_seed of each seeded filter's runs in every table; the first is
# the preset's (RFE_TID_SEED_DEFAULT), its runs keyed without a seed; five draws over the four
# tables take the make target to about 25 min on 2 shared cores, the bootstrap filter's five
# draws of the first table about 10 min more (docs/TYRE_ID_RESULTS.md)
SEEDED = ("apf", "sir")  # the filters with a random stream; the SCKF is deterministic


def label(feed, letter=""):
    """The column label of a feed: the filter's letter, its tid_feed_sd_rel, the evidence
    asked for, tid_feed_ax_max when the feed sets it (a third entry not None; else the
    default), " E" when it sets tid_ellipse (a fourth entry), "bX" after it when it sets
    the ellipse's dead band tid_ell_ax_min X > 0 (a fifth entry), and " dX" when it sets the
    SCKF's delta state tid_delta_state_q X > 0 (a sixth entry)."""
    return (f"{letter}{feed[0]:g}" + (f" e{feed[1]:g}" if feed[1] > 0 else "")
            + (f" a{feed[2]:g}" if len(feed) > 2 and feed[2] is not None else "")
            + (" E" if len(feed) > 3 and feed[3] else "")
            + (f"b{feed[4]:g}" if len(feed) > 4 and feed[4] else "")
            + (f" d{feed[5]:g}" if len(feed) > 5 and feed[5] else ""))


def columns():
    """The first table's fed runs of a log, in column order: (filter, letter, feed), every feed
    of FEEDS for each filter of FEED_FILTERS in turn."""
    return [(flt, letter, feed) for flt, letter in FEED_FILTERS for feed in FEEDS]


def logs():
    out = [f"scenarios/{s}{v}.csv" for s in STEERING for v in VARIANTS]
    out += sorted(f"scenarios/tyre_id/{f}" for f in os.listdir(os.path.join(ROOT, "scenarios",
                                                                             "tyre_id"))
                  if f.endswith(".csv"))
    return out


def run(exe, log, flt, feed, seed=None):
    """(RMSE when valid, consistency when valid, valid share, share fed) of one run; flt the
    --tyre-id filter, feed (tid_feed_sd_rel, tid_feed_evidence[, tid_feed_ax_max[,
    tid_ellipse[, tid_ell_ax_min[, tid_delta_state_q]]]]; an entry left out, or None, is not
    written: the key's default), None: without the identifier; seed the tid_seed written
    (None: not written, the preset's)."""
    with tempfile.TemporaryDirectory() as tmp:
        js = os.path.join(tmp, "m.json")
        args = [exe, "--in", os.path.join(ROOT, log), "--out", os.path.join(tmp, "e.csv"),
                "--metrics", js, "--quiet"]
        if feed is not None:
            par = os.path.join(tmp, "feed.params")
            with open(par, "w", encoding="utf-8") as fh:
                fh.write(f"tid_feed_sd_rel = {feed[0]!r}\ntid_feed_evidence = {feed[1]!r}\n")
                for key, x in zip(("tid_feed_ax_max", "tid_ellipse", "tid_ell_ax_min",
                                   "tid_delta_state_q"), feed[2:]):
                    if x is not None:
                        fh.write(f"{key} = {x!r}\n")
                if seed is not None:
                    fh.write(f"tid_seed = {int(seed)}\n")
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


def dstate_columns():
    """The fifth table's pairs: (filter, letter, feed, the same feed with tid_delta_state_q
    DSTATE_Q), the SCKF at each feed of FEEDS (the first table's S runs the "before")."""
    flt, letter = DSTATE_FILTER
    return [(flt, letter, f, (f[0], f[1], None, None, None, DSTATE_Q)) for f in FEEDS]


HOLD_WORDS = (f"tid_feed_ax_max {HOLD_OFF:g} (no hold, aX: its value) → the default",
              "the hold", "no hold")  # the hold table's: before -> after, the change, its base
ELLIPSE_WORDS = ("the feed without the friction ellipse (tid_ellipse 0) → with it (E: "
                 "tid_ellipse 1, tid_ell_ax_min 0: no dead band), held at the default or not "
                 "(aX: tid_feed_ax_max X)", "the ellipse", "no ellipse")
BAND_WORDS = ("the feed without the friction ellipse (tid_ellipse 0) → with it and its dead "
              f"band (EbX: tid_ellipse 1, tid_ell_ax_min X, the default {BAND:g} m/s²), held at "
              "the default or not (aX: tid_feed_ax_max X)", "the ellipse with its band",
              "no ellipse")
DSTATE_WORDS = ("the SCKF's feed with δ an input (tid_delta_state_q 0, the default) → δ a state "
                "(dX: tid_delta_state_q X, TYRE_ID.md section 15.7), the hold at its default",
                "the δ state", "δ an input")


def hold_table(names, res, pairs=None, words=HOLD_WORDS):
    """The before -> after table's lines (the docstring's second table; with @p pairs and
    @p words, the third and the fourth) from the runs @p res (keys as seed_runs reads them):
    per log and pair the figures over the seeds, before and after, and the verdict of the
    change; per pair the counts per seed, given as median [min-max] (one run: as it is)."""
    pairs = hold_columns() if pairs is None else pairs
    heads = " / ".join(f"{label(b, letter)} → {label(f, letter)}" for _, letter, b, f in pairs)
    rows = [f"| log | RMSE when valid: off / {heads} | consistency when valid: off / {heads} "
            f"| valid: off / {heads} | fed: {heads} | {words[1]} helps / hurts against "
            f"{words[2]} |",
            "|---|---|---|---|---|---|"]
    nseed = {p: (len(SEEDS) if p[0] in SEEDED else 1) for p in pairs}
    vs_off = {p: (Tally(nseed[p]), Tally(nseed[p])) for p in pairs}  # before, after against off
    change = {p: Tally(nseed[p]) for p in pairs}  # after against before, seed by seed
    for log in names:
        base = res[(log, None, None)]
        cells = [[cell(base[0], ".3f")], [cell(base[1], ".2f")], [cell(base[2], ".0%")], [], []]
        for p in pairs:
            b, a = seed_runs(res, log, p[0], p[2]), seed_runs(res, log, p[0], p[3])
            for i, fmt in ((0, ".3f"), (1, ".2f"), (2, ".0%"), (3, ".0%")):
                cells[i].append(f"{seed_cell([r[i] for r in b], fmt)} → "
                                f"{seed_cell([r[i] for r in a], fmt)}")
            vs_off[p][0].add([base], b)
            vs_off[p][1].add([base], a)
            cells[4].append(change_cell(*change[p].add(b, a), len(a)))
        name = log[len("scenarios/"):-len(".csv")]
        rows.append(f"| {name} | " + " | ".join(" / ".join(c) for c in cells) + " |")
    rows.append("")
    rows.append(f"Before → after: {words[0]}. Helps / hurts against off: "
                + "; ".join(f"{label(p[3], p[1])}: {vs_off[p][0].count(0)} / "
                            f"{vs_off[p][0].count(2)} → {vs_off[p][1].count(0)} / "
                            f"{vs_off[p][1].count(2)}" for p in pairs)
                + ". Meets issue 20's targets: "
                + "; ".join(f"{label(p[3], p[1])}: {vs_off[p][0].count(3)} → "
                            f"{vs_off[p][1].count(3)}" for p in pairs)
                + f". {words[1][0].upper()}{words[1][1:]} against {words[2]}, helps / hurts: "
                + "; ".join(f"{label(p[3], p[1])}: {change[p].count(0)} / {change[p].count(2)}"
                            for p in pairs)
                + ".")
    seeded = [p for p in pairs if nseed[p] > 1]
    if seeded:
        rows.append("")
        rows.append(f"Seeds: the APF's pairs ({', '.join(label(p[3], p[1]) for p in seeded)}) "
                    f"are run with tid_seed {', '.join(str(sd) for sd in SEEDS)}, each seed's "
                    "before and after from the same seed, and their cells are the median over "
                    "the seeds with [min–max] where they differ, as in the first table; their "
                    f"verdict cells count the seeds on which {words[1]} helps or hurts against "
                    f"{words[2]} on the same seed, of those with a verdict (\"=\": neither on "
                    "any). "
                    "The SCKF and off are deterministic: one run each. The counts above give "
                    "per pair the median over the seeds and [min–max] where they differ.")
        rows.append("")
        rows.append(f"Per log over the seeds with a verdict ({words[1]} against {words[2]}: "
                    "logs it helps on every such seed / on some but not all; hurts on every "
                    "such seed / on some but not all): "
                    + "; ".join(f"{label(p[3], p[1])}: {change[p].every_cell()}"
                                for p in seeded) + ".")
    return rows


def change_cell(h, u, nseeds):
    """The verdict cell of a before -> after pair from its verdicts per seed @p h (helps) and
    @p u (hurts): one run "helps", "hurts", "=" or "–" (no verdict); over several seeds "helps
    k/n" and "hurts j/n" (n the seeds with a verdict) where k, j > 0, else "=" (with "(n of
    @p nseeds seeds)" where some have none)."""
    nh, nu, nv = verdict_counts(h, u)
    if nv == 0:
        return "–"
    if nseeds == 1:
        return "helps" if h[0] else ("hurts" if u[0] else "=")
    out = [f"{word} {n}/{nv}" for word, n in (("helps", nh), ("hurts", nu)) if n]
    return ", ".join(out) if out else "=" + (f" ({nv} of {nseeds} seeds)" if nv < nseeds
                                             else "")


def verdict_counts(h, u):
    """(seeds helped, seeds hurt, seeds with a verdict) of the verdicts per seed @p h, @p u."""
    return (sum(1 for x in h if x), sum(1 for x in u if x), sum(1 for x in h if x is not None))


class Tally:
    """A column's counts over the logs, per seed: [helps, logs with a verdict, hurts, meets,
    logs with a valid sample] (seed), and over the seeds, per log: [helped on every seed with a
    verdict, on some but not all, hurt on every such seed, on some but not all] (every)."""

    def __init__(self, nseeds):
        self.seed = [[0, 0, 0, 0, 0] for _ in range(nseeds)]
        self.every = [0, 0, 0, 0]

    def add(self, bases, runs):
        """Counts one log's @p runs (one per seed) against @p bases (one per seed, or a single
        base for every seed); returns the verdicts per seed (helps, hurts)."""
        bases = bases if len(bases) == len(runs) else bases * len(runs)
        h = [helps(b, r) for b, r in zip(bases, runs)]
        u = [hurts(b, r) for b, r in zip(bases, runs)]
        for k, r in enumerate(runs):
            mk = meets(r)
            for i, x in enumerate((h[k], h[k] is not None, u[k], mk, mk is not None)):
                self.seed[k][i] += 1 if x else 0
        nh, nu, nv = verdict_counts(h, u)
        if nv:
            self.every[0 if nh == nv else 1] += 1 if nh else 0
            self.every[2 if nu == nv else 3] += 1 if nu else 0
        return h, u

    def count(self, i):
        """The count @p i (an index of seed) as count_cell gives it over the seeds."""
        return count_cell([k[i] for k in self.seed])

    def every_cell(self):
        e = self.every
        return f"{e[0]} / {e[1]}; {e[2]} / {e[3]}"


def spread(xs):
    """(median, min, max) of the figures @p xs, None entries (a run without a valid sample) left
    out; None when none is left. The median of an even count is the mean of the middle two."""
    vals = [x for x in xs if x is not None]
    if not vals:
        return None
    return statistics.median(vals), min(vals), max(vals)


def seed_cell(xs, fmt):
    """A cell of the first table from one run's figure per seed: the median, "[min–max]" after
    it where the seeds differ at the format's digits, "(k of n seeds)" where only k of them have
    a figure; "–" where none has."""
    sp = spread(xs)
    if sp is None:
        return "–"
    lo, hi = format(sp[1], fmt), format(sp[2], fmt)
    out = format(sp[0], fmt) + (f" [{lo}–{hi}]" if lo != hi else "")
    k = sum(1 for x in xs if x is not None)
    return out + (f" ({k} of {len(xs)} seeds)" if k < len(xs) else "")


def count_cell(ns):
    """A count per seed as its median and, where the seeds differ, "[min–max]"."""
    sp = spread(ns)
    return f"{sp[0]:g}" + (f" [{sp[1]}–{sp[2]}]" if sp[1] != sp[2] else "")


def seed_runs(res, log, flt, feed):
    """The runs of one log and fed column, one per seed of SEEDS for a filter of SEEDED (the
    first the preset's run, keyed without a seed), else the one run."""
    first = res[(log, flt, feed)]
    return [first] + [res[(log, flt, feed, sd)] for sd in SEEDS[1:]] if flt in SEEDED else [first]


def seed_jobs(names, specs=None):
    """The runs beyond the preset's seed of the (filter, feed) pairs @p specs (default: the
    first table's columns) on each log: (log, filter, feed, seed), for a filter of SEEDED."""
    specs = [(c[0], c[2]) for c in columns()] if specs is None else specs
    return [(log, flt, feed, sd) for log in names for flt, feed in specs if flt in SEEDED
            for sd in SEEDS[1:]]


def table_specs():
    """Every (filter, feed) that the five tables read, each once: the first table's columns,
    the hold table's "before" runs, the ellipse's, the band's and the delta state's "after" runs
    (their "before" runs are among the first two)."""
    specs = [(c[0], c[2]) for c in columns()] + [(p[0], p[2]) for p in hold_columns()]
    specs += [(p[0], p[3]) for p in ellipse_columns() + ellipse_columns(BAND)
              + dstate_columns()]
    return list(dict.fromkeys(specs))


def all_jobs(names):
    """Every run of the five tables: each log without the identifier, and each (filter, feed)
    of table_specs with the preset's seed and, for a filter of SEEDED, each further seed."""
    specs = table_specs()
    return ([(log, None, None) for log in names]
            + [(log, flt, feed) for log in names for flt, feed in specs]
            + seed_jobs(names, specs))


def feed_table(names, res):
    """The first table's lines from the runs @p res (keys as seed_runs reads them): per log and
    column the figures over the seeds, per column the counts of helps, hurts and issue 20's
    targets met, per seed and then as median [min–max]."""
    cols = columns()
    labels = [label(c[2], c[1]) for c in cols]
    feeds = " / ".join(labels)
    rows = [f"| log | RMSE when valid: off / {feeds} | consistency when valid: off / {feeds} "
            f"| valid: off / {feeds} | fed: {feeds} | helps: {feeds} | hurts: {feeds} |",
            "|---|---|---|---|---|---|---|"]
    tally = {c: Tally(len(SEEDS) if c[0] in SEEDED else 1) for c in cols}
    met_off = [0, 0]
    for log in names:
        base = res[(log, None, None)]
        m = meets(base)
        met_off[0] += 1 if m else 0
        met_off[1] += 1 if m is not None else 0
        per = [seed_runs(res, log, c[0], c[2]) for c in cols]
        hcells, ucells = [], []
        for c, runs in zip(cols, per):
            h, u = tally[c].add([base], runs)
            nh, nu, nv = verdict_counts(h, u)
            if len(runs) == 1:
                hcells.append("–" if h[0] is None else ("yes" if h[0] else "no"))
                ucells.append("–" if u[0] is None else ("yes" if u[0] else "no"))
            else:
                hcells.append("–" if nv == 0 else f"{nh}/{nv}")
                ucells.append("–" if nv == 0 else f"{nu}/{nv}")
        name = log[len("scenarios/"):-len(".csv")]
        rows.append(f"| {name} | "
                    + " | ".join(" / ".join([cell(base[i], fmt)]
                                            + [seed_cell([r[i] for r in runs], fmt)
                                               for runs in per])
                                 for i, fmt in ((0, ".3f"), (1, ".2f"), (2, ".0%")))
                    + " | " + " / ".join(seed_cell([r[3] for r in runs], ".0%") for runs in per)
                    + " | " + " / ".join(hcells) + " | " + " / ".join(ucells) + " |")
    seeded = [lab for lab, c in zip(labels, cols) if c[0] in SEEDED]
    rows.append("")
    rows.append("Columns: A the APF's curve fed, B the bootstrap (SIR) filter's, S the SCKF's; "
                "the number its tid_feed_sd_rel, eX: after X s of evidence.")
    rows.append("")
    rows.append(f"Seeds: the APF's and SIR's columns ({', '.join(seeded)}) are the median over "
                f"tid_seed {', '.join(str(sd) for sd in SEEDS)} of the filter's random stream, "
                "with [min–max] over "
                "the seeds where they differ at the table's digits (RMSE and consistency over the "
                "seeds with a valid sample; \"(k of n seeds)\" where only k have one), and "
                "their helps and hurts cells the number of seeds on which the feed helps or "
                "hurts, of those with a verdict. The SCKF and off are deterministic: one run "
                "each. The counts below give per column the median over the seeds and "
                "[min–max] where they differ. The hold, ellipse and band tables below run "
                "their APF pairs over the same seeds.")
    rows.append("")
    rows.append("Helps / hurts (of the logs with valid samples both ways): "
                + "; ".join(f"{lab}: {tally[c].count(0)} / {tally[c].count(2)} of "
                            f"{tally[c].count(1)}" for lab, c in zip(labels, cols)) + ".")
    rows.append("")
    rows.append("Per log over the seeds with a verdict (logs on which the feed helps on every "
                "such seed / on some but not all; hurts on every such seed / on some but not "
                "all): "
                + "; ".join(f"{lab}: {tally[c].every_cell()}"
                            for lab, c in zip(labels, cols) if c[0] in SEEDED) + ".")
    rows.append("")
    rows.append(f"Meets issue 20's targets (RMSE when valid <= {RMSE_TARGET:g}, consistency "
                f"when valid >= {CONS_TARGET:g}; of the logs with valid samples): "
                f"off: {met_off[0]} of {met_off[1]}; "
                + "; ".join(f"{lab}: {tally[c].count(3)} of {tally[c].count(4)}"
                            for lab, c in zip(labels, cols)) + ".")
    return rows


def cell(x, fmt):
    return "–" if x is None else format(x, fmt)


def map_progress(fn, items, workers, what, every=0):
    """[fn(x) for x in @p items], @p workers at a time (threads: each fn waits on a replay
    process), in @p items' order; prints "<what>: k / n runs, t s" to stderr every @p every
    runs (0: about every tenth) and after the last, so a long study shows it is alive."""
    n = len(items)
    step = every if every > 0 else max(n // 10, 1)
    t0 = time.monotonic()
    done = [0]
    lock = threading.Lock()

    def one(x):
        r = fn(x)
        with lock:
            done[0] += 1
            k = done[0]
        if k % step == 0 or k == n:
            print(f"{what}: {k} / {n} runs, {time.monotonic() - t0:.0f} s", file=sys.stderr,
                  flush=True)
        return r

    with ThreadPoolExecutor(max_workers=max(1, workers)) as ex:
        return list(ex.map(one, items))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mu-replay", default=os.path.join(ROOT, "build", "mu_replay"))
    ap.add_argument("--page", default="")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    if not os.access(a.mu_replay, os.X_OK):
        raise SystemExit(f"tyre_id_feed_results: {a.mu_replay} not found: run make first")
    names = logs()
    jobs = all_jobs(names)
    res = dict(zip(jobs, map_progress(lambda job: run(a.mu_replay, *job), jobs, a.jobs,
                                      "tyre_id_feed_results", every=20)))
    rows = feed_table(names, res)
    text = "\n".join(rows)
    print(text)
    held = hold_table(names, res)
    print("\n".join(held))
    ell = hold_table(names, res, ellipse_columns(), ELLIPSE_WORDS)
    print("\n".join(ell))
    band = hold_table(names, res, ellipse_columns(BAND), BAND_WORDS)
    print("\n".join(band))
    dstate = hold_table(names, res, dstate_columns(), DSTATE_WORDS)
    print("\n".join(dstate))
    if a.page:
        replace_region(Path(a.page), "<!-- tyre-feed:begin -->", "<!-- tyre-feed:end -->",
                       text.splitlines(), "tyre_id_feed_results")
        replace_region(Path(a.page), "<!-- tyre-feed-hold:begin -->",
                       "<!-- tyre-feed-hold:end -->", held, "tyre_id_feed_results")
        replace_region(Path(a.page), "<!-- tyre-feed-ellipse:begin -->",
                       "<!-- tyre-feed-ellipse:end -->", ell, "tyre_id_feed_results")
        replace_region(Path(a.page), "<!-- tyre-feed-band:begin -->",
                       "<!-- tyre-feed-band:end -->", band, "tyre_id_feed_results")
        replace_region(Path(a.page), "<!-- tyre-feed-dstate:begin -->",
                       "<!-- tyre-feed-dstate:end -->", dstate, "tyre_id_feed_results")


if __name__ == "__main__":
    main()
