"""`make bench`: cost per estimator step, measured (issue 8, docs/BENCHMARKS.md).

Runs the benchmark binaries (bench/: build/bench/bench_{f32,f64,q31}) on one sensor log and
collects, per case (the whole estimator step in five configurations and every module):
  - host time per call: median, min and max over --reps passes over the log (each pass timed
    as a whole and divided by the number of samples);
  - instructions per call: one pass under valgrind --tool=callgrind, collected only inside
    bench_region() (deterministic: comparable run to run); the callgrind files of the step
    cases are kept with their per-function profile;
  - a filter-level case (sckf.*, ckf.*, qr.*) minus its baseline (restoring the state it
    starts from), in time and in instructions;
then FilterPy's CubatureKalmanFilter on the same model and log (scripts/bench/bench_filterpy.py:
time per step, ratio, agreement of its mu with this library's double CKF and SCKF), the
operation-count lower bound (scripts/bench/bench_lowerbound.py) and, when the firmware's emulated
run wrote build/firmware/pil.json, the Cortex-M4 instructions per step and the share of a
168 MHz core at 100 Hz. Writes OUT/bench.json and, with --page PAGE (alias --readme, the
former name), the tables between the markers <!-- bench:begin --> / <!-- bench:end --> of
PAGE (`make bench`: docs/BENCHMARKS.md); --no-page (alias --no-readme) skips that.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import csv
import datetime
import json
import os
import platform
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)
import bench_filterpy  # noqa: E402
import bench_lowerbound  # noqa: E402

FLAVOURS = ("f32", "f64", "q31")
FLAVOUR_NAME = {"f32": "float32", "f64": "double", "q31": "fixed point"}
STEP_CASES = {
    "step.paper.sckf.paper": ("paper preset, SCKF, paper tyre", "sckf", "paper"),
    "step.paper.ckf.paper": ("paper preset, CKF, paper tyre", "ckf", "paper"),
    "step.paper.sckf.absolute": ("paper preset, SCKF, absolute tyre", "sckf", "absolute"),
    "step.paper.ckf.absolute": ("paper preset, CKF, absolute tyre", "ckf", "absolute"),
    "step.default": ("default preset (2 states, Magic Formula tyre, gate)", None, "magic"),
}
MODULE_DOC = {
    "tyre.kinematics": "tyre: kinematics, slips, loads (per sample)",
    "tyre.forces_norm": "tyre: normalised Dugoff, 4 wheels",
    "tyre.forces_abs": "tyre: absolute Dugoff, 4 wheels, one mu",
    "tyre.forces_magic": "tyre: Magic Formula, 4 wheels, one mu",
    "obsmat.build": "obsmat: H(u) from the forces",
    "meas.setup.paper": "meas: set-up, paper tyre (kinematics + Dugoff + H)",
    "meas.setup.absolute": "meas: set-up, absolute tyre (kinematics)",
    "meas.eval.paper": "meas: h at one cubature point, paper (H x)",
    "meas.eval.absolute": "meas: h at one cubature point, absolute",
    "sckf.predict": "SCKF time update",
    "sckf.update.paper": "SCKF measurement update, paper tyre (2n points)",
    "sckf.update.absolute": "SCKF measurement update, absolute tyre",
    "ckf.predict": "CKF time update",
    "ckf.update.paper": "CKF measurement update, paper tyre",
    "ckf.update.absolute": "CKF measurement update, absolute tyre",
    "qr.tria.4x12": "qr: Tria() of a 4 x 12 matrix",
    "chol.4x4": "chol: Cholesky of a 4 x 4 matrix",
    "velocity.step": "velocity observer: one step (yaw-rate differentiator, vx, vy; OBSERVER.md)",
    "pipeline.step": "composed entry: observer + default-preset friction step (rfe/pipeline.h)",
}
M4_HZ = 168e6
STEP_HZ = 100.0


def say(msg: str) -> None:
    print(f"[bench] {msg}", flush=True)


# ---- host time ----------------------------------------------------------------------------
def host_times(bin_dir: str, log: str, reps: int) -> dict:
    res: dict = {}
    for fl in FLAVOURS:
        exe = os.path.join(bin_dir, f"bench_{fl}")
        if not os.path.exists(exe):
            say(f"{exe} missing: {fl} not measured")
            continue
        say(f"host time, {FLAVOUR_NAME[fl]}: {reps} passes over the log per case")
        out = subprocess.run([exe, "--log", log, "--reps", str(reps)], check=True,
                             capture_output=True, text=True).stdout
        for line in out.splitlines():
            r = json.loads(line)
            res[(fl, r["case"])] = r
    return res


# ---- callgrind ----------------------------------------------------------------------------
def _callgrind_one(exe: str, fl: str, case: str, log: str, keep_dir: str) -> tuple:
    keep = case.startswith("step.")
    out_file = (os.path.join(keep_dir, f"{fl}.{case}.callgrind") if keep
                else tempfile.mktemp(prefix="bench_cg_"))
    cmd = ["valgrind", "--tool=callgrind", "--toggle-collect=bench_region*",
           f"--callgrind-out-file={out_file}", exe, "--log", log, "--count", case]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"callgrind {fl} {case}: {r.stderr[-2000:]}")
    calls = json.loads(r.stdout.strip().splitlines()[-1])["calls"]
    total = None
    with open(out_file) as f:
        for line in f:
            if line.startswith("totals:") or line.startswith("summary:"):
                total = int(line.split()[1])
    profile = _profile(out_file, calls) if keep else None
    if not keep:
        os.unlink(out_file)
    return fl, case, total / calls, profile


_ANN = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(\S+?):(\S+)")


def _profile(out_file: str, calls: int, top: int = 12) -> list:
    """Exclusive instructions per step of the top functions (callgrind_annotate)."""
    r = subprocess.run(["callgrind_annotate", "--threshold=100", out_file],
                       capture_output=True, text=True)
    rows = []
    for line in r.stdout.splitlines():
        m = _ANN.match(line)
        if m and "PROGRAM TOTALS" not in line:
            fn = m.group(3)
            src = m.group(2)
            rows.append({"function": fn, "file": src,
                         "instr_per_step": int(m.group(1).replace(",", "")) / calls})
    merged: dict = {}
    for r_ in rows:  # inlined code of one function is listed per source file: merge
        merged.setdefault(r_["function"], 0.0)
        merged[r_["function"]] += r_["instr_per_step"]
    ranked = sorted(merged.items(), key=lambda kv: -kv[1])[:top]
    return [{"function": k, "instr_per_step": round(v, 1)} for k, v in ranked]


def callgrind_counts(bin_dir: str, log: str, out_dir: str, jobs: int) -> tuple:
    keep_dir = os.path.join(out_dir, "callgrind")
    os.makedirs(keep_dir, exist_ok=True)
    tasks = []
    for fl in FLAVOURS:
        exe = os.path.join(bin_dir, f"bench_{fl}")
        if not os.path.exists(exe):
            continue
        cases = subprocess.run([exe, "--list"], check=True, capture_output=True,
                               text=True).stdout.split("\n")
        tasks += [(exe, fl, c.split()[0]) for c in cases if c.strip()]
    say(f"callgrind: {len(tasks)} cases, {jobs} at a time")
    counts: dict = {}
    profiles: dict = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futs = [pool.submit(_callgrind_one, exe, fl, c, log, keep_dir) for exe, fl, c in tasks]
        for i, fut in enumerate(concurrent.futures.as_completed(futs), 1):
            fl, case, per_call, prof = fut.result()
            counts[(fl, case)] = per_call
            if prof is not None:
                profiles[(fl, case)] = prof
            if i % 10 == 0 or i == len(futs):
                say(f"callgrind: {i}/{len(futs)} done")
    return counts, profiles


# ---- our own estimates, for the FilterPy agreement -----------------------------------------
def our_mu(replay: str, log: str, filt: str, tyre: str, real: str = "double") -> np.ndarray:
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "est.csv")
        subprocess.run([replay, "--in", log, "--out", out, "--preset", "paper", "--filter", filt,
                        "--tyre", tyre, "--real", real, "--quiet"], check=True)
        with open(out) as f:
            rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    head = rows[0]
    idx = [head.index(c) for c in ("mu_fl", "mu_fr", "mu_rl", "mu_rr")]
    return np.array([[float(r[i]) for i in idx] for r in rows[1:]])


def filterpy_peer(log: str, replay: str, reps: int) -> dict:
    res = {}
    for tyre in ("paper", "absolute"):
        say(f"FilterPy CubatureKalmanFilter, {tyre} tyre: {reps} passes")
        prob = bench_filterpy.Problem(log, tyre)
        mu, med, lo, hi = bench_filterpy.timed(prob, reps)
        stock = bench_filterpy.run(prob, same_algorithm=False)
        d_ckf = float(np.max(np.abs(mu - our_mu(replay, log, "ckf", tyre))))
        d_sckf = float(np.max(np.abs(mu - our_mu(replay, log, "sckf", tyre))))
        res[tyre] = {"median_ns": med * 1e9, "min_ns": lo * 1e9, "max_ns": hi * 1e9,
                     "reps": reps, "steps": len(prob.vx),
                     "max_dmu_vs_double_ckf": d_ckf, "max_dmu_vs_double_sckf": d_sckf,
                     "max_dmu_stock_vs_same_algorithm": float(np.max(np.abs(stock - mu)))}
    return res


# ---- Cortex-M4 (firmware's emulated run) ----------------------------------------------------
# build/firmware/pil.json (make pil, mk/firmware.mk): {"runs": [{"core": "cortex-m4",
# "variant": "f32"|"q31", "preset": ..., "config": "paper.sckf"|"default.sckf", ...,
# "instructions_per_step": {"mean": ..., "min": ..., "max": ..., "steps": N}}, ...]}.
CONFIG_CASE = {"paper.sckf": "step.paper.sckf.paper", "paper.ckf": "step.paper.ckf.paper",
               "absolute.sckf": "step.paper.sckf.absolute",
               "absolute.ckf": "step.paper.ckf.absolute", "default.sckf": "step.default"}


def cortex_m4(path: str) -> dict:
    """{(flavour, step case): record} of the Cortex-M4 runs in pil.json ({} when absent)."""
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        data = json.load(f)
    out = {}
    for r in data.get("runs", []) if isinstance(data, dict) else []:
        if "m4" not in str(r.get("core", "")).lower():
            continue
        ips = r.get("instructions_per_step")
        if isinstance(ips, dict):
            ips = ips.get("mean")
        case = CONFIG_CASE.get(str(r.get("config", "")))
        fl = str(r.get("variant", ""))
        if ips is None or case is None or fl not in FLAVOURS:
            continue
        out[(fl, case)] = {"instructions_per_step": float(ips), "record": r,
                           "generated": datetime.datetime.fromtimestamp(
                               os.path.getmtime(path), datetime.timezone.utc).isoformat(
                                   timespec="seconds")}
    return out


def m4_lookup(m4: dict, fl: str, case: str):
    return m4.get((fl, case))


# ---- table -------------------------------------------------------------------------------
def fmt_ns(r) -> str:
    if r is None:
        return "–"
    return f"{r['median_ns']:,.0f} ({r['min_ns']:,.0f}–{r['max_ns']:,.0f})"


def fmt_int(x) -> str:
    return "–" if x is None else f"{x:,.0f}"


def build(args) -> dict:
    times = host_times(args.bin_dir, args.log, args.reps)
    counts, profiles = ({}, {}) if args.no_callgrind else callgrind_counts(
        args.bin_dir, args.log, args.out, args.jobs)
    peer = filterpy_peer(args.log, args.replay, args.filterpy_reps)
    m4 = cortex_m4(args.pil)
    say("Cortex-M4: " + (f"{len(m4)} records from {args.pil}" if m4 else
                         f"{args.pil} not there: not measured"))

    def net(fl, case):
        """time dict and instructions of a case less its baseline."""
        t = times.get((fl, case))
        c = counts.get((fl, case))
        base = t.get("baseline") if t else None
        if t is not None and base:
            b = times[(fl, base)]
            t = dict(t)
            for k in ("median_ns", "min_ns", "max_ns"):
                t[k] = max(t[k] - b["median_ns"], 0.0)
            if c is not None and (fl, base) in counts:
                c = c - counts[(fl, base)]
        return t, c

    steps = []
    for case, (label, filt, tyre) in STEP_CASES.items():
        bound = bench_lowerbound.step_total(filt, tyre) if filt else None
        for fl in FLAVOURS:
            t, c = net(fl, case)
            if t is None:
                continue
            row = {"case": case, "config": label, "flavour": fl, "host_ns": t,
                   "instructions": c, "lower_bound_ops": bound,
                   "instr_per_op": (c / bound) if (c and bound) else None}
            if filt and fl in ("f64", "f32"):
                row["filterpy_ratio"] = peer[tyre]["median_ns"] / t["median_ns"]
            m = m4_lookup(m4, fl, case)
            if m is not None:
                ips = m["instructions_per_step"]
                row["cortex_m4_instructions"] = ips
                row["cortex_m4_share_168MHz_100Hz"] = ips * STEP_HZ / M4_HZ
            steps.append(row)
    modules = []
    for case, doc in MODULE_DOC.items():
        row = {"case": case, "what": doc}
        for fl in FLAVOURS:
            t, c = net(fl, case)
            row[fl] = {"host_ns": t, "instructions": c}
        modules.append(row)
    lb = {f"{f}.{t}": bench_lowerbound.step_ops(f, t)
          for f in ("sckf", "ckf") for t in ("paper", "absolute")}
    return {
        "generated": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "host": {"machine": platform.machine(), "processor": _cpu_name(),
                 "python": platform.python_version()},
        "log": os.path.basename(args.log), "steps_per_pass": _calls(times),
        "reps": args.reps, "steps": steps, "modules": modules,
        "profiles": {f"{fl}.{case}": p for (fl, case), p in profiles.items()},
        "filterpy": peer, "lower_bound": lb,
        "cortex_m4": {"source": args.pil if m4 else None,
                      "generated": next(iter(m4.values()))["generated"] if m4 else None,
                      "records": [v["record"] for v in m4.values()]},
    }


def _calls(times: dict):
    for r in times.values():
        return r["calls"]
    return None


def _cpu_name() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def markdown(res: dict) -> str:
    L = []
    L.append(f"Measured by `make bench` on {res['host']['processor']} "
             f"({res['host']['machine']}), log `{res['log']}` ({res['steps_per_pass']} steps, all "
             "above v_est_min: every step runs the measurement update, which the default "
             f"preset's information gate may then hold), {res['reps']} passes; generated "
             f"{res['generated']}. *host ns/step*: median (min–max) over the passes; "
             "*instr/step*: callgrind, deterministic; *bound*: the operation-count lower bound "
             "of the step (below), *instr/op* the measured instructions per bound operation; "
             "*× FilterPy*: how many times faster than FilterPy's `CubatureKalmanFilter` on the "
             "same model, log and tyre mode; *Cortex-M4*: instructions per step of the "
             "firmware build under QEMU and the share of a 168 MHz core at 100 Hz (taking one "
             "instruction per cycle).")
    L.append("")
    L.append("| configuration | build | host ns/step | instr/step | bound [ops] | instr/op "
             "| × FilterPy | Cortex-M4 instr/step | share of 168 MHz at 100 Hz |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for r in res["steps"]:
        ratio = r.get("filterpy_ratio")
        m4 = r.get("cortex_m4_instructions")
        share = r.get("cortex_m4_share_168MHz_100Hz")
        ipo = "–" if r["instr_per_op"] is None else f"{r['instr_per_op']:.1f}"
        L.append(f"| {r['config']} | {FLAVOUR_NAME[r['flavour']]} | {fmt_ns(r['host_ns'])} | "
                 f"{fmt_int(r['instructions'])} | {fmt_int(r['lower_bound_ops'])} | "
                 f"{ipo} | "
                 f"{'–' if ratio is None else f'{ratio:,.0f}×'} | "
                 f"{'not measured' if m4 is None else fmt_int(m4)} | "
                 f"{'not measured' if share is None else f'{share * 100:.2f} %'} |")
    L.append("")
    src = res["cortex_m4"]
    if src["records"]:
        rec = src["records"][0]
        steps = rec.get("instructions_per_step", {})
        L.append("Cortex-M4 column: `make pil` (`build/firmware/pil.json`, written "
                 f"{src['generated']}): the firmware build on QEMU's {rec.get('machine', '')} "
                 "Cortex-M4, mean instructions per step over the first "
                 f"{steps.get('steps', '?') if isinstance(steps, dict) else '?'} steps of "
                 f"`{os.path.basename(str(rec.get('scenario', '')))}`; it measures the library "
                 "as that run built it, and covers the configurations it runs (\"not "
                 "measured\" elsewhere). One instruction per cycle is the optimistic case; "
                 "flash wait states and the FPU's multi-cycle divide and square root add to it.")
    else:
        L.append("Cortex-M4 column: not measured (no `build/firmware/pil.json`; `make pil` "
                 "writes it).")
    L.append("")
    fp = res["filterpy"]
    L.append("FilterPy peer (`scripts/bench/bench_filterpy.py`, FilterPy "
             f"{_filterpy_version()}): per step "
             f"{fp['paper']['median_ns'] / 1e3:,.0f} µs (paper tyre) and "
             f"{fp['absolute']['median_ns'] / 1e3:,.0f} µs (absolute tyre). Its μ agrees with "
             "this library's double CKF within "
             f"{fp['paper']['max_dmu_vs_double_ckf']:.1e} / "
             f"{fp['absolute']['max_dmu_vs_double_ckf']:.1e} and with the double SCKF within "
             f"{fp['paper']['max_dmu_vs_double_sckf']:.1e} / "
             f"{fp['absolute']['max_dmu_vs_double_sckf']:.1e} (paper / absolute, every step of "
             "the log): the same estimator. FilterPy's `update()` reuses the points its "
             "`predict()` drew before Q was added; the peer redraws them from the predicted P "
             "with FilterPy's `spherical_radial_sigmas`, as MODEL.md §6 specifies (unchanged "
             f"FilterPy differs by up to {fp['paper']['max_dmu_stock_vs_same_algorithm']:.1e}).")
    L.append("")
    L.append("Per module (per call, less the cost of restoring the state a filter-level case "
             "starts from; the states are those of the paper-preset run of the same log):")
    L.append("")
    L.append("| module | float32 ns | float32 instr | double ns | double instr | fixed-point ns "
             "| fixed-point instr |")
    L.append("|---|---|---|---|---|---|---|")
    for r in res["modules"]:
        cells = []
        for fl in FLAVOURS:
            t = r[fl]["host_ns"]
            c = r[fl]["instructions"]
            cells.append("–" if t is None else f"{t['median_ns']:,.0f}")
            cells.append(fmt_int(c))
        L.append(f"| {r['what']} | " + " | ".join(cells) + " |")
    L.append("")
    lb = res["lower_bound"]
    tot = {k: sum(v.values()) for k, v in lb.items()}
    L.append("Lower bound (`scripts/bench/bench_lowerbound.py`): every +, −, ×, ÷, √ and "
             "transcendental call of one step counted once, each stage as MODEL.md §6 writes "
             "it (dense formulas, only the structure that is there for free used: S is "
             "triangular, the centred state points are ±S/√2; the random walk's time update "
             "needs no points), n = 4, m = 3; for the fixed-point build the same count of "
             "integer multiply-accumulates, divisions and roots. SCKF, paper tyre, "
             f"{tot['sckf.paper']:,} operations: "
             + "; ".join(f"{k} {v}" for k, v in lb["sckf.paper"].items())
             + f". CKF, paper tyre: {tot['ckf.paper']:,}; SCKF, absolute tyre: "
             f"{tot['sckf.absolute']:,}; CKF, absolute tyre: {tot['ckf.absolute']:,} "
             "(itemised in `bench.json`).")
    prof = res["profiles"].get("f32.step.paper.sckf.paper")
    if prof:
        L.append("")
        L.append("Where a float32 SCKF step (paper tyre) spends its instructions (callgrind, "
                 "exclusive per step): "
                 + ", ".join(f"`{p['function']}` {p['instr_per_step']:,.0f}" for p in prof[:8])
                 + ".")
    return "\n".join(L)


def _filterpy_version() -> str:
    try:
        import filterpy
        return filterpy.__version__
    except (ImportError, AttributeError):
        return "?"


BEGIN, END = "<!-- bench:begin -->", "<!-- bench:end -->"


def write_page(path: str, table: str) -> None:
    with open(path) as f:
        text = f.read()
    block = f"{BEGIN}\n{table}\n{END}"
    if BEGIN in text and END in text:
        text = re.sub(re.escape(BEGIN) + r".*?" + re.escape(END), lambda _: block, text,
                      flags=re.S)
    else:
        raise SystemExit(f"{path}: markers {BEGIN} / {END} not found")
    with open(path, "w") as f:
        f.write(text)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin-dir", default="build/bench")
    ap.add_argument("--replay", default="build/mu_replay")
    ap.add_argument("--log", default="scenarios/brake_in_turn.csv")
    ap.add_argument("--reps", type=int, default=51)
    ap.add_argument("--filterpy-reps", type=int, default=11)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default="build/bench")
    ap.add_argument("--pil", default="build/firmware/pil.json")
    ap.add_argument("--page", "--readme", dest="page", default=None,
                    help="rewrite the tables between the bench markers of this page")
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--no-page", "--no-readme", dest="no_page", action="store_true")
    ap.add_argument("--quick", action="store_true", help="few passes (a smoke run)")
    ap.add_argument("--render-only", action="store_true",
                    help="no measurement: the tables from OUT/bench.json of an earlier run")
    a = ap.parse_args(argv)
    if a.quick:
        a.reps, a.filterpy_reps = 5, 1
    os.makedirs(a.out, exist_ok=True)
    out_json = os.path.join(a.out, "bench.json")
    if a.render_only:
        with open(out_json) as f:
            res = json.load(f)
    else:
        res = build(a)
        with open(out_json, "w") as f:
            json.dump(res, f, indent=1, default=str)
    table = markdown(res)
    with open(os.path.join(a.out, "bench.md"), "w") as f:
        f.write(table + "\n")
    say(f"wrote {out_json} and {os.path.join(a.out, 'bench.md')}")
    if a.page and not a.no_page:
        write_page(a.page, table)
        say(f"table written into {a.page}")
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
