#!/usr/bin/env python3
"""Flash against speed per optimisation level (make firmware-opt, issue 21 "Firmware builds"):
the PIL images of make pil built with -Os, -O2, -O3 and each with link-time optimisation
(mk/firmware.mk builds them, one tree per setting under build/firmware-opt/<setting>/), and
for each core, variant and setting:

- flash: the library's linked share of the default configuration's PIL image (text + rodata
  of librfe*.a's members in the linker map, make firmware-check's definition), which the map
  cannot give under LTO (the library's code is in the link-time objects then); and, for
  every setting, the image's text + rodata less newlib and libgcc (the map's archive members,
  never LTO'd) and less the log's data arrays (the pil_* objects): the library and the small
  PIL program around it;
- instructions per step, mean over the log's first --steps samples of each configuration,
  counted as make pil counts them (firmware_pil.count_instructions);
- the outputs: every line the image prints over the whole log compared with the shipped
  build's (build/firmware, FW_OPT_* of mk/firmware.mk): an optimisation level may not change
  what the estimator computes (C99 mode, no contraction: the same IEEE operations in the
  same order; fixed point is integer arithmetic).

Writes --json and, with --page, the table between <!-- firmware-opt:begin --> and
<!-- firmware-opt:end -->. A measurement, not part of make test (a few minutes).
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(os.path.dirname(HERE), "tools")]

import firmware_check as fc  # noqa: E402
import firmware_pil as fp  # noqa: E402
from md_tables import replace_region  # noqa: E402

BEGIN, END = "<!-- firmware-opt:begin -->", "<!-- firmware-opt:end -->"
NAMES = {"m4f-f32": "Cortex-M4F float32", "m4f-q31": "Cortex-M4F fixed point",
         "m3-q31": "Cortex-M3 fixed point", "m0p-q31": "Cortex-M0+ fixed point"}


def flags(setting):
    """Os-lto -> -Os -flto (the make target adds -ffat-lto-objects: the archive's index)."""
    level, _, lto = setting.partition("-")
    return f"-{level}" + (" -flto" if lto == "lto" else "")


def image_code(elf):
    """(library share from the map or None, image text + rodata less newlib/libgcc and the
    log's data arrays)."""
    sizes = {}
    for ln in subprocess.run([fp.CROSS + "size", "-A", elf], stdout=subprocess.PIPE, text=True,
                             check=True).stdout.splitlines():
        p = ln.split()
        if len(p) == 3 and p[1].isdigit():
            sizes[p[0]] = int(p[1])
    code = sizes.get(".text", 0) + sizes.get(".rodata", 0)
    code -= sum(v for k, v in fp.image_flash(elf).items() if k.startswith("newlib"))
    nm = subprocess.run([fp.CROSS + "nm", "-S", elf], stdout=subprocess.PIPE, text=True, check=True).stdout
    for ln in nm.splitlines():
        p = ln.split()
        if len(p) == 4 and p[2] in "rR" and p[3].startswith("pil_"):
            code -= int(p[1], 16)
    lib = "librfe_q31.a" if "-q31" in elf else "librfe.a"
    share, _ = fc.linked_share(elf[:-4] + ".map", lib)
    return (share or None), code


def outputs(machine, elf):
    r = subprocess.run(fp.qemu_cmd(machine, elf), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True, timeout=fp.QEMU_TIMEOUT)
    if r.returncode != 0:
        sys.exit(f"firmware-opt: {elf} on {machine}: QEMU exit {r.returncode}\n{r.stderr[-1500:]}")
    # R lines: the estimates; the stack line (S) may differ with the level and is no output
    return [ln for ln in r.stdout.splitlines() if ln.startswith("R ")]


def measure(a):
    res = {"log": os.path.basename(a.log), "steps": a.steps, "shipped": dict(s.split("=") for s in a.shipped.split()),
           "settings": a.settings.split(), "rows": []}
    configs = [c.split(":")[0] for c in a.configs.split()]
    reference = {}
    for run in a.runs.split():
        target, machine = run.split(":")
        for setting in res["settings"]:
            t0 = time.time()
            row = {"target": target, "machine": machine, "setting": setting, "flags": flags(setting),
                   "instructions_per_step": {}, "outputs_equal": {}}
            for tag in configs:
                elf = os.path.join(a.build, setting, target, "pil", tag + ".elf")
                ref = (target, tag)
                if ref not in reference:
                    reference[ref] = outputs(machine, os.path.join(a.shipped_build, target, "pil", tag + ".elf"))
                out = outputs(machine, elf)
                row["outputs_equal"][tag] = out == reference[ref] and len(out) > 0
                counts = fp.count_instructions(machine, elf, a.steps)
                row["instructions_per_step"][tag] = round(sum(counts) / len(counts), 1)
                if tag == a.flash_config:
                    row["library_flash_map"], row["library_and_program_flash"] = image_code(elf)
            print(f"firmware-opt: {target} {flags(setting):>10}: "
                  + ", ".join(f"{t} {v:,.0f}" for t, v in row["instructions_per_step"].items())
                  + f" instructions/step; flash {row['library_and_program_flash']} B"
                  + ("" if all(row["outputs_equal"].values()) else "; OUTPUTS DIFFER from the shipped build")
                  + f" ({time.time() - t0:.0f} s)")
            res["rows"].append(row)
    return res


def rel(x, base):
    return f"{100 * (x / base - 1):+.1f} %" if base else "?"


def markdown(res):
    configs = list(res["rows"][0]["instructions_per_step"])
    L = [f"Measured by `make firmware-opt`, `{res['log']}`, mean instructions per step over the log's "
         f"first {res['steps']} steps (QEMU, as `make pil` counts them) and flash of the "
         "default configuration's PIL image: *library* is the linked share of `librfe*.a` in the "
         "linker map (as in the table above; the map cannot attribute code under LTO); *library + "
         "PIL program* is the image's text + rodata less newlib, libgcc and the log's data arrays, "
         "comparable across all settings. In brackets: the change against the shipped setting "
         "(`FW_OPT_*`, marked). *Outputs*: every estimate the image prints over the whole log "
         "equals the shipped build's.", ""]
    head = ["target", "flags", "library flash", "library + PIL program flash"] + \
        [f"{c}: instr/step" for c in configs] + ["outputs"]
    L += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    verdicts = []
    by_target = {}
    for r in res["rows"]:
        by_target.setdefault(r["target"], []).append(r)
    for target, rows in by_target.items():
        core = target.split("-")[0]
        shipped = res["shipped"].get(target, res["shipped"].get(core))  # a target may override its core
        base = next((r for r in rows if r["flags"] == shipped), rows[0])
        for r in rows:
            mark = " (shipped)" if r is base else ""
            lib = f"{r['library_flash_map'] / 1024:.1f} kB" if r.get("library_flash_map") else "– (LTO)"
            cells = [NAMES.get(target, target), f"`{r['flags']}`{mark}", lib,
                     f"{r['library_and_program_flash'] / 1024:.1f} kB ({rel(r['library_and_program_flash'], base['library_and_program_flash'])})"]
            for c in configs:
                v, b = r["instructions_per_step"][c], base["instructions_per_step"][c]
                cells.append(f"{v:,.0f} ({rel(v, b)})")
            cells.append("equal" if all(r["outputs_equal"].values()) else "**differ**")
            L.append("| " + " | ".join(cells) + " |")
        key = configs[-1]
        # only a setting that computes what the shipped one does can be recommended
        same = [r for r in rows if all(r["outputs_equal"].values())] or [base]
        fast = min(same, key=lambda r: r["instructions_per_step"][key])
        small = min(same, key=lambda r: r["library_and_program_flash"])
        # a setting at least as small and as fast as the shipped one on every configuration
        better = [r for r in same if r is not base
                  and r["library_and_program_flash"] <= base["library_and_program_flash"]
                  and all(r["instructions_per_step"][c] <= base["instructions_per_step"][c] for c in configs)]
        dominant = "".join(
            f" `{r['flags']}` is smaller (flash {rel(r['library_and_program_flash'], base['library_and_program_flash'])}) "
            f"and faster on every configuration ({', '.join(f'`{c}` ' + rel(r['instructions_per_step'][c], base['instructions_per_step'][c]) for c in configs)})."
            for r in better)
        verdicts.append(
            f"- {NAMES.get(target, target)} (shipped `{base['flags']}`): fewest instructions on `{key}` "
            f"with `{fast['flags']}` ({rel(fast['instructions_per_step'][key], base['instructions_per_step'][key])}, "
            f"flash {rel(fast['library_and_program_flash'], base['library_and_program_flash'])}); smallest with "
            f"`{small['flags']}` (flash {rel(small['library_and_program_flash'], base['library_and_program_flash'])}, "
            f"`{key}` {rel(small['instructions_per_step'][key], base['instructions_per_step'][key])})." + dominant)
    return L + ["", "Per target, against its shipped setting (among the settings whose outputs equal "
                 "the shipped build's):", ""] + verdicts


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build/firmware-opt", help="one tree per setting under it")
    ap.add_argument("--shipped-build", default="build/firmware", help="the shipped build (make pil's)")
    ap.add_argument("--shipped", default="m4f=-O2 m3=-O2 m0p=-Os", help="<core>=<FW_OPT_core> ... and <target>=<FW_OPT_target> where a target overrides its core")
    ap.add_argument("--settings", default="Os O2 O3 Os-lto O2-lto O3-lto")
    ap.add_argument("--runs", default="m4f-f32:mps2-an386 m4f-q31:mps2-an386 m3-q31:mps2-an385 m0p-q31:microbit")
    ap.add_argument("--configs", default="paper.sckf default.sckf", help="make pil's PIL_CONFIGS (tags)")
    ap.add_argument("--flash-config", default="default.sckf", help="the configuration whose image is sized")
    ap.add_argument("--log", default="scenarios/brake_in_turn.csv")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--json", default="build/firmware-opt/opt.json")
    ap.add_argument("--page", default="")
    ap.add_argument("--render-only", action="store_true", help="the table from --json, nothing measured")
    a = ap.parse_args(argv)
    if a.render_only:
        with open(a.json) as f:
            res = json.load(f)
    else:
        t0 = time.time()
        res = measure(a)
        res["seconds"] = round(time.time() - t0, 1)
        os.makedirs(os.path.dirname(a.json) or ".", exist_ok=True)
        with open(a.json, "w") as f:
            json.dump(res, f, indent=1)
    if a.page:
        from pathlib import Path
        replace_region(Path(a.page), BEGIN, END, markdown(res), "firmware-opt")
        print(f"firmware-opt: table written to {a.page}")
    print(f"firmware-opt: {a.json} ({res.get('seconds', '?')} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
