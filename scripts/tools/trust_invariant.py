"""The trust invariant of issue 17 over every bundled log, in float, double and Q31.

Usage (from the repository root, after make build/mu_replay):

    .venv/bin/python scripts/tools/trust_invariant.py [--replay build/mu_replay]
        [--scenarios scenarios] [--out build/trust] [--md FILE] [--page docs/RESULTS.md]

The default preset (monitor on), with the logs' measured vx, vy and yaw acceleration, on every
sensor log of scenarios/ (both truth tyres, noisy and noise-free) and scenarios/faults/. Per
log and precision, pooled over the four wheels and mu_replay's settled samples
(src/host/metrics.c): the share of samples valid, RMSE when valid, consistency when valid
(|error| <= 2 sd among the valid samples) and the worst case when valid (max |error|). A log
meets the invariant when consistency when valid >= 0.9, RMSE when valid <= 0.10 and the worst
case when valid <= 0.25 (issue 17); a log never valid meets it (it claims nothing).
Prints one table line per log as it goes; --md writes the table as markdown, --page rewrites
the <!-- trust-invariant:begin/end --> region of a docs page with the summary and the table
(make trust-invariant: docs/RESULTS.md).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))   # scripts/tools: md_tables
from md_tables import replace_region  # noqa: E402
from wheel_figures import WHEELS, pooled, worst_valid  # noqa: E402

PRECISIONS = ("float", "double", "q31")
CONS_MIN, RMSE_MAX, WORST_MAX = 0.9, 0.10, 0.25  # issue 17's targets
BEGIN, END = "<!-- trust-invariant:begin -->", "<!-- trust-invariant:end -->"


def bundled_logs(scen: Path) -> list[Path]:
    """Every sensor log of the friction estimator: scenarios/*.csv and scenarios/faults/*.csv."""
    return sorted(scen.glob("*.csv")) + sorted((scen / "faults").glob("*.csv"))


def figures(metrics: dict) -> dict:
    """Valid share, RMSE, consistency and worst case when valid, pooled over the wheels; the
    excited-valid share (mu_replay's frac_valid_excited: valid among the settled samples whose
    true utilisation is >= its excite_util, 0.5), None on a log without utilisation."""
    n_set = sum(metrics[w]["n_settled"] for w in WHEELS)
    n_val = sum(metrics[w]["n_valid"] for w in WHEELS)
    return {"valid": n_val / n_set if n_set else None, "n_valid": n_val,
            "rmse_valid": pooled(metrics, "rmse_valid", "n_valid", square=True),
            "cons_valid": pooled(metrics, "consistency_valid", "n_valid"),
            "worst_valid": worst_valid(metrics),
            "excited_valid": pooled(metrics, "frac_valid_excited", "n_excited")}


def meets(f: dict) -> bool:
    """The invariant: nothing claimed, or every claim within the targets."""
    return f["n_valid"] == 0 or (f["cons_valid"] >= CONS_MIN and f["rmse_valid"] <= RMSE_MAX
                                 and f["worst_valid"] <= WORST_MAX)


def run_log(replay: Path, log: Path, out: Path, real: str, extra=(), tag: str = "") -> dict:
    """mu_replay on one log (default preset); its pooled figures. @p extra: more mu_replay
    arguments (e.g. --tyre-id and --params), @p tag: a suffix of the output files' names; with
    the tyre identifier run, "fed" is the share of steps whose curve the estimator took."""
    met = out / f"{log.stem}.{real}{tag}.json"
    cmd = [str(replay), "--in", str(log), "--out", str(out / f"{log.stem}.{real}{tag}.csv"),
           "--preset", "default", "--real", real, "--metrics", str(met), "--quiet", *extra]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {res.returncode}: {res.stderr.strip()}")
    j = json.loads(met.read_text())
    f = figures(j["metrics"])
    if "tyre_id" in j:
        f["fed"] = j["tyre_id"]["feed"]["n_fed"] / j["steps"] if j["steps"] else 0.0
    return f


def measure(replay: Path, scen: Path, out: Path, progress=None) -> dict:
    """{(log name, precision): figures} over every bundled log."""
    out.mkdir(parents=True, exist_ok=True)
    res = {}
    logs = bundled_logs(scen)
    for k, log in enumerate(logs, 1):
        for real in PRECISIONS:
            res[(log.relative_to(scen).as_posix(), real)] = run_log(replay, log, out, real)
        if progress:
            progress(k, len(logs), log, res)
    return res


def fmt(x, spec=".3f"):
    return "–" if x is None else format(x, spec)


def pct(x):
    return "–" if x is None else f"{100 * x:.0f} %"


def row(name: str, res: dict) -> str:
    cells = []
    for real in PRECISIONS:
        f = res[(name, real)]
        cells.append(f"{pct(f['valid'])} / {fmt(f['rmse_valid'])} / {pct(f['cons_valid'])} / "
                     f"{fmt(f['worst_valid'])} / {'yes' if meets(f) else '**no**'}")
    return f"| {name} | " + " | ".join(cells) + " |"


HEAD = ("| log | float: valid / RMSE / consistency / worst when valid / meets | double | Q31 |\n"
        "|---|---|---|---|")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="the trust invariant over every bundled log")
    ap.add_argument("--replay", default="build/mu_replay", type=Path)
    ap.add_argument("--scenarios", default="scenarios", type=Path)
    ap.add_argument("--out", default="build/trust", type=Path)
    ap.add_argument("--md", type=Path, help="also write the table as markdown")
    ap.add_argument("--page", type=Path,
                    help=f"rewrite the {BEGIN} ... {END} region of this docs page")
    a = ap.parse_args(argv)
    if not a.replay.is_file():
        sys.exit(f"trust_invariant: {a.replay}: no such file (make build/mu_replay)")
    if a.page and not (a.page.is_file() and BEGIN in a.page.read_text()
                       and END in a.page.read_text()):
        sys.exit(f"trust_invariant: {a.page}: no such file or no {BEGIN} ... {END} region")
    print(HEAD, flush=True)

    def progress(k, n, log, res):
        print(row(log.relative_to(a.scenarios).as_posix(), res), flush=True)

    res = measure(a.replay, a.scenarios, a.out, progress)
    names = sorted({n for n, _ in res}, key=lambda n: (n.startswith("faults/"), n))
    failing = {real: [n for n in names if not meets(res[(n, real)])] for real in PRECISIONS}
    summary = ", ".join(f"{real} {len(names) - len(failing[real])}/{len(names)}"
                        for real in PRECISIONS)
    print(f"trust_invariant: logs meeting it: {summary}", flush=True)
    table = [HEAD] + [row(n, res) for n in names]
    if a.md:
        a.md.write_text("\n".join(table) + "\n")
        print(f"trust_invariant: wrote {a.md}", flush=True)
    if a.page:
        lines = [f"Logs meeting the invariant: {summary}.", ""]
        groups = {}
        for real in PRECISIONS:   # precisions failing the same logs share one line
            groups.setdefault(tuple(failing[real]), []).append(real)
        for logs, reals in groups.items():
            lines.append(f"Not met in {' and '.join(reals)} ({len(logs)}): "
                         + (", ".join(f"`{n}`" for n in logs) if logs else "none") + ".")
        replace_region(a.page, BEGIN, END, lines + [""] + table, "trust_invariant")
        print(f"trust_invariant: rewrote the table of {a.page}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
