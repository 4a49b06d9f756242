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
1 s, "r1"). The identifier runs on every log;
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
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))   # scripts/tools
from md_tables import replace_region  # noqa: E402
from shape_results import summary, summary_table  # noqa: E402
from trust_invariant import bundled_logs, fmt, meets, pct, run_log  # noqa: E402
from tyre_id_feed_results import FEEDS, FILTERS, label  # noqa: E402

REALS = ("float", "double")  # the identifier's precisions (no Q31 twin)
# The feeds of the taint rule (tyre_id_feed_rule.py, MONITOR.md section 7): the APF's at 0.1,
# from the start and after e0.25, with tid_feed_refresh 1 s (tid_feed_outlier_k at its default
# 5): (tid_feed_sd_rel, tid_feed_evidence, tid_feed_refresh)
REFRESH_FEEDS = ((0.1, 0.0, 1.0), (0.1, 0.25, 1.0))


def variants():
    """The fed runs: (label, filter, (tid_feed_sd_rel, tid_feed_evidence[,
    tid_feed_refresh])), e.g. "S0.05", "A0.1 e0.25", "A0.1 r1"."""
    return ([(label(f, letter), flt, f) for flt, letter in reversed(FILTERS) for f in FEEDS]
            + [(label(f[:2], "A") + f" r{f[2]:g}", "apf", f) for f in REFRESH_FEEDS])


def feed_params(feed, folder: Path) -> Path:
    """A parameter file setting one feed (the hold tid_feed_ax_max left at its default; with a
    third entry tid_feed_refresh, tid_feed_outlier_k at its default)."""
    tail = f"_{feed[2]:g}" if len(feed) > 2 else ""
    p = folder / f"feed_{feed[0]:g}_{feed[1]:g}{tail}.params"
    p.write_text(f"tid_feed_sd_rel = {feed[0]!r}\ntid_feed_evidence = {feed[1]!r}\n"
                 + (f"tid_feed_refresh = {feed[2]!r}\n" if len(feed) > 2 else ""))
    return p


def measure(replay: Path, scen: Path, out: Path, reals=REALS, only=None, jobs=2) -> dict:
    """{real: {log name: {"today" | variant label: figures}}}."""
    out.mkdir(parents=True, exist_ok=True)
    logs = [p for p in bundled_logs(scen) if not only or p.name in only]
    with tempfile.TemporaryDirectory() as tmp:
        par = {v[0]: feed_params(v[2], Path(tmp)) for v in variants()}
        todo = []
        for real in reals:
            for log in logs:
                todo.append((real, log, "today", ()))
                todo += [(real, log, lab, ("--tyre-id", flt, "--params", str(par[lab])))
                         for lab, flt, _ in variants()]

        def one(job):
            real, log, lab, extra = job
            tag = "" if lab == "today" else "." + lab.replace(" ", "_")
            return run_log(replay, log, out, real, extra, tag)

        with ThreadPoolExecutor(max_workers=max(jobs, 1)) as ex:
            got = list(ex.map(one, todo))
    res = {real: {} for real in reals}
    for (real, log, lab, _), f in zip(todo, got):
        res[real].setdefault(log.relative_to(scen).as_posix(), {})[lab] = f
    return res


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
    a = ap.parse_args(argv)
    if not a.replay.is_file():
        sys.exit(f"tyre_id_trust: {a.replay}: no such file (make build/mu_replay)")
    res = measure(a.replay, a.scenarios, a.out, a.real, a.only, a.jobs)
    tables = {"summary": summary_lines(res) + ["", "Against today, on all the logs:", ""]
              + change_lines(res)}
    fed = fed_logs(res, a.real[0])
    tables["logs"] = ([f"{a.real[0]}: the {len(fed)} logs where some variant fed its curve "
                       "(valid / excited valid / RMSE / consistency / worst when valid / meets"
                       " / fed).", ""] + log_lines(res, a.real[0]))
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
