#!/usr/bin/env python3
"""Where a friction step's instructions go on the PIL cores (make pil-profile, issue 21 "measure
first"): per function, the instructions per step with its callees (inclusive) and in the
function itself (own), and its calls per step, on QEMU's cores, next to callgrind's profile of
the same program on the host.

Target: firmware_pil.count_instructions on the PIL image of one configuration (default:
default.sckf of make pil, brake_in_turn), the first --steps samples: every executed translation
block is attributed to the function it starts in (arm-none-eabi-nm; a call ends a block, so a
block never spans two functions), a call is an execution of the block at a function's first
instruction, the inclusive counts come from the call stack kept over the blocks (callees=), and
the object each function comes from is the linker map's. Host: the same program built for the
host (firmware/pil/pil_main.c with -DPIL_HOST, mk/firmware.mk) under valgrind
--tool=callgrind, collecting inside rfe_friction_step_<f32|q31> only, inclusive and own
instructions per function from callgrind_annotate. The host's compiler inlines other functions
than the target's, so a function missing from one column was inlined there.

Writes --json and the tables between <!-- firmware-profile:begin --> and
<!-- firmware-profile:end --> of --page (docs/FIRMWARE.md). Not part of make test: a
measurement (about a minute, most of it the Cortex-M0+'s execution log).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(os.path.dirname(HERE), "tools")]

import firmware_pil as fp  # noqa: E402
from md_tables import replace_region  # noqa: E402

BEGIN, END = "<!-- firmware-profile:begin -->", "<!-- firmware-profile:end -->"
TOP = 16   # functions per run by inclusive instructions (a table lists the union of its runs')
WHOLE = 0.999  # a function with this share of the step or more wraps the whole step
CORES = {"m4f": "Cortex-M4F", "m3": "Cortex-M3", "m0p": "Cortex-M0+"}
VARIANTS = {"f32": "float32", "q31": "fixed point"}


def target_profile(build, target, machine, config, steps):
    """{total, functions: [[name, self instructions per step, calls per step, object,
    inclusive instructions per step]], most inclusive first}."""
    elf = os.path.join(build, target, "pil", config + ".elf")
    incl = {}
    counts, _, per_func = fp.count_instructions(machine, elf, steps, functions=True, callees=incl)
    objects = fp.code_objects(elf)
    starts, names = fp.function_table(elf)
    # librfe_q31.a(fxmath_q31.o) -> fxmath_q31.o, as the float32 image's map already names it
    where = {n: re.sub(r"^lib\w+\.a\((.*)\)$", r"\1", fp.object_of(objects, a)) for a, n in zip(starts, names)}
    funcs = sorted(([f, v / steps, c / steps, where.get(f, "?"), incl.get(f, v) / steps]
                    for f, (v, c) in per_func["step"].items()), key=lambda x: (-x[4], -x[1]))
    return {"total": sum(counts) / steps, "functions": funcs}


def host_profile(build, variant, config, steps):
    """The host program of the configuration under callgrind, collecting inside the step
    function: {total, self: {name: instructions per step}, inclusive: {...}}."""
    prog = os.path.join(build, f"host-{variant}", "pil", config)
    step = f"rfe_friction_step_{variant}"
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        r = subprocess.run(["valgrind", "--tool=callgrind", f"--toggle-collect={step}",
                            f"--callgrind-out-file={out}", prog, str(steps)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            sys.exit(f"pil-profile: callgrind on {prog} failed: {r.stderr[-1500:]}")
        prof = {}
        for kind in ("self", "inclusive"):
            ann = subprocess.run(["callgrind_annotate", "--auto=no", "--threshold=100",
                                  f"--inclusive={'yes' if kind == 'inclusive' else 'no'}", out],
                                 stdout=subprocess.PIPE, text=True, check=True).stdout
            p = parse_annotate(ann, steps, inclusive=kind == "inclusive")
            if p is None:
                sys.exit(f"pil-profile: no totals in callgrind_annotate's output for {prog}")
            prof["total"], prof[kind] = p["total"], dict(p["functions"])
    return prof


def parse_annotate(text, steps, inclusive=False):
    """callgrind_annotate's totals and its per-function lines ("1,234 (5.6%)  file.c:name [exe]")
    per step; None without totals. A name on several lines (a recursive call's "name'2", code of
    the function under another source file: an inlined header, the path spelt otherwise) is
    summed for own counts, which are disjoint, and the largest taken for inclusive ones, which
    overlap (--inclusive=yes lists a function once per spelling of its file, each line with
    all of its callees)."""
    total, funcs = None, {}
    for ln in text.splitlines():
        m = re.match(r"^\s*([\d,]+)\s+(?:\([^)]*\)\s+)?(?:PROGRAM TOTALS|(\S+):(\S+))", ln)
        if not m:
            continue
        n = int(m.group(1).replace(",", ""))
        if m.group(2) is None:
            total = n / steps
        else:
            name = m.group(3).split("'")[0]
            funcs[name] = max(funcs.get(name, 0.0), n / steps) if inclusive else funcs.get(name, 0.0) + n / steps
    if total is None:
        return None
    return {"total": total, "functions": sorted(([f, v] for f, v in funcs.items()), key=lambda x: -x[1])}


def fmt(x):
    return f"{x:,.0f}"


def table(runs, host):
    """One markdown table for one variant: the union of each run's TOP functions by inclusive
    instructions, in the first run's order; per run the inclusive instructions per step (share
    of the step), the function's own and its calls per step; the host's inclusive and own."""
    top = []
    for r in runs:
        # the wrappers of the whole step (PIL's main, the public step) say no more than its total
        inner = [f for f in r["profile"]["functions"] if f[4] < WHOLE * r["profile"]["total"]]
        for f in inner[:TOP]:
            if f[0] not in top:
                top.append(f[0])
    head = ["function", "object"]
    for r in runs:
        c = CORES[r["core"]]
        head += [f"{c}: with callees (share)", f"{c}: own", f"{c}: calls"]
    head += ["host x86-64: with callees", "host: own"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for name in top:
        row = [f"`{name}`", "?"]
        for r in runs:
            d = {f[0]: f for f in r["profile"]["functions"]}
            if name in d:
                _, own, calls, obj, incl = d[name]
                row[1] = obj if row[1] == "?" else row[1]
                row += [f"{fmt(incl)} ({100 * incl / r['profile']['total']:.1f} %)", fmt(own), f"{calls:.1f}"]
            else:
                row += ["–", "–", "–"]
        row += [fmt(host[k][name]) if name in host[k] else "–" for k in ("inclusive", "self")]
        out.append("| " + " | ".join(row) + " |")
    total = ["**the step**", ""]
    for r in runs:
        total += [f"**{fmt(r['profile']['total'])}**", "", ""]
    total += [f"**{fmt(host['total'])}**", ""]
    out.append("| " + " | ".join(total) + " |")
    return out


def markdown(res):
    L = [f"Measured by `make pil-profile` (QEMU: {res['qemu']}; valgrind's callgrind on the host "
         f"program built with the host's `-O2`), `{res['log']}`, configuration `{res['config']}`, "
         f"the log's first {res['steps']} steps, per function: instructions per step with its callees "
         "(inclusive) and their share of the step, in the function itself (own), calls per step; the "
         "object is the linker map's (`libgcc`: the compiler's helpers, e.g. the 64-bit multiply "
         "`__muldi3` and division `__udivmoddi4` of the Cortex-M0+, which has no 32x32->64 "
         "multiply). A dash: no such function in that build (inlined into its caller, or, on the "
         "host, glibc's libm instead of newlib's).", ""]
    for variant in ("f32", "q31"):
        runs = [r for r in res["runs"] if r["variant"] == variant]
        if not runs:
            continue
        L.append(f"{VARIANTS[variant].capitalize()} ("
                 + ", ".join(f"`{r['target']}` on `{r['machine']}`" for r in runs) + "):")
        L.append("")
        L += table(runs, res["host"][variant])
        L.append("")
    return L[:-1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build/firmware")
    ap.add_argument("--log", default="scenarios/brake_in_turn.csv")
    ap.add_argument("--config", default="default.sckf")
    ap.add_argument("--runs", default="m4f-f32:mps2-an386 m4f-q31:mps2-an386 m0p-q31:microbit",
                    help="<target>:<QEMU machine> ...")
    ap.add_argument("--steps", type=int, default=100, help="the log's first steps, profiled")
    ap.add_argument("--json", default="build/firmware/pil_profile.json")
    ap.add_argument("--page", default="", help="docs/FIRMWARE.md: write the tables there")
    a = ap.parse_args(argv)
    t0 = time.time()
    res = {"log": os.path.basename(a.log), "config": a.config, "steps": a.steps,
           "qemu": subprocess.run(["qemu-system-arm", "--version"], stdout=subprocess.PIPE,
                                  text=True).stdout.splitlines()[0], "runs": [], "host": {}}
    for spec in a.runs.split():
        target, machine = spec.split(":")
        core, variant = target.split("-")
        prof = target_profile(a.build, target, machine, a.config, a.steps)
        res["runs"].append({"target": target, "core": core, "variant": variant, "machine": machine,
                            "profile": prof})
        print(f"pil-profile: {target} on {machine}: {prof['total']:,.0f} instructions/step, top "
              + ", ".join(f"{f[0]} {f[1]:,.0f}" for f in prof["functions"][:4]))
        if variant not in res["host"]:
            res["host"][variant] = host_profile(a.build, variant, a.config, a.steps)
            print(f"pil-profile: host {variant} (callgrind): {res['host'][variant]['total']:,.0f} instructions/step")
    res["seconds"] = round(time.time() - t0, 1)
    os.makedirs(os.path.dirname(a.json) or ".", exist_ok=True)
    with open(a.json, "w") as f:
        json.dump(res, f, indent=1)
    if a.page:
        from pathlib import Path
        replace_region(Path(a.page), BEGIN, END, markdown(res), "pil-profile")
        print(f"pil-profile: tables written to {a.page}")
    print(f"pil-profile: {a.json} ({res['seconds']} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
