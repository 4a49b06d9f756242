#!/usr/bin/env python3
"""The dependency rules of the source tree (docs/LAYOUT.md), checked on every #include.

    python3 scripts/checks/check_layers.py [--root DIR]

Layers, lowest first. A file may include its own layer and the layers listed for it:

    numerics    (src/numerics/)   nothing above: linear algebra, fixed-point math, helpers
    filters     (src/filters/)    numerics: the generic cubature filters
    params      (src/params/)     numerics: parameters, presets, validation, conversion
    models      (src/models/)     numerics, params: vehicle kinematics, loads, tyres, h(x, u)
    estimators  (src/estimators/) everything above: the friction estimator, its parts
    host        (src/host/)       anything: CSV, parameter files, metrics, the CLI

Public headers (include/rfe/) belong to the layer of the code they declare (PUBLIC below);
a header nobody assigned is an error, so a new one gets its place when it is added.

The fixed-point rule: a *_q31.c / *_q31.h file of the library, and a header shared by both number types
(Q31_SHARED), includes only such files and the freestanding <stddef.h>, <stdint.h>: never a
float header (rfe/types.h, rfe/params.h, a float twin, numerics/internal.h) or <math.h>.
Exit 0 when every rule holds, 1 with one line per violation, 2 on a usage error.
"""

from __future__ import annotations

import argparse
import os
import re
import sys

LAYERS = ("numerics", "filters", "params", "models", "estimators", "host")
ALLOWED = {
    "numerics": {"numerics"},
    "filters": {"numerics", "filters"},
    "params": {"numerics", "params"},
    "models": {"numerics", "params", "models"},
    "estimators": {"numerics", "filters", "params", "models", "estimators"},
    "host": set(LAYERS),
}
PUBLIC = {
    "numerics": ("common.h", "config.h", "types.h", "fixed.h", "fxmath.h", "qr.h", "qr_q31.h",
                 "chol.h", "chol_q31.h", "philox.h"),
    "filters": ("sckf.h", "sckf_q31.h", "ckf.h", "ckf_q31.h", "kf2.h", "kf2_q31.h"),
    "params": ("modes.h", "params.h", "params_q31.h", "params_conv.h", "velocity_params.h",
               "velocity_params_q31.h",
               "velocity_bits.h", "tyre_id_params.h", "mass_grade_params.h", "mass_grade_params_q31.h",
               "mass_grade_bits.h"),
    "models": ("tyre.h", "tyre_q31.h", "obsmat.h", "obsmat_q31.h", "meas.h", "meas_q31.h"),
    "estimators": ("step_noise.h", "step_noise_q31.h", "conditioner.h", "conditioner_q31.h",
                   "monitor.h", "monitor_q31.h", "friction.h", "friction_q31.h", "velocity.h", "velocity_q31.h", "pipeline.h",
                   "pipeline_q31.h", "tyre_id.h", "mass_grade.h", "mass_grade_q31.h"),
}
# Headers of both number types: no real type in them.
Q31_SHARED = ({"include/rfe/" + h for h in ("common.h", "config.h", "fixed.h", "modes.h",
                                             "velocity_bits.h", "mass_grade_bits.h")}
              | {"include/rfe/component/fxmath.h", "src/numerics/sizes.h",
                 "src/models/meas_inputs.h", "src/estimators/friction/friction_logic.h",
                 "src/estimators/friction/monitor_logic.h",
                 "src/estimators/velocity/velocity_logic.h",
                 "src/estimators/mass_grade/mass_grade_logic.h"})
Q31_SYSTEM = {"stddef.h", "stdint.h"}
INCLUDE_RE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def layer_of(rel: str) -> str | None:
    """The layer of a repository-relative path, None when it has none."""
    parts = rel.split("/")
    if parts[0] == "src" and len(parts) > 2 and parts[1] in LAYERS:
        return parts[1]
    if rel.startswith("include/rfe/"):
        for layer, names in PUBLIC.items():
            if parts[-1] in names:
                return layer
    return None


def is_q31(rel: str) -> bool:
    """A file of the fixed-point library (host code is double, even its q31 replay)."""
    base = os.path.basename(rel)
    if rel.startswith("src/host/"):
        return False
    return base.endswith(("_q31.c", "_q31.h")) or rel in Q31_SHARED


def sources(root: str) -> list[str]:
    """Every .c and .h of src/ and include/rfe/, repository-relative, sorted."""
    out = []
    for top in ("src", os.path.join("include", "rfe")):
        for d, _, files in os.walk(os.path.join(root, top)):
            out += [os.path.relpath(os.path.join(d, f), root).replace(os.sep, "/")
                    for f in files if f.endswith((".c", ".h"))]
    return sorted(out)


def resolve(root: str, rel: str, name: str) -> str | None:
    """The file an #include "name" of rel means: its own folder first, then -Iinclude, -Isrc
    (the compilers' order for quoted includes)."""
    for base in (os.path.dirname(rel), "include", "src"):
        cand = os.path.normpath(os.path.join(base, name)).replace(os.sep, "/")
        if os.path.isfile(os.path.join(root, cand)):
            return cand
    return None


def check(root: str) -> tuple[list[str], int, int]:
    """(violations, files checked, includes checked)."""
    problems, n_inc = [], 0
    files = sources(root)
    for rel in files:
        layer = layer_of(rel)
        if layer is None:
            problems.append(f"{rel}: no layer (a folder of src/ in LAYERS, or a PUBLIC entry "
                            "for a public header)")
            continue
        with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as fh:
            for lineno, line in enumerate(fh, 1):
                m = INCLUDE_RE.match(line)
                if not m:
                    continue
                n_inc += 1
                where = f"{rel}:{lineno}"
                kind, name = m.groups()
                if kind == "<":
                    if is_q31(rel) and name not in Q31_SYSTEM:
                        problems.append(f"{where}: fixed-point file includes <{name}> (only "
                                        f"{', '.join(sorted(Q31_SYSTEM))})")
                    continue
                target = resolve(root, rel, name)
                if target is None:
                    problems.append(f'{where}: #include "{name}" found in neither its folder, '
                                    "include/ nor src/")
                    continue
                tl = layer_of(target)
                if tl is None:
                    continue                      # reported as a file of its own
                if tl not in ALLOWED[layer]:
                    problems.append(f"{where}: {layer} includes {target} ({tl}): {layer} may "
                                    f"include only {', '.join(sorted(ALLOWED[layer]))}")
                if is_q31(rel) and not is_q31(target):
                    problems.append(f"{where}: fixed-point file includes the float header "
                                    f"{target}")
    return problems, len(files), n_inc


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    a = ap.parse_args(argv)
    if not os.path.isdir(os.path.join(a.root, "src")):
        print(f"layers: {a.root}: no src/ folder", file=sys.stderr)
        return 2
    problems, n_files, n_inc = check(a.root)
    for p in problems:
        print(f"layers: {p}")
    if problems:
        print(f"layers: {len(problems)} violation(s) of the dependency rules (docs/LAYOUT.md)")
        return 1
    print(f"layers: {n_files} files, {n_inc} includes: numerics < filters, params < models < "
          "estimators < host, and the fixed-point files include no float header")
    return 0


if __name__ == "__main__":
    sys.exit(main())
