"""Why the friction estimator on observer inputs misses issue 16's rule on five logs
(docs/OBSERVER_RESULTS.md "The friction estimator on observer inputs", "Misses of issue 16's
rule"), and whether feeding its errors-in-variables terms a larger sd(vy) fixes them.

    .venv/bin/python scripts/tools/observer_feed_study.py [--replay build/mu_replay] \
        [--out build/observer_feed] [--feed-replay BIN --variant LABEL:MODE:C ...]

Every run is `mu_replay --preset default --real float` as observer_results.py runs the trust
table. The truth vx, vy, yaw_acc come from each log's noise-free twin: scenarios/NAME.nf.csv
for the Dugoff truth; for the Magic Formula truth the simulator writes it here
(make_scenarios.py --tyre mf --only ..., deterministic: its noisy log is the bundled one byte
for byte, which the script checks).

Tables (markdown on stdout):
1. Where the RMSE-when-valid rise comes from: the samples valid in both runs (the error of each
   run on them), the samples valid only on observer inputs, only on measured velocities.
2. The observer run's valid samples, split into consistent (|error| <= 2 sd) and wrong claims,
   and by tyre utilisation: the friction error, the measured run's error on the same samples,
   the observer's vy, vx, yaw-acceleration errors, and the sd the friction estimator was given
   for vy (the pipeline's sd_in_vy: the lateral filter's own sd, OBSERVER.md §6).
3. Column swaps on the measured-velocity path: the log's vx, vy or yaw_acc replaced by the
   observer's (or the truth), the rest of the run unchanged (constant sd_in_vx, sd_in_vy).
4. With --feed-replay BIN: the misses with an oracle's sd (the observer's actual |error| per
   sample fed as sd_in_vy, and sd_in_vx): can any sd rule fix them?
5. With --feed-replay BIN: the whole trust table (every bundled log, both truths), RMSE when
   valid / valid / consistency, off against each --variant run with BIN and the environment
   FEEDMODE=MODE, FEEDC=C (MODE 3 also passes obs_vy_out_floor_mu = C). BIN is mu_replay built
   with observer_feed_study.patch applied (a study-only change of pipeline_flt.c that reads
   the environment; the library has no such option): docs/OBSERVER_RESULTS.md "Feeding the
   friction estimator a larger sd (2026-12-07)" gives the commands.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(Path(__file__).resolve().parent))
from demo import WHEELS, fmt, read_csv, settled_mask  # noqa: E402
from observer_results import pct, trust_cells  # noqa: E402

MISSES = ("ramp_steer_high_mu", "ramp_steer_high_mu.mf", "ramp_steer_low_mu",
          "ramp_steer_low_mu.mf", "wrong_tyre_data", "wrong_tyre_data.mf")
UTIL_BINS = ((0.0, 0.5), (0.5, 0.8), (0.8, 0.95), (0.95, 9.0))
RULE_RMSE = 0.02   # issue 16: RMSE when valid rises by at most this
RULE_CONS = 0.9    # and consistency stays at least this


def replay(binary: Path, log: Path, out: Path, tag: str, velocity: str,
           env: dict | None = None, params: Path | None = None) -> tuple[dict, dict]:
    est, met = out / f"{log.stem}.{tag}.csv", out / f"{log.stem}.{tag}.json"
    cmd = [str(binary), "--in", str(log), "--out", str(est), "--preset", "default",
           "--real", "float", "--velocity", velocity, "--metrics", str(met), "--quiet"]
    if params is None and velocity == "observer":
        # the reported sd(vy)'s floor off (4 by default): the log's sd_vy is then the fed
        # sd_in_vy; every friction output is the same either way (OBSERVER.md §6)
        params = out / "out_floor_off.par"
        params.write_text("obs_vy_out_floor_mu = 0\n")
    cmd += ["--params", str(params)] if params else []
    subprocess.run(cmd, check=True, capture_output=True, env={**os.environ, **(env or {})})
    return read_csv(est), json.loads(met.read_text())["metrics"]


def truth_logs(names, out: Path) -> dict[str, Path]:
    """The noise-free twin of each log (see the module doc)."""
    mf = [n.replace(".mf", "") for n in names if n.endswith(".mf")]
    gen = out / "mf_nf"
    if mf and not all((gen / f"{n}.mf.nf.csv").is_file() for n in mf):
        gen.mkdir(parents=True, exist_ok=True)
        subprocess.run([sys.executable, str(ROOT / "scripts" / "data" / "make_scenarios.py"),
                        "--out", str(gen), "--tyre", "mf", "--jobs", "2", "--only", *mf],
                       check=True, capture_output=True)
    for n in mf:
        if (gen / f"{n}.mf.csv").read_bytes() != (ROOT / "scenarios" / f"{n}.mf.csv").read_bytes():
            sys.exit(f"observer_feed_study: the simulator no longer writes scenarios/{n}.mf.csv")
    return {n: (gen / f"{n}.nf.csv" if n.endswith(".mf") else ROOT / "scenarios" / f"{n}.nf.csv")
            for n in names}


def rms(x):
    return math.sqrt(sum(v * v for v in x) / len(x)) if x else None


def valid_split(sensor, meas, obs) -> str:
    """Table 1's cells: (n, RMSE measured, RMSE observer) on the samples valid in both runs,
    (n, RMSE) valid only with the observer, only with measured velocities."""
    both_m, both_o, only_o, only_m = [], [], [], []
    for w in WHEELS:
        for k, ok in enumerate(settled_mask(sensor, w)):
            if not ok:
                continue
            vm, vo = meas[f"valid_{w}"][k], obs[f"valid_{w}"][k]
            em = meas[f"mu_{w}"][k] - sensor[f"mu_{w}"][k]
            eo = obs[f"mu_{w}"][k] - sensor[f"mu_{w}"][k]
            if vm and vo:
                both_m.append(em)
                both_o.append(eo)
            elif vo:
                only_o.append(eo)
            elif vm:
                only_m.append(em)
    return (f"{len(both_m)} | {fmt(rms(both_m))} | {fmt(rms(both_o))} | {len(only_o)} | "
            f"{fmt(rms(only_o))} | {len(only_m)} | {fmt(rms(only_m))}")


def claims(sensor, tru, meas, obs) -> list[dict]:
    """The observer run's valid settled samples with what table 2 needs of each."""
    rows = []
    for w in WHEELS:
        for k, ok in enumerate(settled_mask(sensor, w)):
            if not ok or not obs[f"valid_{w}"][k]:
                continue
            e = obs[f"mu_{w}"][k] - sensor[f"mu_{w}"][k]
            rows.append({"t": sensor["t"][k], "e": e, "wrong": abs(e) > 2 * obs[f"sd_{w}"][k],
                         "em": meas[f"mu_{w}"][k] - sensor[f"mu_{w}"][k],
                         "evy": obs["vy_est"][k] - tru["vy"][k], "sdvy": obs["sd_vy"][k],
                         "evx": obs["vx_est"][k] - tru["vx"][k], "sdvx": obs["sd_vx"][k],
                         "erd": obs["yaw_acc_est"][k] - tru["yaw_acc"][k],
                         "util": tru[f"util_{w}"][k]})
    return rows


def claim_cells(rows) -> str:
    if not rows:
        return "0 | – | – | – | – | – | – | – | – | –"
    n = len(rows)
    mean = lambda key: sum(r[key] for r in rows) / n  # noqa: E731
    col = lambda key: [r[key] for r in rows]  # noqa: E731
    return (f"{n} | {fmt(rms(col('e')))} | {fmt(rms(col('em')))} | {mean('evy'):+.3f} | "
            f"{fmt(rms(col('evy')))} | {mean('sdvy'):.3f} | {fmt(rms(col('evx')))} | "
            f"{mean('sdvx'):.3f} | {fmt(rms(col('erd')))} | "
            f"{min(col('t')):.1f}–{max(col('t')):.1f} s")


def swap_log(log: Path, new: Path, cols: dict) -> None:
    """The log with the columns @cols replaced (same rows), metadata kept."""
    lines = log.read_text().splitlines()
    h = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    head = lines[h].split(",")
    out = lines[:h + 1]
    for k, line in enumerate(lines[h + 1:]):
        f = line.split(",")
        for c, v in cols.items():
            f[head.index(c)] = repr(float(v[k]))
        out.append(",".join(f))
    new.write_text("\n".join(out) + "\n")


def trust_text(m) -> str:
    r, v, c = trust_cells(m)
    return f"{fmt(r)} / {pct(v)} / {pct(c)}"


def diagnosis(binary: Path, out: Path) -> None:
    truth = truth_logs(MISSES, out)
    t1 = ["| log | valid in both: n | RMSE measured | RMSE observer | valid only with "
          "observer: n | RMSE | valid only measured: n | RMSE |",
          "|---|---|---|---|---|---|---|---|"]
    t2 = ["| log | claims | n | μ error RMS | measured run's μ error RMS | vy error mean [m/s] | "
          "vy error RMS | sd_in_vy | vx error RMS | sd_in_vx | ṙ error RMS [rad/s²] | t |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    swaps = (("observer vy", ("vy",)), ("observer vx", ("vx",)),
             ("observer ṙ", ("yaw_acc",)), ("observer vx, vy, ṙ", ("vx", "vy", "yaw_acc")),
             ("truth vx, vy, ṙ", None))
    t3 = ["| log | measured | " + " | ".join(s for s, _ in swaps) + " | pipeline |",
          "|---|---|" + "---|" * (len(swaps) + 1)]
    for name in MISSES:
        log = ROOT / "scenarios" / f"{name}.csv"
        sensor, tru = read_csv(log), read_csv(truth[name])
        meas, mm = replay(binary, log, out, "measured", "measured")
        obs, mo = replay(binary, log, out, "observer", "observer")
        t1.append(f"| {name} | {valid_split(sensor, meas, obs)} |")
        rows = claims(sensor, tru, meas, obs)
        t2.append(f"| {name} | consistent | {claim_cells([r for r in rows if not r['wrong']])} |")
        t2.append(f"| | wrong (> 2 sd) | {claim_cells([r for r in rows if r['wrong']])} |")
        for lo, hi in UTIL_BINS:
            sel = [r for r in rows if lo <= r["util"] < hi]
            if sel:
                t2.append(f"| | utilisation {lo}–{min(hi, 1.0)} | {claim_cells(sel)} |")
        cells = []
        for label, cols in swaps:
            src = {"vx": "vx_est", "vy": "vy_est", "yaw_acc": "yaw_acc_est"}
            rep = ({c: obs[src[c]] for c in cols} if cols else
                   {c: tru[c] for c in ("vx", "vy", "yaw_acc")})
            sw = out / f"{name}.swap.csv"
            swap_log(log, sw, rep)
            cells.append(trust_text(replay(binary, sw, out, "swapped", "measured")[1]))
        t3.append(f"| {name} | {trust_text(mm)} | " + " | ".join(cells) +
                  f" | {trust_text(mo)} |")
        print(f"[diagnosis] {name}", file=sys.stderr, flush=True)
    print("\n".join(t1 + [""] + t2 + [""] + t3 + [""]))


def rule_misses(table: dict, tag: str) -> tuple[list[str], list[str]]:
    """The logs valid with measured velocities that miss issue 16's rule with run @tag: RMSE
    when valid up by more than RULE_RMSE; consistency below RULE_CONS where it is at least
    that with measured velocities (below it already is a friction-side matter, issue 17)."""
    rmse, cons = [], []
    for name, d in table.items():
        (rm, _, cm), (ro, _, co) = d["measured"], d[tag]
        if rm is None:
            continue
        if ro is not None and ro - rm > RULE_RMSE:
            rmse.append(name)
        if cm >= RULE_CONS > co:
            cons.append(name)
    return rmse, cons


def costs(table: dict, tag: str) -> tuple[list[str], list[str]]:
    """What run @tag costs against "off": the logs meeting the rule with "off" whose valid
    share drops by more than 5 points; the logs 0 % valid with both measured velocities and
    "off" (never excited) that become valid."""
    drop, woke = [], []
    for name, d in table.items():
        if name not in sum(rule_misses({name: d}, "off"), []) and d[tag][1] < d["off"][1] - 0.05:
            drop.append(f"{name} {pct(d['off'][1])} → {pct(d[tag][1])}")
        if d["measured"][1] == 0.0 and d["off"][1] == 0.0 and d[tag][1] > 0.0:
            woke.append(name)
    return drop, woke


def sweep(binary: Path, feed: Path, variants: list[str], out: Path) -> None:
    logs = sorted(p for p in (ROOT / "scenarios").glob("*.csv") if not p.name.endswith(".nf.csv"))
    jobs = []
    for log in logs:
        jobs.append((log, "measured", binary, "measured", None, None, "measured"))
        jobs.append((log, "off", binary, "observer", None, None, "off"))
        for i, v in enumerate(variants):
            label, mode, c = v.split(":")
            par = None
            if mode == "3":
                par = out / f"out_floor_{c}.par"
                par.write_text(f"obs_vy_out_floor_mu = {c}\n")
            jobs.append((log, label, feed, "observer", {"FEEDMODE": mode, "FEEDC": c}, par,
                         f"variant{i}"))
    with ThreadPoolExecutor(2) as ex:
        res = list(ex.map(lambda j: trust_cells(
            replay(j[2], j[0], out, j[6], j[3], j[4], j[5])[1]), jobs))
    table: dict = {}
    for j, r in zip(jobs, res):
        table.setdefault(j[0].name, {})[j[1]] = r
    tags = ["measured", "off"] + [v.split(":")[0] for v in variants]
    lines = ["| scenario | truth tyre | " + " | ".join(tags) + " |",
             "|---|---|" + "---|" * len(tags)]
    for name, d in table.items():
        truth = "Magic Formula" if ".mf" in name else "Dugoff"
        n = name.replace(".mf.csv", "").replace(".csv", "")
        lines.append(f"| {n} | {truth} | " + " | ".join(
            f"{fmt(d[t][0])} / {pct(d[t][1])} / {pct(d[t][2])}" for t in tags) + " |")
    lines.append("")
    for t in tags[1:]:
        rmse, cons = rule_misses(table, t)
        drop, woke = costs(table, t)
        lines.append(f"- {t}: RMSE half missed on {len(rmse)} ({', '.join(rmse)}); consistency "
                     f"half on {len(cons)} ({', '.join(cons)}); valid share down > 5 points on "
                     f"{len(drop)} logs meeting the rule ({'; '.join(drop)}); never-excited logs "
                     f"made valid: {len(woke)} ({', '.join(woke)})")
    print("\n".join(lines))


ORACLE = (("e", "5", "1"), ("2e", "5", "2"), ("4e", "5", "4"), ("e, vx too", "6", "1"),
          ("2e, vx too", "6", "2"))


def oracle(binary: Path, feed: Path, out: Path) -> None:
    """Table 4: the misses with an oracle's sd: sd_in_vy at least c |vy error| (and sd_in_vx
    at least c |vx error|), the errors per sample of the default run against the truth (so
    open loop: the fed run's own estimate moves a little with its friction)."""
    truth = truth_logs(MISSES, out)
    lines = ["| log | measured | off | " +
             " | ".join(f"sd ≥ {lab}" for lab, _, _ in ORACLE) + " |",
             "|---|---|---|" + "---|" * len(ORACLE)]
    for name in MISSES:
        log = ROOT / "scenarios" / f"{name}.csv"
        tru = read_csv(truth[name])
        _, mm = replay(binary, log, out, "measured", "measured")
        obs, mo = replay(binary, log, out, "observer", "observer")
        ff = out / f"{name}.errors.txt"
        ff.write_text("".join(f"{abs(a - b)!r} {abs(c - d)!r}\n" for a, b, c, d in
                              zip(obs["vx_est"], tru["vx"], obs["vy_est"], tru["vy"])))
        cells = [trust_text(replay(feed, log, out, f"oracle{i}", "observer",
                                   {"FEEDMODE": m, "FEEDC": c, "FEEDFILE": str(ff)})[1])
                 for i, (_, m, c) in enumerate(ORACLE)]
        lines.append(f"| {name} | {trust_text(mm)} | {trust_text(mo)} | " +
                     " | ".join(cells) + " |")
    print("\n".join(lines + [""]))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "observer_feed")
    ap.add_argument("--feed-replay", type=Path, help="mu_replay with the study's feed patch")
    ap.add_argument("--variant", action="append", default=[], help="LABEL:FEEDMODE:FEEDC")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    diagnosis(a.replay, a.out)
    if a.feed_replay:
        oracle(a.replay, a.feed_replay, a.out)
        sweep(a.replay, a.feed_replay, a.variant, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
