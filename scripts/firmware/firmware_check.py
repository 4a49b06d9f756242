#!/usr/bin/env python3
"""Mechanical checks of the cross-built library (make firmware-check, issue 5).

For every target <core>-<variant> under --build (build/firmware/<target>/lib/<layer>/*.o, compiled
with -fstack-usage, -fcallgraph-info=su and -fdump-ipa-cgraph by mk/firmware.mk) and its
example image (build/firmware/<target>/example.elf, linked with --gc-sections):

  heap        no object references an allocator (malloc, free, _sbrk, ...; nm -u) and the
              linked example image defines none;
  soft-float  fixed-point objects and everything built for a core without FPU: no soft-float
              helper (the rules of scripts/checks/check_nofloat.sh: __aeabi_f*, __aeabi_d*, __addsf3,
              ...), neither referenced by an object nor linked into the example image; the
              float32 build for the Cortex-M4F: no single-precision helper either (the FPU
              does that arithmetic);
  double      float32 build: no double-precision helper (__aeabi_d*, __aeabi_f2d, ...) and no
              double libm function (floor, ldexp, sqrt, ...) referenced by an object, except
              the objects in DOUBLE_BY_DESIGN (host-side converters documented to compute in
              double), and none at all in the linked example image;
  fixed deps  fixed-point objects: every undefined symbol is a library function, an integer
              libgcc helper or memcpy/memmove/memset/memcmp;
  stack       worst-case stack of each public estimator function (init, step, get; in the
              float32 build also the mass and grade estimator's and the tyre identifier's
              init and step, PUBLIC_F32): the call
              graph of -fcallgraph-info=su (indirect calls reach every address-taken library
              function, as scripts/checks/check_structural.py resolves them), each library
              function's frame from -fstack-usage, and for functions outside the library
              (libgcc, libm, libc) the frame read from the disassembly of the linked example
              image (every push, vpush and sp decrement of the function summed, callees
              followed); no recursion, no frame sized at run time;
  sizes       flash (text + rodata) and RAM (data + bss) of the library objects, the part of
              them the example image links, the estimator state (the example's static g_est),
              and the example image's totals;
  budgets     stack per public call, linked library flash and state size against BUDGETS;
              the flash budget per core (--budget-flash "m0p:49152 m4f:65536 ..." or one
              figure for every core).

Writes the figures to --out (JSON, read by scripts/firmware/firmware_table.py). Exit status 1 when a
check fails or a budget is exceeded.
"""
import argparse
import glob
import json
import os
import re
import subprocess
import sys

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "checks"))
from check_structural import Checker  # noqa: E402  (its .ci / cgraph reader)

CROSS = "arm-none-eabi-"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Default budgets; make firmware-check passes mk/firmware.mk's FW_BUDGET_* (justified there).
BUDGETS = {"stack_per_call": 2048, "flash_linked": 40 * 1024, "state": 2048}

HEAP = {"malloc", "calloc", "realloc", "reallocarray", "free", "aligned_alloc",
        "posix_memalign", "memalign", "valloc", "pvalloc", "alloca", "_sbrk", "sbrk", "_sbrk_r",
        "_malloc_r", "_calloc_r", "_realloc_r", "_free_r", "_memalign_r", "__malloc_lock",
        "strdup", "strndup"}
MEM_FUNCS = {"memcpy", "memmove", "memset", "memcmp"}
# Integer libgcc helpers (ARM run-time ABI and libgcc's generic names).
INT_HELPER_RE = re.compile(
    r"^(__aeabi_(u?idiv|u?idivmod|u?ldivmod|lmul|llsl|llsr|lasr|lcmp|ulcmp|idiv0|ldiv0|"
    r"uread4|uwrite4|uread8|uwrite8)|__(u?div|u?mod)(si|di)3|__udivmoddi4|__divmoddi4|"
    r"__clz[sd]i2|__ctz[sd]i2|__ffs[sd]i2|__popcount[sd]i2|__muldi3|__(ashl|ashr|lshr)di3|"
    r"__gnu_thumb1_case_[a-z]+|__gnu_ldivmod_helper|__gnu_uldivmod_helper)$")
# Double precision: the ARM run-time ABI's double helpers and conversions to double, libgcc's
# df-mode names, and the double functions of libm (their float twins end in f).
DOUBLE_HELPER_RE = re.compile(
    r"^(__aeabi_d[a-z0-9_]*|__aeabi_cd[a-z0-9_]*|__aeabi_[a-z0-9]*2d|"
    r"__[a-z]+df[0-9]|__float(un)?[sdt]idf|__fix(uns)?df[sdt]i|__extendsfdf2|__truncdfsf2)$")
DOUBLE_LIBM = {
    "acos", "asin", "atan", "atan2", "cos", "sin", "tan", "acosh", "asinh", "atanh", "cosh",
    "sinh", "tanh", "exp", "exp2", "expm1", "frexp", "ilogb", "ldexp", "log", "log10", "log1p",
    "log2", "logb", "modf", "scalbn", "scalbln", "cbrt", "fabs", "hypot", "pow", "sqrt", "erf",
    "erfc", "lgamma", "tgamma", "ceil", "floor", "nearbyint", "rint", "lrint", "llrint",
    "round", "lround", "llround", "trunc", "fmod", "remainder", "remquo", "copysign", "nan",
    "nextafter", "fdim", "fmax", "fmin", "fma", "sincos", "__ieee754_sqrt", "__ieee754_atan2",
    "__ieee754_rem_pio2", "__kernel_sin", "__kernel_cos", "__kernel_tan", "__kernel_rem_pio2"}
# Objects of the float32 library that compute in double on purpose: the parameter converter
# to Q formats (include/rfe/component/params_conv.h: "part of the float and double libraries (host
# tools, calibration, tests)", computing the derived constants "in double precision in both
# builds"). It is never called by the estimator, and the example image (--gc-sections)
# shows that nothing of it is linked into firmware that does not call it.
DOUBLE_BY_DESIGN = {"params_conv_flt.o": "rfe_params_to_q31_f32: host-side converter, "
                                         "double by design (include/rfe/component/params_conv.h)"}

PUBLIC = ("rfe_friction_init", "rfe_friction_step", "rfe_friction_get")
# The float-only estimators' calls, sized in the float32 build too (same stack budget): the
# mass and grade estimator and the tyre identifier (docs/FIRMWARE.md "Other estimators").
PUBLIC_F32 = ("rfe_mass_grade_init", "rfe_mass_grade_step", "rfe_tyre_id_init", "rfe_tyre_id_step")


def sh(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"firmware-check: {' '.join(cmd)} failed:\n{r.stderr}")
    return r.stdout


def float_helper_re():
    """The soft-float helper rule of scripts/checks/check_nofloat.sh (one definition)."""
    script = os.path.join(ROOT, "scripts", "checks", "check_nofloat.sh")
    out = sh(["bash", "-c", f'source <(sed -n "/^FM=/,/^is_float_helper/p" "{script}"); '
                            'printf %s "$FLOAT_HELPER_RE"'])
    if not out.startswith("^("):
        sys.exit("firmware-check: could not read FLOAT_HELPER_RE from check_nofloat.sh")
    return re.compile(out)


def undefined(path):
    return [ln.split()[-1] for ln in sh([CROSS + "nm", "-u", path]).splitlines() if ln.strip()]


def elf_symbols(path):
    """{name: (type, size)} of an ELF (nm -S)."""
    out = {}
    for ln in sh([CROSS + "nm", "-S", path]).splitlines():
        p = ln.split()
        if len(p) == 4:
            out[p[3]] = (p[2], int(p[1], 16))
        elif len(p) == 3:
            out[p[2]] = (p[1], 0)
        elif len(p) == 2:
            out[p[1]] = (p[0], 0)
    return out


def section_sizes(obj):
    """(flash, ram) bytes of one object: .text*/.rodata* and .data*/.bss* sections."""
    flash = ram = 0
    for ln in sh([CROSS + "size", "-A", obj]).splitlines():
        p = ln.split()
        if len(p) < 2 or not p[1].isdigit():
            continue
        name, size = p[0], int(p[1])
        if name.startswith((".text", ".rodata")):
            flash += size
        elif name.startswith((".data", ".bss")):
            ram += size
    return flash, ram


def linked_share(map_path, archive):
    """Bytes of flash (text + rodata) and RAM (data + bss) that the image links from archive."""
    lines = open(map_path).read().split("Linker script and memory map", 1)[-1].splitlines()
    flash = ram = 0
    name = None
    base = os.path.basename(archive)
    for ln in lines:
        m = re.match(r"^ (\.\S+)\s*$", ln)
        if m:
            name = m.group(1)
            continue
        m = re.match(r"^ (\.\S+)?\s+0x[0-9a-f]+\s+0x([0-9a-f]+)\s+(\S+)$", ln)
        if m:
            sec = m.group(1) or name
            name = None
            if sec is None or base + "(" not in m.group(3):
                continue
            size = int(m.group(2), 16)
            if sec.startswith((".text", ".rodata")):
                flash += size
            elif sec.startswith((".data", ".bss")):
                ram += size
        else:
            name = None
    return flash, ram


def object_findings(t, name, undef, variant, soft_core, lib_syms, fhelper):
    """The symbol rules on one object's undefined symbols: (failures, double symbols allowed
    by DOUBLE_BY_DESIGN)."""
    failures, allowed = [], []
    for s in undef:
        if s in HEAP:
            failures.append(f"{t}: {name} references the heap function {s}")
        if (variant == "q31" or soft_core) and fhelper.match(s):
            failures.append(f"{t}: {name} references the soft-float helper {s}")
        if variant == "f32":
            if DOUBLE_HELPER_RE.match(s) or s in DOUBLE_LIBM:
                if name in DOUBLE_BY_DESIGN:
                    allowed.append(s)
                else:
                    failures.append(f"{t}: {name} uses double: {s} (float32 build)")
            elif not soft_core and fhelper.match(s):
                failures.append(f"{t}: {name} calls the soft-float helper {s} on an FPU core")
        if variant == "q31" and not (s in lib_syms or s in MEM_FUNCS or INT_HELPER_RE.match(s)):
            failures.append(f"{t}: {name} needs {s}: neither the library, an integer "
                            f"libgcc helper nor memcpy/memmove/memset/memcmp")
    return failures, allowed


# Self-test fixtures: (name, core, variant, source, patterns every one of which a failure
# must contain; [] = must pass). Compiled for the core, then judged by object_findings.
ARCH = {"m4f": ["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard", "-mfpu=fpv4-sp-d16"],
        "m0p": ["-mcpu=cortex-m0plus", "-mthumb", "-mfloat-abi=soft"]}
FIXTURES = [
    ("q31_float_mul", "m0p", "q31", "float f(float a, float b) { return a * b; }",
     ["soft-float helper __aeabi_fmul"]),
    ("q31_int_div", "m0p", "q31",
     "long long f(long long a, long long b) { return a / b + a * b; }", []),
    ("q31_libc", "m0p", "q31", "int rand(void); int f(void) { return rand(); }", ["needs rand"]),
    ("heap", "m4f", "f32", "#include <stdlib.h>\nvoid *f(void) { return malloc(4); }",
     ["heap function malloc"]),
    ("f32_double_math", "m4f", "f32",
     "#include <math.h>\nfloat f(float x) { return (float)floor((double)x * 0.1); }",
     ["uses double: floor"]),
    ("f32_double_div", "m4f", "f32", "float f(float x, double y) { return (float)(x / y); }",
     ["uses double: __aeabi_ddiv"]),
    ("f32_clean", "m4f", "f32",
     "#include <math.h>\nfloat f(float x) { return sqrtf(x) * sinf(x) + atan2f(x, 2.0f); }", []),
    ("f32_softfloat_on_fpu_core", "m0p", "f32", "float f(float a) { return a * 3.0f; }",
     ["soft-float helper __aeabi_fmul"]),
]


def self_test(out):
    import tempfile
    fhelper = float_helper_re()
    bad = 0
    with tempfile.TemporaryDirectory(dir=out if os.path.isdir(out) else None) as tmp:
        for name, core, variant, src, want in FIXTURES:
            c = os.path.join(tmp, name + ".c")
            o = os.path.join(tmp, name + ".o")
            with open(c, "w") as f:
                f.write(src + "\n")
            sh([CROSS + "gcc", *ARCH[core], "-O2", "-std=c99", "-c", c, "-o", o])
            found, _ = object_findings(core + "-" + variant, name + ".o", undefined(o), variant,
                                       core in ("m0p", "m3"), set(), fhelper)
            ok = (not found) if not want else all(any(w in f for f in found) for w in want)
            if not ok:
                bad += 1
                print(f"firmware-check: self-test: {name}: expected {want or 'no finding'}, got {found}")
    # The stack walk: a chain, an external function, a recursion, a run-time-sized frame.
    # An integer libgcc helper the image does not link adds nothing; another missing callee
    # is a finding.
    graph = {"a": {"b", "ext"}, "b": {"c"}, "c": set(), "r1": {"r2"}, "r2": {"r1"}, "v": set(),
             "h": {"__aeabi_ldivmod"}, "m": {"missing"}}
    frames = {"a": (16, "static"), "b": (100, "static"), "c": (8, "static"),
              "r1": (8, "static"), "r2": (8, "static"), "v": (8, "dynamic"),
              "h": (24, "static"), "m": (24, "static")}
    ext = {"ext": [40, {"ext2"}, []], "ext2": [90, set(), []]}
    checks = [("a", 146, []), ("r1", None, ["recursion"]), ("v", None, ["sized at run time"]),
              ("h", 24, []), ("m", None, ["missing: called by the library but not in the linked image"])]
    for fn, want_bytes, want_problems in checks:
        problems = []
        got, _ = worst_stack(fn, graph, frames, ext, {}, problems)
        if (want_bytes is not None and got != want_bytes) or \
                not all(any(w in p for p in problems) for w in want_problems) or \
                (not want_problems and problems):
            bad += 1
            print(f"firmware-check: self-test: stack of {fn}: {got} B, problems {problems}")
    # The flash budget: one figure for all cores, a figure per core, and the malformed forms.
    budget_cases = [("49152", {"m0p": 49152, "m4f": 49152}),
                    ("m0p:49152 m4f:65536", {"m0p": 49152, "m4f": 65536}),
                    ("m0p:49152", None), ("m0p:1 m0p:2 m4f:3", None), ("m0p49152 m4f:1", None)]
    for text, want in budget_cases:
        try:
            got = parse_flash_budget(text, ["m0p", "m4f"])
        except ValueError:
            got = None
        if got != want:
            bad += 1
            print(f"firmware-check: self-test: flash budget {text!r}: {got}, expected {want}")
    if reg_count("{r4, r5, r6, r7, lr}") != 5 or reg_count("{d8-d15}") != 8 or \
            reg_count("{r4-r11, lr}") != 9:
        bad += 1
        print("firmware-check: self-test: register lists miscounted")
    if bad:
        print(f"firmware-check: self-test FAILED: {bad} case(s)")
        return 1
    print(f"firmware-check: self-test: {len(FIXTURES)} objects, {len(checks)} stack walks and "
          f"{len(budget_cases)} flash budgets judged as expected")
    return 0


# ---- stack of functions outside the library, from the disassembly ------------------------
FUNC_RE = re.compile(r"^([0-9a-f]+) <([^>]+)>:$")
INSN_RE = re.compile(r"^\s+[0-9a-f]+:\s+(\S+)\s*(.*)$")
CALL_RE = re.compile(r"^[0-9a-f]+ <([^>+]+)>$")


def reg_count(lst):
    n = 0
    for part in lst.strip("{} ").split(","):
        part = part.strip()
        m = re.match(r"^([a-z]+)(\d+)-[a-z]+(\d+)$", part)
        n += (int(m.group(3)) - int(m.group(2)) + 1) if m else (1 if part else 0)
    return n


def disasm_frames(elf):
    """{function: (frame bytes, callees, problems)} for every function of the image."""
    funcs, cur = {}, None
    for ln in sh([CROSS + "objdump", "-d", "--no-show-raw-insn", elf]).splitlines():
        m = FUNC_RE.match(ln)
        if m:
            cur = m.group(2)
            funcs[cur] = [0, set(), []]
            continue
        m = INSN_RE.match(ln)
        if not m or cur is None:
            continue
        op, args = m.group(1), re.split(r"[;@]", m.group(2))[0].strip()
        f = funcs[cur]
        if op.startswith("push") or (op.startswith("stmdb") and args.startswith("sp!")):
            f[0] += 4 * reg_count(args[args.index("{"):])
        elif op.startswith("vpush") or (op.startswith("vstmdb") and args.startswith("sp!")):
            regs = args[args.index("{"):]
            f[0] += (8 if "d" in regs else 4) * reg_count(regs)
        elif re.match(r"^subw?(\.w)?$", op) and re.match(r"^sp,\s*(sp,\s*)?#", args):
            f[0] += int(args.split("#")[1], 0)
        elif op.startswith("str") and re.search(r"\[sp, #-(\d+)\]!", args):
            f[0] += int(re.search(r"\[sp, #-(\d+)\]!", args).group(1))
        elif op in ("bl", "blx") or re.match(r"^b(\.[nw])?$", op) or re.match(r"^b[a-z]{2}(\.[nw])?$", op):
            t = CALL_RE.match(args)
            if t and t.group(1) != cur:
                f[1].add(t.group(1))
            elif op == "blx" and not t:
                f[2].append(f"indirect call ({op} {args})")
    return funcs


def external_stack(funcs, name, memo, path=()):
    if name in memo:
        return memo[name]
    if name not in funcs:
        raise KeyError(name)
    if name in path:
        raise RuntimeError("recursion through " + " -> ".join(path + (name,)))
    frame, callees, problems = funcs[name]
    if problems:
        raise RuntimeError(f"{name}: {problems[0]}")
    deepest = 0
    for c in callees:
        deepest = max(deepest, external_stack(funcs, c, memo, path + (name,)))
    memo[name] = frame + deepest
    return memo[name]


# ---- the library's call graph ------------------------------------------------------------
def library_graph(libdir):
    bases = sorted(os.path.splitext(p)[0]
                   for p in glob.glob(os.path.join(libdir, "**", "*.o"), recursive=True))
    ck = Checker(CROSS + "gcc", [], libdir, ["src", "include"])
    nodes, edges, addr_taken, stack = ck.read_graph(bases)
    if ck.findings:
        sys.exit("firmware-check: " + "; ".join(m for _, m in ck.findings))
    frames = {}
    for base in bases:
        # -fstack-usage leaves out the area a function reserves below its saved registers
        # for an argument passed by value partly in registers (the "sub sp, #8" before the
        # push of rfe_xf_add, which takes an rfe_xf_t): the object's own disassembly counts
        # every push and sp decrement, so each frame is the larger of the two figures
        obj = disasm_frames(base + ".o") if os.path.exists(base + ".o") else {}
        for ln in open(base + ".ci"):
            m = re.match(r'^node: \{ title: "([^"]+)" label: "[^"]*\\n(\d+) bytes \(([^)]*)\)"', ln)
            if m:
                own = int(m.group(2))
                seen = obj.get(m.group(1).rsplit(":", 1)[-1])
                frames[m.group(1)] = (max(own, seen[0]) if seen else own, m.group(3))
    # Edges parsed here again: calls GCC emits itself (libgcc helpers such as
    # __aeabi_uldivmod, builtins such as memcpy) carry no "label" (no source location), and
    # the reader above skips those.
    edges = []
    for base in bases:
        for ln in open(base + ".ci"):
            m = re.match(r'^edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"', ln)
            if m:
                edges.append((m.group(1), m.group(2), None))
    graph = {}
    for src, dst, _ in edges:
        targets = sorted(addr_taken) if dst == "__indirect_call" else [dst]
        graph.setdefault(src, set()).update(targets)
    return nodes, graph, frames, sorted(addr_taken)


def worst_stack(fn, graph, frames, ext_funcs, ext_memo, problems, memo=None, path=()):
    """(bytes, path) of the deepest call chain from fn."""
    memo = {} if memo is None else memo
    if fn in memo:
        return memo[fn]
    if fn in path:
        problems.append("recursion: " + " -> ".join(path + (fn,)))
        return 0, [fn]
    if fn in frames:
        own, qual = frames[fn]
        if "dynamic" in qual and "bounded" not in qual:
            problems.append(f"{fn}: stack frame sized at run time ({qual})")
        best = (0, [])
        for c in sorted(graph.get(fn, ())):
            best = max(best, worst_stack(c, graph, frames, ext_funcs, ext_memo, problems, memo,
                                         path + (fn,)), key=lambda t: t[0])
        res = (own + best[0], [fn] + best[1])
    else:
        try:
            res = (external_stack(ext_funcs, fn, ext_memo), [fn + " (disassembly)"])
        except KeyError:
            if INT_HELPER_RE.match(fn):
                # GCC's call graph can keep an edge to a libgcc helper whose call the
                # optimiser then removed (seen: __aeabi_ldivmod from an inlined 64-bit
                # division): had any linked code called it, the linker would have linked
                # it, so it runs nowhere and adds no stack
                res = (0, [fn + " (no call in the linked image)"])
            else:
                problems.append(f"{fn}: called by the library but not in the linked image: "
                                f"no stack figure")
                res = (0, [fn + " (unknown)"])
        except RuntimeError as e:
            problems.append(str(e))
            res = (0, [fn])
    memo[fn] = res
    return res


def parse_flash_budget(text, cores):
    """--budget-flash: one figure for every core ("49152"), or a figure per core
    ("m0p:49152 m4f:65536 m3:65536"); every core of cores must have one.
    Returns {core: bytes}; raises ValueError on a malformed or missing entry."""
    words = text.split()
    if len(words) == 1 and ":" not in words[0]:
        return {c: int(words[0]) for c in cores}
    out = {}
    for w in words:
        core, sep, val = w.partition(":")
        if not sep or not core or core in out:
            raise ValueError(f"--budget-flash: malformed or repeated entry {w!r}")
        out[core] = int(val)
    missing = [c for c in cores if c not in out]
    if missing:
        raise ValueError(f"--budget-flash: no budget for core(s) {' '.join(missing)}")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build/firmware")
    ap.add_argument("--targets", default="")
    ap.add_argument("--examples", default="")
    ap.add_argument("--self-test", action="store_true")
    ap.add_argument("--cflags", default="")
    ap.add_argument("--out", default="build/firmware/report.json")
    ap.add_argument("--budget-stack", type=int, default=BUDGETS["stack_per_call"])
    ap.add_argument("--budget-flash", default=str(BUDGETS["flash_linked"]),
                    help="bytes for every core, or core:bytes pairs (one per core of --targets)")
    ap.add_argument("--budget-state", type=int, default=BUDGETS["state"])
    a = ap.parse_args()
    if a.self_test:
        return self_test(os.path.dirname(a.out))
    cores = sorted({t.split("-")[0] for t in a.targets.split()})
    try:
        flash_budget = parse_flash_budget(a.budget_flash, cores)
    except ValueError as e:
        print(f"firmware-check: FAIL: {e}")
        return 1
    BUDGETS.update({"stack_per_call": a.budget_stack, "flash_linked": flash_budget,
                    "state": a.budget_state})
    fhelper = float_helper_re()
    failures = []
    report = {"budgets": BUDGETS, "cflags": a.cflags, "targets": {}}
    examples = a.examples.split()

    for t in a.targets.split():
        core, variant = t.split("-")
        soft_core = core in ("m0p", "m3")
        libdir = os.path.join(a.build, t, "lib")
        objs = sorted(glob.glob(os.path.join(libdir, "**", "*.o"), recursive=True))
        if not objs:
            failures.append(f"{t}: no objects in {libdir}")
            continue
        lib_syms = set()
        for o in objs:
            for ln in sh([CROSS + "nm", "--defined-only", o]).splitlines():
                if ln.strip():
                    lib_syms.add(ln.split()[-1])
        flash_all = ram_all = 0
        allowed_double = []
        for o in objs:
            fl, ra = section_sizes(o)
            flash_all += fl
            ram_all += ra
            found, dbl = object_findings(t, os.path.basename(o), undefined(o), variant, soft_core,
                                         lib_syms, fhelper)
            failures += found
            allowed_double += dbl
        entry = {"core": core, "variant": variant, "objects": len(objs),
                 "lib_flash_all": flash_all, "lib_ram_all": ram_all,
                 "double_by_design": {k: v for k, v in DOUBLE_BY_DESIGN.items()
                                      if allowed_double and variant == "f32"}}
        if ram_all:
            failures.append(f"{t}: the library has {ram_all} bytes of static data (data + bss)")

        elf = os.path.join(a.build, t, "example.elf")
        ext_funcs, ext_memo = {}, {}
        if t in examples:
            if not os.path.exists(elf):
                failures.append(f"{t}: {elf} missing")
            else:
                syms = elf_symbols(elf)
                for s in syms:
                    if s in HEAP:
                        failures.append(f"{t}: the example image links the heap function {s}")
                    if (variant == "q31" or soft_core) and fhelper.match(s):
                        failures.append(f"{t}: the example image links the soft-float helper {s}")
                    if variant == "f32" and (DOUBLE_HELPER_RE.match(s) or s in DOUBLE_LIBM):
                        failures.append(f"{t}: the float32 example image links double code: {s}")
                lib = os.path.join(a.build, t, "librfe_q31.a" if variant == "q31" else "librfe.a")
                lf, lr = linked_share(elf[:-4] + ".map", lib)
                text, data, bss = (int(x) for x in sh([CROSS + "size", elf]).splitlines()[1].split()[:3])
                entry.update({"lib_flash_linked": lf, "lib_ram_linked": lr,
                              "state": syms.get("g_est", ("?", 0))[1],
                              "image": {"text": text, "data": data, "bss": bss}})
                ext_funcs = disasm_frames(elf)

        # stack
        nodes, graph, frames, addr_taken = library_graph(libdir)
        suffix = "_q31" if variant == "q31" else "_f32"
        entry["stack"] = {}
        entry["address_taken"] = addr_taken
        for pub in PUBLIC + (PUBLIC_F32 if variant == "f32" else ()):
            fn = pub + suffix
            problems = []
            if fn not in frames:
                failures.append(f"{t}: {fn} not found in the call graph")
                continue
            if not ext_funcs:
                failures.append(f"{t}: no linked image to size the stack of external functions")
                break
            depth, path = worst_stack(fn, graph, frames, ext_funcs, ext_memo, problems)
            for p in problems:
                failures.append(f"{t}: {fn}: {p}")
            entry["stack"][fn] = {"bytes": depth, "path": path}
            if depth > BUDGETS["stack_per_call"]:
                failures.append(f"{t}: {fn} needs {depth} B of stack, budget "
                                f"{BUDGETS['stack_per_call']} B (path: {' -> '.join(path)})")
        if "lib_flash_linked" in entry and entry["lib_flash_linked"] > flash_budget[core]:
            failures.append(f"{t}: the library links {entry['lib_flash_linked']} B of flash, "
                            f"budget {flash_budget[core]} B ({core})")
        if entry.get("state", 0) > BUDGETS["state"]:
            failures.append(f"{t}: the estimator state is {entry['state']} B, budget {BUDGETS['state']} B")
        report["targets"][t] = entry

        st = entry["stack"].get("rfe_friction_step" + suffix, {})
        print(f"firmware-check: {t:8s} library {flash_all:6d} B flash (linked {entry.get('lib_flash_linked', '-')}), "
              f"{ram_all} B data+bss; state {entry.get('state', '-')} B; step stack {st.get('bytes', '-')} B "
              f"({' -> '.join(st.get('path', [])[:12])})")

    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(report, f, indent=2, sort_keys=True)
    if failures:
        for m in failures:
            print("firmware-check: FAIL: " + m)
        print(f"firmware-check: {len(failures)} failure(s)")
        return 1
    print(f"firmware-check: OK — no heap, no soft-float helper in the fixed-point and soft-float "
          f"builds, no double in the float32 build (outside {', '.join(sorted(DOUBLE_BY_DESIGN))}, "
          f"never linked), budgets met (stack <= {BUDGETS['stack_per_call']} B per call, linked "
          f"flash <= {' '.join(f'{c}: {v} B' for c, v in sorted(flash_budget.items()))}, state <= {BUDGETS['state']} B); {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
