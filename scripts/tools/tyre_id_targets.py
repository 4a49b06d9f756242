#!/usr/bin/env python3
"""Issue 20's two targets for mu from D, per log, filter and axle, read from the accuracy table
of docs/TYRE_ID_RESULTS.md (written by tyre_id_results.py between <!-- tyre-id-accuracy:begin
/end -->), and written as one table between <!-- tyre-id-targets:begin/end --> of the page.

    .venv/bin/python scripts/tools/tyre_id_targets.py [--page docs/TYRE_ID_RESULTS.md]

The targets (tyre_id_results.TARGETS, the page's definitions):
  mu@lim   the RMSE of mu_id = D/Fz against the truth where |ay| > 0.6 mu g: within 0.05;
  sd_lin   the smallest sd of mu_id while the axle's tyre stayed linear: at least 0.2.
The accuracy table gives, per (log, filter), mu@lim per axle as the median over its seeds with
the worst seed in brackets (the SCKF: one run, the two equal), and sd_lin per axle as the
smallest over every seed. Each cell here is the figure and "yes" / "no" against its target; a
mu@lim cell adds the worst seed's figure and verdict in brackets where it differs from the
median's; "–" where the log has no sample for it (never at the limit, or never linear from
0.5 s). Below the table, per filter, the number of (log, axle) cells that meet each target of
those with a figure: mu@lim on the median and on every seed (the worst seed), sd_lin.
Nothing is measured here: the figures are the accuracy table's, so rerunning tyre_id_results.py
(make tyre-id-results, which runs this script after it) rewrites both.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE)]

from md_tables import cells, replace_region  # noqa: E402

ROOT = HERE.parent.parent
ACC = ("<!-- tyre-id-accuracy:begin -->", "<!-- tyre-id-accuracy:end -->")
MARK = ("<!-- tyre-id-targets:begin -->", "<!-- tyre-id-targets:end -->")
# tyre_id_results.TARGETS' two mu targets, kept here as numbers so this script needs neither
# NumPy nor the reference (the pytest checks they are the same)
MULIM_MAX = 0.05
SDLIN_MIN = 0.2
_MULIM = re.compile(r"^(\S+) \[(\S+)\]$")  # "0.048 [0.083]": the median [the worst seed]


def parse(page_text):
    """[(log, filter, (mu@lim f, worst f), (mu@lim r, worst r), (sd_lin f, sd_lin r))] from the
    accuracy table's rows, figures as float or None ("–")."""
    if ACC[0] not in page_text or ACC[1] not in page_text:
        raise SystemExit(f"tyre_id_targets: no {ACC[0]} ... {ACC[1]} section")
    region = page_text.split(ACC[0], 1)[1].split(ACC[1], 1)[0]
    lines = [ln for ln in region.splitlines() if ln.startswith("|")]
    head = cells(lines[0])
    try:
        i_f, i_r = head.index("mu@lim f"), head.index("mu@lim r")
        i_sd = head.index("min sd_mu linear f / r")
    except ValueError as e:
        raise SystemExit(f"tyre_id_targets: the accuracy table's header changed: {e}") from e
    out = []
    for ln in lines[2:]:
        c = cells(ln)
        mu = []
        for i in (i_f, i_r):
            m = _MULIM.match(c[i])
            if m is None:
                raise SystemExit(f"tyre_id_targets: cannot read mu@lim cell {c[i]!r}")
            mu.append((num(m.group(1)), num(m.group(2))))
        sd = tuple(num(x.strip()) for x in c[i_sd].split("/"))
        if len(sd) != 2:
            raise SystemExit(f"tyre_id_targets: cannot read sd_mu cell {c[i_sd]!r}")
        out.append((c[0], c[1], mu[0], mu[1], sd))
    return out


def num(s):
    return None if s == "–" else float(s)


def yes(v, ok):
    return "yes" if ok(v) else "no"


def mu_ok(v):
    return v <= MULIM_MAX


def sd_ok(v):
    return v >= SDLIN_MIN


def mu_cell(med, worst, text_med, text_worst):
    """A mu@lim cell: the median and its verdict, the worst seed's in brackets where its figure
    differs from the median's (the page's digits)."""
    if med is None:
        return "–"
    out = f"{text_med} {yes(med, mu_ok)}"
    if worst is not None and text_worst != text_med:
        out += f" [{text_worst} {yes(worst, mu_ok)}]"
    return out


def table(rows):
    """The table's lines from the parsed rows (parse())."""
    lines = [f"Issue 20's targets for μ from D per log, filter and axle, from the accuracy table "
             f"above (1024 particles, median over seeds 1, 2, 3; SCKF one run): μ@lim ≤ "
             f"{MULIM_MAX:g} (median, [worst seed] where it differs) and min sd_mu linear ≥ "
             f"{SDLIN_MIN:g} (over every seed); \"–\": no sample for it.",
             "",
             "| log | filter | μ@lim f | μ@lim r | sd_mu linear f | sd_mu linear r |",
             "|---|---|---|---|---|---|"]
    filters = list(dict.fromkeys(r[1] for r in rows))
    # per filter: mu@lim met on the median, met on every seed, cells; sd_lin met, cells
    count = {f: [0, 0, 0, 0, 0] for f in filters}
    for log, flt, mf, mr, sd in rows:
        cs = []
        for med, worst in (mf, mr):
            cs.append(mu_cell(med, worst, fmt(med, 3), fmt(worst, 3)))
            if med is not None:
                k = count[flt]
                k[0] += 1 if mu_ok(med) else 0
                k[1] += 1 if mu_ok(med) and (worst is None or mu_ok(worst)) else 0
                k[2] += 1
        for v in sd:
            cs.append("–" if v is None else f"{fmt(v, 2)} {yes(v, sd_ok)}")
            if v is not None:
                count[flt][3] += 1 if sd_ok(v) else 0
                count[flt][4] += 1
        lines.append(f"| {log} | {flt} | " + " | ".join(cs) + " |")
    lines.append("")
    lines.append("(log, axle) cells that meet each target, of those with a figure: μ@lim ≤ "
                 f"{MULIM_MAX:g} on the median / on every seed; sd_mu linear ≥ {SDLIN_MIN:g}: "
                 + "; ".join(f"{f} {count[f][0]} / {count[f][1]} of {count[f][2]}, "
                             f"{count[f][3]} of {count[f][4]}" for f in filters) + ".")
    return lines


def fmt(v, digits):
    return "–" if v is None else f"{v:.{digits}f}"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", default=str(ROOT / "docs" / "TYRE_ID_RESULTS.md"))
    ap.add_argument("--print-only", action="store_true", help="print, do not write the page")
    a = ap.parse_args(argv)
    page = Path(a.page)
    lines = table(parse(page.read_text()))
    print("\n".join(lines))
    if not a.print_only:
        replace_region(page, MARK[0], MARK[1], lines, "tyre_id_targets")


if __name__ == "__main__":
    main()
