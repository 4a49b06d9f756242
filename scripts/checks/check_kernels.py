"""Prove that the golden checks do not depend on the CPU: regenerate the reference goldens
under several numerical configurations of this machine and compare them with the committed
goldens and with each other (scripts/reference/compare.py: mu and sd within 1e-9, decisions
and metadata exactly).

Usage (from the repository root; `make check-kernels`, part of `make test`):

    .venv/bin/python scripts/checks/check_kernels.py [--scenarios scenarios] [--goldens scenarios/golden]
        [--out build/kernels] [--jobs N] [--subset LOG,LOG]

What varies, and why: the reference's QR, Cholesky and products go to OpenBLAS, which picks a
kernel per CPU (OPENBLAS_CORETYPE forces one) and a thread count (OPENBLAS_NUM_THREADS); its
elementwise exp, log, arctan, arctan2 and tanh go to SIMD paths numpy picks per CPU
(NPY_DISABLE_CPU_FEATURES turns them off). Configurations:

  as-is     the environment as given (the kernel the CPU or the caller chose), 1 thread,
            on the --subset logs (every golden when no generic configuration differs
            from it here);
  generic   the architecture's oldest kernel (x86-64: Prescott, SSE3; aarch64: ARMV8) with
            numpy's dispatched SIMD paths off, 1 thread, every golden; if that is what as-is
            already runs, the next kernel the CPU has;
  <kernel>  every further kernel of the architecture the CPU can run (x86-64: Haswell with
            AVX2/FMA, SkylakeX with AVX-512), on the --subset logs;
  threads   as-is with OPENBLAS_NUM_THREADS = the number of CPUs (OpenBLAS's own default),
            on the first --subset log.

A kernel the CPU lacks the instructions for is reported and skipped, never forced (and a
run that dies of a signal anyway is reported and skipped). On an architecture without a
kernel list the BLAS configurations are skipped with that reason and numpy's are still
compared. Exit 0 when every run agrees, 1 when one differs (the report names the file, the
row and the margin of a flipped decision), 2 on a usage error.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import json
import os
import platform
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.dirname(HERE)                 # reference/, and data/ (make_goldens)
sys.path[:0] = [SCRIPTS, os.path.join(SCRIPTS, "data")]

# Per architecture: (OPENBLAS_CORETYPE name, CPU flags it needs), oldest first. The names are
# OpenBLAS's (driver/others/dynamic.c); the flags /proc/cpuinfo's.
KERNELS = {
    "x86_64": [("Prescott", {"pni"}), ("Haswell", {"avx2", "fma"}),
               ("SkylakeX", {"avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl"})],
    "aarch64": [("ARMV8", set()), ("NEOVERSEN1", {"asimd", "fp"}),
                ("NEOVERSEV1", {"sve"})],
}
DEFAULT_SUBSET = "brake_in_turn.csv,paper_mu_step.nf.csv"


def cpu_flags() -> set[str]:
    """The CPU's feature flags (x86 'flags', Arm 'Features' in /proc/cpuinfo); empty if none."""
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as fh:
            for line in fh:
                key, _, value = line.partition(":")
                if key.strip() in ("flags", "Features"):
                    return set(value.split())
    except OSError:
        pass
    return set()


def probe(env: dict) -> dict:
    """What a fresh process computes with under env: BLAS, kernel, threads, numpy SIMD.
    {'error': ...} when it fails (a signal: the kernel cannot run on this CPU)."""
    code = ("import json; from reference import runtime; "
            "print(json.dumps({'blas': runtime.blas(), 'kernel': runtime.blas_kernel(), "
            "'numpy_simd': runtime.numpy_simd(), 'dispatched': runtime.numpy_dispatched()}))")
    r = subprocess.run([sys.executable, "-c", code], env=env, cwd=SCRIPTS, capture_output=True,
                       text=True, check=False)
    if r.returncode != 0:
        return {"error": _death(r.returncode, r.stderr)}
    return json.loads(r.stdout)


def _death(rc: int, stderr: str) -> str:
    if rc < 0:
        return f"killed by {signal.Signals(-rc).name}"
    tail = stderr.strip().splitlines()[-1:] or [""]
    return f"exit {rc}: {tail[0]}"


def env_for(base: dict, coretype: str | None, threads: str, numpy_off: list[str] | None) -> dict:
    """base with the BLAS thread count set, OPENBLAS_CORETYPE forced when coretype is given
    (else as in base) and numpy's SIMD targets numpy_off disabled (None: as in base)."""
    e = {k: v for k, v in base.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")}
    if coretype is not None:
        e["OPENBLAS_CORETYPE"] = coretype
    e["OPENBLAS_NUM_THREADS"] = e["OMP_NUM_THREADS"] = threads
    if numpy_off is not None:
        e["NPY_DISABLE_CPU_FEATURES"] = " ".join(numpy_off)
        if not numpy_off:
            e.pop("NPY_DISABLE_CPU_FEATURES")
    return e


def _config(name: str, env: dict, logs) -> dict:
    return {"name": name, "env": env, "logs": logs, "probe": probe(env)}


def _key(cfg: dict):
    return (cfg["probe"]["kernel"], cfg["probe"]["numpy_simd"])


def plan(base: dict, flags: set[str], arch: str, subset: list[str]):
    """The configurations to run (dicts: name, env, logs 'all' or a list, probe) and the
    (name, reason) pairs skipped."""
    runs, skipped = [], []
    # as-is runs the subset: the generic configuration below is the one that walks every
    # golden (the oldest kernel, numpy's SIMD off: the farthest from the machine that wrote
    # them), and test-py's test_goldens_up_to_date runs the subset as-is too; a second full
    # walk cost a third of the check's time
    as_is = _config("as-is", env_for(base, None, "1", None), subset)
    if "error" in as_is["probe"]:
        raise SystemExit(f"check_kernels: the reference cannot run as-is: {as_is['probe']['error']}")
    runs.append(as_is)
    seen = {_key(as_is)}
    kernels = KERNELS.get(arch)
    if kernels is None:
        skipped.append(("BLAS kernels", f"no OpenBLAS kernel list for architecture {arch!r} "
                        f"(known: {', '.join(KERNELS)}); only numpy's SIMD paths vary"))
    numpy_off = as_is["probe"]["dispatched"]
    generic = None
    for coretype, need in kernels or [(None, set())]:
        label = coretype or "as-is kernel"
        missing = sorted(need - flags)
        if missing:
            skipped.append((label, "the CPU lacks " + ", ".join(missing)))
            continue
        if generic is None:         # the oldest runnable kernel, numpy's baseline: every log
            cfg = _config("generic", env_for(base, coretype, "1", numpy_off), "all")
        else:                       # a further kernel, numpy as given: the subset
            cfg = _config(label, env_for(base, coretype, "1", None), subset)
        if "error" in cfg["probe"]:
            skipped.append((label, f"cannot run here ({cfg['probe']['error']})"))
            continue
        if _key(cfg) in seen:
            skipped.append((label, f"the same kernel ({cfg['probe']['kernel']}) and numpy paths "
                            "as a configuration already run"))
            continue
        seen.add(_key(cfg))
        runs.append(cfg)
        generic = generic or cfg
    if generic is None:
        skipped.append(("generic", "no second configuration differs from as-is here"))
        as_is["logs"] = "all"       # then as-is is the walk over every golden
    ncpu = str(os.cpu_count() or 1)
    # the first subset log only: how many threads share a product does not depend on the
    # log. OPENBLAS_THREAD_TIMEOUT=4 (its minimum: 2^4 cycles) lets a waiting thread sleep
    # instead of spinning: it changes no result, only idling, and with make test's other jobs
    # on the same cores the spinning threads took 6x the CPU time of the 1-thread run
    env = env_for(base, None, ncpu, None)
    env["OPENBLAS_THREAD_TIMEOUT"] = "4"
    thr = _config("threads", env, subset[:1])
    if ncpu == "1":
        thr["note"] = "1 CPU: OpenBLAS's default is 1 thread here too"
    runs.append(thr)
    return runs, skipped


def worker(names: list[str], scenarios: str, out: str) -> int:
    """Regenerate the goldens of the given sensor logs into out, with diagnostics beside them
    (<golden>.diag.npz) and the runtime description (runtime.json)."""
    import numpy as np
    import make_goldens
    from reference import compare, estimate, runtime

    os.makedirs(out, exist_ok=True)
    for name in names:
        src = os.path.join(scenarios, name)
        for preset, tyre, kind, tag in make_goldens.jobs_for(name):
            dst = os.path.join(out, f"{name[:-len('.csv')]}.{tag}.csv")
            res = estimate.estimate_file(src, dst, None, kind, tyre, preset)
            np.savez(dst[:-len(".csv")] + ".diag.npz", **compare.diagnostics(res))
    with open(os.path.join(out, "runtime.json"), "w", encoding="utf-8") as fh:
        json.dump({"blas": runtime.blas(), "numpy_simd": runtime.numpy_simd()}, fh)
    return 0


def _diag(path: str):
    import numpy as np
    p = path[:-len(".csv")] + ".diag.npz"
    if not os.path.exists(p):
        return None
    with np.load(p) as z:
        return {k: z[k] for k in z.files}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenarios", default="scenarios")
    ap.add_argument("--goldens", default=os.path.join("scenarios", "golden"))
    ap.add_argument("--out", default=os.path.join("build", "kernels"))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="configurations run side by side (speed only; default: the CPUs)")
    ap.add_argument("--subset", default=DEFAULT_SUBSET,
                    help="sensor logs of the further kernels and the threads run")
    ap.add_argument("--worker", nargs="*", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.worker is not None:
        return worker(a.worker, a.scenarios, a.out)

    import make_goldens
    from reference import compare

    names = sorted(f for f in os.listdir(a.scenarios)
                   if os.path.isfile(os.path.join(a.scenarios, f)) and make_goldens.jobs_for(f))
    subset = [s for s in a.subset.split(",") if s]
    unknown = [s for s in subset if s not in names]
    if not names or unknown:
        print(f"check_kernels: {'no sensor logs in ' + a.scenarios if not names else ''}"
              f"{'unknown --subset logs: ' + ', '.join(unknown) if unknown else ''}", file=sys.stderr)
        return 2
    arch = platform.machine()
    flags = cpu_flags()
    runs, skipped = plan(dict(os.environ), flags, arch, subset)
    print(f"check_kernels: {arch}, {os.cpu_count()} CPUs; {len(runs)} configurations, "
          f"{a.jobs} at a time")
    for name, why in skipped:
        print(f"  skipped {name}: {why}")

    def run(cfg):
        logs_ = names if cfg["logs"] == "all" else cfg["logs"]
        out = os.path.join(a.out, cfg["name"])
        t0 = time.perf_counter()
        r = subprocess.run([sys.executable, os.path.abspath(__file__), "--scenarios",
                            os.path.abspath(a.scenarios), "--out", os.path.abspath(out),
                            "--worker", *logs_], env=cfg["env"], capture_output=True, text=True,
                           check=False)
        return cfg, logs_, out, r, time.perf_counter() - t0

    failed = False
    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for cfg, logs_, out, r, secs in pool.map(run, runs):
            p = cfg["probe"]
            desc = f"{p.get('blas', '?')}; numpy {p.get('numpy_simd', '?')}"
            if r.returncode != 0:
                if r.returncode < 0 and cfg["name"] != "as-is":
                    print(f"  skipped {cfg['name']}: {_death(r.returncode, r.stderr)} ({desc})")
                    continue
                print(f"  {cfg['name']}: FAILED to run ({_death(r.returncode, r.stderr)})\n{r.stderr}")
                failed = True
                continue
            results[cfg["name"]] = (cfg, logs_, out)
            print(f"  ran {cfg['name']}: {desc}; {len(logs_)} logs in {secs:.0f} s"
                  f"{' (' + cfg['note'] + ')' if cfg.get('note') else ''}", flush=True)

    print(f"{'configuration':<14} {'against':<10} {'files':>5} {'max |dmu|':>10} {'max |dsd|':>10}  result")
    for name, (cfg, logs_, out) in results.items():
        files = sorted(f for f in os.listdir(out) if f.endswith(".csv"))
        against = [("committed", a.goldens)]
        if name != "as-is" and "as-is" in results:
            against.append(("as-is", results["as-is"][2]))
        for label, ref_dir in against:
            worst_mu = worst_sd = 0.0
            bad = []
            compared = 0
            # against the as-is run: the files both ran (as-is runs the subset when a
            # generic configuration walks every golden)
            for f in (files if label == "committed"
                      else [g for g in files if os.path.exists(os.path.join(ref_dir, g))]):
                ref = os.path.join(ref_dir, f)
                if not os.path.exists(ref):
                    bad.append(f"{f}: no {label} golden {ref} (run make goldens)")
                    continue
                compared += 1
                res = compare.compare_logs(ref, os.path.join(out, f), _diag(ref),
                                           _diag(os.path.join(out, f)))
                worst_mu, worst_sd = max(worst_mu, res.max_dmu), max(worst_sd, res.max_dsd)
                if not res.ok:
                    bad.append(compare.report(res))
            print(f"{name:<14} {label:<10} {compared:>5} {worst_mu:>10.2e} {worst_sd:>10.2e}  "
                  f"{'ok' if not bad else 'DIFFERS'}")
            for b in bad:
                print("  " + b.replace("\n", "\n  "))
            failed |= bool(bad)
    if len(results) < 2:
        print("check_kernels: only one numerical configuration ran here; nothing was compared "
              "across configurations (reasons above)")
    verdict = ("FAILED: a run differs (above) from" if failed else "ok: every run agrees with")
    print(f"check_kernels: {verdict} the committed goldens and the as-is run within "
          f"{compare.TOL_MU:g} (mu, sd), decisions exactly")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
