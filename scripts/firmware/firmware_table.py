#!/usr/bin/env python3
"""Writes the firmware tables of docs/FIRMWARE.md (section "Measured: size, stack and emulated
runs"; make firmware-table, issue 5) between the markers <!-- firmware:begin --> and
<!-- firmware:end --> of the page given by --page (alias --readme, the former name) from
build/firmware/report.json (scripts/firmware/firmware_check.py: sizes, stack, budgets) and
build/firmware/pil.json (scripts/firmware/firmware_pil.py: emulated runs, comparisons, instructions
per step). Never typed by hand: `make firmware-table` regenerates them.
"""
import argparse
import json
import sys

BEGIN, END = "<!-- firmware:begin -->", "<!-- firmware:end -->"
CORES = {"m4f": "Cortex-M4F", "m3": "Cortex-M3", "m0p": "Cortex-M0+"}
VARIANTS = {"f32": "float32", "q31": "fixed point"}
PART = {"m4f": "STM32F407xG", "m3": "MPS2 AN385", "m0p": "STM32G071xB"}
ORDER = ["m4f-f32", "m4f-q31", "m3-q31", "m0p-q31"]


def kb(n):
    return f"{n / 1024:.1f} kB"


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
               f"public call, linked library flash ≤ {kb(b['flash_linked'])}, state ≤ "
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
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--report", required=True)
    ap.add_argument("--pil", required=True)
    ap.add_argument("--page", "--readme", dest="page", required=True,
                    help="the markdown page holding the markers (docs/FIRMWARE.md)")
    a = ap.parse_args()
    report = json.load(open(a.report))
    try:
        pil = json.load(open(a.pil))
    except OSError:
        pil = {}
    text = open(a.page).read()
    if BEGIN not in text or END not in text:
        sys.exit(f"firmware-table: {a.page} has no {BEGIN} ... {END} section")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(a.page, "w") as f:
        f.write(head + BEGIN + "\n" + "\n".join(tables(report, pil)) + "\n" + END + tail)
    print(f"firmware-table: {a.page} updated")
    return 0


if __name__ == "__main__":
    sys.exit(main())
