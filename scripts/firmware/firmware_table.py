#!/usr/bin/env python3
"""Writes the firmware tables of docs/FIRMWARE.md (section "Measured: size, stack and emulated
runs"; make firmware-table, issue 5) between the markers <!-- firmware:begin --> and
<!-- firmware:end --> of the page given by --page (alias --readme, the former name) from
build/firmware/report.json (scripts/firmware/firmware_check.py: sizes, stack, budgets) and
build/firmware/pil.json (scripts/firmware/firmware_pil.py: emulated runs, comparisons, instructions
per step). Never typed by hand: `make firmware-table` regenerates them.

With --obs-page / --readme-page it also writes the observer's cost (the observer entries of
pil.json: instructions per observer step against the default friction step, and where the
observer's instructions go) between <!-- observer-cost:begin --> and <!-- observer-cost:end -->
of those pages (docs/OBSERVER_RESULTS.md: the table; README.md: one line), with the host's
figure from --bench (build/bench/bench.json of `make bench`) when it exists. One row per observer
entry (float32 and fixed point, each core) with its ratio to the default friction step of the
same build; the 15 % target is judged (met / missed) on the Cortex-M4 rows, and the breakdown of
where the observer's instructions go is given for those.
"""
import argparse
import os
import json
import sys

BEGIN, END = "<!-- firmware:begin -->", "<!-- firmware:end -->"
OBS_BEGIN, OBS_END = "<!-- observer-cost:begin -->", "<!-- observer-cost:end -->"
AUX_BEGIN, AUX_END = "<!-- firmware-aux:begin -->", "<!-- firmware-aux:end -->"
TARGET_SHARE = 0.15   # issue 16: the observer adds at most 15 % to the default step (M4)
TARGET_CORE = "m4f"   # ... on the Cortex-M4, float and fixed point
TOP_FUNCTIONS = 12    # functions listed in the breakdown of the observer's instructions
CORES = {"m4f": "Cortex-M4F", "m3": "Cortex-M3", "m0p": "Cortex-M0+"}
VARIANTS = {"f32": "float32", "q31": "fixed point"}
PART = {"m4f": "STM32F407xG", "m3": "MPS2 AN385", "m0p": "STM32G071xB"}
ORDER = ["m4f-f32", "m4f-q31", "m3-q31", "m0p-q31"]


def pct(x, digits=1):
    """A share as the project writes it: 22.9 %."""
    return f"{100 * x:.{digits}f} %"


def kb(n):
    return f"{n / 1024:.1f} kB"


def flash_budget(fb):
    """The linked-flash budget: one figure (older reports) or one per core (make firmware-check)."""
    if isinstance(fb, dict):
        return ", ".join(f"{kb(fb[c])} ({CORES.get(c, c)})" for c in
                         [c for c in CORES if c in fb] + sorted(c for c in fb if c not in CORES))
    return kb(fb)


def tables(report, pil):
    b = report["budgets"]
    out = []
    out.append("| target | library flash, linked (all functions) | state `sizeof` | library data+bss "
               "| stack per call, static: init / step / get | step stack measured (PIL) "
               "| example image text / data / bss |")
    out.append("|---|---|---|---|---|---|---|")
    measured = {}
    for r in pil.get("runs", []):
        if r.get("stack_measured") is not None:
            measured[r["target"]] = max(measured.get(r["target"], 0), r["stack_measured"])
    for t in [x for x in ORDER if x in report["targets"]] + \
             [x for x in sorted(report["targets"]) if x not in ORDER]:
        e = report["targets"][t]
        suf = "_q31" if e["variant"] == "q31" else "_f32"
        st = [e["stack"].get(f"rfe_friction_{f}{suf}", {}).get("bytes", "?")
              for f in ("init", "step", "get")]
        img = e.get("image", {})
        out.append(f"| {CORES[e['core']]} {VARIANTS[e['variant']]} "
                   f"| {kb(e.get('lib_flash_linked', 0))} ({kb(e['lib_flash_all'])}) "
                   f"| {e.get('state', '?')} B | {e['lib_ram_all']} B "
                   f"| {st[0]} / {st[1]} / {st[2]} B "
                   f"| {str(measured[t]) + ' B' if t in measured else '— (not run)'} "
                   f"| {img.get('text', '?')} / {img.get('data', '?')} / {img.get('bss', '?')} B "
                   f"({PART[e['core']]}) |")
    out.append("")
    out.append(f"Budgets (`make firmware` fails beyond them): stack ≤ {b['stack_per_call']} B per "
               f"public call, linked library flash ≤ {flash_budget(b['flash_linked'])}, state ≤ "
               f"{b['state']} B. Static stack: the deepest chain of the `-fcallgraph-info=su` call "
               f"graph with `-fstack-usage` frames (libgcc/libm frames from the linked image's "
               f"disassembly); the PIL run measures the deepest stack of any step (painted stack) "
               f"and requires it to stay within the static figure.")
    runs = pil.get("runs", [])
    if runs:
        hz, sh = pil["core_hz"], pil["step_hz"]
        out.append("")
        out.append(f"Emulated runs ({pil['qemu']}), `{pil['log']}`, every step of the log "
                   f"compared; instructions per step over the log's first steps (how many: "
                   f"last column), and the share of a {hz / 1e6:.0f} MHz core at {sh:.0f} Hz that implies at one "
                   f"instruction per cycle (a lower bound: flash wait states, loads, divisions "
                   f"and long multiplies take more cycles on a real part):")
        out.append("")
        out.append("| core (QEMU machine) | variant | configuration | outputs vs the host build "
                   "| instructions per step, mean (max) | share of the core, mean (max) | steps counted |")
        out.append("|---|---|---|---|---|---|---|")
        for r in runs:
            c = r.get("compare", {})
            if r["variant"] == "q31":
                if c.get("mismatches") == 0:
                    cmp_ = f"bit-identical, {r['steps']} steps" + \
                        (" (so is the committed golden)" if c.get("golden_mismatches") == 0 else "")
                else:
                    cmp_ = f"{c.get('mismatches')} values differ"
            else:
                cmp_ = (f"max \\|Δμ\\| {c.get('max_abs_dmu_golden', float('nan')):.1e} vs the double "
                        f"golden ({c.get('outside')} of {c.get('estimates')} beyond "
                        f"{c.get('tolerance')}), {c.get('max_abs_dmu_host_f32', float('nan')):.1e} "
                        f"vs host float32")
            ips = r.get("instructions_per_step")
            ipc = f"{ips['mean']:,.0f} ({ips['max']:,})" if ips else "—"
            share = (f"{100 * r['core_share_mean']:.1f} % ({100 * r['core_share_max']:.1f} %)"
                     if ips else "—")
            core = f"{r['core']} ({r['machine']}"
            if r.get("build_core") and r["build_core"] != r["core"]:
                core += f", the {r['build_core']} build"
            out.append(f"| {core}) | {VARIANTS[r['variant']]} | {r['config']} "
                       f"| {cmp_} | {ipc} | {share} | {ips['steps'] if ips else '—'} |")
    obs = pil.get("observer_runs", [])
    if obs:
        out.append("")
        out.append(f"Observer entries on `{pil.get('obs_log')}` (every step compared; float32 "
                   f"bound per output: {pil.get('obs_tolerance')}; fixed point: every word bit for "
                   f"bit); the observer and friction columns count the instructions inside "
                   f"`rfe_velocity_step` and `rfe_friction_step` (`_f32`, `_q31`) of each pipeline "
                   f"step, the ratio is against the default friction step of the same build above:")
        out.append("")
        out.append("| core (QEMU machine) | variant | entry | outputs vs the host build "
                   "| instructions per step, mean (max) | observer, mean (max) | friction, mean (max) "
                   "| observer / default friction step | steps counted |")
        out.append("|---|---|---|---|---|---|---|---|---|")
        for r in obs:
            c = r.get("compare", {})
            if r["variant"] == "q31":
                values = sum(e.get("values", 0) for e in c.get("fields", {}).values())
                cmp_ = ((f"bit-identical ({values:,} words); status, valid, flags, saturations equal"
                         if c.get("mismatches") == 0 else f"{c.get('mismatches')} values differ") +
                        ("; host program = `mu_replay`" if c.get("replay", {}).get("mismatches") == 0 else ""))
            else:
                worst = max((e["max_abs_diff"] / e["bound"] for e in c.get("fields", {}).values()
                             if e["bound"] > 0), default=0.0)
                cmp_ = ((f"within the bound (largest difference {pct(worst, 1)} of its bound), "
                         if c.get("mismatches") == 0 else f"{c.get('mismatches')} values beyond the bound, ") +
                        f"{pct(c.get('bit_identical_fraction', 0), 0)} of values bit-identical; "
                        "status, valid, flags equal" +
                        ("; host program = `mu_replay`" if c.get("replay", {}).get("mismatches") == 0 else ""))
            ips = r.get("instructions_per_step")
            parts = r.get("instructions_per_part", {})

            def fmt(d):
                return f"{d['mean']:,.0f} ({d['max']:,})" if d else "—"

            vel = next((v for k, v in parts.items() if k.startswith("rfe_velocity_step")), None)
            fri = next((v for k, v in parts.items() if k.startswith("rfe_friction_step")), None)
            ratio = observer_ratio(pil, r)
            core = f"{r['core']} ({r['machine']}"
            if r.get("build_core") and r["build_core"] != r["core"]:
                core += f", the {r['build_core']} build"
            out.append(f"| {core}) | {VARIANTS[r['variant']]} | {r['tag']} | {cmp_} | {fmt(ips)} "
                       f"| {fmt(vel)} | {fmt(fri)} | {ratio_text(ratio)} | {ips['steps'] if ips else '—'} |")
    return out


def default_step(pil, target):
    """Mean instructions of the default friction step (default.sckf) on @p target."""
    for r in pil.get("runs", []):
        if r["target"] == target and r.get("config") == "default.sckf" and r.get("instructions_per_step"):
            return r["instructions_per_step"]["mean"]
    return None


def observer_ratio(pil, r):
    """(observer instructions, default friction step, ratio) of an observer entry, or None."""
    parts = r.get("instructions_per_part", {})
    vel = next((v for k, v in parts.items() if k.startswith("rfe_velocity_step")), None)
    if vel is None and r.get("tag") == "velocity":
        vel = r.get("instructions_per_step")
    base = default_step(pil, r["target"])
    if vel is None or not base:
        return None
    return vel["mean"], base, vel["mean"] / base


def ratio_text(ratio):
    return f"{pct(ratio[2], 1)} ({ratio[0]:,.0f} / {ratio[1]:,.0f})" if ratio else "—"


def host_ratio(bench):
    """(observer, default step, ratio) in host instructions (callgrind) from bench.json."""
    try:
        vel = next(m for m in bench["modules"] if m["case"] == "velocity.step")["f32"]["instructions"]
        base = next(s for s in bench["steps"] if s["case"] == "step.default" and s["flavour"] == "f32")["instructions"]
    except (KeyError, StopIteration, TypeError):
        return None
    return (vel, base, vel / base) if vel and base else None


def observer_cost(pil, bench, short):
    """The observer-cost section of OBSERVER_RESULTS.md, or the README's line (short)."""
    rows = [(r, observer_ratio(pil, r)) for r in pil.get("observer_runs", [])]
    rows = [(r, q) for r, q in rows if q]
    host = host_ratio(bench) if bench else None
    if short:
        parts = [f"+{pct(q[2], 0)} on the {CORES.get(r['target'].split('-')[0], r['target'])} "
                 f"({VARIANTS[r['variant']]})" for r, q in rows]
        if host:
            parts.append(f"+{pct(host[2], 0)} on the host")
        return [("Observer cost over the default friction step (instructions): " +
                 ", ".join(parts) + f" (target ≤ {pct(TARGET_SHARE, 0)} on the M4; "
                 "[OBSERVER_RESULTS](docs/OBSERVER_RESULTS.md#cost-per-step))."
                 if parts else "The velocity observer's cost: not measured (`make pil`, `make firmware-table`).")]
    out = ["| where | observer step, instructions | default friction step | observer / default step "
           f"| target ≤ {pct(TARGET_SHARE, 0)} (Cortex-M4) |", "|---|---|---|---|---|"]
    for r, q in rows:
        verdict = "met" if q[2] <= TARGET_SHARE else "missed"
        if r["target"].split("-")[0] != TARGET_CORE:
            verdict = f"– (the target's core is the M4; {verdict} here)"
        out.append(f"| {CORES.get(r['target'].split('-')[0], r['target'])} {VARIANTS[r['variant']]} "
                   f"({r['machine']}, `make pil`: in the pipeline on {r['scenario']}, first "
                   f"{r['instructions_per_step']['steps']} steps; friction: default.sckf of the same "
                   f"build on {pil.get('log', '?')}) | {q[0]:,.0f} | {q[1]:,.0f} | {pct(q[2], 1)} "
                   f"| {verdict} |")
    if host:
        out.append(f"| host x86-64 float32 (`make bench`, callgrind, {bench.get('log', '?')}) "
                   f"| {host[0]:,.0f} | {host[1]:,.0f} | {pct(host[2], 1)} | – |")
    for r, q in rows:
        if r["target"].split("-")[0] != TARGET_CORE:
            continue  # the breakdown on the target's core (float32 and fixed point) only
        funcs = r.get("instructions_per_function", {})
        key = next((k for k in funcs if k.startswith("rfe_velocity_step")), None)
        if key is None:
            continue
        total = sum(f[1] for f in funcs[key])
        out.append("")
        out.append(f"Where the observer's instructions go on the {CORES.get(r['target'].split('-')[0])} "
                   f"{VARIANTS[r['variant']]} build (per step, the functions whose code runs inside "
                   f"`{key}`, each counted where its own instructions are; the first {TOP_FUNCTIONS}):")
        out.append("")
        out.append("| function | object | instructions per step | share of the observer | calls per step |")
        out.append("|---|---|---|---|---|")
        for f in funcs[key][:TOP_FUNCTIONS]:
            obj = f[3] if len(f) > 3 else "?"
            out.append(f"| `{f[0]}` | {obj} | {f[1]:,.0f} | {pct(f[1] / total, 1)} | {f[2]:g} |")
        rest = sum(f[1] for f in funcs[key][TOP_FUNCTIONS:])
        out.append(f"| {len(funcs[key]) - TOP_FUNCTIONS} others | | {rest:,.0f} | {pct(rest / total, 1)} | |")
        by_obj = {}
        for f in funcs[key]:
            obj = f[3] if len(f) > 3 else "?"
            by_obj[obj] = by_obj.get(obj, 0.0) + f[1]
        out.append("")
        out.append("The same by object file (librfe.a's modules, newlib's C library):")
        out.append("")
        out.append("| object | instructions per step | share of the observer |")
        out.append("|---|---|---|")
        for obj, v in sorted(by_obj.items(), key=lambda x: -x[1]):
            out.append(f"| {obj} | {v:,.0f} | {pct(v / total, 1)} |")
    return out


def aux_table(aux):
    """The mass and grade estimator and the tyre identifier on the Cortex-M4F (make pil-aux,
    build/firmware/pil_aux.json)."""
    runs = aux.get("aux_runs", [])
    if not runs:
        return ["Not measured yet: run `make pil-aux`."]
    L = [f"Emulated runs ({aux.get('qemu', 'QEMU')}), float32 on the Cortex-M4F (`mps2-an386`); outputs "
         f"vs the host float32 build within {aux.get('aux_tolerance', '?')} (status and flags equal; "
         f"the tyre identifier's SCKF vs the host double build instead, {aux.get('aux_double_tolerance', '?')}, "
         "the host float32 build for information); "
         "instructions per step over the log's first steps, the share of a 100 MHz core at the "
         "estimator's rate (the log's sample rate) at one instruction per cycle; flash: what the PIL "
         "image links (text + rodata) of the module's objects, of the whole library, of newlib's libm; "
         "state: `sizeof` the estimator's state.", "",
         "| entry | log, rows compared | outputs vs the host build | instructions per step, mean (max) | "
         "share of 100 MHz, mean (max) | steps counted | stack static / measured | flash: module / library / libm | state |",
         "|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        c, i, fl = r.get("compare", {}), r.get("instructions_per_step", {}), r.get("flash", {})
        if c.get("reference") == "double":
            h = c.get("host_f32", {})
            outs = (f"{'within' if not c.get('mismatches') else 'OUTSIDE'} {c.get('bound', 0):.2g} of the host "
                    f"double build (largest difference {c.get('max_rel_diff', 0):.2g} of value plus sd); status, "
                    f"flags {'equal' if c.get('discrete_equal') else 'DIFFER'}; vs the host float32 build "
                    f"(information): {h.get('mismatches', '?')} values beyond twice its float32-vs-double "
                    f"difference, {100 * h.get('bit_identical_fraction', 0):.1f} % bit-identical")
        else:
            worst = max((e["max_abs_diff"] / e["bound"] for e in c.get("fields", {}).values() if e["bound"] > 0),
                        default=0.0)
            outs = (f"{'within' if not c.get('mismatches') else 'OUTSIDE'} the bound (largest difference "
                    f"{100 * worst:.0f} % of the host's float32-vs-double difference, 200 % allowed), {100 * c.get('bit_identical_fraction', 0):.1f} % of values "
                    f"bit-identical; status, flags {'equal' if c.get('discrete_equal') else 'DIFFER'}")
        L.append(f"| {r['what']} | `{os.path.basename(r['log'])}` ({r['rate_hz']:.0f} Hz), {r['steps']} | {outs} | "
                 f"{i.get('mean', 0):,.0f} ({i.get('max', 0):,}) | {pct(r.get('core_share_mean', 0), 2)} at "
                 f"{r['rate_hz']:.0f} Hz ({pct(r.get('core_share_max', 0), 2)}) | {i.get('steps', '-')} | "
                 f"{r.get('stack_static')} / {r.get('stack_measured')} B | {kb(fl.get('module', 0))} / "
                 f"{kb(fl.get('library', 0))} / {kb(fl.get('newlib_libm', 0))} | {r.get('state')} B |")
    return L


def aux_q31_table(aux):
    """The mass and grade estimator's fixed-point twin on the Cortex-M4, M3 and M0+ (make
    pil-aux's --aux-q31-entries)."""
    runs = aux.get("aux_q31_runs", [])
    if not runs:
        return []
    L = ["", "The mass and grade estimator's fixed-point twin (`rfe_mass_grade_step_q31`), on the same "
         "rows (the data file's PIL_Q31 arm), on each fixed-point target; every output word, "
         "status and saturation count compared with the same program built for the host "
         "(`host-q31`); the share of a 100 MHz core at 100 Hz (issue 19's cost target: 5 %) and at "
         "the log's 50 Hz.", "",
         "| entry | target (QEMU machine) | rows compared | outputs vs the host q31 build | "
         "instructions per step, mean (max) | share of 100 MHz at 100 Hz, mean (max) | at 50 Hz | "
         "steps counted | stack measured | flash: module | state |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        c, i, fl = r.get("compare", {}), r.get("instructions_per_step", {}), r.get("flash", {})
        outs = ("bit-identical" if c.get("bit_identical") else f"{c.get('mismatches')} rows DIFFER") + \
               f", {c.get('saturations', 0)} saturations"
        L.append(f"| {r['what']} | {r['target']} ({r['machine']}) | {r['steps']} | {outs} | "
                 f"{i.get('mean', 0):,.0f} ({i.get('max', 0):,}) | {pct(r.get('core_share_mean_100hz', 0), 2)} "
                 f"({pct(r.get('core_share_max_100hz', 0), 2)}) | {pct(r.get('core_share_mean', 0), 2)} | "
                 f"{i.get('steps', '-')} | {r.get('stack_measured')} B | {kb(fl.get('module', 0))} | "
                 f"{r.get('state')} B |")
    return L


def replace_section(path, begin, end, lines):
    text = open(path).read()
    if begin not in text or end not in text:
        sys.exit(f"firmware-table: {path} has no {begin} ... {end} section")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    with open(path, "w") as f:
        f.write(head + begin + "\n" + "\n".join(lines) + "\n" + end + tail)
    print(f"firmware-table: {path} updated")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--report", default=None)
    ap.add_argument("--pil", default=None)
    ap.add_argument("--aux-only", action="store_true",
                    help="only the other estimators' section, from --pil-aux (no make pil needed)")
    ap.add_argument("--page", "--readme", dest="page", required=True,
                    help="the markdown page holding the markers (docs/FIRMWARE.md)")
    ap.add_argument("--obs-page", default=None, help="the page of the observer's cost table")
    ap.add_argument("--readme-page", default=None, help="the page of the observer's cost line")
    ap.add_argument("--bench", default=None, help="bench.json of make bench (host figure)")
    ap.add_argument("--pil-aux", default=None, help="make pil-aux's pil_aux.json (the other estimators)")
    a = ap.parse_args()
    if a.aux_only:
        aux = json.load(open(a.pil_aux))
        replace_section(a.page, AUX_BEGIN, AUX_END, aux_table(aux) + aux_q31_table(aux))
        return 0
    if a.report is None or a.pil is None:
        ap.error("--report and --pil are required (or --aux-only)")
    report = json.load(open(a.report))
    try:
        pil = json.load(open(a.pil))
    except OSError:
        pil = {}
    replace_section(a.page, BEGIN, END, tables(report, pil))
    if a.pil_aux:
        try:
            aux = json.load(open(a.pil_aux))
        except OSError:
            aux = {}
        replace_section(a.page, AUX_BEGIN, AUX_END, aux_table(aux) + aux_q31_table(aux))
    bench = None
    if a.bench:
        try:
            bench = json.load(open(a.bench))
        except OSError:
            bench = None
    if a.obs_page:
        replace_section(a.obs_page, OBS_BEGIN, OBS_END, observer_cost(pil, bench, short=False))
    if a.readme_page:
        replace_section(a.readme_page, OBS_BEGIN, OBS_END, observer_cost(pil, bench, short=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
