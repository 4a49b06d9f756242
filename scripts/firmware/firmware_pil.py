#!/usr/bin/env python3
"""Processor in the loop (make pil, issue 5): runs the PIL images of mk/firmware.mk on QEMU's
emulated Cortex-M cores, compares their estimates with the host build and counts the
instructions each estimator step executes.

For every run <target>:<machine> (m4f-f32:mps2-an386, m4f-q31:mps2-an386, m3-q31:mps2-an385)
and every configuration <tag>:<mu_replay options> (paper.sckf, default.sckf):

 1. the whole log: qemu-system-arm -M <machine> -nographic -semihosting-config
    enable=on,target=native -kernel build/firmware/<target>/pil/<tag>.elf; QEMU's exit
    status is main's return value and must be 0; every step prints one line
    (firmware/pil/pil_main.c);
 2. the host build on the same log and options: build/mu_replay --real q31 (fixed point) or
    --real float (float32). Fixed point: every mu, sd, valid flag and status must equal the
    host's bit for bit (equality with the committed golden scenarios/golden/<stem>.<tag>.q31.csv
    is reported too; test/golden/test_golden_q31.c is what holds the host to it).
    Float32: mu and sd against the double golden scenarios/golden/<stem>.<tag>.csv with the
    tolerance of test/golden/test_golden_flt.c (2e-3; for the default preset at least 97 % of the
    estimates, as the host float32 build is held to); the difference from the host float32
    run is reported, not required (the two builds use different C libraries: newlib's
    sinf, cosf, tanf, atan2f need not round like glibc's);
 3. instruction count: the first --count-steps samples again under QEMU's execution log
    (count_instructions: every translation block's length from -d in_asm, every executed
    block from -d exec, nochain); what runs between the calls of pil_step_begin and
    pil_step_end (addresses from arm-none-eabi-nm) is one step, counted with the call's own
    few instructions (argument set-up, bl). The first --singlestep-check steps are counted
    again with -singlestep (one instruction per block, one log line per instruction) and must
    agree. Deterministic: the same image executes the same instructions every run.
Writes --out (JSON: per run and configuration the comparison and the instructions per step,
mean/max/min), read by scripts/firmware/firmware_table.py and the benchmark script.
"""
import argparse
import csv
import json
import math
import os
import struct
import subprocess
import sys
import re
import tempfile
import time

CROSS = "arm-none-eabi-"
BUILD_CORE = {"m4f": "cortex-m4", "m3": "cortex-m3", "m0p": "cortex-m0plus"}
# The core each QEMU board emulates (the micro:bit's nRF51 is a Cortex-M0, the same ARMv6-M
# instruction set as the Cortex-M0+ build it runs).
MACHINE_CORE = {"mps2-an386": "cortex-m4", "mps2-an385": "cortex-m3", "microbit": "cortex-m0"}
FLOAT_TOL = 2e-3                 # test/golden/test_golden_flt.c TOL_MU / TOL_SD (float32)
FLOAT_FRACTION_OUT = {"default": 0.03}  # ... MAX_FRACTION_OUT_DEFAULT; 0 for the paper preset
QEMU_TIMEOUT = 300
CORE_HZ = 100e6                  # docs/FIRMWARE.md's reference core: 100 MHz, 100 Hz step rate
STEP_HZ = 100.0


def qemu_cmd(machine, elf, extra=()):
    return ["qemu-system-arm", "-M", machine, "-nographic", "-monitor", "none", "-serial", "none",
            "-semihosting-config", "enable=on,target=native", "-kernel", elf, *extra]


def parse_pil(text):
    rows, stack, end = [], None, None
    for ln in text.splitlines():
        p = ln.split()
        if not p:
            continue
        if p[0] == "R" and len(p) == 13:
            rows.append({"status": int(p[2]), "valid": int(p[3]), "sat": int(p[4]),
                         "mu": [int(x, 16) for x in p[5:9]], "sd": [int(x, 16) for x in p[9:13]]})
        elif p[0] == "S":
            stack = int(p[1])
        elif p[0] == "E":
            end = int(p[1])
    return rows, stack, end


def read_estimates(path):
    out = []
    with open(path) as f:
        r = csv.DictReader(ln for ln in f if not ln.startswith("#"))
        for row in r:
            out.append({"mu": [float(row["mu_" + w]) for w in ("fl", "fr", "rl", "rr")],
                        "sd": [float(row["sd_" + w]) for w in ("fl", "fr", "rl", "rr")],
                        "valid": [int(float(row["valid_" + w])) for w in ("fl", "fr", "rl", "rr")],
                        "status": int(float(row["status"]))})
    return out


def f32(bits):
    return struct.unpack("<f", struct.pack("<I", bits))[0]


def s32(bits):
    return bits - (1 << 32) if bits & 0x80000000 else bits


def target_values(row, variant):
    """mu, sd as doubles (exact) and the valid flags as the replay logs them."""
    if variant == "q31":
        mu = [math.ldexp(s32(b), -29) for b in row["mu"]]
        sd = [math.ldexp(s32(b), -30) for b in row["sd"]]
    else:
        mu = [f32(b) for b in row["mu"]]
        sd = [f32(b) for b in row["sd"]]
    err = row["status"] >= 16
    valid = [0 if err else (row["valid"] >> w) & 1 for w in range(4)]
    return mu, sd, valid


def compare_exact(rows, ref, variant):
    """Number of (row, field) mismatches against ref (bit-exact doubles)."""
    bad = 0
    first = None
    for i, (r, g) in enumerate(zip(rows, ref)):
        mu, sd, valid = target_values(r, variant)
        n = sum(a != b for a, b in zip(mu, g["mu"])) + sum(a != b for a, b in zip(sd, g["sd"]))
        n += sum(a != b for a, b in zip(valid, g["valid"])) + (r["status"] != g["status"])
        if n and first is None:
            first = f"row {i}: target mu {mu} sd {sd} valid {valid} status {r['status']}; " \
                    f"host mu {g['mu']} sd {g['sd']} valid {g['valid']} status {g['status']}"
        bad += n
    return bad + abs(len(rows) - len(ref)), first


def compare_float(rows, ref):
    worst, out, same, total = 0.0, 0, 0, 0
    for r, g in zip(rows, ref):
        mu, sd, _ = target_values(r, "f32")
        for a, b, c, d in zip(mu, g["mu"], sd, g["sd"]):
            dmu, dsd = abs(a - b), abs(c - d)
            worst = max(worst, dmu)
            out += not (dmu <= FLOAT_TOL and dsd <= FLOAT_TOL)
            same += (a == b) + (c == d)
            total += 2
    return worst, out, same, total


def host_run(replay, log, opts, real, path):
    cmd = [replay, "--in", log, "--out", path, *opts, "--real", real, "--quiet"]
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode not in (0,):
        sys.exit(f"pil: {' '.join(cmd)} failed ({r.returncode}):\n{r.stdout}")
    return read_estimates(path)


def marker_addresses(elf):
    out = {}
    nm = subprocess.run([CROSS + "nm", elf], stdout=subprocess.PIPE, text=True, check=True).stdout
    for ln in nm.splitlines():
        p = ln.split()
        if len(p) == 3 and p[2] in ("pil_step_begin", "pil_step_end"):
            out[p[2]] = int(p[0], 16) & ~1
    if len(out) != 2:
        sys.exit(f"pil: {elf}: pil_step_begin / pil_step_end not found")
    return out


def _trace(machine, elf, steps, qemu_args):
    """Runs the first `steps` samples with QEMU logging to a pipe; yields the log's lines."""
    rfd, wfd = os.pipe()
    cmd = qemu_cmd(machine, elf, ["-append", str(steps), *qemu_args, "-D", f"/dev/fd/{wfd}"])
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, pass_fds=(wfd,))
    os.close(wfd)
    deadline = time.time() + QEMU_TIMEOUT
    carry = b""
    with os.fdopen(rfd, "rb", buffering=0) as f:
        while True:
            chunk = f.read(1 << 22)
            if not chunk:
                break
            if time.time() > deadline:
                proc.kill()
                sys.exit(f"pil: instruction count on {elf} took longer than {QEMU_TIMEOUT} s")
            data = carry + chunk
            cut = data.rfind(b"\n") + 1
            data, carry = data[:cut], data[cut:]
            yield from data.split(b"\n")
    rc = proc.wait()
    if rc != 0:
        sys.exit(f"pil: instruction count on {elf}: QEMU exit {rc}\n"
                 f"{proc.stderr.read().decode(errors='replace')[-2000:]}")


def count_instructions(machine, elf, steps, singlestep=False):
    """Instructions per step over the first `steps` samples.

    Default: -d in_asm,exec,nochain. in_asm prints each translation block (TB) once, when it
    is translated, instruction by instruction; exec prints every execution of a TB with its
    host code address (unique per TB) and guest pc, right after that translation for a new
    TB. So every TB's length is known from its in_asm listing, keyed by its host address, and
    a step is the sum of the lengths of the TBs executed between the TB of pil_step_begin
    (one instruction: bx lr) and the TB of pil_step_end. No chaining (nochain) means every
    execution is logged; nothing interrupts a TB here (no interrupts, no I/O in a step).
    singlestep=True: -singlestep -d exec,nochain, one instruction per TB, a line each (the
    slow reference the default is checked against: make pil PIL_SINGLESTEP=1)."""
    marks = marker_addresses(elf)
    begin, end = marks["pil_step_begin"], marks["pil_step_end"]
    args = ["-singlestep", "-d", "exec,nochain"] if singlestep else ["-d", "in_asm,exec,nochain"]
    tb_len, counts = {}, []
    inside, n, pending_pc, pending_len = False, 0, None, 0
    for line in _trace(machine, elf, steps, args):
        if line.startswith(b"Trace "):
            # "Trace 0: 0x<host> [<cs_base>/<pc>/<flags>/<cflags>] symbol"
            parts = line.split(b" ", 4)
            host, pc = parts[2], int(parts[3][10:18], 16)
            if singlestep:
                length = 1
            else:
                if pending_pc is not None:
                    if pending_pc != pc:
                        sys.exit(f"pil: {elf}: TB listed at {pending_pc:#x} but {pc:#x} executed next")
                    tb_len[host] = pending_len
                    pending_pc = None
                length = tb_len.get(host)
                if length is None:
                    sys.exit(f"pil: {elf}: TB at {pc:#x} executed without its in_asm listing")
            if pc == begin:
                inside, n = True, 0
            elif pc == end and inside:
                counts.append(n)
                inside = False
            elif inside:
                n += length
        elif line.startswith(b"IN:"):
            pending_pc, pending_len = None, 0
        elif line.startswith(b"0x") and b":  " in line:
            if pending_pc is None:
                pending_pc = int(line[2:10], 16)
            pending_len += 1
    if len(counts) != steps:
        sys.exit(f"pil: instruction count on {elf}: {len(counts)} of {steps} steps traced")
    return counts


def example_smoke(machine, elf, seconds=2.0):
    """Runs the example firmware (firmware/example/main.c, linked for the emulated board) for
    a while and reads its globals through the QEMU monitor: SysTick must have ticked, every
    step must have been accepted (g_rejected 0) and the published estimate must carry an
    information status (< 16). Returns (ok, message)."""
    syms = {}
    nm = subprocess.run([CROSS + "nm", "-S", elf], stdout=subprocess.PIPE, text=True, check=True).stdout
    for ln in nm.splitlines():
        p = ln.split()
        if len(p) == 4:
            syms[p[3]] = (int(p[0], 16), int(p[1], 16))
    need = ("g_ticks", "g_rejected", "g_overruns", "g_estimate")
    if not all(n in syms for n in need):
        return False, f"{elf}: symbols {need} not all found"
    proc = subprocess.Popen(["qemu-system-arm", "-M", machine, "-nographic", "-serial", "none",
                             "-monitor", "stdio", "-kernel", elf], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    time.sleep(seconds)
    cmds = "".join(f"xp /{max(1, syms[n][1] // 4)}wx {syms[n][0]:#x}\n" for n in need) + "quit\n"
    out, _ = proc.communicate(cmds, timeout=30)
    words = {}
    for ln in out.splitlines():
        m = re.match(r"^.*?([0-9a-f]{16}): ((?:0x[0-9a-f]{8} ?)+)$", ln.strip())
        if m:
            base = int(m.group(1), 16)
            for i, w in enumerate(m.group(2).split()):
                words[base + 4 * i] = int(w, 16)
    try:
        ticks = words[syms["g_ticks"][0]]
        rejected = words[syms["g_rejected"][0]]
        overruns = words[syms["g_overruns"][0]]
        est = [words[syms["g_estimate"][0] + 4 * i] for i in range(syms["g_estimate"][1] // 4)]
    except KeyError:
        return False, f"{elf}: could not read the globals from the QEMU monitor:\n{out[-800:]}"
    status = est[9] & 0xFF  # rfe_estimate_*_t: mu[4], sd[4], valid[4] bytes, then the status
    ok = ticks > 0 and rejected == 0 and status < 16
    return ok, (f"example firmware on {machine}: {ticks} SysTick ticks, {rejected} rejected, "
                f"{overruns} overruns, last status {status}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build/firmware")
    ap.add_argument("--log", required=True)
    ap.add_argument("--runs", required=True)
    ap.add_argument("--configs", required=True)
    ap.add_argument("--replay", required=True)
    ap.add_argument("--count-steps", type=int, default=0,
                    help="steps to count in every configuration (0: each configuration's own)")
    ap.add_argument("--singlestep-check", type=int, default=2,
                    help="steps also counted with -singlestep, which must agree")
    ap.add_argument("--goldens", default="scenarios/golden")
    ap.add_argument("--example", default="",
                    help="<target>:<machine> whose example firmware (example.elf) to run a while")
    ap.add_argument("--report", default="build/firmware/report.json",
                    help="make firmware's figures (static stack), when present")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    stem = os.path.splitext(os.path.basename(a.log))[0]
    # <tag>:<mu_replay options, comma separated>[:<steps to count>]
    configs = []
    for c in a.configs.split():
        f = c.split(":")
        steps = int(f[2]) if len(f) > 2 else 100
        configs.append((f[0], f[1].split(","), a.count_steps if a.count_steps > 0 else steps))
    result = {"log": a.log, "count_steps": {t: n for t, _, n in configs}, "core_hz": CORE_HZ, "step_hz": STEP_HZ,
              "qemu": subprocess.run(["qemu-system-arm", "--version"], stdout=subprocess.PIPE,
                                     text=True).stdout.splitlines()[0], "runs": []}
    failures = []
    t_start = time.time()
    try:
        report = json.load(open(a.report))
    except OSError:
        report = {}
    with tempfile.TemporaryDirectory() as tmp:
        host = {}
        for tag, opts, _ in configs:
            host[(tag, "q31")] = host_run(a.replay, a.log, opts, "q31", os.path.join(tmp, tag + ".q31.csv"))
            host[(tag, "f32")] = host_run(a.replay, a.log, opts, "float", os.path.join(tmp, tag + ".f32.csv"))
        for run in a.runs.split():
            target, machine = run.split(":")
            core, variant = target.split("-")
            for tag, opts, count_steps in configs:
                elf = os.path.join(a.build, target, "pil", tag + ".elf")
                t0 = time.time()
                r = subprocess.run(qemu_cmd(machine, elf), stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True, timeout=QEMU_TIMEOUT)
                secs = time.time() - t0
                rows, stack, end = parse_pil(r.stdout)
                entry = {"target": target, "core": MACHINE_CORE.get(machine, machine),
                         "build_core": BUILD_CORE[core], "machine": machine, "variant": variant,
                         "preset": opts[opts.index("--preset") + 1] if "--preset" in opts else "default",
                         "config": tag, "scenario": stem, "steps": len(rows), "exit": r.returncode,
                         "qemu_seconds": round(secs, 2), "stack_measured": stack}
                label = f"{target} on {machine}, {stem} {tag}"
                if r.returncode != 0 or end != len(rows) or not rows:
                    failures.append(f"{label}: QEMU exit {r.returncode}, {len(rows)} rows, end marker "
                                    f"{end}\n{r.stderr[-1500:]}")
                    result["runs"].append(entry)
                    continue
                # The measured stack may never exceed the static worst case of make firmware
                # (scripts/firmware/firmware_check.py): else the call-graph analysis missed a call.
                static = report.get("targets", {}).get(target, {}).get("stack", {}).get(
                    f"rfe_friction_step_{variant}", {}).get("bytes")
                entry["stack_static"] = static
                if static is not None and stack is not None and stack > static:
                    failures.append(f"{label}: a step used {stack} B of stack, more than the static "
                                    f"worst case {static} B of {a.report}")
                ref = host[(tag, variant)]
                if variant == "q31":
                    bad, first = compare_exact(rows, ref, "q31")
                    golden = os.path.join(a.goldens, f"{stem}.{tag}.q31.csv")
                    bad_g, first_g = compare_exact(rows, read_estimates(golden), "q31")
                    entry["compare"] = {"host": "mu_replay --real q31", "mismatches": bad,
                                        "golden": golden, "golden_mismatches": bad_g}
                    # The gate is the host build of the same sources; the committed golden is
                    # reported (test_golden_q31 owns it: a stale golden fails there).
                    if bad:
                        failures.append(f"{label}: {bad} values differ from the host build: {first}")
                    verdict = ("bit-identical to the host build" if not bad else "DIFFERS from the host build") + \
                        (" and the committed golden" if not bad_g else
                         f"; {bad_g} values differ from the committed {golden} (stale golden?)")
                else:
                    golden = os.path.join(a.goldens, f"{stem}.{tag}.csv")
                    worst_g, out_g, _, total = compare_float(rows, read_estimates(golden))
                    worst_h, _, same_h, total_h = compare_float(rows, ref)
                    allowed = FLOAT_FRACTION_OUT.get(entry["preset"], 0.0)
                    entry["compare"] = {"golden": golden, "tolerance": FLOAT_TOL,
                                        "max_abs_dmu_golden": worst_g, "outside": out_g,
                                        "estimates": total // 2, "allowed_fraction_outside": allowed,
                                        "host": "mu_replay --real float",
                                        "max_abs_dmu_host_f32": worst_h,
                                        "bit_identical_to_host_f32": same_h / total_h if total_h else 0.0}
                    if out_g > allowed * (total // 2) or len(rows) != len(ref):
                        failures.append(f"{label}: {out_g} of {total // 2} estimates beyond {FLOAT_TOL} "
                                        f"of the double golden (allowed {allowed:.0%})")
                    verdict = (f"max |dmu| {worst_g:.2e} vs the double golden ({out_g} beyond {FLOAT_TOL}), "
                               f"{worst_h:.2e} vs host float32 ({same_h / total_h:.1%} of values bit-identical)")
                if count_steps > 0:
                    t0 = time.time()
                    counts = count_instructions(machine, elf, min(count_steps, len(rows)))
                    # The method checked on the spot: the first steps again, one instruction
                    # per TB and a log line each, must give the very same counts.
                    k = min(a.singlestep_check, len(counts))
                    if k and count_instructions(machine, elf, k, singlestep=True) != counts[:k]:
                        failures.append(f"{label}: instruction counts of the TB method differ "
                                        f"from -singlestep over the first {k} steps")
                    mean = sum(counts) / len(counts)
                    entry["instructions_per_step"] = {"mean": round(mean, 1), "max": max(counts),
                                                      "min": min(counts), "steps": len(counts),
                                                      "first_steps_of_log": True}
                    entry["core_share_mean"] = mean * STEP_HZ / CORE_HZ
                    entry["core_share_max"] = max(counts) * STEP_HZ / CORE_HZ
                    entry["count_seconds"] = round(time.time() - t0, 1)
                    verdict += (f"; {mean:.0f} instructions/step (max {max(counts)}) over "
                                f"{len(counts)} steps")
                print(f"pil: {label}: {len(rows)} steps, {verdict}; stack {stack} B measured")
                result["runs"].append(entry)
    if a.example:
        target, machine = a.example.split(":")
        ok, msg = example_smoke(machine, os.path.join(a.build, target, "example.elf"))
        result["example"] = {"target": target, "machine": machine, "ok": ok, "message": msg}
        print("pil: " + msg)
        if not ok:
            failures.append(msg)
    result["seconds"] = round(time.time() - t_start, 1)
    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(result, f, indent=2, sort_keys=True)
    if failures:
        for m in failures:
            print("pil: FAIL: " + m)
        return 1
    print(f"pil: OK ({result['seconds']} s); {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
