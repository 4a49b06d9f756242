"""Builds the rfe extension (docs/PYTHON.md "How it is built").

Nothing here lists a C source: the library is every *.c of the folders LIB_DIRS names in
mk/lib.mk (float/double sources compiled twice, the *_q31.c twins once), the host code is
src/host/*.c, so a module added to a folder joins the package as it joins the Makefile's
build. Every C file is compiled with the Makefile's strict WARN and its -O2 -g (the flags
mu_replay is built with), so the package runs the same machine code paths and its results
equal mu_replay's bit for bit. mu_replay.c itself is compiled with main renamed
rfe_mu_replay_main: `rfe.replay` and `python -m rfe` call the CLI's own code.

cffi (API mode) writes the extension's C wrapper; the wrapper releases the GIL around each C
call.
"""
from __future__ import annotations

import os
import re
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from cffi import FFI
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
(ROOT / "build/python").mkdir(parents=True, exist_ok=True)  # egg_base below


def make_var(path: str, name: str) -> list[str]:
    """The words of `name := ...` (with its continuation lines) in a Makefile fragment."""
    text = (ROOT / path).read_text(encoding="utf-8")
    m = re.search(rf"^{re.escape(name)}\s*:?=((?:[^\n]*\\\n)*[^\n]*)$", text, re.M)
    if m is None:
        raise SystemExit(f"setup.py: {path} has no {name} := ...")
    return m.group(1).replace("\\\n", " ").split()


LIB_DIRS = make_var("mk/lib.mk", "LIB_DIRS")
# The Makefile's strict flags (WARN, and the -Werror=vla it appends) and optimisation (OPT).
WARN = make_var("Makefile", "WARN") + ["-Werror=vla"]
OPT = ["-O2", "-g"]
# What Python's own compile flags (sysconfig CFLAGS, before ours) add that the Makefile's build
# does not have: -DNDEBUG and -fwrapv undone (their -O3 is overridden by OPT).
PY_UNDO = ["-UNDEBUG", "-fno-wrapv"]
LIB_ALL = sorted(str(p.relative_to(ROOT)) for d in LIB_DIRS for p in (ROOT / d).glob("*.c"))
Q31_SRC = [s for s in LIB_ALL if s.endswith("_q31.c")]
FLT_SRC = [s for s in LIB_ALL if s not in Q31_SRC]
# mk/lib.mk HOST_SRC, plus the replay cores and the CLI (as mu_replay links them).
HOST_SPECIAL = ("src/host/mu_replay.c", "src/host/replay_real.c", "src/host/replay_q31.c")
HOST_SRC = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "src/host").glob("*.c")
                  if str(p.relative_to(ROOT)) not in HOST_SPECIAL)
INC_LIB = ["include", "src"]
INC_HOST = ["include", "src", "src/host"]
POSIX = [("_POSIX_C_SOURCE", "200809L")]
DOUBLE = [("RFE_REAL_DOUBLE", None)]

# (tree, sources, macros, include dirs): the objects of build/{f32,f64,q31}/ and mu_replay.
UNITS = [
    ("f32", FLT_SRC, [], INC_LIB),
    ("f64", FLT_SRC, DOUBLE, INC_LIB),
    ("q31", Q31_SRC, [], INC_LIB),
    ("host", HOST_SRC + ["src/host/replay_q31.c"], POSIX, INC_HOST),
    ("host-f32", ["src/host/replay_real.c"], POSIX, INC_HOST),
    ("host-f64", ["src/host/replay_real.c"], POSIX + DOUBLE, INC_HOST),
    ("cli", ["src/host/mu_replay.c"], POSIX + [("main", "rfe_mu_replay_main")], INC_HOST),
]

CDEF = """
int rfe_mu_replay_main(int argc, char **argv);
const char *rfe_py_status_str(int status);
int fflush(FILE *stream);

/* the in-memory replay (src/host/replay_mem.h); "...;": the rest as the C header has it */
#define RFE_MEM_COLS ...
#define RFE_MEM_INPUT ...
#define RFE_MEM_USAGE ...
typedef struct { const char *key; const char *value; } rfe_kv_t;
typedef struct { const char *name; const double *values; } rfe_column_t;
typedef struct { const char *file; size_t line; size_t col; char msg[]; ...; } rfe_io_error_t;
typedef struct { size_t n_steps; size_t status_count[]; size_t n_gaps; uint64_t n_skipped;
                 size_t n_restarts; ...; } rfe_replay_stats_t;
typedef struct { rfe_replay_stats_t base; uint64_t input_sat; size_t input_sat_rows;
                 uint64_t est_sat; uint32_t est_sat_max; size_t est_sat_rows; ...; }
    rfe_replay_q31_stats_t;
typedef struct { int real; int observer; int mass_grade; int tyre_id; int tyre_feed;
                 int dt_given; int preset_vehicle;
                 int ready; ...; } rfe_replay_mem_t;
size_t rfe_replay_mem_state_size(int real);
int rfe_mu_replay_open(rfe_replay_mem_t *m, int argc, char **argv, const char *params_text,
                       const rfe_kv_t *meta, size_t n_meta, const rfe_column_t *cols,
                       size_t n_cols, size_t n_rows, void *state, rfe_io_error_t *err);
int rfe_replay_mem_feed(rfe_replay_mem_t *m, const rfe_kv_t *meta, size_t n_meta,
                        const rfe_column_t *cols, size_t n_cols, size_t n_rows, double *out,
                        rfe_io_error_t *err);
int rfe_replay_mem_stats(const rfe_replay_mem_t *m, rfe_replay_q31_stats_t *stats);
const char *rfe_replay_mem_col(size_t i);
"""
CSRC = """
#include <stdio.h>
#include "rfe/common.h"
#include "replay_mem.h"
int rfe_mu_replay_main(int argc, char **argv);
static const char *rfe_py_status_str(int status) { return rfe_status_str((rfe_status_t)status); }
"""


class BuildExt(build_ext):
    """Compiles UNITS (two at a time, or RFE_BUILD_JOBS) into objects of their own tree,
    writes cffi's wrapper, and links them into rfe._rfe."""

    def build_extension(self, ext: Extension) -> None:
        temp = Path(self.build_temp) / "rfe"
        ffi = FFI()
        ffi.cdef(CDEF)
        ffi.set_source("rfe._rfe", CSRC)
        temp.mkdir(parents=True, exist_ok=True)
        wrapper = temp / "_rfe.c"
        ffi.emit_c_code(str(wrapper))
        # Every object compiled and linked again: the compiler's up-to-date test compares a
        # source with its object only, not with the headers it includes, and the link's
        # compares the wrapper with the extension, not the objects; so a change in the C
        # library left build/python's old extension in place (measured: 207 package tests off
        # the CLI after a change to rfe/friction.h and friction_flt.c).
        self.compiler.force = True
        self.force = True
        jobs = int(os.environ.get("RFE_BUILD_JOBS", "2"))
        tasks = [(tree, src, macros, inc) for tree, srcs, macros, inc in UNITS for src in srcs]

        def compile_one(task: tuple) -> list[str]:
            tree, src, macros, inc = task
            return self.compiler.compile([src], output_dir=str(temp / tree), macros=macros,
                                         include_dirs=inc,
                                         extra_postargs=WARN + OPT + PY_UNDO)

        with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
            objects = [o for objs in pool.map(compile_one, tasks) for o in objs]
        ext.sources = [str(wrapper)]
        ext.extra_objects = objects
        # build_ext relinks only when a source or a dependency is newer than the extension:
        # the wrapper is unchanged when only the C code changed, so without the objects here
        # a rebuild in the same build/python kept the extension of the previous C code
        ext.depends = objects
        ext.include_dirs = INC_HOST
        ext.libraries = ["m"]
        super().build_extension(ext)


setup(
    ext_modules=[Extension("rfe._rfe", sources=["setup.py"])],  # sources: set in BuildExt
    cmdclass={"build_ext": BuildExt},
    options={"build": {"build_base": "build/python"},
             "egg_info": {"egg_base": "build/python"}},
)
