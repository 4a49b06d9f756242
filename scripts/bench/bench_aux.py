#!/usr/bin/env python3
"""Host cost per step of the mass and grade estimator and the tyre identifier (make bench,
docs/BENCHMARKS.md "Other estimators").

For each case (mg_ukf: UKF + ax, the recommended car preset; mg_aukf: the seed's AUKF;
tid: the tyre identifier, RFE_TID_N = 256 particles) and build (float32, double) of
bench/bench_aux.c:
  - host time per step: the whole log, --reps passes (each from a fresh init), mean of the
    passes' ns per step (and the median and the fastest pass);
  - instructions per step: valgrind --tool=callgrind --toggle-collect=bench_aux_region over
    the log's first COUNT_ROWS[case] steps, the same steps make pil-aux counts on the
    Cortex-M4F (deterministic; a short window keeps make bench's added time to seconds);
  - the Cortex-M4F figures of build/firmware/pil_aux.json when make pil-aux wrote it.
Writes --out/bench_aux.json, the table between <!-- bench-aux:begin --> and
<!-- bench-aux:end --> of --page, and the cost tables of the results pages (--mg-page,
--tid-page) between <!-- cost-per-step:begin --> and <!-- cost-per-step:end -->.
"""
import argparse
import concurrent.futures
import datetime
import json
import os
import re
import subprocess
import sys
import tempfile

CASES = {
    "mg_ukf": ("mass and grade, UKF + ax (recommended car preset)", "mg"),
    "mg_aukf": ("mass and grade, the seed's AUKF (speed and torque only)", "mg"),
    "tid": ("tyre identifier, APF, 256 particles", "tid"),
}
# Steps counted under callgrind: the first ones of the log, as mk/firmware.mk's PIL_AUX_ENTRIES.
COUNT_ROWS = {"mg_ukf": 500, "mg_aukf": 500, "tid": 20}
RATE_HZ = {"mg": 50.0, "tid": 100.0}
BUILDS = {"f32": "float32", "f64": "double"}
BEGIN, END = "<!-- bench-aux:begin -->", "<!-- bench-aux:end -->"
COST_BEGIN, COST_END = "<!-- cost-per-step:begin -->", "<!-- cost-per-step:end -->"


def run_time(exe, case, log, reps):
    out = subprocess.run([exe, "--case", case, "--log", log, "--reps", str(reps)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, check=True).stdout.split()
    return {"mean_ns": float(out[1]), "min_ns": float(out[2]), "median_ns": float(out[3]), "steps": int(out[5]),
            "reps": reps}


def run_callgrind(exe, case, log, rows):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "cg.out")
        r = subprocess.run(["valgrind", "--tool=callgrind", "--toggle-collect=bench_aux_region",
                            f"--callgrind-out-file={out}", exe, "--case", case, "--log", log, "--rows",
                            str(rows), "--reps", "1"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"callgrind {exe} {case}: {r.stderr[-1500:]}")
        m = re.search(r"^(?:summary|totals):\s*(\d+)", open(out).read(), re.M)
        return int(m.group(1)) / rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin-dir", required=True)
    ap.add_argument("--mg-log", required=True)
    ap.add_argument("--tid-log", required=True)
    ap.add_argument("--pil", default="build/firmware/pil_aux.json")
    ap.add_argument("--reps", type=int, default=21, help="timed passes (the tyre identifier: 3)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--page", default="")
    ap.add_argument("--mg-page", default="", help="MASS_GRADE_RESULTS.md: its cost table")
    ap.add_argument("--tid-page", default="", help="TYRE_ID_RESULTS.md: its cost table")
    a = ap.parse_args(argv)
    logs = {"mg": a.mg_log, "tid": a.tid_log}
    res = {"generated": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
           "logs": logs, "count_rows": COUNT_ROWS, "cases": {}}
    try:
        pil = {r["entry"]: r for r in json.load(open(a.pil)).get("aux_runs", [])}
    except (OSError, ValueError):
        pil = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        futs = {}
        for case, (_, est) in CASES.items():
            for b in BUILDS:
                exe = os.path.join(a.bin_dir, f"bench_aux_{b}")
                futs[(case, b, "cg")] = pool.submit(run_callgrind, exe, case, logs[est], COUNT_ROWS[case])
        # times once callgrind is done, one at a time (the two cores are shared)
        concurrent.futures.wait(list(futs.values()))
        times = {(case, b): run_time(os.path.join(a.bin_dir, f"bench_aux_{b}"), case, logs[est],
                                     a.reps if est == "mg" else 3)
                 for case, (_, est) in CASES.items() for b in BUILDS}
        for (case, b, _), f in futs.items():
            e = res["cases"].setdefault(case, {"what": CASES[case][0], "log": logs[CASES[case][1]],
                                               "rate_hz": RATE_HZ[CASES[case][1]]})
            e[b] = dict(times[(case, b)], instructions_per_step=round(f.result(), 1))
    for case, e in res["cases"].items():
        p = pil.get(case)
        if p and "instructions_per_step" in p:
            e["m4f"] = {"mean": p["instructions_per_step"]["mean"], "max": p["instructions_per_step"]["max"],
                        "steps": p["instructions_per_step"]["steps"], "share_mean": p["core_share_mean"],
                        "share_max": p["core_share_max"], "stack_measured": p.get("stack_measured"),
                        "bit_identical_fraction": p["compare"]["bit_identical_fraction"]}
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "bench_aux.json"), "w") as f:
        json.dump(res, f, indent=2, sort_keys=True)
    table = markdown(res)
    print(table)
    for page, begin, end, body in ((a.page, BEGIN, END, table),
                                   (a.mg_page, COST_BEGIN, COST_END, cost_table(res, ("mg_ukf", "mg_aukf"))),
                                   (a.tid_page, COST_BEGIN, COST_END, cost_table(res, ("tid",)))):
        if not page:
            continue
        text = open(page).read()
        if begin not in text or end not in text:
            sys.exit(f"{page}: markers {begin} / {end} not found")
        head, rest = text.split(begin, 1)
        open(page, "w").write(head + begin + "\n" + body + end + rest.split(end, 1)[1])
    return 0


def cost_table(res, cases):
    """The results page's cost table: host float32 and double, the Cortex-M4F."""
    L = [f"Generated by `make bench` ({res['generated']}; host: this machine, x86-64, glibc, a machine "
         "shared with other jobs, so the times move by tens of percent run to run and the "
         "instruction counts are the steady figure; "
         "M4F: `make pil-aux`, float32 under QEMU, one instruction per cycle assumed).", "",
         "| configuration | host float32 ns/step median (fastest pass) | host double ns/step median (fastest pass) | "
         "host float32 instr/step | M4F instr/step mean (max) | share of a 100 MHz M4F at its rate | "
         "same at 100 Hz |", "|---|---|---|---|---|---|---|"]
    for case in cases:
        e = res["cases"][case]
        m = e.get("m4f")
        f, d = e["f32"], e["f64"]
        if m:
            m4 = f"{m['mean']:,.0f} ({m['max']:,})"
            share = f"{100 * m['share_mean']:.2f} % at {e['rate_hz']:.0f} Hz"
            at100 = f"{100 * m['mean'] * 100.0 / 100e6:.2f} %"
        else:
            m4 = share = at100 = "not measured (run make pil-aux first)"
        L.append(f"| {e['what']} | {f['median_ns']:,.0f} ({f['min_ns']:,.0f}) | {d['median_ns']:,.0f} "
                 f"({d['min_ns']:,.0f}) | {f['instructions_per_step']:,.0f} | {m4} | {share} | {at100} |")
    return "\n".join(L) + "\n"


def markdown(res):
    L = [f"Measured by `make bench` (scripts/bench/bench_aux.py), generated {res['generated']}. "
         f"Logs: `{os.path.basename(res['logs']['mg'])}` (mass and grade, 50 Hz) and "
         f"`{os.path.basename(res['logs']['tid'])}` (tyre identifier, 100 Hz). *host ns/step*: mean over "
         f"the passes of the whole log (median and fastest pass in brackets; 21 passes, the tyre identifier 3: "
         f"a shared machine, the median is the steadier figure); "
         f"*instr/step*: callgrind over the log's first {res['count_rows']['mg_ukf']} (mass and grade) or "
         f"{res['count_rows']['tid']} (tyre identifier) steps, the ones `make pil-aux` counts on the "
         f"Cortex-M4F; *M4F*: `make pil-aux`'s float32 instructions per step (mean, max) and the share of a "
         f"100 MHz core at the estimator's rate (one instruction per cycle), when "
         f"`build/firmware/pil_aux.json` exists.", "",
         "| estimator | build | host ns/step | instr/step | M4F instr/step (max) | share of 100 MHz at its rate |",
         "|---|---|---|---|---|---|"]
    for case, e in res["cases"].items():
        m = e.get("m4f")
        for b, name in BUILDS.items():
            r = e[b]
            if b == "f32" and m:
                m4 = f"{m['mean']:,.0f} ({m['max']:,})"
                share = f"{100 * m['share_mean']:.2f} % at {e['rate_hz']:.0f} Hz (max {100 * m['share_max']:.2f} %)"
            elif b == "f32":
                m4, share = "not measured", "not measured"
            else:
                m4, share = "– (float32 only)", "–"
            L.append(f"| {e['what']} | {name} | {r['mean_ns']:,.0f} ({r['median_ns']:,.0f}, {r['min_ns']:,.0f}) | "
                     f"{r['instructions_per_step']:,.0f} | {m4} | {share} |")
    return "\n".join(L) + "\n"


if __name__ == "__main__":
    sys.exit(main())
