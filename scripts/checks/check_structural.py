#!/usr/bin/env python3
"""Mechanical checks of three rules of the library: no dynamic memory, no recursion, no
variable-length arrays (docs/MISRA.md, "Structural checks"; MISRA C:2012 Rules 21.3, 17.2,
18.8 and Dir 4.12).

Each source is compiled once with the project's strict flags plus -O0 (every call kept, no
inlining), -fcallgraph-info=su (a VCG call graph with the stack usage of each function) and
-fdump-ipa-cgraph (which functions have their address taken). Then:

  symbols    no undefined symbol of an object is an allocator (malloc, calloc, realloc,
             free, aligned_alloc, alloca, ...), checked with nm on these objects and on the
             libraries given with --archive (the optimised builds);
  source     no such identifier appears in the preprocessed text of the project's own files
             (macros expanded, comments gone), which also catches __builtin_alloca, which
             leaves no symbol;
  stack      every function's stack usage is "static" or "dynamic,bounded" (GCC's
             qualifiers); plain "dynamic" is a frame sized at run time: a VLA or alloca;
  vla        the flags contain -Werror=vla (or -Wvla with -Werror), so a VLA does not
             compile at all; the stack check is the second line of defence;
  recursion  the call graph of all the sources together has no cycle. An indirect call
             (through a function pointer) is taken to reach every function of the sources
             whose address is taken; callbacks supplied by an application are outside it.

  check_structural.py [--cflags FLAGS] [--archive LIB.a ...] [--out DIR] SOURCE.c ...
  check_structural.py --self-test [--cflags FLAGS]     # each fixture in test/structural/
                                                       # must be rejected for its reason
Exit status 0 when clean (or, with --self-test, when every fixture was rejected).
"""
import argparse
import os
import re
import shlex
import subprocess
import sys

ALLOCATORS = ("malloc", "calloc", "realloc", "reallocarray", "free", "aligned_alloc",
              "posix_memalign", "memalign", "valloc", "pvalloc", "alloca", "__builtin_alloca",
              "__builtin_alloca_with_align", "__alloca", "strdup", "strndup")
ALLOC_RE = re.compile(r"\b(" + "|".join(re.escape(a) for a in ALLOCATORS) + r")\b")
NODE_RE = re.compile(r'^node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE_RE = re.compile(r'^edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)" label: "([^"]*)"')
LINEMARK_RE = re.compile(r'^# (\d+) "([^"]+)"')
CGRAPH_FN_RE = re.compile(r"^(\S+)/\d+ \(")


def run(cmd):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


class Checker:
    def __init__(self, cc, cflags, out, own_dirs):
        self.cc = cc
        self.cflags = cflags
        self.out = out
        self.own_dirs = own_dirs  # preprocessed lines from these files are the project's own
        self.findings = []  # (check, message)

    def add(self, check, msg):
        self.findings.append((check, msg))

    def flags_forbid_vla(self):
        f = self.cflags
        ok = "-Werror=vla" in f or ("-Wvla" in f and "-Werror" in f and "-Wno-error=vla" not in f)
        if not ok:
            self.add("vla", "the compile flags do not reject VLAs (-Werror=vla missing)")

    def compile(self, src):
        base = os.path.join(self.out, os.path.splitext(os.path.basename(src))[0])
        obj = base + ".o"
        cmd = [self.cc] + self.cflags + ["-O0", "-fcallgraph-info=su", "-fdump-ipa-cgraph",
                                         "-c", src, "-o", obj]
        r = run(cmd)
        if r.returncode != 0:
            msg = [m for m in r.stdout.strip().splitlines() if "error" in m] or \
                r.stdout.strip().splitlines()
            vla = any("variable length array" in line or "-Werror=vla" in line for line in msg)
            self.add("vla" if vla else "compile",
                     f"{src} does not compile with the strict flags:\n      "
                     + "\n      ".join(msg[:6]))
            return None
        return base

    def check_preprocessed(self, src):
        r = run([self.cc] + self.cflags + ["-E", src])
        if r.returncode != 0:
            return  # reported by compile()
        current = ""
        line_no = 0
        for line in r.stdout.splitlines():
            m = LINEMARK_RE.match(line)
            if m:
                line_no, current = int(m.group(1)), m.group(2)
                continue
            own = any(os.path.abspath(current).startswith(os.path.abspath(d) + os.sep)
                      for d in self.own_dirs)
            if own:
                for hit in ALLOC_RE.findall(line):
                    self.add("source", f"{current}:{line_no}: '{hit}' in the preprocessed source")
            line_no += 1

    def check_symbols(self, path):
        r = run(["nm", "-u", path])
        if r.returncode != 0:
            self.add("symbols", f"nm failed on {path}: {r.stdout.strip()}")
            return
        member = path
        for line in r.stdout.splitlines():
            line = line.strip()
            if line.endswith(":"):
                member = f"{path}({line[:-1]})"
                continue
            sym = line.split()[-1] if line else ""
            if sym.split("@")[0] in ALLOCATORS:
                self.add("symbols", f"{member} references '{sym}'")

    def read_graph(self, bases):
        nodes, edges, addr_taken, stack = {}, [], set(), {}
        for base in bases:
            ci = base + ".ci"
            try:
                text = open(ci).read()
            except OSError:
                self.add("compile", f"{ci} missing (needs GCC >= 12 for -fcallgraph-info)")
                continue
            for line in text.splitlines():
                m = NODE_RE.match(line)
                if m:
                    title, label = m.groups()
                    nodes.setdefault(title, label.split("\\n")[0])
                    q = re.search(r"\d+ bytes \(([^)]*)\)", label)
                    if q:
                        stack[title] = q.group(1)
                    continue
                m = EDGE_RE.match(line)
                if m:
                    edges.append(m.groups())
            # Functions whose address is taken: a static one is "file:name" in the .ci.
            dump = [f for f in os.listdir(self.out)
                    if f.startswith(os.path.basename(base) + ".") and f.endswith(".cgraph")]
            for d in dump:
                fn = None
                for line in open(os.path.join(self.out, d)):
                    m = CGRAPH_FN_RE.match(line)
                    if m:
                        fn = m.group(1)
                    elif fn and line.strip() == "Address is taken.":
                        statics = [t for t in nodes if t.endswith(":" + fn)
                                   and t.rsplit(":", 1)[0].endswith(os.path.basename(base) + ".c")]
                        addr_taken.add(statics[0] if statics else fn)
        return nodes, edges, addr_taken, stack

    def check_stack(self, nodes, stack):
        for title, q in sorted(stack.items()):
            if "dynamic" in q and "bounded" not in q:
                name = nodes.get(title, title)
                where = f" ({title})" if title != name else ""
                self.add("stack", f"{name}{where}: stack frame sized at run time ({q}): "
                                  f"a VLA or alloca")

    def check_recursion(self, nodes, edges, addr_taken):
        graph = {}
        for src, dst, where in edges:
            targets = sorted(addr_taken) if dst == "__indirect_call" else [dst]
            for t in targets:
                graph.setdefault(src, set()).add((t, where))
        # Tarjan's strongly connected components, iterative (no recursion here either).
        index, low, on, stack, sccs, counter = {}, {}, set(), [], [], [0]
        for root in sorted(set(graph) | {t for v in graph.values() for t, _ in v}):
            if root in index:
                continue
            work = [(root, iter(sorted(graph.get(root, ()))))]
            index[root] = low[root] = counter[0]
            counter[0] += 1
            stack.append(root)
            on.add(root)
            while work:
                v, it = work[-1]
                advanced = False
                for w, _ in it:
                    if w not in index:
                        index[w] = low[w] = counter[0]
                        counter[0] += 1
                        stack.append(w)
                        on.add(w)
                        work.append((w, iter(sorted(graph.get(w, ())))))
                        advanced = True
                        break
                    if w in on:
                        low[v] = min(low[v], index[w])
                if advanced:
                    continue
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    self_loop = any(t == v for t, _ in graph.get(v, ()))
                    if len(comp) > 1 or self_loop:
                        sccs.append(sorted(comp))
        for comp in sccs:
            names = [nodes.get(c, c) for c in comp]
            calls = [f"{nodes.get(s, s)} -> {nodes.get(t, t)} at {w}"
                     for s in comp for t, w in sorted(graph.get(s, ())) if t in comp]
            self.add("recursion", "call cycle through " + ", ".join(names) + ":\n      "
                     + "\n      ".join(calls))
        return graph

    def check(self, sources, archives):
        os.makedirs(self.out, exist_ok=True)
        self.flags_forbid_vla()
        bases = []
        for src in sources:
            base = self.compile(src)
            self.check_preprocessed(src)
            if base:
                bases.append(base)
                self.check_symbols(base + ".o")
        for a in archives:
            self.check_symbols(a)
        nodes, edges, addr_taken, stack = self.read_graph(bases)
        self.check_stack(nodes, stack)
        graph = self.check_recursion(nodes, edges, addr_taken)
        own = [t for t in nodes if t in stack]
        return {"functions": len(own), "calls": sum(len(v) for v in graph.values()),
                "address_taken": sorted(nodes.get(a, a) for a in addr_taken)}


# Fixtures of the self-test: each must be rejected by the named check.
FIXTURES = [
    (["bad_malloc.c"], "symbols", True),
    (["bad_malloc.c"], "source", True),
    (["bad_alloca.c"], "stack", True),
    (["bad_alloca.c"], "source", True),
    (["bad_vla.c"], "vla", True),            # with the project's flags: does not compile
    (["bad_vla.c"], "stack", False),         # without -Werror=vla: a run-time-sized frame
    (["bad_recursion_a.c", "bad_recursion_b.c"], "recursion", True),
    (["bad_recursion_fnptr.c"], "recursion", True),
]


def self_test(cc, cflags, out):
    ok = True
    loose = [f for f in cflags if f not in ("-Werror=vla", "-Wvla")]
    for i, (files, check, strict) in enumerate(FIXTURES):
        srcs = [os.path.join("test", "structural", f) for f in files]
        c = Checker(cc, cflags if strict else loose, os.path.join(out, f"selftest{i}"),
                    ["test/structural"])
        c.check(srcs, [])
        hits = [m for k, m in c.findings if k == check]
        flags = "project flags" if strict else "without -Werror=vla"
        if hits:
            first = " ".join(x.strip() for x in hits[0].splitlines()[:2])
            print(f"structural self-test: {' + '.join(files)} ({flags}): rejected by '{check}' "
                  f"as it must be: {first[:160]}")
        else:
            ok = False
            print(f"structural self-test: FAIL: {' + '.join(files)} ({flags}) was not rejected "
                  f"by '{check}' (findings: {c.findings})")
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cc", default=os.environ.get("CC", "gcc"))
    ap.add_argument("--cflags", default="", help="compile flags (one string)")
    ap.add_argument("--archive", action="append", default=[], help="library to check with nm")
    ap.add_argument("--out", default="build/structural")
    ap.add_argument("--self-test", action="store_true")
    ap.add_argument("--label", default="", help="name of the configuration in the summary")
    ap.add_argument("sources", nargs="*")
    a = ap.parse_args()
    cflags = shlex.split(a.cflags)
    if a.self_test:
        return 0 if self_test(a.cc, cflags, a.out) else 1
    if not a.sources:
        ap.error("no sources")
    c = Checker(a.cc, cflags, a.out, ["src", "include"])
    info = c.check(a.sources, a.archive)
    report = os.path.join(a.out, "report.txt")
    with open(report, "w") as f:
        for k, m in c.findings:
            f.write(f"{k}: {m}\n")
    for k, m in c.findings:
        print(f"structural: {k}: {m}")
    if c.findings:
        print(f"structural: {len(c.findings)} finding(s); report {report}")
        return 1
    label = f" [{a.label}]" if a.label else ""
    print(f"structural{label}: {len(a.sources)} sources, {info['functions']} functions, "
          f"{info['calls']} call edges: no allocator referenced (objects and "
          f"{len(a.archive)} optimised librar{'y' if len(a.archive) == 1 else 'ies'}), no run-time-sized stack frame, VLAs rejected by "
          f"the flags, no call cycle (indirect calls resolved to the address-taken "
          f"{', '.join(info['address_taken']) or 'none'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
