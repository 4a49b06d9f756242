#!/usr/bin/env python3
"""The tyre identifier's fed curve as evidence of the tyre's shape: does it make more logs meet
issue 17's trust invariant, and at what cost (docs/MONITOR.md section 7)?

    .venv/bin/python scripts/tools/tyre_id_trust.py [--replay build/mu_replay]
        [--scenarios scenarios] [--out build/tyre_id_trust] [--real float double]
        [--only NAME ...] [--jobs 2] [--page docs/MONITOR.md]

The 72 logs of the trust invariant (trust_invariant.bundled_logs), each replayed by the C
library as trust_invariant.run_log replays it (mu_replay, the default preset, the logs'
measured vx, vy and yaw acceleration), once without the tyre identifier ("today") and once per
fed variant: each filter of tyre_id_feed_results.FILTERS (the APF, the SCKF) at each feed of
tyre_id_feed_results.FEEDS (tid_feed_sd_rel 0.05 and 0.1, from the start, and only after
tid_feed_evidence 0.25 s of the friction estimator's evidence that its curve is wrong:
"e0.25"), with the braking hold at its default (tid_feed_ax_max 0.5 m/s^2: no curve fed after a
sample whose |ax| exceeds it; docs/TYRE_ID.md section 14), and the APF's at 0.1 from the start
and after e0.25 with the taint rule of tyre_id_feed_rule.py (REFRESH_FEEDS: tid_feed_refresh
1 s, "r1"), and the SCKF's at the same two feeds with the same rule (REFRESH_FILTERS: does the
rule help with the other filter's curve too), and last the SCKF's at each feed of FEEDS with
the steering angle as its state (tid_delta_state_q tyre_id_feed_results.DSTATE_Q,
docs/TYRE_ID.md section 15.7: "d0.04"). The identifier runs on every log;
it feeds only where its cornering stiffness is known within tid_feed_sd_rel, i.e. where the
driver steers (the "fed" share). The identifier is float and double only (no Q31 twin), so
--real takes float and double.

Per run the figures of trust_invariant.figures (pooled over the four wheels and mu_replay's
settled samples; the excited-valid share is mu_replay's frac_valid_excited, true utilisation
>= 0.5), the invariant trust_invariant.meets, and the summary of docs/MONITOR.md section 6
(shape_results.summary / summary_table: logs meeting it, all / Dugoff truth / MF truth; on the
Magic Formula-truth logs that meet it today, the largest drop of the excited-valid share, how
many drop more than 5 points and how many no longer meet it), with, per variant, the logs of
either truth tyre it makes meet the invariant and those it makes fail it. --page rewrites
<!-- tyre-trust-summary:begin/end --> and <!-- tyre-trust-logs:begin/end --> (the logs where
some variant fed) of the page.

The taint rule's sensitivity (--sens, on by default; make tyre-id-trust): each base feed of
SENS_BASES (the APF's at 0.1, from the start and after e0.25) with the rule at every
tid_feed_refresh of SENS_REFRESH and tid_feed_outlier_k of SENS_K, per precision: logs meeting
the invariant, logs gained and lost against today (either truth tyre), and the MF-truth logs
meeting it today whose excited-valid share drops by more than 5 points. The rule only withholds
curves the base feed would feed (tyre_feed_due's conditions are the base's and more), so on a
log where the base fed nothing the rule feeds nothing and the run is today's (the reset of the
model error sets the value the estimator already has): those logs are not replayed again, their
figures are today's (asserted on one log by test_tyre_id_trust.py). The grid point (1 s, 5) is
the "r1" column of the summary, not replayed again. --page also rewrites
<!-- tyre-trust-sens:begin/end -->.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))   # scripts/tools
from md_tables import replace_region  # noqa: E402
from shape_results import summary, summary_table  # noqa: E402
from trust_invariant import bundled_logs, fmt, meets, pct, run_log  # noqa: E402
from tyre_id_feed_results import (DSTATE_FILTER, DSTATE_Q, FEEDS, FILTERS, label,  # noqa: E402
                                  map_progress)

REALS = ("float", "double")  # the identifier's precisions (no Q31 twin)
# The feeds of the taint rule (tyre_id_feed_rule.py, MONITOR.md section 7): the APF's at 0.1,
# from the start and after e0.25, with tid_feed_refresh 1 s (tid_feed_outlier_k at its default
# 5): (tid_feed_sd_rel, tid_feed_evidence, tid_feed_refresh)
REFRESH_FEEDS = ((0.1, 0.0, 1.0), (0.1, 0.25, 1.0))
# the filters whose curve is fed with the rule: the APF's (the rule's own), then the SCKF's
REFRESH_FILTERS = (("apf", "A"), ("sckf", "S"))
# The rule's sensitivity: the APF's base feeds (tid_feed_sd_rel, tid_feed_evidence) and the grid
# of (tid_feed_refresh [s], tid_feed_outlier_k); (1, 5) is the summary's "r1"
SENS_BASES = ((0.1, 0.0), (0.1, 0.25))
SENS_REFRESH = (0.5, 1.0, 2.0, 4.0)
SENS_K = (3.0, 4.0, 5.0, 7.0)
SENS_REUSED = (1.0, 5.0)  # the summary's r1 (tid_feed_outlier_k at its default 5)


def variants():
    """The fed runs: (label, filter, (tid_feed_sd_rel, tid_feed_evidence[,
    tid_feed_refresh]), further keys ((key, value), ...)), e.g. "S0.05", "A0.1 e0.25",
    "A0.1 r1", "S0.1 e0.25 r1", "S0.05 d0.04" (the SCKF with delta as a state)."""
    dflt, dletter = DSTATE_FILTER
    return ([(label(f, letter), flt, f, ()) for flt, letter in reversed(FILTERS) for f in FEEDS]
            + [(label(f[:2], letter) + f" r{f[2]:g}", flt, f, ())
               for flt, letter in REFRESH_FILTERS for f in REFRESH_FEEDS]
            + [(label(f, dletter) + f" d{DSTATE_Q:g}", dflt, f,
                (("tid_delta_state_q", DSTATE_Q),)) for f in FEEDS])


def feed_params(feed, folder: Path, extra=()) -> Path:
    """A parameter file setting one feed (the hold tid_feed_ax_max left at its default; with a
    third entry tid_feed_refresh, with a fourth tid_feed_outlier_k, else at its default), and
    the (key, value) pairs of @p extra after it."""
    tail = "".join(f"_{x:g}" for x in feed[2:]) + "".join(f"_{k}_{v:g}" for k, v in extra)
    p = folder / f"feed_{feed[0]:g}_{feed[1]:g}{tail}.params"
    keys = ("tid_feed_sd_rel", "tid_feed_evidence", "tid_feed_refresh", "tid_feed_outlier_k")
    p.write_text("".join(f"{k} = {v!r}\n" for k, v in (*zip(keys, feed), *extra)))
    return p


def run_all(replay: Path, out: Path, todo, jobs: int, what: str) -> list:
    """run_log on each (real, log, tag, extra) of @p todo, @p jobs at a time, printing progress
    (stderr) about every tenth of the runs; the figures in @p todo's order."""
    return map_progress(lambda job: run_log(replay, job[1], out, job[0], job[3], job[2]),
                        todo, jobs, f"tyre_id_trust: {what}")


def measure(replay: Path, scen: Path, out: Path, reals=REALS, only=None, jobs=2) -> dict:
    """{real: {log name: {"today" | variant label: figures}}}."""
    out.mkdir(parents=True, exist_ok=True)
    logs = [p for p in bundled_logs(scen) if not only or p.name in only]
    with tempfile.TemporaryDirectory() as tmp:
        par = {v[0]: feed_params(v[2], Path(tmp), v[3]) for v in variants()}
        todo = []
        for real in reals:
            for log in logs:
                todo.append((real, log, "today", ()))
                todo += [(real, log, lab, ("--tyre-id", flt, "--params", str(par[lab])))
                         for lab, flt, *_ in variants()]
        got = run_all(replay, out, [(r, g, tag_of(lab), x) for r, g, lab, x in todo], jobs,
                      "the feeds")
    res = {real: {} for real in reals}
    for (real, log, lab, _), f in zip(todo, got):
        res[real].setdefault(log.relative_to(scen).as_posix(), {})[lab] = f
    return res


def tag_of(lab: str) -> str:
    """The output files' suffix of a run label."""
    return "" if lab == "today" else "." + lab.replace(" ", "_")


def sens_label(base, refresh: float, k: float) -> str:
    """e.g. "A0.1 e0.25 r0.5 k3"."""
    return label(base, "A") + f" r{refresh:g} k{k:g}"


def measure_sens(replay: Path, scen: Path, out: Path, res: dict, jobs=2) -> dict:
    """The rule's grid on the APF's base feeds: {real: {base label: {(refresh, k): {log name:
    {"today": figures, "run": figures}}}}} and the number of runs, replayed only on the logs
    where the base fed (res[real][log][base label]["fed"] > 0); elsewhere the run is today's
    (module doc); the grid point SENS_REUSED is res's r1 column."""
    out.mkdir(parents=True, exist_ok=True)
    grid = [(r, k) for r in SENS_REFRESH for k in SENS_K]
    sens, todo = {}, []
    with tempfile.TemporaryDirectory() as tmp:
        for real, per_log in res.items():
            sens[real] = {}
            for base in SENS_BASES:
                blab = label(base, "A")
                fed = [n for n, f in per_log.items() if f[blab].get("fed", 0.0) > 0.0]
                cells = sens[real][blab] = {}
                for r, k in grid:
                    cells[(r, k)] = {n: {"today": f["today"], "run": f["today"]}
                                     for n, f in per_log.items()}
                    for n in fed:
                        if (r, k) == SENS_REUSED:
                            cells[(r, k)][n]["run"] = per_log[n][f"{blab} r{r:g}"]
                            continue
                        par = feed_params((*base, r, k), Path(tmp))
                        todo.append((real, blab, (r, k), n,
                                     (real, scen / n, tag_of(sens_label(base, r, k)),
                                      ("--tyre-id", "apf", "--params", str(par)))))
        got = run_all(replay, out, [t[4] for t in todo], jobs, "the rule's grid")
    for (real, blab, rk, n, _), f in zip(todo, got):
        sens[real][blab][rk][n]["run"] = f
    return sens, len(todo)


def sens_cell(per_log: dict) -> dict:
    """One grid point: logs meeting the invariant, the logs gained and lost against today
    (either truth tyre), and the MF-truth logs meeting it today whose excited-valid share drops
    by more than 5 points (shape_results.summary)."""
    s = summary(per_log, ["today", "run"], meets)["run"]
    ok = {n: (meets(f["today"]), meets(f["run"])) for n, f in per_log.items()}
    return {"meets": s["meets"]["all"], "total": s["total"]["all"],
            "won": sorted(n for n, (t, r) in ok.items() if r and not t),
            "lost": sorted(n for n, (t, r) in ok.items() if t and not r),
            "over_drop": s["over_drop"]}


def sens_lines(sens: dict) -> list[str]:
    """Per precision and base feed, one row per tid_feed_refresh, one column per
    tid_feed_outlier_k: "meeting / gained / lost / MF drops > 5 points"; then the logs lost or
    dropping at some grid point."""
    lines, notes = [], []
    head = ("| precision, base feed | tid_feed_refresh | "
            + " | ".join(f"k {k:g}" for k in SENS_K) + " |")
    lines += [head, "|" + "|".join(["---"] * (len(SENS_K) + 2)) + "|"]
    for real, bases in sens.items():
        for blab, cells in bases.items():
            for r in SENS_REFRESH:
                row = []
                for k in SENS_K:
                    c = sens_cell(cells[(r, k)])
                    row.append(f"{c['meets']}/{c['total']} / +{len(c['won'])} / "
                               f"−{len(c['lost'])} / {len(c['over_drop'])}")
                    if c["lost"] or c["over_drop"]:
                        notes.append(f"- {real} {blab} r{r:g} k{k:g}: no longer meeting it: "
                                     + (", ".join(f"`{n}`" for n in c["lost"]) or "none")
                                     + "; excited-valid share down > 5 points: "
                                     + (", ".join(f"`{n}`" for n in c["over_drop"]) or "none")
                                     + ".")
                lines.append(f"| {real} {blab} | {r:g} s | " + " | ".join(row) + " |")
    return lines + ["", "Grid points that lose a log or an excited-valid share:", ""] + (
        notes or ["- none."])


def labels():
    return ["today"] + [v[0] for v in variants()]


def summary_lines(res: dict) -> list[str]:
    """MONITOR.md section 6's summary table, one row per (precision, run)."""
    lines = []
    for real, per_log in res.items():
        s = summary(per_log, labels(), meets)
        rows = summary_table({f"{real} {lab}": v for lab, v in s.items()})
        lines += rows if not lines else rows[2:]
    return lines


def change_lines(res: dict) -> list[str]:
    """Per precision and fed variant, the logs (either truth tyre) that meet the invariant with it
    and not today, and those that meet it today and not with it."""
    out = []
    for real, per_log in res.items():
        for lab in labels()[1:]:
            won = [n for n, f in per_log.items() if meets(f[lab]) and not meets(f["today"])]
            lost = [n for n, f in per_log.items() if meets(f["today"]) and not meets(f[lab])]
            out.append(f"- {real} {lab}: meets it now ({len(won)}): "
                       + (", ".join(f"`{n}`" for n in won) or "none")
                       + f"; no longer ({len(lost)}): "
                       + (", ".join(f"`{n}`" for n in lost) or "none") + ".")
    return out


def log_lines(res: dict, real: str) -> list[str]:
    """Per log where some variant fed: valid / excited valid / RMSE / consistency / worst when
    valid / meets, and the share fed."""
    labs = labels()
    lines = ["| log | " + " | ".join(labs) + " |", "|" + "|".join(["---"] * (len(labs) + 1)) + "|"]
    for n, f in res[real].items():
        if not any(f[lab].get("fed", 0.0) > 0.0 for lab in labs[1:]):
            continue
        cells = []
        for lab in labs:
            g = f[lab]
            cells.append(f"{pct(g['valid'])} / {pct(g['excited_valid'])} / {fmt(g['rmse_valid'])}"
                         f" / {pct(g['cons_valid'])} / {fmt(g['worst_valid'])} / "
                         f"{'yes' if meets(g) else '**no**'}"
                         + (f" / fed {pct(g['fed'])}" if "fed" in g else ""))
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    return lines


def fed_logs(res: dict, real: str) -> list[str]:
    """The logs where some variant fed its curve."""
    return [n for n, f in res[real].items()
            if any(f[lab].get("fed", 0.0) > 0.0 for lab in labels()[1:])]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", default="build/mu_replay", type=Path)
    ap.add_argument("--scenarios", default="scenarios", type=Path)
    ap.add_argument("--out", default="build/tyre_id_trust", type=Path)
    ap.add_argument("--real", nargs="+", default=list(REALS), choices=REALS)
    ap.add_argument("--only", nargs="*", help="only these log names (a quick look; no --page)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--page", type=Path, help="rewrite the tables of this page (docs/MONITOR.md)")
    ap.add_argument("--no-sens", action="store_true", help="skip the taint rule's grid")
    a = ap.parse_args(argv)
    if not a.replay.is_file():
        sys.exit(f"tyre_id_trust: {a.replay}: no such file (make build/mu_replay)")
    t0 = time.monotonic()
    res = measure(a.replay, a.scenarios, a.out, a.real, a.only, a.jobs)
    t1 = time.monotonic()
    tables = {"summary": summary_lines(res) + ["", "Against today, on all the logs:", ""]
              + change_lines(res)}
    fed = fed_logs(res, a.real[0])
    tables["logs"] = ([f"{a.real[0]}: the {len(fed)} logs where some variant fed its curve "
                       "(valid / excited valid / RMSE / consistency / worst when valid / meets"
                       " / fed).", ""] + log_lines(res, a.real[0]))
    if not a.no_sens:
        sens, n_runs = measure_sens(a.replay, a.scenarios, a.out / "sens", res, a.jobs)
        print(f"tyre_id_trust: the feeds {t1 - t0:.0f} s, the rule's grid "
              f"{time.monotonic() - t1:.0f} s ({n_runs} runs)", file=sys.stderr, flush=True)
        tables["sens"] = sens_lines(sens)
    for k, v in tables.items():
        print(f"\n## {k}\n" + "\n".join(v), flush=True)
    if a.page and not a.only:
        for k, v in tables.items():
            replace_region(a.page, f"<!-- tyre-trust-{k}:begin -->",
                           f"<!-- tyre-trust-{k}:end -->", v, "tyre_id_trust")
        print(f"tyre_id_trust: rewrote the tables of {a.page}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
