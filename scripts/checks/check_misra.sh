#!/usr/bin/env bash
# make misra: cppcheck with its MISRA C:2012 addon over the library (include/rfe/**.h through
# their inclusion, the library's src/<group>/*.c -- src/host/ is not library code), once per
# real type:
#   float  : -URFE_REAL_DOUBLE, every source in every configuration its preprocessor
#            conditionals name (no compiler, __GNUC__, the Arm cores), less the ones no build
#            has (see "Configurations" below)
#   double : -DRFE_REAL_DOUBLE, the float sources only (the *_q31.c files have no real type)
# plus cppcheck's own warning/style/portability/performance checks, which implement the
# MISRA rules the addon leaves to the core (5.3, 8.13, 9.1, 14.3, 18.1, ... -- docs/MISRA.md).
# Reports: build/misra/{float,double}.xml (cppcheck XML) and .txt (one finding per line).
# Gate: zero findings. The only suppressions are the inline ones that cite a deviation
# (MISRA-DEV-nn) or a tool false positive (MISRA-FP-nn) recorded in docs/MISRA.md, and the
# disapplied advisory rule 15.5 (MISRA-GRP-01); a suppression that no longer matches
# anything is itself a finding (unmatchedSuppression). Finally the deviation IDs in the
# code and in docs/MISRA.md must match both ways.
set -euo pipefail
cd "$(dirname "$0")/../.."

OUT=${MISRA_OUT:-build/misra}
# The library's sources and private headers: every folder of src/ but src/host/.
LIB_FILES=$(find src -path src/host -prune -o \( -name '*.c' -o -name '*.h' \) -print | sort)
SRC=${MISRA_SRC:-$(grep '\.c$' <<<"$LIB_FILES")}
DOC=docs/MISRA.md
mkdir -p "$OUT"

command -v cppcheck >/dev/null || { echo "misra: cppcheck not installed (make deps-analysis)"; exit 2; }
echo "misra: $(cppcheck --version), addon misra, $(echo "$SRC" | wc -w) library sources"

run_variant() { # $1 = name, $2.. = cppcheck's input and options (sources, or --project=)
    local name=$1; shift
    # A fresh build dir every run: with a warm cache cppcheck analyses nothing and then
    # reports the command-line suppression of missingIncludeSystem as unmatched.
    rm -rf "$OUT/cache-$name"
    mkdir -p "$OUT/cache-$name"
    # MISRA-GRP-01: Rule 15.5 (advisory) is disapplied project-wide (docs/MISRA.md).
    local rc=0
    cppcheck --addon=misra --std=c99 --language=c --error-exitcode=1 -Iinclude -Isrc \
        --enable=warning,style,portability,performance,information \
        --inline-suppr --suppress=misra-c2012-15.5 --suppress=missingIncludeSystem \
        --cppcheck-build-dir="$OUT/cache-$name" --xml --output-file="$OUT/$name.xml" -q \
        "$@" || rc=$?
    echo "$rc" >"$OUT/$name.rc"
    python3 - "$OUT/$name.xml" "$OUT/$name.txt" <<'EOF'
import os, sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
lines = []
for e in root.iter('error'):
    loc = e.find('location')  # (a compile database's run names its files by absolute path)
    where = (f"{os.path.relpath(loc.get('file'))}:{loc.get('line')}:{loc.get('column')}" if loc is not None
             else "nofile:0:0")
    lines.append(f"{where}: {e.get('severity')}: {e.get('id')}: {e.get('msg')}")
open(sys.argv[2], 'w').write(''.join(l + '\n' for l in sorted(set(lines))))
EOF
}

# The fixed-point sources (*_q31.c) do not depend on RFE_REAL_DOUBLE (make check-nofloat: no
# real type in them), so the double configuration would repeat their float analysis word for
# word: they are checked once, in the float one (measured: 322 -> 275 s of CPU). Rule 2.5
# (a macro never used) is a whole-program rule: judged in the float configuration, over every
# source, not in the double one, which no longer sees the fixed-point sources that use the
# fixed-point headers' macros (a macro used only under RFE_REAL_DOUBLE is still caught: the
# float configuration, which checks every source, finds it unused).
DOUBLE_SRC=$(tr ' ' '\n' <<<"$SRC" | grep -v '_q31\.c$' | tr '\n' ' ')

# Configurations. Given no -D, cppcheck checks each source in every combination of the macros
# its conditionals test (up to --max-configs, 12 by default), headers included. Two kinds
# describe no build, and the float configuration leaves them out through a compile database
# that gives each source its own -U list (measured: 310 -> 140 configurations; make misra's
# CPU about halved):
# - RFE_<X>_IMPL: a public header hides its convenience macro from the one source that
#   defines the function (MISRA-DEV-08); every other source is only ever built without it;
# - the Arm cores' macros (__arm__, __thumb2__, __ARM_FEATURE_*) in a source whose own text
#   tests none of them (nor RFE_FIX_MUL64_W16, which fixed.h derives from them): its code is
#   the same on every core, and the cores' paths of the shared headers (fixed.h,
#   internal_q31.h) are checked through the sources that test those macros themselves
#   (fxmath_q31.c and qr_q31.c include both headers), in every Arm configuration.
# A violation planted in each kind of place (a plain float and a plain Q31 source, fixed.h's
# Cortex-M0+ path, internal_q31.h's Arm path) is found with the database as without it.
python3 - "$OUT/float-compile_commands.json" $SRC <<'EOF'
import json, os, re, sys
out, srcs = sys.argv[1], sys.argv[2:]
impl = re.compile(r'^#define (RFE_[A-Z0-9_]+_IMPL)\b', re.M)
core = re.compile(r'__arm__|__thumb2__|__ARM_FEATURE|RFE_FIX_MUL64_W16')
CORES = ["-U__arm__", "-U__thumb2__", "-U__ARM_FEATURE_CLZ", "-U__ARM_FEATURE_IDIV"]
text = {f: open(f, encoding="utf-8").read() for f in srcs}
own = {f: set(impl.findall(text[f])) for f in srcs}
impls = sorted(set().union(*own.values()))
json.dump([{"directory": os.getcwd(), "file": f,
            "arguments": ["cc", "-std=c99", "-Iinclude", "-Isrc", "-URFE_REAL_DOUBLE"]
            + ["-U" + m for m in impls if m not in own[f]]
            + ([] if core.search(text[f]) else CORES) + ["-c", f]} for f in srcs],
          open(out, "w", encoding="utf-8"), indent=1)
EOF
run_variant float --project="$OUT/float-compile_commands.json" --max-configs=12 &
pf=$!
run_variant double -DRFE_REAL_DOUBLE $DOUBLE_SRC --suppress=misra-c2012-2.5 &
pd=$!
wait $pf
wait $pd

status=0
for name in float double; do
    n=$(wc -l <"$OUT/$name.txt")
    rc=$(cat "$OUT/$name.rc")
    if [ "$rc" -ne 0 ] && [ "$n" -eq 0 ]; then
        echo "misra: $name build: cppcheck failed (exit $rc) without a finding in $OUT/$name.xml"
        status=1
    elif [ "$n" -ne 0 ]; then
        echo "misra: $name build: $n finding(s) (rule numbers only: MISRA's rule texts are licensed)"
        sed 's/^/  /' "$OUT/$name.txt"
        status=1
    else
        echo "misra: $name build: 0 findings"
    fi
done

# cppcheck checks a header only through an #include: say which public headers no library
# file includes, so nobody reads them as checked.
PUB_HDRS="include/rfe/*.h include/rfe/component/*.h"
for h in $PUB_HDRS; do
    if ! grep -qs "#include \"${h#include/}\"" $LIB_FILES $PUB_HDRS; then
        echo "misra: note: $h is included by no library file: not checked (host-only header?)"
    fi
done

# Deviation records: each inline suppression cites an ID recorded in docs/MISRA.md, and each
# ID recorded there is cited in the code.
code_ids=$(grep -hoE 'MISRA-(DEV|FP)-[0-9]+' $PUB_HDRS $LIB_FILES | sort -u)
doc_ids=$(grep -oE '^\| *MISRA-(DEV|FP)-[0-9]+' "$DOC" | grep -oE 'MISRA-(DEV|FP)-[0-9]+' | sort -u)
while IFS= read -r line; do
    if ! grep -qE 'MISRA-(DEV|FP)-[0-9]+' <<<"$line"; then
        echo "misra: suppression without a MISRA-DEV/FP id: $line"; status=1
    fi
done < <(grep -nE 'cppcheck-suppress' $PUB_HDRS $LIB_FILES || true)
for id in $code_ids; do
    grep -qx "$id" <<<"$doc_ids" || { echo "misra: $id is cited in the code but not recorded in $DOC"; status=1; }
done
for id in $doc_ids; do
    grep -qx "$id" <<<"$code_ids" || { echo "misra: $id is recorded in $DOC but cited nowhere in the code"; status=1; }
done

if [ "$status" -eq 0 ]; then
    echo "misra: clean ($(echo "$code_ids" | wc -w) deviation/false-positive IDs, all recorded in $DOC); reports in $OUT/"
fi
exit "$status"
