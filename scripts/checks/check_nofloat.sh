#!/usr/bin/env bash
# check_nofloat.sh — proves mechanically that the fixed-point translation units
# (src/<group>/*_q31.c) contain no floating point: no `float` or `double` in the source and no
# soft-float helper or libm symbol in the Cortex-M0+ build.
#
#   scripts/checks/check_nofloat.sh                     check the library's *_q31.c
#   scripts/checks/check_nofloat.sh [--out DIR] FILE.c… check these files instead (one set, linked
#                                                together); objects go to DIR (build/m0plus)
#   scripts/checks/check_nofloat.sh --self-test         run the same check on the fixtures in
#                                                test/nofloat/ and assert each verdict
#
# For the set of files it
#   1. compiles each one with arm-none-eabi-gcc for -mcpu=cortex-m0plus -mthumb
#      -mfloat-abi=soft, the project's strict warnings and -Werror, -Iinclude -Isrc, -Os
#      -ffunction-sections -fdata-sections (make deps-arm installs no C library for the
#      target, so a TU that includes <math.h>, even through a header, does not compile);
#   2. rejects the tokens float, double, _FloatN[x], __fp16, __bf16, _DecimalN in each .c
#      file, comments stripped by `arm-none-eabi-gcc -fpreprocessed -dD -E` (headers are
#      not scanned: include/rfe/types.h typedefs the float variant's real type);
#   3. rejects every undefined symbol of each object (`arm-none-eabi-nm -u`) that is a
#      soft-float helper or a libm function (rules: is_float_helper, is_libm below);
#   4. links all objects into one Cortex-M0+ ELF against libgcc only (-nostdlib, no libc,
#      no libm, no --gc-sections, so every function is kept) and rejects a soft-float helper
#      anywhere in its symbol table (i.e. linked from libgcc) and every symbol left
#      unresolved — a libm or libc function — except memcpy, memmove, memset and memcmp,
#      which GCC itself may emit (struct copies) and requires of every freestanding
#      environment;
#   5. prints the files checked, the text/data/bss sizes of the objects and of the linked
#      image, and the integer libgcc helpers that were linked.
# Exit status: 0 clean (also when there is nothing to check), 1 a violation, 2 a usage or
# tool error (arm-none-eabi-gcc missing: `make deps-arm`).
set -euo pipefail
export LC_ALL=C  # stable tool messages (parsed below)

PROG=check_nofloat
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
SELF="$ROOT/scripts/checks/check_nofloat.sh"
CROSS=arm-none-eabi-
CC=${CROSS}gcc
NM=${CROSS}nm
SIZE=${CROSS}size
ARCH=(-mcpu=cortex-m0plus -mthumb -mfloat-abi=soft)
WARN=(-std=c99 -pedantic -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow
      -Wdouble-promotion -Wcast-qual -Wstrict-prototypes -Wundef -Werror)
OPTS=(-Os -ffunction-sections -fdata-sections)
# Freestanding for real: only GCC's own headers (stdint.h, stddef.h, limits.h, ...), never a
# C library's, even where newlib is installed (make deps-firmware installs it): the
# fixed-point sources must not need libc/libm headers at all.
FREESTANDING=(-ffreestanding -nostdinc -isystem "$("$CC" -print-file-name=include 2>/dev/null)")
# Functions GCC may call on its own (block copies, zeroing) and requires of a freestanding
# environment (GCC manual, "Standards"); float-free, so allowed to stay unresolved.
ALLOWED_UNRESOLVED=" memcpy memmove memset memcmp "
FORBIDDEN_TOKEN_RE='^(float|double|_Float[0-9]+x?|__fp16|__bf16|_Decimal[0-9]+)$'

die() { echo "$PROG: $*" >&2; exit 2; }

# ---- symbol rules --------------------------------------------------------------------
# Soft-float helpers, by name. ARM run-time ABI: every __aeabi_f* and __aeabi_d* (float and
# double arithmetic, compares, conversions), __aeabi_cf*/__aeabi_cd* (flag-setting
# compares), any __aeabi_*2f / *2d (conversions to float/double, e.g. __aeabi_i2f,
# __aeabi_ul2d, __aeabi_h2f). libgcc's generic names: operations on the float machine
# modes sf, df, tf, xf, hf, bf (__addsf3, __muldf3, __negsf2, __powidf2, __eqsf2,
# __unordsf2 …), complex sc/dc/tc/xc/hc (__mulsc3, __divdc3), conversions int <-> float
# (__floatsisf, __floatundidf, __fixsfsi, __fixunsdfdi …), float <-> float (__extendsfdf2,
# __truncdfsf2, __extendhfsf2), half-precision (__gnu_f2h_ieee, __gnu_h2f_alternative,
# __gnu_d2h_ieee), and fixed-point-type conversions from/to float (__gnu_fractsfsq,
# __gnu_satfractdfda …). The integer helpers (__aeabi_idiv, __aeabi_uidivmod,
# __aeabi_ldivmod, __aeabi_lmul, __aeabi_llsl/llsr/lasr, __aeabi_lcmp, __clzsi2, __divdi3,
# __udivmoddi4, __gnu_ldivmod_helper, __gnu_thumb1_case_* …) match none of these.
FM='(sf|df|tf|xf|hf|bf)'
INTM='(qi|hi|si|di|ti|bitint)'
FLOAT_HELPER_RE="^(__aeabi_[fd][a-z0-9_]*|__aeabi_c[fd][a-z0-9_]*|__aeabi_[a-z0-9]*2[fd]"
FLOAT_HELPER_RE+="|__(add|sub|mul|div|neg|abs|powi|cmp|eq|ne|gt|ge|lt|le|unord)${FM}[0-9]"
FLOAT_HELPER_RE+="|__(mul|div)(sc|dc|tc|xc|hc)3"
FLOAT_HELPER_RE+="|__float(un)?${INTM}${FM}|__fix(uns)?${FM}${INTM}"
FLOAT_HELPER_RE+="|__(extend|trunc)${FM}${FM}[0-9]"
FLOAT_HELPER_RE+="|__gnu_(f2h|h2f|d2h)_[a-z]+"
FLOAT_HELPER_RE+="|__gnu_(sat)?fract(uns)?[a-z]*${FM}[a-z0-9]*)\$"

is_float_helper() { [[ $1 =~ $FLOAT_HELPER_RE ]]; }

# libm: every function of C99 <math.h> (7.12), <complex.h> (7.3) and <fenv.h> (7.6), each
# with its f and l variants, the common extensions of newlib and glibc, and the
# classification helpers behind isnan()/isinf()/fpclassify()/signbit(). A libm function
# missing here is still rejected at the link step, as an unresolved symbol.
declare -A LIBM=()
libm_add() { local n; for n in "$@"; do LIBM[$n]=1; LIBM[${n}f]=1; LIBM[${n}l]=1; done; }
libm_add acos asin atan atan2 cos sin tan acosh asinh atanh cosh sinh tanh \
         exp exp2 expm1 frexp ilogb ldexp log log10 log1p log2 logb modf scalbn scalbln \
         cbrt fabs hypot pow sqrt erf erfc lgamma tgamma ceil floor nearbyint rint lrint \
         llrint round lround llround trunc fmod remainder remquo copysign nan nextafter \
         nexttoward fdim fmax fmin fma \
         cacos casin catan ccos csin ctan cacosh casinh catanh ccosh csinh ctanh cexp clog \
         cabs cpow csqrt carg cimag conj cproj creal \
         j0 j1 jn y0 y1 yn gamma exp10 pow10 sincos significand drem scalb \
         finite isinf isnan infinity clog10 roundeven nextup nextdown \
         __fpclassify __signbit __isinf __isnan __finite __clog10
for n in feclearexcept fegetexceptflag feraiseexcept fesetexceptflag fetestexcept \
         fegetround fesetround fegetenv feholdexcept fesetenv feupdateenv matherr \
         __fpclassifyd __signbitd __isinfd __isnand __finited signgam \
         lgamma_r lgammaf_r lgammal_r gamma_r gammaf_r gammal_r; do
    LIBM[$n]=1
done
unset n

is_libm() { [[ -n ${LIBM[$1]+x} ]]; }

# "float-helper", "libm" or "ok"
classify() {
    if is_float_helper "$1"; then echo float-helper
    elif is_libm "$1"; then echo libm
    else echo ok; fi
}

# ---- the check -------------------------------------------------------------------------
problems=0
problem() { echo "$PROG: $*" >&2; problems=$((problems + 1)); }

# Forbidden tokens of one .c file, comments stripped, as "LINE TOKEN" lines.
scan_tokens() {
    "$CC" -fpreprocessed -dD -E -x c "$1" | awk -v re="$FORBIDDEN_TOKEN_RE" '
        /^# [0-9]+ "/ { n = $2 - 1; next }
        {
            n++; s = $0
            gsub(/[^A-Za-z0-9_]+/, " ", s)
            k = split(s, w, " ")
            split("", seen)
            for (i = 1; i <= k; i++) if (w[i] ~ re && !(w[i] in seen)) { seen[w[i]] = 1; print n, w[i] }
        }'
}

# check_set OUTDIR FILE… — steps 1 to 5 above for one set of files.
check_set() {
    local out=$1; shift
    local f obj base log sym kind line tok msg
    local -a objs=()
    local -A referenced_by=()
    local compiled_all=1
    mkdir -p "$out"

    for f in "$@"; do
        base=$(basename "$f" .c)
        obj="$out/$base.o"
        log="$out/$base.log"
        rm -f "$obj"
        # 1. compile
        if ! "$CC" "${ARCH[@]}" "${WARN[@]}" "${OPTS[@]}" "${FREESTANDING[@]}" -I"$ROOT/include" -I"$ROOT/src" -c "$f" -o "$obj" \
                >"$log" 2>&1; then
            compiled_all=0
            msg=$(grep -m1 -E '(fatal )?error:' "$log" || head -n1 "$log")
            if [[ $msg =~ fatal\ error:\ ([^:]+):\ No\ such\ file ]]; then
                problem "$f: does not compile for Cortex-M0+: includes <${BASH_REMATCH[1]}>," \
                        "which the freestanding build does not have (no libc/libm headers) — at ${msg%%: fatal error*}"
            else
                problem "$f: does not compile for Cortex-M0+: $msg (full log: $log)"
            fi
        else
            objs+=("$obj")
        fi
        # 2. tokens
        while read -r line tok; do
            problem "$f:$line: token '$tok' in a fixed-point translation unit"
        done < <(scan_tokens "$f")
        # 3. the object's undefined symbols
        [[ -f $obj ]] || continue
        while read -r sym; do
            referenced_by[$sym]+=" $f"
            kind=$(classify "$sym")
            case $kind in
                float-helper) problem "$f: references soft-float helper $sym" ;;
                libm) problem "$f: calls libm function $sym" ;;
            esac
        done < <("$NM" -u "$obj" | awk '{print $NF}')
    done

    # 4. link against libgcc only
    local elf="$out/rfe_q31.elf" map="$out/rfe_q31.map" linklog="$out/rfe_q31.link.log"
    rm -f "$elf" "$map"
    if ((compiled_all == 0)); then
        echo "$PROG: link step skipped: not every file compiled" >&2
        return
    fi
    if ! "$CC" "${ARCH[@]}" -nostdlib -Wl,-e,0 -Wl,--warn-unresolved-symbols \
            -Wl,-Map="$map" -o "$elf" "${objs[@]}" -lgcc >"$linklog" 2>&1; then
        problem "link for Cortex-M0+ failed: $(grep -m1 -E 'error|multiple definition' "$linklog" \
                 || head -n1 "$linklog") (full log: $linklog)"
        return
    fi
    local -A defined=()
    while read -r sym; do defined[$sym]=1; done < <("$NM" --defined-only "$elf" | awk '{print $NF}')
    while read -r sym; do
        if is_float_helper "$sym"; then
            problem "$elf: soft-float helper $sym linked from libgcc (referenced by:${referenced_by[$sym]:- another libgcc helper})"
        fi
    done < <("$NM" "$elf" | awk '{print $NF}' | sort -u)
    # unresolved: referenced by an object but defined nowhere in the image, or reported by ld
    local -A unresolved=()
    for sym in "${!referenced_by[@]}"; do
        [[ -n ${defined[$sym]+x} ]] || unresolved[$sym]=1
    done
    while read -r sym; do
        unresolved[$sym]=1
    done < <(sed -n "s/.*undefined reference to \`\\([^']*\\)'.*/\\1/p" "$linklog" | sort -u)
    local -a mem_needed=()
    for sym in $(printf '%s\n' "${!unresolved[@]}" | sort); do
        if [[ $ALLOWED_UNRESOLVED == *" $sym "* ]]; then
            mem_needed+=("$sym")
        elif is_libm "$sym"; then
            problem "$elf: unresolved libm function $sym (referenced by:${referenced_by[$sym]:- libgcc})"
        else
            problem "$elf: unresolved symbol $sym (referenced by:${referenced_by[$sym]:- libgcc}):" \
                    "neither defined in the checked sources nor an integer libgcc helper (libc/libm use?)"
        fi
    done

    # 5. summary
    echo "$PROG: $# file(s) built for Cortex-M0+ (${ARCH[*]} ${OPTS[0]}), linked against libgcc only:"
    "$SIZE" "${objs[@]}" "$elf" | sed 's/^/    /'
    local -A libgcc=()
    while read -r sym; do libgcc[$sym]=1; done < <("$NM" -g --defined-only \
        "$("$CC" "${ARCH[@]}" -print-libgcc-file-name)" 2>/dev/null | awk 'NF==3{print $3}')
    local helpers=""
    while read -r sym; do
        [[ -z ${libgcc[$sym]+x} ]] || helpers+=" $sym"
    done < <("$NM" -g --defined-only "$elf" | awk 'NF==3{print $3}' | sort -u)
    echo "$PROG: libgcc helpers linked:${helpers:- none}"
    if ((${#mem_needed[@]})); then
        echo "$PROG: left to the firmware's C library (emitted by GCC, allowed): ${mem_needed[*]}"
    fi
}

run_check() {
    local out=$1; shift
    if (($# == 0)); then
        echo "$PROG: no *_q31.c source: nothing to check"
        return 0
    fi
    check_set "$out" "$@"
    if ((problems)); then
        echo "$PROG: FAILED: $problems problem(s) in $*" >&2
        return 1
    fi
    echo "$PROG: OK: $* (no forbidden token, no floating-point or libm symbol)"
}

# ---- self-test -------------------------------------------------------------------------
# Each fixture in test/nofloat/ has an expectation: the exit status and patterns (grep -E)
# its output must contain, or, prefixed with '!', must not contain.
selftest() {
    local fixdir="$ROOT/test/nofloat" out="$ROOT/build/m0plus/selftest"
    local -A want_rc=() want_pat=()
    local failures=0 checked=0
    want() { local name=$1 rc=$2; shift 2; want_rc[$name]=$rc; want_pat[$name]=$(printf '%s\n' "$@"); }
    want bad_float 1 "bad_float\\.c:[0-9]+: token 'float'" \
        "references soft-float helper __aeabi_fmul" "references soft-float helper __aeabi_fadd" \
        "soft-float helper __aeabi_fadd linked from libgcc"
    want bad_double_div 1 "bad_double_div\\.c:[0-9]+: token 'double'" \
        "references soft-float helper __aeabi_ddiv" "soft-float helper __aeabi_ddiv linked from libgcc"
    want bad_libm 1 "calls libm function sqrt" "unresolved libm function sqrt" \
        "references soft-float helper __aeabi_i2d"
    want bad_conv 1 "bad_conv\\.c:[0-9]+: token 'float'" \
        "references soft-float helper __aeabi_i2f" "soft-float helper __aeabi_i2f linked from libgcc"
    want bad_literal 1 "references soft-float helper __aeabi_dmul" \
        "soft-float helper __aeabi_dmul linked from libgcc" "!token '"
    want bad_token 1 "bad_token\\.c:[0-9]+: token 'double'" "!soft-float helper" "!libm function"
    want bad_libc 1 "unresolved symbol rand " "!soft-float helper" "!libm function"
    want bad_mathh 1 "does not compile for Cortex-M0\\+: includes <math\\.h>|calls libm function floor"
    want good_int 0 "OK: .*good_int\\.c" "libgcc helpers linked:.* __aeabi_ldivmod" \
        "libgcc helpers linked:.* __aeabi_lmul" "libgcc helpers linked:.* __clzsi2" \
        "libgcc helpers linked:.* __aeabi_idiv" "!soft-float helper" "!libm function"

    local f name output rc pat before line
    for f in "$fixdir"/*.c; do
        name=$(basename "$f" .c)
        if [[ -z ${want_rc[$name]+x} ]]; then
            echo "$PROG: self-test: fixture $f has no expectation in selftest()" >&2
            failures=$((failures + 1)); continue
        fi
        rc=0
        output=$(bash "$SELF" --out "$out/$name" "$f" 2>&1) || rc=$?
        checked=$((checked + 1))
        before=$failures
        if [[ $rc != "${want_rc[$name]}" ]]; then
            echo "$PROG: self-test: $name.c: exit status $rc, expected ${want_rc[$name]}" >&2
            failures=$((failures + 1))
        fi
        while IFS= read -r pat; do
            if [[ $pat == '!'* ]]; then
                if grep -qE -- "${pat#!}" <<<"$output"; then
                    echo "$PROG: self-test: $name.c: output must not match '${pat#!}'" >&2
                    failures=$((failures + 1))
                fi
            elif ! grep -qE -- "$pat" <<<"$output"; then
                echo "$PROG: self-test: $name.c: output does not match '$pat'" >&2
                failures=$((failures + 1))
            fi
        done <<<"${want_pat[$name]}"
        if ((failures > before)); then
            echo "$PROG: self-test: $name.c: the checker's output was:" >&2
            while IFS= read -r line; do echo "    $line" >&2; done <<<"$output"
        fi
    done
    for name in "${!want_rc[@]}"; do
        [[ -f $fixdir/$name.c ]] || { echo "$PROG: self-test: fixture $fixdir/$name.c missing" >&2
                                      failures=$((failures + 1)); }
    done

    # The symbol rules on names, against both kinds of libgcc helper.
    local n names=0
    for n in __aeabi_idiv __aeabi_uidiv __aeabi_idivmod __aeabi_uidivmod __aeabi_ldivmod \
             __aeabi_uldivmod __aeabi_lmul __aeabi_llsl __aeabi_llsr __aeabi_lasr __aeabi_lcmp \
             __aeabi_ulcmp __aeabi_idiv0 __aeabi_ldiv0 __aeabi_uread4 __aeabi_uwrite8 \
             __clzsi2 __clzdi2 __ctzsi2 __ctzdi2 __ffsdi2 __popcountsi2 __paritydi2 __bswapsi2 \
             __clrsbdi2 __divsi3 __udivsi3 __modsi3 __umodsi3 __divdi3 __udivdi3 __moddi3 \
             __umoddi3 __udivmoddi4 __divmoddi4 __muldi3 __negdi2 __ashldi3 __ashrdi3 \
             __lshrdi3 __cmpdi2 __ucmpdi2 __mulvsi3 __addvdi3 __absvsi2 __gnu_ldivmod_helper \
             __gnu_thumb1_case_uqi __gnu_thumb1_case_shi memcpy rfe_fix_sqrt_q31 \
             default_handler; do
        names=$((names + 1))
        [[ $(classify "$n") == ok ]] || { echo "$PROG: self-test: $n classified $(classify "$n"), expected ok" >&2
                                          failures=$((failures + 1)); }
    done
    for n in __aeabi_fadd __aeabi_fsub __aeabi_frsub __aeabi_fmul __aeabi_fdiv __aeabi_fneg \
             __aeabi_fcmpeq __aeabi_fcmpun __aeabi_dadd __aeabi_ddiv __aeabi_drsub \
             __aeabi_dcmplt __aeabi_cfcmpeq __aeabi_cfrcmple __aeabi_cdcmple __aeabi_cdrcmple \
             __aeabi_f2iz __aeabi_f2uiz __aeabi_f2lz __aeabi_f2ulz __aeabi_d2iz __aeabi_d2ulz \
             __aeabi_f2d __aeabi_d2f __aeabi_i2f __aeabi_ui2f __aeabi_l2f __aeabi_ul2f \
             __aeabi_i2d __aeabi_ui2d __aeabi_l2d __aeabi_ul2d __aeabi_h2f __aeabi_f2h \
             __aeabi_d2h __addsf3 __adddf3 __subsf3 __muldf3 __divsf3 __divtf3 __negsf2 \
             __negdf2 __powisf2 __powidf2 __eqsf2 __nedf2 __gtsf2 __gedf2 __ltsf2 __ledf2 \
             __cmpsf2 __unordsf2 __unorddf2 __mulsc3 __divdc3 __floatsisf __floatunsisf \
             __floatdisf __floatundisf __floatsidf __floatundidf __floattidf __fixsfsi \
             __fixunssfsi __fixdfsi __fixdfdi __fixunsdfdi __fixtfsi __extendsfdf2 \
             __truncdfsf2 __extendhfsf2 __truncsfhf2 __gnu_f2h_ieee __gnu_h2f_ieee \
             __gnu_h2f_alternative __gnu_d2h_ieee __gnu_fractsfsq __gnu_fractdfda \
             __gnu_satfractsfqq __gnu_fractunsdfsi; do
        names=$((names + 1))
        [[ $(classify "$n") == float-helper ]] || { echo "$PROG: self-test: $n classified $(classify "$n"), expected float-helper" >&2
                                                    failures=$((failures + 1)); }
    done
    for n in sqrt sqrtf sqrtl floor lround llrintf fabs fmaf atan2 sincosf exp10 cabs \
             fesetround __fpclassifyf __isnand nan; do
        names=$((names + 1))
        [[ $(classify "$n") == libm ]] || { echo "$PROG: self-test: $n classified $(classify "$n"), expected libm" >&2
                                            failures=$((failures + 1)); }
    done

    if ((failures)); then
        echo "$PROG: self-test FAILED: $failures failure(s)" >&2
        return 1
    fi
    echo "$PROG: self-test: $checked fixtures (test/nofloat/) and $names symbol names judged as expected"
}

# ---- command line ----------------------------------------------------------------------
main() {
    local out="$ROOT/build/m0plus" mode=check
    local -a files=()
    while (($#)); do
        case $1 in
            --self-test) mode=selftest ;;
            --out) (($# >= 2)) || die "--out needs a directory"; out=$2; shift ;;
            -h|--help) sed -n '2,31p' "$SELF"; exit 0 ;;
            -*) die "unknown option '$1' (see --help)" ;;
            *) [[ -f $1 ]] || die "$1: no such file"; files+=("$1") ;;
        esac
        shift
    done
    local tool
    for tool in "$CC" "$NM" "$SIZE"; do
        command -v "$tool" >/dev/null 2>&1 || die "$tool not found: install it with 'make deps-arm'"
    done
    if [[ $mode == selftest ]]; then
        ((${#files[@]} == 0)) || die "--self-test takes no files"
        selftest
        return
    fi
    if ((${#files[@]} == 0)); then
        cd "$ROOT"
        mapfile -t files < <(find src -path src/host -prune -o -name '*_q31.c' -print | sort)
        out=${out#"$ROOT"/}
    fi
    run_check "$out" "${files[@]}"
}

main "$@"
