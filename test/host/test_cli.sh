#!/usr/bin/env bash
# Command-line tests of mu_replay: exit codes, the one-line error format
# `mu_replay: FILE:LINE:COL: message`, --help, usage errors, outputs of a good run.
#
# usage: bash test/host/test_cli.sh path/to/mu_replay
# Prints one line per check and closes with "cli: N passed, N failed"; exits 1 on a failure.
# Requirements (docs/REQUIREMENTS.md; the script is one test case "test_cli"):
# REQ-CLI-001 REQ-CLI-003 REQ-CLI-004 REQ-CSV-002 REQ-CSV-005 REQ-CSV-006 REQ-PARF-002 REQ-PARF-003
# REQ-PARF-004 REQ-MET-002 REQ-CLI-005 REQ-CSV-007 REQ-CLI-006 REQ-DOC-001 REQ-CLI-007 REQ-CLI-008
# REQ-OBS-029
set -u

BIN=${1:?usage: test_cli.sh path/to/mu_replay}
DATA="$(cd "$(dirname "$0")" && pwd)/data"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
PASS=0
FAIL=0
# a whole vehicle in a log's metadata (printf text): a run on it warns of no preset value
VEH='# m = 1830\n# Lf = 1.4\n# Lr = 1.65\n# Bf = 1.6\n# Br = 1.6\n# R = 0.325\n# J = 3234\n# hg = 0.54\n'

ok()  { PASS=$((PASS + 1)); echo "ok   $1"; }
bad() { FAIL=$((FAIL + 1)); echo "FAIL $1"; }

# run NAME EXPECTED_EXIT ARGS... : runs the binary, keeps stdout/stderr, checks the exit code.
run() {
    local name=$1 want=$2
    shift 2
    "$BIN" "$@" >"$TMP/out" 2>"$TMP/err"
    local got=$?
    if [ "$got" -eq "$want" ]; then ok "$name: exit $want"; else bad "$name: exit $got, want $want"; fi
}

# one_line NAME REGEX : stderr is exactly one line and matches REGEX.
one_line() {
    local name=$1 re=$2 n
    n=$(wc -l <"$TMP/err")
    if [ "$n" -eq 1 ] && grep -Eq "$re" "$TMP/err"; then
        ok "$name: message '$(cat "$TMP/err")'"
    else
        bad "$name: want one line matching '$re', got $n line(s): $(head -c 300 "$TMP/err")"
    fi
}

# input_error NAME FILE REGEX: malformed input exits 1 with one matching line, writes nothing.
input_error() {
    local name=$1 file=$2 re=$3
    run "$name" 1 --in "$file" --out "$TMP/est.csv"
    one_line "$name" "$re"
    if [ -e "$TMP/est.csv" ]; then bad "$name: estimate log written despite the error"; rm -f "$TMP/est.csv"; fi
}

# ---- help and usage errors (exit 2)
run help 0 --help
if grep -q '^usage: mu_replay' "$TMP/out"; then ok "help: usage on stdout"; else bad "help: no usage on stdout"; fi
run help_short 0 -h
run no_args 2
if grep -q 'usage:' "$TMP/err"; then ok "no_args: usage on stderr"; else bad "no_args: no usage on stderr"; fi
run unknown_option 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --frobnicate
grep -q "unknown option '--frobnicate'" "$TMP/err" && ok "unknown_option: named" || bad "unknown_option: not named"
run missing_out 2 --in "$DATA/good_small.csv"
run missing_value 2 --in "$DATA/good_small.csv" --out
run bad_filter 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --filter ekf
run bad_tyre 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --tyre=pacejka
run bad_real 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --real half
grep -q "^mu_replay: --real must be float, double or q31, not 'half'$" "$TMP/err" && ok "bad_real: named" || bad "bad_real: not named"
run bad_real_case 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --real Q31
run bad_preset 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --preset fast
grep -q "^mu_replay: --preset must be default or paper, not 'fast'$" "$TMP/err" && ok "bad_preset: named" || bad "bad_preset: not named"
[ ! -e "$TMP/e.csv" ] && ok "bad_preset: nothing written" || bad "bad_preset: estimate log written"
run bad_preset_case 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --preset=Paper
run preset_twice 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --preset paper --preset default
run preset_no_value 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --preset
run twice 2 --in "$DATA/good_small.csv" --in "$DATA/good_small.csv" --out "$TMP/e.csv"
run positional 2 "$DATA/good_small.csv"
run flag_with_value 2 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --quiet=1
cp "$DATA/good_small.csv" "$TMP/in.csv"
ln -s "$TMP/in.csv" "$TMP/link.csv"
run out_is_in_via_link 2 --in "$TMP/in.csv" --out "$TMP/link.csv"
run out_is_in 2 --in "$TMP/in.csv" --out "$TMP/in.csv"
cmp -s "$DATA/good_small.csv" "$TMP/in.csv" && ok "out_is_in: input untouched" || bad "out_is_in: input clobbered"

# ---- malformed input (exit 1, one line naming FILE:LINE:COL)
input_error bad_number "$DATA/bad_number.csv" "^mu_replay: .*bad_number\.csv:4:3: column 'vx': "
input_error wrong_count "$DATA/wrong_count.csv" "^mu_replay: .*wrong_count\.csv:3:12: wrong column count"
# --strict: a nan cell stops the run at its line and column (as a broken file)
run nan_strict 1 --in "$DATA/nan_value.csv" --out "$TMP/est.csv" --strict
one_line nan_strict "^mu_replay: .*nan_value\.csv:3:7: column 'ax': nan"
[ ! -e "$TMP/est.csv" ] && ok "nan_strict: nothing written" || { bad "nan_strict: estimate log written"; rm -f "$TMP/est.csv"; }
input_error missing_column "$DATA/missing_column.csv" "^mu_replay: .*missing_column\.csv:2: velocity column 'vy' missing \(give all of vx, vy, yaw_acc or none\)$"
input_error empty_file "$DATA/empty.csv" "^mu_replay: .*empty\.csv: empty file"
input_error time_backwards "$DATA/time_backwards.csv" "^mu_replay: .*time_backwards\.csv:4:1: "
input_error bad_metadata "$DATA/bad_meta.csv" "^mu_replay: .*bad_meta\.csv:2: metadata 'm'"
input_error no_such_file "$TMP/nope.csv" "^mu_replay: .*nope\.csv: cannot open"
input_error partial_util "$DATA/partial_util.csv" "^mu_replay: .*partial_util\.csv:1: truth column 'util_rl' missing"

run unknown_param_key 1 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --params "$DATA/params_unknown_key.par"
one_line unknown_param_key "^mu_replay: .*params_unknown_key\.par:3:1: unknown parameter key 'mass'"
run bad_param_number 1 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --params "$DATA/params_bad_number.par"
one_line bad_param_number "^mu_replay: .*params_bad_number\.par:3:7: value of 'Lr'"
run invalid_param_value 1 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --params "$DATA/params_invalid_value.par"
one_line invalid_param_value "^mu_replay: .*params_invalid_value\.par:1: invalid parameter mu0 = 2 "
printf 'mu_min = 0.45\nmu0 = 0.4\n' >"$TMP/combo.par"
run invalid_param_combination 1 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --params "$TMP/combo.par"
one_line invalid_param_combination "^mu_replay: .*good_small\.csv: estimator init failed: invalid parameter"
run unwritable_metrics 1 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --metrics "$TMP/no_dir/m.json"
one_line unwritable_metrics "^mu_replay: .*no_dir/m\.json: cannot open for writing"
if [ -w /dev/full ]; then
    run metrics_disk_full 1 --in "$DATA/good_small.csv" --out "$TMP/e.csv" --metrics /dev/full
    one_line metrics_disk_full "^mu_replay: /dev/full: write failed"
fi
run unwritable_out 1 --in "$DATA/good_small.csv" --out "$TMP/no_dir/e.csv"
one_line unwritable_out "^mu_replay: .*no_dir/e\.csv: cannot open for writing"

# ---- good runs
run good_float 0 --in "$DATA/good_small.csv" --out "$TMP/f.csv" --metrics "$TMP/f.json"
grep -q '^wheel ' "$TMP/out" && ok "good_float: accuracy table" || bad "good_float: no accuracy table"
grep -q '^steps: 3$' "$TMP/out" && ok "good_float: step count" || bad "good_float: no step count"
[ "$(grep -vc '^#' "$TMP/f.csv")" -eq 4 ] && ok "good_float: header + 3 rows" || bad "good_float: row count"
grep -q '^# real = float$' "$TMP/f.csv" && ok "good_float: real metadata" || bad "good_float: real metadata"
# The log's metadata says mu0 = 0.6 and tyre = absolute: both used.
grep -q '^# mu0 = 0.6$' "$TMP/f.csv" && ok "good_float: metadata parameter used" || bad "good_float: mu0 from metadata"
grep -q '^# tyre = absolute$' "$TMP/f.csv" && ok "good_float: metadata tyre used" || bad "good_float: tyre from metadata"
grep -q '"metrics": {' "$TMP/f.json" && ok "good_float: metrics JSON" || bad "good_float: metrics JSON"
grep -q '^# preset = default$' "$TMP/f.csv" && ok "good_float: preset default by default" || bad "good_float: preset metadata"
grep -q '"preset": "default",' "$TMP/f.json" && ok "good_float: preset in JSON" || bad "good_float: preset in JSON"
# The new figures: every key in every series, the config knobs, null excitation without util.
for key in n_settled rmse max_abs_err max_rel_err t_converge_s n_valid rmse_valid frac_valid \
           consistency n_changes n_reconverged reconverge_s n_excited frac_valid_excited \
           rmse_excited_valid; do
    n=$(grep -o "\"$key\": " "$TMP/f.json" | wc -l)
    [ "$n" -eq 5 ] && ok "good_float: JSON key $key in all 5 series" || bad "good_float: JSON key $key $n times, want 5"
done
grep -q '"consistency_k": 2, "excite_util": 0.5}' "$TMP/f.json" && ok "good_float: JSON config knobs" || bad "good_float: JSON config knobs"
[ "$(grep -o '"n_excited": null' "$TMP/f.json" | wc -l)" -eq 5 ] && ok "good_float: no util, n_excited null" || bad "good_float: n_excited not null"
grep -Eq '^wheel +rmse +max_err +rmse_v +valid% +cons% +t_conv +reconv +settled$' "$TMP/out" \
    && ok "good_float: table columns" || bad "good_float: table columns: $(grep '^wheel' "$TMP/out")"

# --preset: the base set, exact library decimals, beaten by metadata, recorded.
run preset_paper 0 --in "$DATA/good_small.csv" --out "$TMP/pp.csv" --metrics "$TMP/pp.json" --preset paper -q
grep -q '^# preset = paper$' "$TMP/pp.csv" && ok "preset_paper: metadata line" || bad "preset_paper: metadata line"
grep -q '"preset": "paper",' "$TMP/pp.json" && ok "preset_paper: JSON" || bad "preset_paper: JSON"
grep -q '^# R = 0.325$' "$TMP/pp.csv" && grep -q '^# q_mu = 0.003$' "$TMP/pp.csv" \
    && ok "preset_paper: exact library values (double library)" || bad "preset_paper: values"
grep -q '^# mu0 = 0.6$' "$TMP/pp.csv" && ok "preset_paper: metadata beats preset" || bad "preset_paper: mu0"
run preset_default 0 --in "$DATA/good_small.csv" --out "$TMP/pd.csv" --preset=default -q
grep -q '^# preset = default$' "$TMP/pd.csv" && ok "preset_default: metadata line" || bad "preset_default: metadata line"

# util columns: excitation figures are numbers, the table gets the exc_val column.
run good_util 0 --in "$DATA/good_util.csv" --out "$TMP/u.csv" --metrics "$TMP/u.json"
[ "$(grep -o '"n_excited": 0,' "$TMP/u.json" | wc -l)" -eq 5 ] && ok "good_util: n_excited a number" || bad "good_util: n_excited"
grep -Eq '^wheel .* exc_val +n_exc +settled$' "$TMP/out" && ok "good_util: exc_val column" || bad "good_util: no exc_val column"

# Precedence: --params beats metadata, flags beat both. (params_good.par asks for the CKF,
# which runs only the paper subset: --preset paper.)
run precedence 0 --in "$DATA/good_small.csv" --out "$TMP/p.csv" --params "$DATA/params_good.par" \
    --tyre paper --real double --quiet --preset paper
[ ! -s "$TMP/out" ] && ok "precedence: --quiet prints nothing" || bad "precedence: output despite --quiet"
grep -q '^# mu0 = 0.7$' "$TMP/p.csv" && ok "precedence: file beats metadata" || bad "precedence: mu0"
grep -q '^# tyre = paper$' "$TMP/p.csv" && ok "precedence: flag beats file" || bad "precedence: tyre"
grep -q '^# filter = ckf$' "$TMP/p.csv" && ok "precedence: filter from file" || bad "precedence: filter"
run filter_flag 0 --in "$DATA/good_small.csv" --out "$TMP/q.csv" --params "$DATA/params_good.par" --filter sckf -q
grep -q '^# filter = sckf$' "$TMP/q.csv" && ok "filter_flag: flag beats file" || bad "filter_flag: filter"
grep -q '^# real = float$' "$TMP/q.csv" && ok "filter_flag: float by default" || bad "filter_flag: real"
grep -q '^# param_file = params_good.par$' "$TMP/p.csv" && ok "precedence: param_file named" || bad "precedence: param_file"

# The CKF baseline runs only the paper subset (docs/ESTIMATOR.md): with the default preset
# it is refused in one line that says what to do.
# --filter ckf on the command line without --preset paper is a usage error (2), before any file
run ckf_default_preset 2 --in "$DATA/good_small.csv" --out "$TMP/c.csv" --filter ckf
grep -q "^mu_replay: --filter ckf: the CKF baseline needs --preset paper" "$TMP/err" \
    && ok "ckf_default_preset: named" || bad "ckf_default_preset: $(head -1 "$TMP/err")"
[ ! -e "$TMP/c.csv" ] && ok "ckf_default_preset: nothing written" || bad "ckf_default_preset: estimate log written"
run ckf_default_preset_file 1 --in "$DATA/good_small.csv" --out "$TMP/c.csv" --params "$DATA/params_good.par"
one_line ckf_default_preset_file "^mu_replay: .*params_good\.par:6: filter = ckf: the CKF baseline needs --preset paper"
printf 'tau_v = 0.3\n' >"$TMP/ckf_tau.par"
run ckf_paper_plus_addition 1 --in "$DATA/good_small.csv" --out "$TMP/c.csv" --preset paper --filter ckf \
    --params "$TMP/ckf_tau.par"
one_line ckf_paper_plus_addition "^mu_replay: command line: filter = ckf: the CKF baseline needs --preset paper"

# docs/ESTIMATOR.md keys: the word key structure and the numeric keys, in files and metadata.
grep -q '^# structure = sides$' "$TMP/pd.csv" && ok "default: structure metadata" || bad "default: structure metadata"
grep -q '^# info_min = 25$' "$TMP/pd.csv" && grep -q '^# sd_valid = 0.15$' "$TMP/pd.csv" \
    && ok "default: new keys in metadata" || bad "default: new keys in metadata"
grep -q '^# structure = wheels$' "$TMP/pp.csv" && grep -q '^# info_min = 0$' "$TMP/pp.csv" \
    && ok "paper: additions off in metadata" || bad "paper: additions off in metadata"
printf 'structure = wheels\ninfo_min = 50\nsd_in_omega = 0\n' >"$TMP/struct.par"
run structure_key 0 --in "$DATA/good_small.csv" --out "$TMP/s.csv" --params "$TMP/struct.par" -q
grep -q '^# structure = wheels$' "$TMP/s.csv" && grep -q '^# info_min = 50$' "$TMP/s.csv" \
    && grep -q '^# sd_in_omega = 0$' "$TMP/s.csv" && ok "structure_key: file values used" || bad "structure_key: values"
printf 'structure = axles\n' >"$TMP/struct_bad.par"
run structure_bad_word 1 --in "$DATA/good_small.csv" --out "$TMP/s2.csv" --params "$TMP/struct_bad.par"
one_line structure_bad_word "^mu_replay: .*struct_bad\.par:1:13: value of 'structure': not one of the allowed words"
printf 'sd_max = -1\n' >"$TMP/sdmax.par"
run invalid_new_key 1 --in "$DATA/good_small.csv" --out "$TMP/s3.csv" --params "$TMP/sdmax.par"
one_line invalid_new_key "^mu_replay: .*sdmax\.par:1: invalid parameter sd_max = -1 "
grep -q 'docs/ESTIMATOR.md' <("$BIN" --help) && ok "help: names docs/ESTIMATOR.md" || bad "help: no docs/ESTIMATOR.md"

# ---- --velocity: a production car's log (no vx, vy, yaw_acc) runs the observer (docs/OBSERVER.md)
run esc_auto 0 --in "$DATA/good_esc.csv" --out "$TMP/v.csv"
grep -q '^# velocity = observer$' "$TMP/v.csv" && ok "esc_auto: observer metadata" || bad "esc_auto: observer metadata"
grep -q '^t,.*,status,vx_est,vy_est,beta_est,yaw_acc_est,sd_vx,sd_vy,sd_beta$' "$TMP/v.csv" \
    && ok "esc_auto: observer columns" || bad "esc_auto: observer columns"
[ "$(grep -vc '^#' "$TMP/v.csv")" -eq 4 ] && ok "esc_auto: header + 3 rows" || bad "esc_auto: row count"
# the first row's vx_est is the mean wheel speed: 60 rad/s x R 0.325 m = 19.5 m/s
awk -F, '!/^#/ { n++ } n == 2 { exit !($15 > 19.49 && $15 < 19.51) }' "$TMP/v.csv" \
    && ok "esc_auto: vx_est from the wheels" || bad "esc_auto: vx_est"
run esc_measured 1 --in "$DATA/good_esc.csv" --out "$TMP/v.csv" --velocity measured
one_line esc_measured "^mu_replay: .*good_esc\.csv: --velocity measured needs the columns vx, vy, yaw_acc"
run observer_on_measured 0 --in "$DATA/good_small.csv" --out "$TMP/v.csv" --velocity observer
grep -q '^# velocity = observer$' "$TMP/v.csv" && ok "observer_on_measured: metadata" || bad "observer_on_measured: metadata"
run measured_default 0 --in "$DATA/good_small.csv" --out "$TMP/v.csv"
grep -q '^# velocity' "$TMP/v.csv" && bad "measured_default: no velocity metadata" || ok "measured_default: no velocity metadata"
run bad_velocity 2 --in "$DATA/good_small.csv" --out "$TMP/v.csv" --velocity optical

# ---- --real q31 with the observer: the fixed-point pipeline (rfe_pipeline_*_q31), --velocity
#      chosen as in float and double
run esc_q31 0 --in "$DATA/good_esc.csv" --out "$TMP/vq.csv" --metrics "$TMP/vq.json" --real q31
grep -q '^# velocity = observer$' "$TMP/vq.csv" && grep -q '^# real = q31$' "$TMP/vq.csv" \
    && ok "esc_q31: auto ran the observer, in q31" || bad "esc_q31: velocity/real metadata"
grep -q '^t,.*,status,vx_est,vy_est,beta_est,yaw_acc_est,sd_vx,sd_vy,sd_beta$' "$TMP/vq.csv" \
    && ok "esc_q31: observer columns" || bad "esc_q31: observer columns"
[ "$(grep -vc '^#' "$TMP/vq.csv")" -eq 4 ] && ok "esc_q31: header + 3 rows" || bad "esc_q31: row count"
for key in saturation_estimator_total saturation_input_values; do
    grep -q "^# $key = 0$" "$TMP/vq.csv" && ok "esc_q31: metadata $key = 0" || bad "esc_q31: metadata $key"
done
grep -q '"saturation": {"estimator_total": 0,' "$TMP/vq.json" && ok "esc_q31: saturation in JSON" || bad "esc_q31: saturation in JSON"
awk -F, '!/^#/ { n++ } n == 2 { exit !($15 > 19.49 && $15 < 19.51) }' "$TMP/vq.csv" \
    && ok "esc_q31: vx_est from the wheels" || bad "esc_q31: vx_est"
# Every estimate is its Q value exactly (mu Q29, sd Q30, vx, vy, sd_vx, sd_vy Q23, beta, sd_beta
# Q29, r-dot Q24): times 2^q an integer, which a value rounded to 9 digits is not in general.
awk -F, '!/^#/ { n++ } n >= 2 {
    for (c = 2; c <= 9; c++) { q = (c <= 5) ? 536870912 : 1073741824; if ($c * q != int($c * q)) exit 1 }
    split("8388608 8388608 536870912 16777216 8388608 8388608 536870912", f, " ")
    for (c = 15; c <= 21; c++) if ($c * f[c - 14] != int($c * f[c - 14])) exit 1 }' "$TMP/vq.csv" \
    && ok "esc_q31: exact Q values" || bad "esc_q31: a value that is not its Q value"
run esc_q31_again 0 --in "$DATA/good_esc.csv" --out "$TMP/vq2.csv" --metrics "$TMP/vq2.json" --real q31 -q
cmp -s "$TMP/vq.csv" "$TMP/vq2.csv" && ok "esc_q31_again: byte-identical estimate log" || bad "esc_q31_again: logs differ"
run esc_measured_q31 1 --in "$DATA/good_esc.csv" --out "$TMP/v.csv" --velocity measured --real q31
one_line esc_measured_q31 "^mu_replay: .*good_esc\.csv: --velocity measured needs the columns vx, vy, yaw_acc"
run observer_q31 0 --in "$DATA/good_small.csv" --out "$TMP/v.csv" --velocity observer --real q31
grep -q '^# velocity = observer$' "$TMP/v.csv" && ok "observer_q31: metadata" || bad "observer_q31: metadata"
run measured_q31 0 --in "$DATA/good_small.csv" --out "$TMP/v.csv" --velocity auto --real q31
grep -q '^# velocity' "$TMP/v.csv" && bad "measured_q31: auto on a log with vx ran the observer" || ok "measured_q31: auto measured"
run car_format_q31 0 --in "$DATA/car_format_small.csv" --out "$TMP/c.csv" --real q31
awk -F, '!/^#/ { n++ } n == 2 { exit !($1 == 1 && $15 > 19.49 && $15 < 19.51) }' "$TMP/c.csv" \
    && ok "car_format_q31: t and vx_est in SI" || bad "car_format_q31: t, vx_est"
# An observer parameter outside its Q format (torque in Q15: < 65536 N m): named, one line.
printf 'obs_torque_on = 1e5\n' >"$TMP/torque.par"
run q31_obs_param_range 1 --in "$DATA/good_esc.csv" --out "$TMP/qt.csv" --params "$TMP/torque.par" --real q31
one_line q31_obs_param_range "^mu_replay: .*torque\.par:1: parameter obs_torque_on = 100000 does not fit the fixed-point formats \(rfe_velocity_params_to_q31"
[ ! -e "$TMP/qt.csv" ] && ok "q31_obs_param_range: nothing written" || bad "q31_obs_param_range: estimate log written"

# ---- a production car's log in its logger's units (DATA.md "Units, scales and names of a
#      recorded log"): 50 Hz with jitter, ms, steering-wheel angle, deg/s, g, km/h
run car_format 0 --in "$DATA/car_format_small.csv" --out "$TMP/c.csv"
grep -q '^mu_replay: note: dt = 0.019 s, the median period' "$TMP/err" \
    && ok "car_format: dt from the time stamps noted" || bad "car_format: dt note: $(cat "$TMP/err")"
grep -Eq '^# dt = 0\.0190{6,}[0-9]*$' "$TMP/c.csv" && ok "car_format: dt in metadata" || bad "car_format: dt metadata"
grep -q '^# obs_steer_ratio = 16$' "$TMP/c.csv" && ok "car_format: ratio in metadata" || bad "car_format: ratio"
# periods 19, 22.5, 18.5 ms: the lower median is 19 ms. t in s; vx_est = 70.2 km/h = 19.5 m/s on the first row (the wheels' mean)
awk -F, '!/^#/ { n++ } n == 2 { exit !($1 == 1 && $15 > 19.49 && $15 < 19.51) }' "$TMP/c.csv" \
    && ok "car_format: t and vx_est in SI" || bad "car_format: t, vx_est"
run car_format_measured 0 --in "$DATA/car_format_small.csv" --out "$TMP/c.csv" --velocity observer --real double
grep -v '^# obs_steer_ratio' "$DATA/car_format_small.csv" >"$TMP/noratio.csv"
input_error car_no_ratio "$TMP/noratio.csv" \
    "^mu_replay: .*noratio\.csv: the log gives the steering-wheel angle \(swa\): declare the car's obs_steer_ratio"
sed 's/^# obs_steer_ratio = 16$/# obs_steer_ratio = 16\n# dt = 0.01/' "$DATA/car_format_small.csv" >"$TMP/wrongdt.csv"
input_error car_wrong_dt "$TMP/wrongdt.csv" \
    "^mu_replay: .*wrongdt\.csv:4: dt = 0.01 s, but the log's time stamps have a median period of 0.019 s"
sed 's/^# unit_yaw_rate = deg\/s$/# unit_yawrate = deg\/s/' "$DATA/car_format_small.csv" >"$TMP/typo.csv"
input_error car_unit_typo "$TMP/typo.csv" "^mu_replay: .*typo\.csv:9: metadata 'unit_yawrate': 'yawrate' is not a sensor-log column"
printf 'R = -1\n' >"$TMP/negR.par"
run car_negative_R 1 --in "$DATA/car_format_small.csv" --out "$TMP/c.csv" --params "$TMP/negR.par"
one_line car_negative_R "^mu_replay: .*car_format_small\.csv: the wheel speeds are circumferential speeds and need a positive rolling radius R"
# a steering-wheel log with measured velocities (a test car): delta = swa / ratio on the host
printf '# obs_steer_ratio = -2\nt,swa,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,20,0,0,0,0,0,61.5,61.5,61.5,61.5\n' >"$TMP/swa_neg.csv"
input_error car_negative_ratio "$TMP/swa_neg.csv" "^mu_replay: .*swa_neg\.csv:1: obs_steer_ratio = -2: must be a positive number"
printf "$VEH"'t,delta,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,0,0,0,61.5,61.5,61.5,61.5\n' >"$TMP/one_row.csv"
run one_row 0 --in "$TMP/one_row.csv" --out "$TMP/o.csv"
[ -s "$TMP/err" ] && bad "one_row: stderr not empty: $(cat "$TMP/err")" || ok "one_row: no period, no note"
# no dt line, 100 Hz: the median period is 0.01 only to the stamps' rounding (1.02 - 1.01 is
# 0.010000000000000009): it matches the preset's 0.01 s within the 1 % of a given dt, no note
printf '# m = 1830\nt,delta,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n' >"$TMP/p100.csv"
for t in 1 1.01 1.02 1.03 1.04 1.05 1.06 1.07 1.08 1.09; do
    printf '%s,0,0,0,0,61.5,61.5,61.5,61.5\n' "$t" >>"$TMP/p100.csv"
done
run dt_100hz_no_line 0 --in "$TMP/p100.csv" --out "$TMP/o.csv"
grep -q 'note: dt' "$TMP/err" && bad "dt_100hz_no_line: $(grep 'note: dt' "$TMP/err")" || ok "dt_100hz_no_line: no note"
printf '# dt = 0.01\n'"$VEH"'t,delta,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,0,0,0,61.5,61.5,61.5,61.5\n0.01,0,0,0,0,61.5,61.5,61.5,61.5\n0.02,0,0,0,0,61.5,61.5,61.5,61.5\n0.5,0,0,0,0,61.5,61.5,61.5,61.5\n0.51,0,0,0,0,61.5,61.5,61.5,61.5\n' >"$TMP/gap.csv"
run gap 0 --in "$TMP/gap.csv" --out "$TMP/g.csv"
one_line gap "^mu_replay: note: 1 gap\(s\) longer than 2 periods \(2 x 0.01 s\), the longest 0.48 s before t = 0.5 s: behind the observer the friction estimator makes the time updates of the missed periods at once and restarts its input filter; the observer steps with the real period and starts afresh after 1 gap\(s\) longer than obs_dt_max = 0.1 s \(rfe/pipeline.h\)$"
# REQ-OBS-023: behind the observer the gap is told to both estimators, in every precision:
# round(0.48 / 0.01) - 1 = 47 missed periods, the observer restarted once, no sample refused
for real in float double q31; do
    run "gap_observer_$real" 0 --in "$TMP/gap.csv" --out "$TMP/g_$real.csv" --real $real --metrics "$TMP/g_$real.json"
    grep -q '^gaps: 1 longer than 2 dt, 47 missed sample periods time-updated (rfe_friction_skip)$' "$TMP/out" \
        && grep -q '^observer: started afresh at 1 sample(s) after a period beyond obs_dt_max (rfe_velocity_restart)$' "$TMP/out" \
        && ! grep -q 'status 18' "$TMP/out" && ok "gap_observer_$real: summary" \
        || bad "gap_observer_$real: $(cat "$TMP/out")"
    grep -q '"gaps": {"count": 1, "missed_periods": 47, "observer_restarts": 1}' "$TMP/g_$real.json" \
        && ok "gap_observer_$real: JSON" || bad "gap_observer_$real: $(grep gaps "$TMP/g_$real.json")"
done
# the restarted observer takes the row at t = 0.5 as its first: its vx is the wheels' mean,
# as at t = 0 (the same wheel speeds), to the last digit
vx0=$(grep -v '^#' "$TMP/g_double.csv" | awk -F, 'NR == 1 {for (i = 1; i <= NF; i++) if ($i == "vx_est") c = i} NR == 2 {print $c}')
vx5=$(grep -v '^#' "$TMP/g_double.csv" | awk -F, 'NR == 1 {for (i = 1; i <= NF; i++) if ($i == "vx_est") c = i} $1 == "0.5" {print $c}')
[ -n "$vx0" ] && [ "$vx0" = "$vx5" ] && ok "gap_observer: restarted at t = 0.5 (vx $vx5 as at t = 0)" \
    || bad "gap_observer: vx at t = 0 '$vx0', at t = 0.5 '$vx5'"
# REQ-OBS-029: issue 16's rule on the high-mu ramp steer (Magic Formula truth): the friction
# estimator on the observer's inputs has a pooled RMSE when valid at most 0.02 above the
# measured-velocity run's (the trust table's runs: default preset, float). The pooled RMSE is
# sqrt(sum n_valid rmse_valid^2 / sum n_valid) over the wheels of the metrics JSON, as
# observer_results.py pools it. Measured 2026-12-07: 0.175 measured, 0.156 on observer inputs,
# 0.256 with obs_model_ay_rel 0.1 (the default before it): the check can fail, and fails there.
RAMP="$(cd "$(dirname "$0")/../.." && pwd)/scenarios/ramp_steer_high_mu.mf.csv"
pooled_rmse_valid() {
    awk '/^ *"(fl|fr|rl|rr)": \{/ {
        n = $0; sub(/.*"n_valid": /, "", n); sub(/,.*/, "", n)
        r = $0; sub(/.*"rmse_valid": /, "", r); sub(/,.*/, "", r)
        if (n + 0 > 0) { sn += n; s2 += n * r * r }
    } END { if (sn > 0) printf "%.6f\n", sqrt(s2 / sn); else print "none" }' "$1"
}
printf 'obs_model_ay_rel = 0.1\n' >"$TMP/ay_rel_old.par"
for v in measured observer old; do
    extra=()
    [ "$v" = old ] && extra=(--params "$TMP/ay_rel_old.par")
    run "ramp_high_mf_$v" 0 --in "$RAMP" --out "$TMP/ramp_$v.csv" --preset default --real float \
        --velocity "${v/old/observer}" --metrics "$TMP/ramp_$v.json" --quiet "${extra[@]}"
done
rm_=$(pooled_rmse_valid "$TMP/ramp_measured.json")
ro_=$(pooled_rmse_valid "$TMP/ramp_observer.json")
rold=$(pooled_rmse_valid "$TMP/ramp_old.json")
awk -v m="$rm_" -v o="$ro_" 'BEGIN { exit !(m != "none" && o != "none" && o <= m + 0.02) }' \
    && ok "ramp_high_mf: observer inputs within issue 16's rule ($ro_ against measured $rm_)" \
    || bad "ramp_high_mf: observer inputs $ro_ against measured $rm_ + 0.02"
awk -v m="$rm_" -v o="$rold" 'BEGIN { exit !(o != "none" && o > m + 0.02) }' \
    && ok "ramp_high_mf: obs_model_ay_rel 0.1 misses the rule ($rold against measured $rm_)" \
    || bad "ramp_high_mf: obs_model_ay_rel 0.1 gives $rold against measured $rm_ + 0.02"
# REQ-CSV-006: a gap of 3 periods in a measured-velocity log is reported too; jitter is not
# (braking at 4 m/s^2 with 4 % slip: updating steps, so the sd is below the prior's and a gap
# has room to grow it; then cruising, held: the sd after the gap is the time updates' alone)
printf '# dt = 0.01\n'"$VEH"'t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,20,0,0,0,-4,0,59.08,59.08,59.08,59.08\n0.01,0,20,0,0,0,-4,0,59.08,59.08,59.08,59.08\n0.0205,0,20,0,0,0,-4,0,59.08,59.08,59.08,59.08\n0.0295,0,20,0,0,0,-4,0,59.08,59.08,59.08,59.08\n0.06,0,20,0,0,0,0,0,61.54,61.54,61.54,61.54\n0.07,0,20,0,0,0,0,0,61.54,61.54,61.54,61.54\n' >"$TMP/gapm.csv"
run gap_measured 0 --in "$TMP/gapm.csv" --out "$TMP/gm.csv"
one_line gap_measured "^mu_replay: note: 1 gap\(s\) longer than 2 periods \(2 x 0.01 s\), the longest 0.0305 s before t = 0.06 s: the friction estimator makes the time updates of the missed periods at once and restarts its input filter \(rfe_friction_skip\)$"
# REQ-EST-015: the estimator is told: round(0.0305 / 0.01) - 1 = 2 missed periods, in the
# summary and the JSON, in both precisions; its sd after the gap is larger than without it
grep -q '^gaps: 1 longer than 2 dt, 2 missed sample periods time-updated (rfe_friction_skip)$' "$TMP/out" \
    && ok "gap_measured: summary" || bad "gap_measured: $(grep gaps "$TMP/out")"
for real in float q31; do
    run "gap_json_$real" 0 --in "$TMP/gapm.csv" --out "$TMP/gm_$real.csv" --real $real -q --metrics "$TMP/gm_$real.json"
    grep -q '"gaps": {"count": 1, "missed_periods": 2}' "$TMP/gm_$real.json" && ok "gap_json_$real: JSON" \
        || bad "gap_json_$real: $(grep gaps "$TMP/gm_$real.json")"
done
sed 's/^0\.06,/0.04,/; s/^0\.07,/0.05,/' "$TMP/gapm.csv" >"$TMP/nogap.csv"
run nogap 0 --in "$TMP/nogap.csv" --out "$TMP/ng.csv" -q
sd_gap=$(grep -v '^#' "$TMP/gm.csv" | awk -F, 'NR == 6 {print $6}')
sd_nogap=$(grep -v '^#' "$TMP/ng.csv" | awk -F, 'NR == 6 {print $6}')
awk -v a="$sd_gap" -v b="$sd_nogap" 'BEGIN {exit !(a > b)}' && ok "gap_measured: sd grew over the gap ($sd_gap > $sd_nogap)" \
    || bad "gap_measured: sd after the gap $sd_gap, without it $sd_nogap"
sed '/^0\.06,/d; s/^0\.07,/0.04,/' "$TMP/gapm.csv" >"$TMP/jitter.csv"
run jitter 0 --in "$TMP/jitter.csv" --out "$TMP/j.csv"
[ ! -s "$TMP/err" ] && ok "jitter: accepted without a word" || bad "jitter: $(cat "$TMP/err")"
# dt within 1 %: accepted; 1.5 % off: an error naming both values
sed 's/^# dt = 0.01$/# dt = 0.0101/' "$TMP/jitter.csv" >"$TMP/dt1.csv"
run dt_within_1pct 0 --in "$TMP/dt1.csv" --out "$TMP/j.csv" -q
sed 's/^# dt = 0.01$/# dt = 0.01015/' "$TMP/jitter.csv" >"$TMP/dt15.csv"
input_error dt_off_1_5pct "$TMP/dt15.csv" "^mu_replay: .*dt15\.csv:1: dt = 0.01015 s, but the log's time stamps have a median period of 0.01 s"
sed 's/^0\.5,/3.5,/; s/^0\.51,/3.51,/' "$TMP/gap.csv" >"$TMP/gap3.csv"
# q31: a 3.5 s gap does not fit the period's Q30 (< 2 s): counted as input saturation; the
# saturated period (2 s less 1 LSB) is still beyond obs_dt_max, so the observer restarts and
# the sample is taken as in float and double; the friction estimator counts the 2 s:
# round(200) - 1 = 199 missed periods in q31, round(348) - 1 = 347 in float (docs:
# rfe/pipeline_q31.h)
run gap_q31 0 --in "$TMP/gap3.csv" --out "$TMP/g3.csv" --real q31 --quiet --metrics "$TMP/g3.json"
grep -q '^# saturation_input_values = 1$' "$TMP/g3.csv" && ok "gap_q31: the period's saturation counted" \
    || bad "gap_q31: $(grep saturation_input_values "$TMP/g3.csv")"
grep -Eq '^3\.5,.*,0,0,0,0,3,' "$TMP/g3.csv" && ok "gap_q31: the sample after the gap taken (3, held)" \
    || bad "gap_q31: $(grep '^3.5,' "$TMP/g3.csv")"
grep -q '"gaps": {"count": 1, "missed_periods": 199, "observer_restarts": 1}' "$TMP/g3.json" \
    && ok "gap_q31: 199 missed periods, one restart" || bad "gap_q31: $(grep gaps "$TMP/g3.json")"
run gap_float_long 0 --in "$TMP/gap3.csv" --out "$TMP/g3f.csv" --quiet --metrics "$TMP/g3f.json"
grep -q '"gaps": {"count": 1, "missed_periods": 347, "observer_restarts": 1}' "$TMP/g3f.json" \
    && ok "gap_float_long: 347 missed periods, one restart" || bad "gap_float_long: $(grep gaps "$TMP/g3f.json")"
# REQ-OBS-023: a period shorter than half of dt behind the observer: that sample refused
# (18), a note counting such periods; the next one (its period since the last accepted) taken
sed 's/^0\.51,/0.504,/' "$TMP/gap.csv" >"$TMP/short.csv"
printf '0.514,0,0,0,0,61.5,61.5,61.5,61.5\n' >>"$TMP/short.csv"
run short_period 0 --in "$TMP/short.csv" --out "$TMP/s.csv"
grep -q "^mu_replay: note: 1 period(s) shorter than half of dt = 0.01 s: behind the observer such a sample is refused" "$TMP/err" \
    && ok "short_period: note" || bad "short_period: $(cat "$TMP/err")"
grep -Eq '^0\.504,.*,18,' "$TMP/s.csv" && ! grep -Eq '^0\.514,.*,18,' "$TMP/s.csv" \
    && ok "short_period: that sample refused (18), the next taken" || bad "short_period: $(grep -E '^0\.5' "$TMP/s.csv")"
printf 'obs_driven = 2.5\n' >"$TMP/driven.par"
run obs_bad_driven 1 --in "$DATA/good_esc.csv" --out "$TMP/v.csv" --params "$TMP/driven.par"
one_line obs_bad_driven "^mu_replay: .*driven\.par:1: invalid parameter obs_driven = 2.5 \(rejected by rfe_velocity_params_validate"
printf 'obs_sd_r = 0.01\nobs_driven = 12\n' >"$TMP/obs.par"
run obs_keys 0 --in "$DATA/good_esc.csv" --out "$TMP/v.csv" --params "$TMP/obs.par"
grep -q '^# obs_sd_r = 0.01$' "$TMP/v.csv" && grep -q '^# obs_driven = 12$' "$TMP/v.csv" \
    && ok "obs_keys: applied and written" || bad "obs_keys: metadata"
run measured_no_obs_keys 0 --in "$DATA/good_small.csv" --out "$TMP/v.csv"
grep -q '^# obs_' "$TMP/v.csv" && bad "measured_no_obs_keys: obs_* written" || ok "measured_no_obs_keys: none written"

# ---- bad cells (REQ-CSV-007): by default an empty, nan/inf or out-of-range cell goes to the
#      estimator as NaN/Inf; the library rejects that row (17), the estimate is held, the
#      row is in the estimate log with its status, and the run counts the cells per cause.
for real in float double q31; do
    run "nan_kept_$real" 0 --in "$DATA/nan_value.csv" --out "$TMP/nk.csv" --metrics "$TMP/nk.json" --real $real
    # row 2 (t = 0.01): status 17, not valid, mu and sd those of row 1 (held)
    awk -F, '!/^#/ && $1 == "0" { r0 = $2 FS $3 FS $4 FS $5 FS $6 FS $7 FS $8 FS $9 }
             !/^#/ && $1 == "0.01" { r1 = $2 FS $3 FS $4 FS $5 FS $6 FS $7 FS $8 FS $9; tail = $10 FS $11 FS $12 FS $13 FS $14 }
             END { exit !(r0 != "" && r0 == r1 && tail == "0,0,0,0,17") }' "$TMP/nk.csv" \
        && ok "nan_kept_$real: row held, not valid, status 17" || bad "nan_kept_$real: $(grep -v '^#' "$TMP/nk.csv" | head -3 | tr '\n' ' ')"
    grep -q '^  status 17 non-finite input  *1$' "$TMP/out" && ok "nan_kept_$real: counted" || bad "nan_kept_$real: no status 17 count"
    grep -q '^bad cells (given to the estimator as NaN/Inf, the row rejected): empty 0, nan/inf 1, out of range 0; in 1 row(s), the first at line 3 column 7' "$TMP/out" \
        && ok "nan_kept_$real: count per cause" || bad "nan_kept_$real: summary $(grep '^bad' "$TMP/out")"
    grep -q '"bad_cells": {"empty": 0, "nonfinite": 1, "range": 0, "rows": 1},' "$TMP/nk.json" \
        && ok "nan_kept_$real: JSON" || bad "nan_kept_$real: JSON"
done
grep -q '^mu_replay: note: .*nan_value\.csv: bad cells' "$TMP/err" && ok "nan_kept: note on stderr" || bad "nan_kept: no note: $(cat "$TMP/err")"
# an empty cell and one beyond a double, with the observer (float and q31)
sed 's/^0\.01,0,19\.98,0,0,0,nan,0,59\.9,/0.01,0,19.98,0,,0,1e999,0,59.9,/' "$DATA/nan_value.csv" >"$TMP/cells.csv"
for real in float q31; do
    run "cells_observer_$real" 0 --in "$TMP/cells.csv" --out "$TMP/co.csv" --velocity observer --real $real
    grep -q 'empty 1, nan/inf 0, out of range 1; in 1 row(s), the first at line 3 column 5' "$TMP/out" \
        && ok "cells_observer_$real: both causes" || bad "cells_observer_$real: $(grep '^bad' "$TMP/out")"
    grep -Eq '^0\.01,([^,]*,){8}0,0,0,0,17,' "$TMP/co.csv" && ok "cells_observer_$real: row rejected (17)" \
        || bad "cells_observer_$real: $(grep '^0.01,' "$TMP/co.csv")"
done
run cells_quiet 0 --in "$TMP/cells.csv" --out "$TMP/co.csv" -q
[ ! -s "$TMP/out" ] && [ ! -s "$TMP/err" ] && ok "cells_quiet: nothing printed" || bad "cells_quiet: printed"
# the bad cells of the columns a run does not use (vx, vy, yaw_acc behind the observer)
# reject no row: they are counted apart, as ignored, so the count matches the rejected rows
printf '# m = 1830\n# dt = 0.01\nt,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,20,0,0,0,-2,0,60,60,60,60\n0.01,0,nan,0,0,0,0,0,59.9,59.9,59.9,59.9\n0.02,0,19.98,,0,0,nan,0,59.9,59.9,59.9,59.9\n0.03,0,19.98,0,0,0,0,0,59.9,59.9,59.9,59.9\n0.04,0,19.98,0,0,inf,0,0,59.9,59.9,59.9,59.9\n0.05,0,19.98,0,0,0,0,,59.9,59.9,59.9,59.9\n' >"$TMP/unused.csv"
for real in float q31; do
    run "cells_unused_$real" 0 --in "$TMP/unused.csv" --out "$TMP/cu.csv" --velocity observer --real $real --metrics "$TMP/cu.json"
    grep -q '^bad cells (given to the estimator as NaN/Inf, the row rejected): empty 1, nan/inf 1, out of range 0; in 2 row(s), the first at line 6 column 7; ignored: 3 in the columns this run does not use (vx, vy, yaw_acc), the first at line 5 column 3 (--strict stops there)$' "$TMP/out" \
        && ok "cells_unused_$real: used and ignored apart" || bad "cells_unused_$real: $(grep '^bad' "$TMP/out")"
    grep -q '^  status 17 non-finite input  *2$' "$TMP/out" && ok "cells_unused_$real: 2 rows rejected, as counted" \
        || bad "cells_unused_$real: $(grep 'status 17' "$TMP/out")"
    [ "$(grep -v '^#' "$TMP/cu.csv" | awk -F, '$14 == 17' | wc -l)" -eq 2 ] && ok "cells_unused_$real: 2 rows with status 17" \
        || bad "cells_unused_$real: rows with 17: $(grep -v '^#' "$TMP/cu.csv" | awk -F, '$14 == 17 {print $1}' | tr '\n' ' ')"
    grep -q '"bad_cells": {"empty": 1, "nonfinite": 1, "range": 0, "rows": 2},' "$TMP/cu.json" \
        && grep -q '"bad_cells_ignored": {"cells": 3, "columns": "vx, vy, yaw_acc"},' "$TMP/cu.json" \
        && ok "cells_unused_$real: JSON" || bad "cells_unused_$real: JSON $(grep bad_cells "$TMP/cu.json" | tr '\n' ' ')"
done
# a used and an ignored bad cell on one line: --strict stops at the one further left (vx,
# column 3, ignored; delta, column 2, used)
printf "$VEH"'# dt = 0.01\nt,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,20,0,0,0,-2,0,60,60,60,60\n0.01,0,nan,0,0,0,nan,0,59.9,59.9,59.9,59.9\n0.02,0,19.98,0,0,0,0,0,59.9,59.9,59.9,59.9\n' >"$TMP/same_line.csv"
run cells_same_line_ignored_first 0 --in "$TMP/same_line.csv" --out "$TMP/cu.csv" --velocity observer
grep -q 'the first at line 12 column 7; ignored: 1 in the columns this run does not use (vx, vy, yaw_acc), the first at line 12 column 3 (--strict stops there)$' "$TMP/out" \
    && ok "cells_same_line_ignored_first: strict at column 3" || bad "cells_same_line_ignored_first: $(grep '^bad' "$TMP/out")"
sed 's/^0\.01,0,nan,0,0,0,nan,/0.01,nan,nan,0,0,0,0,/' "$TMP/same_line.csv" >"$TMP/same_line2.csv"
run cells_same_line_used_first 0 --in "$TMP/same_line2.csv" --out "$TMP/cu.csv" --velocity observer
grep -q 'the first at line 12 column 2 (--strict stops there); ignored: 1 in the columns this run does not use (vx, vy, yaw_acc), the first at line 12 column 3$' "$TMP/out" \
    && ok "cells_same_line_used_first: strict at column 2" || bad "cells_same_line_used_first: $(grep '^bad' "$TMP/out")"
# measured (auto): all of them used, none ignored
run cells_used_measured 0 --in "$TMP/unused.csv" --out "$TMP/cu.csv" --metrics "$TMP/cu.json"
grep -q 'empty 2, nan/inf 3, out of range 0; in 4 row(s), the first at line 5 column 3 (--strict stops there)$' "$TMP/out" \
    && grep -q '"bad_cells_ignored": {"cells": 0, "columns": null},' "$TMP/cu.json" \
    && ok "cells_used_measured: every cell counted" || bad "cells_used_measured: $(grep '^bad' "$TMP/out")"
# only ignored cells: said so, nothing rejected
sed '/^0\.02,/d; /^0\.05,/d' "$TMP/unused.csv" >"$TMP/unused2.csv"
run cells_only_unused 0 --in "$TMP/unused2.csv" --out "$TMP/cu.csv" --velocity observer
grep -q '^bad cells: none in the columns this run uses; ignored: 2 in the columns this run does not use (vx, vy, yaw_acc), the first at line 5 column 3 (--strict stops there)$' "$TMP/out" \
    && ! grep -q 'status 17' "$TMP/out" && ok "cells_only_unused: said, none rejected" || bad "cells_only_unused: $(cat "$TMP/out")"
grep -q '^mu_replay: note: .*unused2\.csv: bad cells: none in the columns this run uses; ignored: 2' "$TMP/err" \
    && ok "cells_only_unused: note on stderr" || bad "cells_only_unused: $(cat "$TMP/err")"

# ---- the README's status table and the parameter tables of DATA.md, ESTIMATOR.md, MONITOR.md
#      and OBSERVER.md agree with the code (REQ-DOC-001): the statuses of rfe/common.h, the
#      presets as mu_replay records them, every key in its table
if python3 "$(dirname "$0")/../../scripts/checks/check_doc_tables.py" "$BIN" >"$TMP/doc.txt" 2>&1; then
    ok "$(tail -n 1 "$TMP/doc.txt")"
else
    bad "doc tables: $(tr '\n' ' ' <"$TMP/doc.txt" | head -c 600)"
fi

# ---- several missing columns are named in one line (REQ-CLI-001)
printf 't,delta,yaw_rate,omega_fl,omega_fr,omega_rl\n0,0,0,61.5,61.5,61.5\n' >"$TMP/cols.csv"
input_error missing_columns "$TMP/cols.csv" "^mu_replay: .*cols\.csv:1: missing columns 'ax', 'ay', 'omega_rr'$"
printf '# column_ax = AccX\nt,delta,yaw_rate,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,0,0,61.5,61.5,61.5,61.5\n' >"$TMP/col1.csv"
input_error missing_alias "$TMP/col1.csv" "^mu_replay: .*col1\.csv:2: missing column 'ax' \(named 'AccX' by its column_ax metadata\)$"
# every missing column of every rule in that one line, in DATA.md's order: the steering
# angle (delta or swa), a truth group given in part, the velocities a measuring run needs
# drop_cols FILE COL...: a one-row truth log of every input column but COL...
drop_cols() {
    local f=$1
    shift
    printf '%s\n' 't,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr,mu_fl,mu_fr,mu_rl,mu_rr' \
        '0,0,20,0,0,0,0,0,61.5,61.5,61.5,61.5,0.8,0.8,0.8,0.8' |
    awk -v drop=" $* " 'BEGIN { FS = OFS = "," }
        NR == 1 { for (i = 1; i <= NF; i++) keep[i] = index(drop, " " $i " ") == 0 }
        { s = ""; for (i = 1; i <= NF; i++) if (keep[i]) s = s (s == "" ? "" : ",") $i; print s }' >"$f"
}
steer="'delta' \(the road-wheel angle\) or 'swa' \(the steering-wheel angle, with obs_steer_ratio\)"
truth="\(truth: give all of mu_fl, mu_fr, mu_rl, mu_rr or none\)"
drop_cols "$TMP/m1.csv" t delta omega_rr mu_fr
input_error missing_all_rules "$TMP/m1.csv" "^mu_replay: .*m1\.csv:1: missing columns 't', $steer, 'omega_rr', 'mu_fr' $truth$"
drop_cols "$TMP/m2.csv" delta ax
input_error missing_steer_and_input "$TMP/m2.csv" "^mu_replay: .*m2\.csv:1: missing columns $steer, 'ax'$"
drop_cols "$TMP/m3.csv" mu_fr ax mu_rr
input_error missing_truth_and_input "$TMP/m3.csv" "^mu_replay: .*m3\.csv:1: missing columns 'ax', 'mu_fr', 'mu_rr' $truth$"
drop_cols "$TMP/m4.csv" mu_fr mu_rr
input_error missing_truth_only "$TMP/m4.csv" "^mu_replay: .*m4\.csv:1: truth columns 'mu_fr', 'mu_rr' missing \(give all of mu_fl, mu_fr, mu_rl, mu_rr or none\)$"
drop_cols "$TMP/m5.csv" yaw_acc ax
run missing_velocity_measured 1 --in "$TMP/m5.csv" --out "$TMP/est.csv" --velocity measured
one_line missing_velocity_measured "^mu_replay: .*m5\.csv:1: missing columns 'yaw_acc' \(velocity: measured velocities need all of vx, vy, yaw_acc\), 'ax'$"
drop_cols "$TMP/m6.csv" vx vy yaw_acc ax mu_fl mu_fr mu_rl mu_rr
run missing_velocity_none 1 --in "$TMP/m6.csv" --out "$TMP/est.csv" --velocity measured
one_line missing_velocity_none "^mu_replay: .*m6\.csv:1: missing columns 'vx', 'vy', 'yaw_acc' \(velocity: measured velocities need all of vx, vy, yaw_acc\), 'ax'$"
run missing_velocity_auto 1 --in "$TMP/m6.csv" --out "$TMP/est.csv"
one_line missing_velocity_auto "^mu_replay: .*m6\.csv:1: missing column 'ax'$"

# ---- a log without vehicle parameters (REQ-CLI-006): a warning naming the preset's car,
#      or with --require-params an input error; the estimate log records the values used
printf 't,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,20,0,0,0,0,0,61.5,61.5,61.5,61.5\n' >"$TMP/noveh.csv"
run no_vehicle 0 --in "$TMP/noveh.csv" --out "$TMP/nv.csv"
one_line no_vehicle "^mu_replay: warning: .*noveh\.csv: no vehicle parameters in the metadata and no --params: the default preset's car is used: m = 1830 kg, Lf = 1\.4 m, .* hg = 0\.54 m \(--require-params makes this an error\)$"
grep -q '^# m = 1830$' "$TMP/nv.csv" && ok "no_vehicle: m recorded" || bad "no_vehicle: m not in the metadata"
run no_vehicle_quiet 0 --in "$TMP/noveh.csv" --out "$TMP/nv.csv" -q
[ ! -s "$TMP/err" ] && ok "no_vehicle_quiet: no warning" || bad "no_vehicle_quiet: $(cat "$TMP/err")"
run require_params 1 --in "$TMP/noveh.csv" --out "$TMP/rp.csv" --require-params
one_line require_params "^mu_replay: .*noveh\.csv: no vehicle parameters \(m, Lf, Lr, Bf, Br, R, J, hg\) in the log's metadata and no --params file \(--require-params\)$"
[ ! -e "$TMP/rp.csv" ] && ok "require_params: nothing written" || bad "require_params: estimate log written"
# every vehicle key counts on its own: a log with m alone runs on the preset's other values,
# named in the warning (m not among them); --require-params names the keys missing
printf 'm = 1500\n' >"$TMP/m.par"
run require_params_partial_file 1 --in "$TMP/noveh.csv" --out "$TMP/rp.csv" --require-params --params "$TMP/m.par"
one_line require_params_partial_file "^mu_replay: .*noveh\.csv: vehicle parameters Lf, Lr, Bf, Br, R, J, hg in neither the log's metadata nor a --params file \(--require-params\)$"
[ ! -e "$TMP/rp.csv" ] && ok "require_params_partial_file: nothing written" || bad "require_params_partial_file: estimate log written"
printf 'm = 1500\nLf = 1.2\nLr = 1.5\nBf = 1.55\nBr = 1.55\nR = 0.31\nJ = 2500\nhg = 0.5\n' >"$TMP/car.par"
run require_params_file 0 --in "$TMP/noveh.csv" --out "$TMP/rp.csv" --require-params --params "$TMP/car.par"
[ ! -s "$TMP/err" ] && grep -q '^# m = 1500$' "$TMP/rp.csv" && ok "require_params_file: --params satisfies it" || bad "require_params_file: $(cat "$TMP/err")"
printf '# m = 1700\n' | cat - "$TMP/noveh.csv" >"$TMP/veh.csv"
run partial_vehicle_meta 0 --in "$TMP/veh.csv" --out "$TMP/rp.csv"
one_line partial_vehicle_meta "^mu_replay: warning: .*veh\.csv: vehicle parameters in neither the metadata nor --params: using the default preset's Lf = 1\.4 m, Lr = 1\.65 m, Bf = 1\.6 m, Br = 1\.6 m, R = 0\.325 m, J = 3234 kg m\^2, hg = 0\.54 m \(--require-params makes this an error\)$"
grep -q '^# m = 1700$' "$TMP/rp.csv" && ok "partial_vehicle_meta: m from the metadata" || bad "partial_vehicle_meta: m"
run require_params_partial_meta 1 --in "$TMP/veh.csv" --out "$TMP/rp.csv" --require-params
one_line require_params_partial_meta "^mu_replay: .*veh\.csv: vehicle parameters Lf, Lr, Bf, Br, R, J, hg in neither"
# metadata and --params together: every key from one of them satisfies it
grep -v '^m = ' "$TMP/car.par" | sed '/^hg = /d' >"$TMP/car7.par"
run require_params_split 1 --in "$TMP/veh.csv" --out "$TMP/rp.csv" --require-params --params "$TMP/car7.par"
one_line require_params_split "^mu_replay: .*veh\.csv: vehicle parameter hg in neither the log's metadata nor a --params file \(--require-params\)$"
printf 'hg = 0.5\n' >>"$TMP/car7.par"
run require_params_meta 0 --in "$TMP/veh.csv" --out "$TMP/rp.csv" --require-params --params "$TMP/car7.par"
[ ! -s "$TMP/err" ] && grep -q '^# m = 1700$' "$TMP/rp.csv" && ok "require_params_meta: metadata and --params satisfy it, no warning" || bad "require_params_meta: $(cat "$TMP/err")"

# ---- --real q31: the fixed-point estimator (docs/FIXED_POINT.md "Estimator")
run good_q31 0 --in "$DATA/good_small.csv" --out "$TMP/q.csv" --metrics "$TMP/q.json" --real q31
grep -q '^# real = q31$' "$TMP/q.csv" && ok "good_q31: real metadata" || bad "good_q31: real metadata"
[ "$(grep -vc '^#' "$TMP/q.csv")" -eq 4 ] && ok "good_q31: header + 3 rows" || bad "good_q31: row count"
for key in saturation_estimator_total saturation_estimator_steps saturation_estimator_max_per_step \
           saturation_input_values saturation_input_rows; do
    grep -q "^# $key = 0$" "$TMP/q.csv" && ok "good_q31: metadata $key = 0" || bad "good_q31: metadata $key"
done
grep -q '"real": "q31",' "$TMP/q.json" && ok "good_q31: real in JSON" || bad "good_q31: real in JSON"
grep -q '"saturation": {"estimator_total": 0, "estimator_steps": 0, "estimator_max_per_step": 0, "input_values": 0, "input_rows": 0},' "$TMP/q.json" \
    && ok "good_q31: saturation in JSON" || bad "good_q31: saturation in JSON"
grep -q '^saturation (q31): estimator 0 events in 0 steps' "$TMP/out" && ok "good_q31: saturation summary" || bad "good_q31: saturation summary"
grep -q '^steps: 3$' "$TMP/out" && ok "good_q31: step count" || bad "good_q31: step count"
grep -q '^# mu0 = 0.6$' "$TMP/q.csv" && ok "good_q31: metadata parameter used" || bad "good_q31: mu0 from metadata"
# mu0 = 0.6 in Q29 and the prior's sd (the Q30 Cholesky factor of 0.1^2 I + 0.3^2 11^T), written
# so that they read back as the same doubles: more digits than the float format's 9.
grep -Eq '^0,0\.5999999996[0-9]*,.*,0\.316[0-9]{10,},' "$TMP/q.csv" && ok "good_q31: exact Q values" || bad "good_q31: first row $(grep -m1 '^0,' "$TMP/q.csv")"
grep -q '^saturation' <("$BIN" --in "$DATA/good_small.csv" --out "$TMP/q2.csv" --real double) \
    && bad "double: saturation summary printed" || ok "double: no saturation summary"
grep -q '^# saturation_' "$TMP/q2.csv" && bad "double: saturation metadata" || ok "double: no saturation metadata"
run q31_again 0 --in "$DATA/good_small.csv" --out "$TMP/q3.csv" --metrics "$TMP/q3.json" --real q31 -q
cmp -s "$TMP/q.csv" "$TMP/q3.csv" && ok "q31_again: byte-identical estimate log" || bad "q31_again: logs differ"
run q31_paper_ckf 0 --in "$DATA/good_small.csv" --out "$TMP/qc.csv" --preset paper --filter ckf --real q31 -q
grep -q '^# filter = ckf$' "$TMP/qc.csv" && grep -Eq '^0,[0-9.]*,.*,1,1,1,1,[01]$' "$TMP/qc.csv" \
    && ok "q31_paper_ckf: CKF, paper rule (valid when updated)" || bad "q31_paper_ckf: $(grep -m1 '^0,' "$TMP/qc.csv")"
# A parameter outside its Q format (m in Q16: < 32768 kg): named, one line, nothing written.
printf 'm = 40000\n' >"$TMP/heavy.par"
run q31_param_range 1 --in "$DATA/good_small.csv" --out "$TMP/qh.csv" --params "$TMP/heavy.par" --real q31
one_line q31_param_range "^mu_replay: .*heavy\.par:1: parameter m = 40000 does not fit the fixed-point formats"
[ ! -e "$TMP/qh.csv" ] && ok "q31_param_range: nothing written" || bad "q31_param_range: estimate log written"
run heavy_double 0 --in "$DATA/good_small.csv" --out "$TMP/qh.csv" --params "$TMP/heavy.par" --real double -q
# A prior that does not fit (sd0^2 + sd0_common^2 >= 4: the Q30 factor): init refused.
printf 'sd0 = 1.9\nsd0_common = 1.9\n' >"$TMP/wide.par"
run q31_prior_range 1 --in "$DATA/good_small.csv" --out "$TMP/qw.csv" --params "$TMP/wide.par" --real q31
one_line q31_prior_range "^mu_replay: .*good_small\.csv: estimator init failed: input out of range \(q31 run"
# A sample beyond its Q format (vx = 300 m/s > 256): counted as input saturation, and the
# sample is rejected (status 18) like any sample beyond config.h's limits.
sed 's/^0\.2 , 0\.01 ,second, 0\.85,19\.975,/0.2 , 0.01 ,second, 0.85,300,/' "$DATA/good_small.csv" >"$TMP/fast.csv"
run q31_input_saturation 0 --in "$TMP/fast.csv" --out "$TMP/qf.csv" --metrics "$TMP/qf.json" --real q31
grep -q '^# saturation_input_values = 1$' "$TMP/qf.csv" && grep -q '^# saturation_input_rows = 1$' "$TMP/qf.csv" \
    && ok "q31_input_saturation: counted" || bad "q31_input_saturation: $(grep saturation_input "$TMP/qf.csv")"
grep -q '^0.01,.*,0,0,0,0,18$' "$TMP/qf.csv" && ok "q31_input_saturation: row rejected (18)" || bad "q31_input_saturation: row 2 $(grep '^0.01,' "$TMP/qf.csv")"
grep -q '"input_values": 1, "input_rows": 1}' "$TMP/qf.json" && ok "q31_input_saturation: JSON" || bad "q31_input_saturation: JSON"
grep -q 'input 1 values in 1 rows$' "$TMP/out" && ok "q31_input_saturation: summary" || bad "q31_input_saturation: summary"

# ---- --mass-grade: the mass and road-grade estimator on a log with drive_torque
# (docs/MASS_GRADE.md, DATA.md "Mass and grade logs")
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
MG="$ROOT/scenarios/mass_grade"
MGG="$ROOT/scenarios/golden/mass_grade"
run mg_bad_value 2 --in "$MG/car_grade_step.csv" --out "$TMP/mg.csv" --mass-grade ekf
grep -q "^mu_replay: --mass-grade must be ukf, aukf or off, not 'ekf'$" "$TMP/err" \
    && ok "mg_bad_value: named" || bad "mg_bad_value: $(head -1 "$TMP/err")"
[ ! -e "$TMP/mg.csv" ] && ok "mg_bad_value: nothing written" || bad "mg_bad_value: estimate log written"
run mg_bad_case 2 --in "$MG/car_grade_step.csv" --out "$TMP/mg.csv" --mass-grade=UKF
run mg_no_value 2 --in "$MG/car_grade_step.csv" --out "$TMP/mg.csv" --mass-grade
run mg_twice 2 --in "$MG/car_grade_step.csv" --out "$TMP/mg.csv" --mass-grade ukf --mass-grade off
grep -q -- '--mass-grade ukf|aukf|off' <("$BIN" --help) && grep -q 'RFE_MG_RECOMMENDED' <("$BIN" --help) \
    && ok "help: --mass-grade and its presets" || bad "help: no --mass-grade"

# golden_equal NAME GOLDEN ESTIMATE: each row of the reference's golden (its column k: the
# row of the log) against that row of the estimate log: mass_est, sd_mass, grade_est,
# sd_grade, mg_status and the grade walk's level (the golden's walk, the estimate log's
# grade_walk: the reference's level after that row, MASS_GRADE.md §4.7), on every golden row within the log's length (a prefix of a log gives
# a prefix of the estimates: the estimator is causal). Tolerance 0, derived from the digits written: the golden holds
# Python's repr and the estimate log of a double run the shortest text that reads back as
# the same double (csv_log.h RFE_NUMFMT_DOUBLE), so both read back (awk: strtod, correctly
# rounded) as exactly the doubles computed, and the C double module equals the reference
# bit for bit (docs/MASS_GRADE.md §9, test_mass_grade_golden_flt.c); the replay hands it
# the same inputs in the same order (the speed (omega_fl + omega_fr + omega_rl + omega_rr)
# / 4 * R in double, the period from the time stamps in double). Any difference, one ulp
# included, is a wiring error. Prints "compared/golden rows differing".
golden_equal() {
    local name=$1 golden=$2 est=$3 res
    res=$(awk -F, '
        FNR == 1 { file++ }
        /^#/ { next }
        file == 1 && !gh { for (i = 1; i <= NF; i++) g[$i] = i; gh = 1; next }
        file == 1 { want[$g["k"] + 0] = $0; n++; next }
        file == 2 && !eh { for (i = 1; i <= NF; i++) e[$i] = i; eh = 1; row = 0; next }
        file == 2 {
            if (row in want) {
                split(want[row], w, ",")
                if (w[g["mass"]] + 0 != $e["mass_est"] + 0 || w[g["sd_mass"]] + 0 != $e["sd_mass"] + 0 ||
                    w[g["grade"]] + 0 != $e["grade_est"] + 0 || w[g["sd_grade"]] + 0 != $e["sd_grade"] + 0 ||
                    w[g["status"]] + 0 != $e["mg_status"] + 0 || w[g["walk"]] + 0 != $e["grade_walk"] + 0) {
                    if (!diff) first = row
                    diff++
                }
                seen++
            }
            row++
        }
        END { for (k in want) m += (k + 0 < row); printf "%d/%d %d %s", seen, m, diff, first }' "$golden" "$est")
    set -- $res
    if [ "${1%/*}" = "${1#*/}" ] && [ "${1%/*}" -gt 0 ] && [ "$2" -eq 0 ]; then
        ok "$name: mass, grade, their sd, status and walk level equal the golden on all ${1%/*} rows"
    else
        bad "$name: rows compared/golden $1, differing $2 (the first at log row ${3:-?})"
    fi
}

# default (ukf: the library's recommended preset), no parameter file: the log's R and g
run mg_default 0 --in "$MG/car_grade_step.csv" --out "$TMP/mg_d.csv" --real double --metrics "$TMP/mg_d.json"
golden_equal mg_default "$MGG/car_grade_step.recommended.csv" "$TMP/mg_d.csv"
grep -q '^# mass_grade = ukf$' "$TMP/mg_d.csv" && grep -q '^# mg_adaptive = 0$' "$TMP/mg_d.csv" \
    && grep -q '^# mg_use_ax = 1$' "$TMP/mg_d.csv" && grep -q '^# mg_m_rot = 45.4$' "$TMP/mg_d.csv" \
    && ok "mg_default: configuration and keys in the metadata" || bad "mg_default: metadata"
grep -q ',mass_est,sd_mass,grade_est,sd_grade,mg_status,mass_used,grade_walk,mg_mismatch$' "$TMP/mg_d.csv" \
    && ok "mg_default: columns" || bad "mg_default: header $(grep -m1 '^t,' "$TMP/mg_d.csv")"
grep -q '^mass and grade (ukf, car preset, speed, torque and ax): at the end mass ' "$TMP/out" \
    && grep -Eq '^  mass error at the end [-+][0-9.]+ kg \([-+][0-9.]+ %\)$' "$TMP/out" \
    && grep -Eq '^  grade RMSE [0-9.]+ rad, max error [0-9.]+ rad, over 3251 samples from t = 0\.000 s$' "$TMP/out" \
    && ok "mg_default: summary" || bad "mg_default: summary $(grep -A4 '^mass and grade' "$TMP/out")"
grep -q '"mass_grade": {"config": "ukf", "vehicle": "car", "use_ax": 1, "end": {"mass": ' "$TMP/mg_d.json" \
    && grep -Eq '"accuracy": \{"from_t_s": 0, "n": 3251, "mass_err_end": -?[0-9.e-]+, "mass_err_end_rel": -?[0-9.e-]+, "mass_used_err_end_rel": -?[0-9.e-]+, "grade_rmse": [0-9.e-]+, "grade_max_abs_err": [0-9.e-]+\}' "$TMP/mg_d.json" \
    && ok "mg_default: JSON" || bad "mg_default: JSON $(grep -A1 mass_grade "$TMP/mg_d.json")"
# the JSON's end-of-log error is the estimate log's last row against the truth's
want=$(awk -F, '/^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next} {m = $c["mass_true"]} END {print m}' "$MG/car_grade_step.csv")
got=$(awk -F, '/^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next} {m = $c["mass_est"]} END {print m}' "$TMP/mg_d.csv")
awk -v w="$want" -v g="$got" -v j="$(grep -o '"mass_err_end": [^,]*' "$TMP/mg_d.json" | cut -d' ' -f2)" \
    'BEGIN { exit !((g - w) == j + 0) }' && ok "mg_default: mass_err_end = last mass_est - mass_true" \
    || bad "mg_default: mass_err_end $got - $want vs JSON"

# The float run (the CLI's default --real): the float module on the same float inputs as
# test_mass_grade_golden_flt.c (the speed computed in double from the doubles read with the
# float R, the period in double, each then rounded to float), so within that test's bounds,
# derived there: mass within 0.2 sd_mass + 0.1 kg, grade within 0.05 sd_grade + 1e-6 rad,
# their sd within 5e-3 relative (the recommended preset is the plain UKF), statuses exact. The
# log prints each float to 9 digits (%.9g), which reads back as the same float: no error added.
run mg_float 0 --in "$MG/car_grade_step.csv" --out "$TMP/mg_fl.csv" -q
res=$(awk -F, '
    FNR == 1 { file++ }
    /^#/ { next }
    file == 1 && !gh { for (i = 1; i <= NF; i++) g[$i] = i; gh = 1; next }
    file == 1 { want[$g["k"] + 0] = $0; n++; next }
    file == 2 && !eh { for (i = 1; i <= NF; i++) e[$i] = i; eh = 1; row = 0; next }
    function ab(x) { return x < 0 ? -x : x }
    file == 2 {
        if (row in want) {
            split(want[row], w, ",")
            m = w[g["mass"]]; sm = w[g["sd_mass"]]; th = w[g["grade"]]; st = w[g["sd_grade"]]
            if (ab($e["mass_est"] - m) > 0.2 * sm + 0.1 || ab($e["grade_est"] - th) > 0.05 * st + 1e-6 ||
                ab($e["sd_mass"] - sm) > 5e-3 * sm || ab($e["sd_grade"] - st) > 5e-3 * st ||
                w[g["status"]] + 0 != $e["mg_status"] + 0) { if (!bad) first = row; bad++ }
            seen++
        }
        row++
    }
    END { printf "%d %d %d %s", seen, n, bad, first }' "$MGG/car_grade_step.recommended.csv" "$TMP/mg_fl.csv")
set -- $res
[ "$1" -eq "$2" ] && [ "$3" -eq 0 ] && grep -q '^# real = float$' "$TMP/mg_fl.csv" \
    && ok "mg_float: within the float module's bounds on all $1 golden rows" \
    || bad "mg_float: $1/$2 rows compared, $3 outside (the first at log row ${4:-?})"

# grade_walk on the planted grade step (car_grade_step: grade_true leaves 0 at 42.26 s, a ramp
# to +6 %): the walk is tight (0) on every row before the ramp starts and loosens (1) within
# 2 s after it (issue 19's grade-step target, 0.5 deg 2 s after the step, is what the loose
# level is for; the reference's golden has it at row 2144, 0.62 s in, which mg_default's
# golden_equal checks exactly in double). The float and q31 twins: the same, and their first
# loose row within one sample of the double run's: the level is a threshold decision on the
# walk's mean square s, which the twins carry within ~3e-4 (float) and ~2e-3 (Q31) relative of
# double (MASS_GRADE.md §4.7), so a crossing may move by one sample, not more, where s rises
# as steeply as it does on a step (its relative rise per sample there is > 10 %).
MGW_N=2301   # (the first 2300 samples: the step at row 2113, its switch at 2144; q31 light mode too)
awk -v n="$MGW_N" '/^#/ || k++ < n' "$MG/car_grade_step.csv" >"$TMP/mgw.csv"
run mg_walk_q31 0 --in "$TMP/mgw.csv" --out "$TMP/mgw_q.csv" --real q31 -q
walk_switch() {  # LOG ESTIMATE -> "t_step loose_rows_before first_loose_row t_first_loose"
    awk -F, '
        FNR == 1 { file++ }
        /^#/ { next }
        !h[file] { for (i = 1; i <= NF; i++) c[file, $i] = i; h[file] = 1; row = 0; next }
        file == 1 { if (row == 0) g0 = $c[1, "grade_true"]
                    if (ts == "" && $c[1, "grade_true"] != g0) ts = $1; row++; next }
        file == 2 { if ($c[2, "grade_walk"] + 0 == 1) { if ($1 + 0 < ts + 0) before++
                                                       if (first == "") { first = row; tf = $1 } }
                    row++ }
        END { printf "%s %d %s %s", ts, before, (first == "" ? -1 : first), (tf == "" ? -1 : tf) }' "$1" "$2"
}
set -- $(walk_switch "$MG/car_grade_step.csv" "$TMP/mg_d.csv")
WD_FIRST=$3
awk -v ts="$1" -v b="$2" -v tf="$4" 'BEGIN { exit !(b == 0 && tf >= ts && tf <= ts + 2) }' \
    && ok "mg_walk_double: tight before the grade step ($1 s), loose from row $3 ($4 s)" \
    || bad "mg_walk_double: step $1 s, $2 loose rows before it, first loose row $3 ($4 s)"
for tw in "float $TMP/mg_fl.csv" "q31 $TMP/mgw_q.csv"; do
    set -- $tw
    real=$1
    set -- $(walk_switch "$MG/car_grade_step.csv" "$2")
    awk -v ts="$1" -v b="$2" -v r="$3" -v tf="$4" -v rd="$WD_FIRST" \
        'BEGIN { d = r - rd; exit !(b == 0 && tf >= ts && tf <= ts + 2 && d >= -1 && d <= 1) }' \
        && ok "mg_walk_$real: tight before the grade step, loose from row $3 (double: $WD_FIRST)" \
        || bad "mg_walk_$real: $2 loose rows before the step, first loose row $3 ($4 s; double: $WD_FIRST)"
done

# aukf: the seed's preset (adaptive, speed and torque, no rotating mass, adaptation every step)
run mg_aukf 0 --in "$MG/car_gear_shift.csv" --out "$TMP/mg_a.csv" --real double --mass-grade aukf -q
golden_equal mg_aukf "$MGG/car_gear_shift.seed.csv" "$TMP/mg_a.csv"
grep -q '^# mass_grade = aukf$' "$TMP/mg_a.csv" && grep -q '^# mg_use_ax = 0$' "$TMP/mg_a.csv" \
    && grep -q '^# mg_m_rot = 0$' "$TMP/mg_a.csv" && grep -q '^# mg_t_adapt = 0$' "$TMP/mg_a.csv" \
    && ok "mg_aukf: the seed's preset" || bad "mg_aukf: metadata"
# a parameter file with every key the golden ran with (its metadata): the AUKF with ax, brake pauses
sed -n '/^# scenario =/q;p' "$MGG/car_stop_and_go.aukf_ax.csv" | grep -E '^# (R|g|mg_[a-z0-9_]+) = ' \
    | sed 's/^# //' >"$TMP/aukf_ax.par"
# (the first 3000 samples: two brake stops, low speed, restarts, to keep the valgrind run short)
awk '/^#/ || n++ < 3001' "$MG/car_stop_and_go.csv" >"$TMP/stop3000.csv"
run mg_params 0 --in "$TMP/stop3000.csv" --out "$TMP/mg_p.csv" --real double --mass-grade aukf \
    --params "$TMP/aukf_ax.par" -q
golden_equal mg_params "$MGG/car_stop_and_go.aukf_ax.csv" "$TMP/mg_p.csv"
# the speed-only UKF: one key over the default, on the first 2000 samples (causal: a prefix
# of the log gives a prefix of the estimates); light mode (valgrind, ~45x slower; the full
# prefix runs natively and under ASan): the first 600 (12 s, the mass fed from ~10 s), which
# every check below on this file passes with as well
HILLY_N=2001
if [ -n "${RFE_TEST_LIGHT:-}" ] && [ "${RFE_TEST_LIGHT}" != 0 ]; then HILLY_N=601; fi
awk -v n="$HILLY_N" '/^#/ || k++ < n' "$MG/car_hilly_road.csv" >"$TMP/hilly.csv"
printf 'mg_use_ax = 0   # speed and torque only\nmg_q_theta_hi = 0   # the fixed walk, as the golden\n' >"$TMP/ukf.par"
run mg_ukf_speed 0 --in "$TMP/hilly.csv" --out "$TMP/mg_u.csv" --real double --params "$TMP/ukf.par" -q
golden_equal mg_ukf_speed "$MGG/car_hilly_road.ukf.csv" "$TMP/mg_u.csv"

# --mass-grade-vehicle truck: the mg_* keys start from the library's truck preset, so the
# truck drive (its first 1000 samples, 50 s) equals the reference's truck golden, which the
# car's keys do not (the truck log carries its vehicle keys R and m, no mg_* key); named in
# the metadata, the JSON and the summary; a bad value is a usage error
awk '/^#/ || n++ < 1001' "$MG/truck_graded_drive.csv" >"$TMP/truck.csv"
run mg_truck 0 --in "$TMP/truck.csv" --out "$TMP/mg_tr.csv" --real double --mass-grade-vehicle truck \
    --metrics "$TMP/mg_tr.json"
golden_equal mg_truck "$MGG/truck_graded_drive.recommended.csv" "$TMP/mg_tr.csv"
grep -q '^# mass_grade_vehicle = truck$' "$TMP/mg_tr.csv" && grep -q '^# mg_cd = 0.6$' "$TMP/mg_tr.csv" \
    && grep -qF '"mass_grade": {"config": "ukf", "vehicle": "truck", ' "$TMP/mg_tr.json" \
    && grep -q '^mass and grade (ukf, truck preset, ' "$TMP/out" \
    && ok "mg_truck: the truck preset in the metadata, the JSON and the summary" \
    || bad "mg_truck: $(grep 'mass_grade_vehicle\|mg_cd' "$TMP/mg_tr.csv")"
run mg_truck_as_car 0 --in "$TMP/truck.csv" --out "$TMP/mg_tc.csv" --real double -q
grep -q '^# mass_grade_vehicle = car$' "$TMP/mg_tc.csv" \
    && ! cmp -s <(grep -v '^#' "$TMP/mg_tr.csv") <(grep -v '^#' "$TMP/mg_tc.csv") \
    && ok "mg_truck_as_car: the car's keys (the default) give another estimate" \
    || bad "mg_truck_as_car: same estimate or no vehicle line"
run mg_bad_vehicle 2 --in "$TMP/truck.csv" --out "$TMP/mg_x.csv" --mass-grade-vehicle bus
grep -q "^mu_replay: --mass-grade-vehicle must be car or truck, not 'bus'$" "$TMP/err" \
    && [ ! -e "$TMP/mg_x.csv" ] && ok "mg_bad_vehicle: named, nothing written" \
    || bad "mg_bad_vehicle: $(head -1 "$TMP/err")"

# --real q31: the mass and grade estimator's fixed-point twin (rfe_mass_grade_*_q31), ukf and
# aukf, against the double run on the same log: the four columns within the twin's own bounds
# (test/estimators/mass_grade/test_mass_grade_q31.c, derived there and quoted in
# docs/FIXED_POINT.md "Mass and grade"): per step the fixed-point filter differs from the
# double one by at most eps = 1e-6 of the state's sd, which K steps can add up to K eps sd
# (the mass and the grade are random walks the filter need not contract); so mass and grade
# within 0.02 of the double's sd plus 4 LSB of their formats (Q14: 2.4e-4 kg; Q29: 7.5e-9
# rad), their sds within 2 % relative plus 4 LSB; in the AUKF, whose lambda_u has no bounded
# relative derivative where D nears q_s, the mass within 0.2 sd_mass and sd_mass within 50 %.
# Here the double run also takes the unrounded samples and parameters (that test hands the
# double twin the Q values back): the samples' rounding (v, ax 3e-8 m/s(^2), torque 6e-5 N m,
# dt 5e-10 s) is a perturbation of the same order as eps per step (3e-8 m/s against a speed
# innovation sd >= 0.05 m/s: 6e-7), so 2 eps over at most 2000 steps, 0.004 sd; the
# parameters keep >= 20 significant bits (FIXED_POINT.md's table), a model force within 1e-6
# relative, a mass bias of 1e-6 of the mass (2e-3 kg against 0.02 sd_mass >= 0.02 kg here).
# Statuses exactly: a pause decided differently needs a speed within 3e-8 m/s of mg_v_min or a
# pressure within 1.5e-8 MPa of mg_p_brake_on, none on this drive. Light mode (valgrind): the
# first 500 samples (10 s: the feed starts, sd_mass / mass falls below 2 %), else 2000.
MGQ_N=2000
if [ -n "${RFE_TEST_LIGHT:-}" ] && [ "${RFE_TEST_LIGHT}" != 0 ]; then MGQ_N=500; fi
awk -v n="$MGQ_N" '/^#/ || k++ <= n' "$MG/car_hilly_road.csv" >"$TMP/mgq.csv"
for cfg in ukf aukf; do
    run "mg_q31_$cfg" 0 --in "$TMP/mgq.csv" --out "$TMP/mgq_$cfg.csv" --real q31 --mass-grade "$cfg" \
        --metrics "$TMP/mgq_$cfg.json"
    grep -q "\"mass_grade\": {\"config\": \"$cfg\", " "$TMP/mgq_$cfg.json" \
        && grep -Eq '^  mass fed to the friction estimator at [1-9][0-9]* samples' "$TMP/out" \
        && ok "mg_q31_$cfg: JSON and summary, the mass fed" || bad "mg_q31_$cfg: $(grep -A3 '^mass and grade' "$TMP/out")"
    grep -q ',mass_est,sd_mass,grade_est,sd_grade,mg_status,mass_used,grade_walk,mg_mismatch$' "$TMP/mgq_$cfg.csv" \
        && grep -q '^# real = q31$' "$TMP/mgq_$cfg.csv" && grep -q "^# mass_grade = $cfg\$" "$TMP/mgq_$cfg.csv" \
        && ok "mg_q31_$cfg: the columns and metadata" || bad "mg_q31_$cfg: header $(grep -m1 '^t,' "$TMP/mgq_$cfg.csv")"
    run "mg_q31_${cfg}_double" 0 --in "$TMP/mgq.csv" --out "$TMP/mgd_$cfg.csv" --real double --mass-grade "$cfg" -q
    [ "$cfg" = ukf ] && tm=0.02 && ts=0.02 || { tm=0.2; ts=0.5; }
    res=$(awk -F, -v tm="$tm" -v ts="$ts" '
        FNR == 1 { file++ }
        /^#/ { next }
        !h[file] { for (i = 1; i <= NF; i++) c[file, $i] = i; h[file] = 1; row = 0; next }
        function ab(x) { return x < 0 ? -x : x }
        file == 1 { m[row] = $c[1, "mass_est"]; sm[row] = $c[1, "sd_mass"]; g[row] = $c[1, "grade_est"]
                    sg[row] = $c[1, "sd_grade"]; st[row] = $c[1, "mg_status"]; row++; next }
        file == 2 {
            lm = 4 * 2^-14; lg = 4 * 2^-29; dm = $c[2, "sd_mass"]; dg = $c[2, "sd_grade"]
            em = ab(m[row] - $c[2, "mass_est"]); eg = ab(g[row] - $c[2, "grade_est"])
            if (em > tm * dm + lm || eg > 0.02 * dg + lg || ab(sm[row] - dm) > ts * dm + lm ||
                ab(sg[row] - dg) > 0.02 * dg + lg || st[row] != $c[2, "mg_status"]) { if (!nbad) first = row; nbad++ }
            if (dm > 0 && em / dm > wm) wm = em / dm
            if (dg > 0 && eg / dg > wg) wg = eg / dg
            n++; row++
        }
        END { printf "%d %d %d %.2g %.2g", n, nbad, first, wm, wg }' "$TMP/mgq_$cfg.csv" "$TMP/mgd_$cfg.csv")
    set -- $res
    [ "$1" -eq "$MGQ_N" ] && [ "$2" -eq 0 ] \
        && ok "mg_q31_$cfg: within the twin's bounds of the double run on all $1 rows (worst: mass $4 sd, grade $5 sd)" \
        || bad "mg_q31_$cfg: $1 rows, $2 outside (the first at row $3)"
done
# q31 refusals before any row: a key beyond its Q format (Q14 holds 131072 kg) named with the
# converter; a set the float accepts outside the fixed-point domain (n + lambda = 0.75) with
# the domain's rule
printf 'mg_m_max = 2e5\n' >"$TMP/mg_q14.par"
run mg_q31_format 1 --in "$TMP/mgq.csv" --out "$TMP/mg_x.csv" --real q31 --params "$TMP/mg_q14.par"
one_line mg_q31_format "^mu_replay: .*mg_q14\.par:1: parameter mg_m_max = 200000 does not fit the fixed-point formats \(rfe_mass_grade_params_to_q31, q31 run"
printf 'g = 40\n' >"$TMP/mg_g40.par" # the friction estimator's Q24 holds it, the estimator's Q26 not
run mg_q31_format_g 1 --in "$TMP/mgq.csv" --out "$TMP/mg_x.csv" --real q31 --params "$TMP/mg_g40.par"
one_line mg_q31_format_g "^mu_replay: .*mg_g40\.par:1: parameter g = 40 does not fit the fixed-point formats \(rfe_params_to_q31 or rfe_mass_grade_params_to_q31, q31 run"
printf 'mg_ut_alpha = 0.5\n' >"$TMP/mg_alpha.par"
run mg_q31_domain_double 0 --in "$TMP/mgq.csv" --out "$TMP/mg_alpha_d.csv" --real double --params "$TMP/mg_alpha.par" -q
run mg_q31_domain 1 --in "$TMP/mgq.csv" --out "$TMP/mg_x.csv" --real q31 --params "$TMP/mg_alpha.par"
one_line mg_q31_domain "^mu_replay: .*mgq\.csv: estimator init failed: .*mg_ut_\* with 1 < n \+ lambda < 16 and w_c,0 >= 0 in fixed point"
# the flag, when given, sets mg_adaptive over a file, as --filter does
printf 'mg_adaptive = 1\n' >"$TMP/adaptive.par"
run mg_flag_beats_file 0 --in "$TMP/hilly.csv" --out "$TMP/mg_f.csv" --mass-grade ukf --params "$TMP/adaptive.par" -q
grep -q '^# mg_adaptive = 0$' "$TMP/mg_f.csv" && ok "mg_flag_beats_file: mg_adaptive 0" || bad "mg_flag_beats_file: $(grep mg_adaptive "$TMP/mg_f.csv")"
run mg_file_without_flag 0 --in "$TMP/hilly.csv" --out "$TMP/mg_f2.csv" --params "$TMP/adaptive.par" -q
grep -q '^# mass_grade = aukf$' "$TMP/mg_f2.csv" && ok "mg_file_without_flag: the file's mg_adaptive" || bad "mg_file_without_flag: $(grep mass_grade "$TMP/mg_f2.csv")"
# the log's metadata sets mg_* keys too (below --params)
{ echo '# mg_m0 = 2000'; cat "$TMP/hilly.csv"; } >"$TMP/hilly_m0.csv"
run mg_meta_key 0 --in "$TMP/hilly_m0.csv" --out "$TMP/mg_m.csv" --real double -q
grep -q '^# mg_m0 = 2000$' "$TMP/mg_m.csv" && grep -Eq '^0,.*,2000,500,0,0\.05,0,[0-9.]+,0,0$' "$TMP/mg_m.csv" \
    && ok "mg_meta_key: the start from mg_m0 = 2000" || bad "mg_meta_key: $(grep -m1 '^0,' "$TMP/mg_m.csv")"
# invalid keys: named with the function that refused them; a combination: its rule
printf 'mg_m0 = -5\n' >"$TMP/mg_bad.par"
run mg_invalid_key 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/mg_bad.par"
one_line mg_invalid_key "^mu_replay: .*mg_bad\.par:1: invalid parameter mg_m0 = -5 \(rejected by rfe_mass_grade_params_validate, float run\)$"
printf 'mg_use_ax = 0.5\n' >"$TMP/mg_half.par"
run mg_not_a_switch 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/mg_half.par"
one_line mg_not_a_switch "^mu_replay: .*mg_half\.par:1: invalid parameter mg_use_ax = 0\.5 "
printf 'mg_m0 = 5000\nmg_m_max = 4000\n' >"$TMP/mg_combo.par"
run mg_combination 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/mg_combo.par"
one_line mg_combination "^mu_replay: .*hilly\.csv: estimator init failed: .*mass and grade: mg_m_min < mg_m0 < mg_m_max"
printf 'mg_mass0 = 2000\n' >"$TMP/mg_typo.par"
run mg_unknown_key 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/mg_typo.par"
one_line mg_unknown_key "^mu_replay: .*mg_typo\.par:1:1: unknown parameter key 'mg_mass0'"
sed 's/^# driveline_torque_at = wheels$/# driveline_torque_at = engine/' "$TMP/hilly.csv" >"$TMP/engine.csv"
run mg_engine_torque 1 --in "$TMP/engine.csv" --out "$TMP/mg_x.csv"
one_line mg_engine_torque "^mu_replay: .*engine\.csv: driveline_torque_at = engine: the mass and grade estimator takes the torque at the wheels"
run mg_engine_torque_off 0 --in "$TMP/engine.csv" --out "$TMP/mg_eo.csv" --mass-grade off -q
[ ! -e "$TMP/mg_x.csv" ] && ok "mg invalid parameters: nothing written" || bad "mg invalid parameters: estimate log written"

# The mass into the friction estimator (mg_feed_sd_rel, MASS_GRADE.md §10), on the double run
# above: the keys in the metadata; mass_used is the log's m until the first update (mg_status 0)
# with sd_mass <= 0.02 mass_est once the excitation gate is open (mg_feed_excitation 1 m/s of
# |ax| >= mg_feed_ax_min 0.2 m/s^2, summed over the updates after the first sample: this log
# has no period beyond mg_dt_max, so its only start is the first sample; ax and the periods
# from the input log, row by row), then that sample's mass_est at each such update and the
# last one held in between (exact: the double run writes each value so it reads back bit for
# bit); the summary and the JSON count the samples fed and give the last mass used. The gate
# must hold at least one update that the sd rule alone would feed (this log's excitation
# reaches 1 m/s after its sd_mass reaches 2 %: a rule without the gate fails the row check).
# The slip hold (mg_feed_slip_max 0.05): an update whose wheels' speed (the input's mean
# omega times its R) departs from the previous row's observer vx_est by more than 0.05
# max(|vx_est|, mg_v_min = 3 m/s) is not fed and empties the sum (this log has a few: a rule
# without the hold fails the row check); the band (mg_feed_band 0.3): a due mass farther than
# 0.3 m from the log's m is refused and counted (none on this log).
# These checks run the default with the grade's two-level walk off (MASS_GRADE.md §4.7; on in
# the default since issue 19's walk was adopted): with it on, the observer's vx_est on this log
# never departs from the wheels' speed by the slip hold's margin, so the hold would go
# unexercised; the walk does not enter the feed rule, and the default run above (walk on) is
# compared with its golden row by row.
printf 'mg_q_theta_hi = 0   # the fixed grade walk\n' >"$TMP/walk_off.par"
run mg_feed_walk_off 0 --in "$MG/car_grade_step.csv" --out "$TMP/mg_f.csv" --real double \
    --metrics "$TMP/mg_f.json" --params "$TMP/walk_off.par" -q
grep -q '^# mg_feed_sd_rel = 0\.02$' "$TMP/mg_f.csv" && grep -q '^# mg_feed_excitation = 1$' "$TMP/mg_f.csv" \
    && grep -q '^# mg_feed_ax_min = 0\.2$' "$TMP/mg_f.csv" && grep -q '^# mg_feed_slip_max = 0\.05$' "$TMP/mg_f.csv" \
    && grep -q '^# mg_feed_band = 0\.3$' "$TMP/mg_f.csv" && ok "mg_feed: the keys in the metadata" \
    || bad "mg_feed: metadata $(grep mg_feed "$TMP/mg_f.csv")"
res=$(awk -F, '
    function ab(x) { return x < 0 ? -x : x }
    FNR == 1 { file++ }
    file == 1 && /^# R = / { R = $0; sub(/^# R = /, "", R); R += 0; next }
    file == 2 && /^# m = / { used = $0; sub(/^# m = /, "", used); used += 0; m = used; next }
    /^#/ { next }
    !h[file] { for (i = 1; i <= NF; i++) c[file, $i] = i; h[file] = 1; row = 0; next }
    file == 1 { ax[row] = $c[1, "ax"] + 0; t[row] = $c[1, "t"] + 0
                vw[row] = ($c[1, "omega_fl"] + $c[1, "omega_fr"] + $c[1, "omega_rl"] + $c[1, "omega_rr"]) / 4 * R; row++; next }
    {
        upd = ($c[2, "mg_status"] + 0 == 0)
        slips = (row > 0 && upd && ab(vw[row] - vxp) > 0.05 * (ab(vxp) > 3 ? ab(vxp) : 3))
        if (slips) { ex = 0; slip++ }
        else if (row > 0 && upd && ab(ax[row]) >= 0.2) ex += ab(ax[row]) * (t[row] - t[row - 1])
        due = (upd && !slips && $c[2, "sd_mass"] + 0 <= 0.02 * $c[2, "mass_est"])
        inband = (ab($c[2, "mass_est"] - m) <= 0.3 * m)
        if (due && ex >= 1 && inband) { used = $c[2, "mass_est"] + 0; fed++ }
        if (due && ex >= 1 && !inband) refused++
        if (due && ex < 1) held++
        if ($c[2, "mass_used"] + 0 != used) { if (!bad) first = row; bad++ }
        last = $c[2, "mass_used"]; vxp = $c[2, "vx_est"] + 0; row++
    }
    END { printf "%d %d %s %d %d %d %d", fed, bad, last, held, first, slip, refused }' "$MG/car_grade_step.csv" "$TMP/mg_f.csv")
set -- $res
[ "$1" -gt 0 ] && [ "$2" -eq 0 ] && [ "$4" -gt 0 ] && [ "$6" -gt 0 ] \
    && ok "mg_feed: mass_used follows the rule, the gate, the slip hold and the band on every row ($1 fed, $4 held by the gate, $6 by the slip, $7 refused by the band)" \
    || bad "mg_feed: $1 fed, $2 rows differ (the first at row $5), $4 held by the gate, $6 by the slip, $7 refused by the band"
grep -qF "\"feed\": {\"sd_rel\": 0.02, \"excitation\": 1, \"ax_min\": 0.2, \"excitation_end\": " "$TMP/mg_f.json" \
    && grep -qF ", \"slip_max\": 0.05, \"band\": 0.3, \"n_slip_held\": $6, \"n_band_refused\": $7, \"n_mismatch_held\": 0, \"n_fed\": $1, \"mass_used_end\": $3}" "$TMP/mg_f.json" \
    && ok "mg_feed: JSON" || bad "mg_feed: JSON $(grep -o '"feed": [^}]*}' "$TMP/mg_f.json"), want $1 $3"
# §4.8 the model-mismatch flag holds the feed: the headwind's first 30 s (the flag sets at
# 14.1 s, MASS_GRADE_RESULTS.md "A model-mismatch monitor"); on every flagged row mass_used
# is the previous row's, the JSON counts the flagged rows an update would have fed, and
# mg_mm_e = 0 flags nothing and holds nothing
awk '/^#/ || n++ <= 1500' "$MG/car_headwind.csv" >"$TMP/hw.csv"
for real in float q31; do
    run mg_mismatch_$real 0 --in "$TMP/hw.csv" --out "$TMP/mg_mm.csv" --real $real --metrics "$TMP/mg_mm.json" -q
    res=$(awk -F, '/^#/ { next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
        { if ($c["mg_mismatch"] + 0 == 1) { n++; if (p != "" && $c["mass_used"] != p) bad++ } p = $c["mass_used"] }
        END { printf "%d %d", n, bad }' "$TMP/mg_mm.csv")
    set -- $res
    held=$(grep -o '"n_mismatch_held": [0-9]*' "$TMP/mg_mm.json" | grep -o '[0-9]*$')
    [ "$1" -gt 0 ] && [ "$2" -eq 0 ] && [ "${held:-0}" -gt 0 ] && [ "${held:-0}" -le "$1" ] \
        && ok "mg_mismatch_$real: $1 rows flagged, mass_used held on each, $held feeds held" \
        || bad "mg_mismatch_$real: $1 rows flagged, $2 with mass_used moved, ${held:-none} held"
done
printf 'mg_mm_e = 0\n' >"$TMP/mm_off.par"
run mg_mismatch_off 0 --in "$TMP/hw.csv" --out "$TMP/mg_mm0.csv" --params "$TMP/mm_off.par" --metrics "$TMP/mg_mm0.json" -q
n0=$(awk -F, '/^#/ { next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next } { n += $c["mg_mismatch"] } END { print n + 0 }' "$TMP/mg_mm0.csv")
[ "$n0" -eq 0 ] && grep -qF '"n_mismatch_held": 0,' "$TMP/mg_mm0.json" \
    && ok "mg_mismatch_off: mg_mm_e = 0 flags and holds nothing" || bad "mg_mismatch_off: $n0 rows flagged"
# every arithmetic opens the gate at the same row (the sum is of the log's double values; on
# this log the gate, not the sd rule, decides the first feed: 26 updates held above); the
# log's first 500 rows (10 s) hold it, so the runs below take those (cheap under memcheck)
awk '/^#/ || n++ <= 500' "$MG/car_grade_step.csv" >"$TMP/gs.csv"
first_fed() { awk -F, '/^#/ { next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
    { n++; if (n == 1) m0 = $c["mass_used"]; if ($c["mass_used"] != m0) { print n; exit } }' "$1"; }
run mg_feed_float 0 --in "$TMP/gs.csv" --out "$TMP/mg_gfl.csv" --real float -q
run mg_feed_q31 0 --in "$TMP/gs.csv" --out "$TMP/mg_gq.csv" --real q31 -q
fd=$(first_fed "$TMP/mg_d.csv"); ff=$(first_fed "$TMP/mg_gfl.csv"); fq=$(first_fed "$TMP/mg_gq.csv")
[ -n "$fd" ] && [ "$fd" = "$ff" ] && [ "$fd" = "$fq" ] \
    && ok "mg_feed_gate_reals: first fed at row $fd in double, float and q31" \
    || bad "mg_feed_gate_reals: first fed at row double ${fd:-never}, float ${ff:-never}, q31 ${fq:-never}"
# mg_feed_excitation = 0 and no checks: the sd rule alone (the feed before the gate)
printf 'mg_feed_excitation = 0\nmg_feed_slip_max = 0\nmg_feed_band = 0\n' >"$TMP/nogate.par"
run mg_feed_nogate 0 --in "$TMP/gs.csv" --out "$TMP/mg_ng.csv" --real double --params "$TMP/nogate.par" -q
res=$(awk -F, '
    /^# m = / { used = $0; sub(/^# m = /, "", used); used += 0; next }
    /^#/ { next }
    !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
    {
        if ($c["mg_status"] + 0 == 0 && $c["sd_mass"] + 0 <= 0.02 * $c["mass_est"]) { used = $c["mass_est"] + 0; fed++ }
        if ($c["mass_used"] + 0 != used) bad++
    }
    END { printf "%d %d", fed, bad }' "$TMP/mg_ng.csv")
set -- $res
[ "$1" -gt 0 ] && [ "$2" -eq 0 ] && grep -q '^# mg_feed_excitation = 0$' "$TMP/mg_ng.csv" \
    && ok "mg_feed_nogate: the sd rule alone on every row ($1 fed)" || bad "mg_feed_nogate: $1 fed, $2 rows differ"
# a gate no drive reaches: never fed
printf 'mg_feed_excitation = 1e6\n' >"$TMP/gate_far.par"
run mg_feed_gate_far 0 --in "$TMP/hilly.csv" --out "$TMP/mg_gf.csv" --real double --params "$TMP/gate_far.par"
grep -Eq '^  mass fed to the friction estimator at 0 samples \(mg_feed_sd_rel = 0\.02, mg_feed_excitation = 1e\+06 m/s of \|ax\| >= 0\.2 m/s\^2, [0-9.]+ m/s at the end\); its mass at the end 2000\.0 kg$' "$TMP/out" \
    && ok "mg_feed_gate_far: nothing fed" || bad "mg_feed_gate_far: summary $(grep 'mass fed' "$TMP/out")"
# bad gate values: an error naming the key, in every arithmetic (the parameter file itself
# refuses a value that is not finite)
printf 'mg_feed_excitation = -1\n' >"$TMP/gate_bad.par"
run mg_feed_excitation_bad 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/gate_bad.par"
one_line mg_feed_excitation_bad "^mu_replay: .*gate_bad\.par:1: invalid parameter mg_feed_excitation = -1 \(rejected by mu_replay: a finite excitation >= 0 m/s, float run\)$"
printf 'mg_feed_ax_min = -0.1\n' >"$TMP/axmin_bad.par"
run mg_feed_ax_min_bad 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/axmin_bad.par" --real q31
one_line mg_feed_ax_min_bad "^mu_replay: .*axmin_bad\.par:1: invalid parameter mg_feed_ax_min = -0\.1 \(rejected by mu_replay: a finite acceleration >= 0 m/s\^2, q31 run\)$"
printf 'mg_feed_slip_max = -0.05\n' >"$TMP/slip_bad.par"
run mg_feed_slip_max_bad 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/slip_bad.par"
one_line mg_feed_slip_max_bad "^mu_replay: .*slip_bad\.par:1: invalid parameter mg_feed_slip_max = -0\.05 \(rejected by mu_replay: a finite share >= 0, float run\)$"
printf 'mg_feed_band = -0.3\n' >"$TMP/band_bad.par"
run mg_feed_band_bad 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/band_bad.par" --real q31
one_line mg_feed_band_bad "^mu_replay: .*band_bad\.par:1: invalid parameter mg_feed_band = -0\.3 \(rejected by mu_replay: a finite share >= 0, q31 run\)$"
# 0: never fed, mass_used the log's m throughout
printf 'mg_feed_sd_rel = 0\n' >"$TMP/feed0.par"
run mg_feed_off 0 --in "$TMP/hilly.csv" --out "$TMP/mg_f0.csv" --real double --params "$TMP/feed0.par"
grep -Eq '^  mass fed to the friction estimator at 0 samples \(mg_feed_sd_rel = 0, mg_feed_excitation = 1 m/s of \|ax\| >= 0\.2 m/s\^2, [0-9.]+ m/s at the end\); its mass at the end 2000\.0 kg$' "$TMP/out" \
    && ok "mg_feed_off: summary" || bad "mg_feed_off: summary $(grep 'mass fed' "$TMP/out")"
m=$(sed -n 's/^# m = //p' "$TMP/hilly.csv" | head -1)
awk -F, -v m="$m" '/^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next} $c["mass_used"] + 0 != m + 0 {b++} END {exit b > 0}' "$TMP/mg_f0.csv" \
    && grep -q '^# mg_feed_sd_rel = 0$' "$TMP/mg_f0.csv" && ok "mg_feed_off: mass_used = m on every row" \
    || bad "mg_feed_off: mass_used moved"
# a negative value: an error naming the key
printf 'mg_feed_sd_rel = -0.5\n' >"$TMP/feed_bad.par"
run mg_feed_bad 1 --in "$TMP/hilly.csv" --out "$TMP/mg_x.csv" --params "$TMP/feed_bad.par"
one_line mg_feed_bad "^mu_replay: .*feed_bad\.par:1: invalid parameter mg_feed_sd_rel = -0\.5 \(rejected by mu_replay: a relative sd >= 0, float run\)$"
[ ! -e "$TMP/mg_x.csv" ] && ok "mg_feed_bad: nothing written" || bad "mg_feed_bad: estimate log written"

# off: the columns ignored, the run as on a log without them
run mg_off 0 --in "$TMP/hilly.csv" --out "$TMP/mg_o.csv" --mass-grade off --metrics "$TMP/mg_o.json" -q
grep -q 'mass_est' "$TMP/mg_o.csv" || grep -q '^# mass_grade\|^# mg_' "$TMP/mg_o.csv" \
    && bad "mg_off: mass and grade columns or keys written" || ok "mg_off: no mass and grade columns, keys"
grep -q '"mass_grade"' "$TMP/mg_o.json" && bad "mg_off: JSON has mass_grade" || ok "mg_off: no mass_grade in the JSON"
# the same log without its mass and grade columns: the estimate log equal to the off run's
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next }
    !h { for (i = 1; i <= NF; i++) if ($i !~ /^(drive_torque|brake|brake_pressure|gear|mass_true|grade_true)$/) keep[++n] = i; h = 1 }
    { line = $keep[1]; for (i = 2; i <= n; i++) line = line "," $keep[i]; print line }' "$TMP/hilly.csv" >"$TMP/plain.csv"
run mg_no_torque 0 --in "$TMP/plain.csv" --out "$TMP/mg_n.csv" -q
cmp -s <(grep -v '^# input = ' "$TMP/mg_o.csv") <(grep -v '^# input = ' "$TMP/mg_n.csv") \
    && ok "mg_no_torque: byte-identical to the off run" || bad "mg_no_torque: differs from the off run"
run mg_no_torque_flag 0 --in "$TMP/plain.csv" --out "$TMP/mg_n2.csv" --mass-grade aukf -q
cmp -s "$TMP/mg_n.csv" "$TMP/mg_n2.csv" && ok "mg_no_torque_flag: --mass-grade changes nothing without drive_torque" \
    || bad "mg_no_torque_flag: differs"
run esc_mg_flag 0 --in "$DATA/good_esc.csv" --out "$TMP/v_mg.csv" --mass-grade ukf -q
run esc_no_flag 0 --in "$DATA/good_esc.csv" --out "$TMP/v_nomg.csv" -q
cmp -s "$TMP/v_mg.csv" "$TMP/v_nomg.csv" && ok "esc_mg_flag: unchanged" || bad "esc_mg_flag: differs"

# The wiring: without a grade column the observer integrates ax with the estimated grade (its
# vx differs from the off run's, where it takes 0); with one (here all 0) it takes the column,
# so the observer's and the friction estimator's columns equal the off run's. Both runs without
# the mass feed (mg_feed_sd_rel = 0): a fed mass changes both estimators, tested above.
obs_cols() { grep -v '^#' "$1" | cut -d, -f1-21; }
run mg_on 0 --in "$TMP/hilly.csv" --out "$TMP/mg_on.csv" --params "$TMP/feed0.par" -q
obs_cols "$TMP/mg_on.csv" >"$TMP/on.cols"; obs_cols "$TMP/mg_o.csv" >"$TMP/off.cols"
cmp -s "$TMP/on.cols" "$TMP/off.cols" && bad "mg_on: the observer did not take the estimated grade" \
    || ok "mg_on: the observer takes the estimated grade"
awk -F, 'BEGIN { OFS = "," } /^#/ { print "# grade_known = yes"; print; next } !h { h = 1; print $0 ",grade"; next } { print $0 ",0" }' \
    "$TMP/hilly.csv" | awk '!(/^# grade_known = yes$/ && seen++)' >"$TMP/hilly_grade.csv"
run mg_grade_column 0 --in "$TMP/hilly_grade.csv" --out "$TMP/mg_g.csv" --params "$TMP/feed0.par" -q
obs_cols "$TMP/mg_g.csv" >"$TMP/grade.cols"
cmp -s "$TMP/grade.cols" "$TMP/off.cols" && ok "mg_grade_column: the measured grade, not the estimate" \
    || bad "mg_grade_column: the observer did not take the grade column"
cmp -s <(grep -v '^#' "$TMP/mg_g.csv" | cut -d, -f22-) <(grep -v '^#' "$TMP/mg_on.csv" | cut -d, -f22-) \
    && ok "mg_grade_column: the mass and grade estimate unchanged (one way)" || bad "mg_grade_column: estimate changed"
# Measured velocities (a test car's vx, vy, yaw_acc): the estimator runs all the same, on the
# wheels' speed, not on vx (MASS_GRADE.md §1): its columns equal the observer run's (both
# unfed, so mass_used too).
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next }
    !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; print $0 ",vx,vy,yaw_acc"; next }
    { print $0 "," ($c["vx_true"] + 0.3) ",0,0" }' "$TMP/hilly.csv" >"$TMP/hilly_vx.csv"
run mg_measured 0 --in "$TMP/hilly_vx.csv" --out "$TMP/mg_v.csv" --velocity measured \
    --params "$TMP/feed0.par" -q
cmp -s <(grep -v '^#' "$TMP/mg_v.csv" | cut -d, -f15-) <(grep -v '^#' "$TMP/mg_on.csv" | cut -d, -f22-) \
    && ok "mg_measured: the same mass and grade estimate (speed from the wheels)" || bad "mg_measured: estimate differs"

# Bad cells reach only the mass and grade estimator: it refuses the row (mg_status 17, 18)
# and holds its estimate; the friction side takes the row.
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next }
    !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; print; next }
    { r++; if (r == 3) $c["drive_torque"] = "nan"; if (r == 4) $c["gear"] = ""; if (r == 5) $c["gear"] = "1e7";
      if (r == 6) $c["brake"] = "inf"; print }' "$TMP/hilly.csv" >"$TMP/hilly_bad.csv"
run mg_bad_cells 0 --in "$TMP/hilly_bad.csv" --out "$TMP/mg_b.csv" --real double --metrics "$TMP/mg_b.json"
st=$(grep -v '^#' "$TMP/mg_b.csv" | awk -F, 'NR > 1 && NR <= 7 { printf "%s/%s ", $14, $26 }')
[ "$st" = "3/0 3/0 3/17 3/17 3/18 3/17 " ] && ok "mg_bad_cells: statuses (friction/mg) $st" \
    || bad "mg_bad_cells: statuses (friction/mg) $st"
held=$(grep -v '^#' "$TMP/mg_b.csv" | awk -F, 'NR == 3 || NR == 7 { printf "%s ", $22 }')
[ "$(echo $held | cut -d' ' -f1)" = "$(echo $held | cut -d' ' -f2)" ] \
    && ok "mg_bad_cells: estimate held over the refused rows" || bad "mg_bad_cells: not held: $held"
grep -q "\"status_counts\": {\"0\": $((HILLY_N - 5)), \"17\": 3, \"18\": 1}" "$TMP/mg_b.json" \
    && ok "mg_bad_cells: JSON status counts" || bad "mg_bad_cells: $(grep -o '"mass_grade.*status_counts": {[^}]*}' "$TMP/mg_b.json")"
grep -q 'bad cells (given to the estimator as NaN/Inf, the row rejected): empty 1, nan/inf 2, out of range 0; in 3 row(s)' "$TMP/out" \
    && ok "mg_bad_cells: counted" || bad "mg_bad_cells: $(grep 'bad cells' "$TMP/out")"
# no truth columns: no accuracy
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next }
    !h { for (i = 1; i <= NF; i++) if ($i !~ /^(mass_true|grade_true)$/) keep[++n] = i; h = 1 }
    { line = $keep[1]; for (i = 2; i <= n; i++) line = line "," $keep[i]; print line }' "$TMP/hilly.csv" >"$TMP/hilly_nt.csv"
run mg_no_truth 0 --in "$TMP/hilly_nt.csv" --out "$TMP/mg_nt.csv" --metrics "$TMP/mg_nt.json"
grep -q '"accuracy": null}' "$TMP/mg_nt.json" && ok "mg_no_truth: accuracy null" || bad "mg_no_truth: accuracy"
grep -q 'mass error at the end' "$TMP/out" && bad "mg_no_truth: mass error printed" || ok "mg_no_truth: no mass error"
# units of a recorded log: brake_pressure in bar, drive_torque in kN m (the first 1300
# samples of the stop-and-go log: the brake pauses from sample 1001 on)
awk '/^#/ || n++ < 1301' "$MG/car_stop_and_go.csv" >"$TMP/stop.csv"
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next }
    !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; print "# unit_brake_pressure = bar"; print "# unit_drive_torque = kN m"; print; next }
    { $c["brake_pressure"] = sprintf("%.17g", $c["brake_pressure"] / 1e5);
      $c["drive_torque"] = sprintf("%.17g", $c["drive_torque"] / 1e3); print }' \
    "$TMP/stop.csv" >"$TMP/stop_units.csv"
run mg_units 0 --in "$TMP/stop_units.csv" --out "$TMP/mg_un.csv" --real double -q
run mg_units_si 0 --in "$TMP/stop.csv" --out "$TMP/mg_si.csv" --real double -q
cmp -s <(grep -v '^#' "$TMP/mg_un.csv" | cut -d, -f26) <(grep -v '^#' "$TMP/mg_si.csv" | cut -d, -f26) \
    && grep -v '^#' "$TMP/mg_si.csv" | cut -d, -f26 | grep -q '^5$' \
    && ok "mg_units: the same brake pauses (status 5)" || bad "mg_units: statuses differ"
# Tolerance 1e-9 relative on mass and grade: the text / 1e3 (1e5) written to 17 digits and
# read back times the unit's factor is the SI value to within an ulp or two (4e-16 relative)
# of the torque; the filter measures the speed every step, so such input differences stay of
# their own order in the estimate (a brake-pressure ulp changes nothing unless a value lies
# within an ulp of mg_p_brake_on); a unit not applied, or applied twice, is a factor 1e3 on the
# torque: the mass off by far more than 1e-9.
rel=$(paste -d, <(grep -v '^#' "$TMP/mg_un.csv" | cut -d, -f22,24) <(grep -v '^#' "$TMP/mg_si.csv" | cut -d, -f22,24) \
    | awk -F, 'NR > 1 { for (i = 1; i <= 2; i++) { d = $i - $(i + 2); d = d < 0 ? -d : d; s = $(i + 2) < 0 ? -$(i + 2) : $(i + 2);
                          r = d / (s > 1e-3 ? s : 1e-3); if (r > m) m = r } } END { printf "%.3g", m }')
awk -v r="$rel" 'BEGIN { exit !(r <= 1e-9) }' && ok "mg_units: bar and kN m read as Pa and N m (max rel diff $rel)" \
    || bad "mg_units: estimate differs by $rel relative"

awk '/^#/ || n++ < 101' "$MG/car_grade_step.csv" >"$TMP/short.csv"
# every drive_torque cell empty: every sample refused (17), no estimate ever, nothing counted
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; print; next }
    { $c["drive_torque"] = ""; print }' "$TMP/short.csv" >"$TMP/no_torque_values.csv"
run mg_never_started 0 --in "$TMP/no_torque_values.csv" --out "$TMP/mg_ns.csv" --metrics "$TMP/mg_ns.json"
grep -q '"status_counts": {"17": 100}' "$TMP/mg_ns.json" \
    && grep -q '"accuracy": {"from_t_s": null, "n": 0, "mass_err_end": null, "mass_err_end_rel": null, "mass_used_err_end_rel": null, "grade_rmse": null, "grade_max_abs_err": null}' "$TMP/mg_ns.json" \
    && ok "mg_never_started: no accuracy without an estimate" || bad "mg_never_started: $(grep -A1 '"mass_grade"' "$TMP/mg_ns.json")"
grep -q 'grade RMSE\|mass error at the end' "$TMP/out" && bad "mg_never_started: accuracy printed" \
    || ok "mg_never_started: no accuracy printed"
# q31 runs the fixed-point twin by default (ukf) on a log with drive_torque, without a note;
# off: not run, no columns
run mg_q31 0 --in "$TMP/short.csv" --out "$TMP/mg_q.csv" --real q31
grep -q ',mass_est,sd_mass,grade_est,sd_grade,mg_status,mass_used,grade_walk,mg_mismatch$' "$TMP/mg_q.csv" && grep -q '^# mass_grade = ukf$' "$TMP/mg_q.csv" \
    && ok "mg_q31: the mass and grade columns by default" || bad "mg_q31: header $(grep -m1 '^t,' "$TMP/mg_q.csv")"
[ -s "$TMP/err" ] && bad "mg_q31: stderr $(cat "$TMP/err")" || ok "mg_q31: no note"
run mg_q31_off 0 --in "$TMP/short.csv" --out "$TMP/mg_q.csv" --real q31 --mass-grade off
grep -q 'mass_est' "$TMP/mg_q.csv" && bad "mg_q31_off: mass and grade columns" || ok "mg_q31_off: no mass and grade columns"

# ---- --tyre-id: the online tyre identifier (docs/TYRE_ID.md) beside the friction estimator
TID="$ROOT/scenarios/tyre_id/tid_sine_steer.csv"
# light mode (RFE_TEST_LIGHT=1: make valgrind-cli, memcheck ~45x slower): the log's first 200
# of 1000 rows, enough for every check below (the particles resample from row 2, the feed
# first changes the curve at row 133)
if [ -n "${RFE_TEST_LIGHT:-}" ] && [ "${RFE_TEST_LIGHT}" != 0 ]; then
    awk '/^#/ || !h {print; if (!/^#/) h = 1; next} n < 200 {print; n++}' "$TID" >"$TMP/tid_light.csv"
    TID="$TMP/tid_light.csv"
fi
run tid_bad_value 2 --in "$TID" --out "$TMP/tid.csv" --tyre-id ukf
grep -q "^mu_replay: --tyre-id must be apf, sir, sckf or off, not 'ukf'$" "$TMP/err" \
    && ok "tid_bad_value: named" || bad "tid_bad_value: $(cat "$TMP/err")"
run tid_bad_case 2 --in "$TID" --out "$TMP/tid.csv" --tyre-id=APF
run tid_no_value 2 --in "$TID" --out "$TMP/tid.csv" --tyre-id
run tid_twice 2 --in "$TID" --out "$TMP/tid.csv" --tyre-id apf --tyre-id off
run tid_q31_usage 2 --in "$TID" --out "$TMP/tid.csv" --tyre-id sir --real q31
grep -q "^mu_replay: --tyre-id sir: the tyre identifier is float and double only" "$TMP/err" \
    && ok "tid_q31_usage: named" || bad "tid_q31_usage: $(cat "$TMP/err")"
[ ! -e "$TMP/tid.csv" ] && ok "tid usage errors: nothing written" || bad "tid usage errors: estimate log written"
run tid_q31_off 0 --in "$TID" --out "$TMP/tid_q.csv" --tyre-id off --real q31 -q
grep -q 'mu_id_f' "$TMP/tid_q.csv" && bad "tid_q31_off: columns" || ok "tid_q31_off: no tyre identifier columns"
grep -q -- '--tyre-id apf|sir|sckf|off' <("$BIN" --help) && grep -q 'mu_id_f' <("$BIN" --help) \
    && ok "help: --tyre-id and its columns" || bad "help: no --tyre-id"
# off (the default) leaves the estimate log as it was: --tyre-id off is byte for byte the run
# without the option, and neither has a tyre identifier column, key or JSON object
run tid_default 0 --in "$TID" --out "$TMP/tid_none.csv" --metrics "$TMP/tid_none.json" -q
run tid_off 0 --in "$TID" --out "$TMP/tid_off.csv" --tyre-id off -q
cmp -s "$TMP/tid_none.csv" "$TMP/tid_off.csv" && ok "tid_off: byte-identical to the run without --tyre-id" \
    || bad "tid_off: differs from the run without --tyre-id"
grep -q 'mu_id_f\|^# tid_\|^# tyre_id' "$TMP/tid_off.csv" && bad "tid_off: tyre identifier columns or keys" \
    || ok "tid_off: no tyre identifier columns, keys"
grep -q '"tyre_id"' "$TMP/tid_none.json" && bad "tid_default: JSON has tyre_id" || ok "tid_default: no tyre_id in the JSON"
# apf: the issue's columns after the friction estimator's (and the observer's, when it runs),
# the friction columns and every metadata line of the off run unchanged (it feeds nothing)
run tid_apf 0 --in "$TID" --out "$TMP/tid_a.csv" --tyre-id apf --metrics "$TMP/tid_a.json"
H='t,mu_fl,mu_fr,mu_rl,mu_rr,sd_fl,sd_fr,sd_rl,sd_rr,valid_fl,valid_fr,valid_rl,valid_rr,status'
HT='mu_id_f,mu_id_r,sd_mu_id_f,sd_mu_id_r,B_f,C_f,D_f,E_f,B_r,C_r,D_r,E_r,tid_status,tid_flags'
[ "$(grep -v '^#' "$TMP/tid_a.csv" | head -1)" = "$H,$HT" ] && ok "tid_apf: the columns" \
    || bad "tid_apf: header $(grep -v '^#' "$TMP/tid_a.csv" | head -1)"
cmp -s <(grep -v '^#' "$TMP/tid_a.csv" | cut -d, -f1-14) <(grep -v '^#' "$TMP/tid_off.csv") \
    && ok "tid_apf: the friction columns as without it" || bad "tid_apf: the friction columns differ"
[ -z "$(grep '^#' "$TMP/tid_off.csv" | grep -vxFf <(grep '^#' "$TMP/tid_a.csv"))" ] \
    && ok "tid_apf: every metadata line of the off run kept" || bad "tid_apf: metadata lines lost"
grep -q '^# tyre_id = apf$' "$TMP/tid_a.csv" && grep -q '^# tid_n = 256$' "$TMP/tid_a.csv" \
    && grep -q '^# tid_seed = 1$' "$TMP/tid_a.csv" && grep -q '^# tid_resample = multinomial$' "$TMP/tid_a.csv" \
    && ok "tid_apf: configuration in the metadata" || bad "tid_apf: metadata $(grep 'tid\|tyre_id' "$TMP/tid_a.csv" | head -5)"
n=$(grep -vc '^#' "$TID"); n=$((n - 1))
# every sample accepted (status 0); the first draws the prior (flag 8), every other one is
# above tid_v_min = 5 m/s (the log drives at 20 m/s) and updates (flag 1, 3 when it resampled)
res=$(awk -F, '/^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next}
    {st[$c["tid_status"]]++; f = $c["tid_flags"] + 0; if (NR > 0 && f % 2 == 1) up++; if (int(f / 2) % 2 == 1) rs++;
     if (f == 8) first++; if ($c["sd_mu_id_f"] + 0 <= 0 || $c["D_f"] + 0 <= 0) badv++}
    END {printf "%d %d %d %d %d", st[0], up, rs, first, badv}' "$TMP/tid_a.csv")
set -- $res
[ "$1" -eq "$n" ] && [ "$2" -eq $((n - 1)) ] && [ "$4" -eq 1 ] && [ "$5" -eq 0 ] \
    && ok "tid_apf: status 0 on all $n rows, the first draws the prior, $2 updates ($3 resampled)" \
    || bad "tid_apf: status 0 on $1 of $n rows, $2 updates, $4 first, $5 non-positive sd or D"
grep -qF "\"tyre_id\": {\"filter\": \"apf\", \"resample\": \"multinomial\", \"n\": 256, \"seed\": 1, \"status_counts\": {\"0\": $n}," "$TMP/tid_a.json" \
    && grep -qF "\"flag_counts\": {\"updated\": $2, \"resampled\": $3, \"held\": 0, \"first\": 1, \"lost\": 0}, \"restarts\": 0, \"end\": {\"mu_id_f\": " "$TMP/tid_a.json" \
    && ok "tid_apf: JSON status and flag counts" || bad "tid_apf: JSON $(grep -A1 '"tyre_id"' "$TMP/tid_a.json" | head -c 400)"
grep -Eq '^tyre identifier \(apf, multinomial, 256 particles\): at the end mu_id_f [0-9.]+ \(sd [0-9.]+\), mu_id_r ' "$TMP/out" \
    && grep -Eq "^  samples updated $2, resampled $3, held 0, first 1, lost 0; started afresh after a period beyond tid_dt_max: 0$" "$TMP/out" \
    && ok "tid_apf: summary" || bad "tid_apf: summary $(grep -A3 'tyre identifier' "$TMP/out")"
# the stream is seeded: the same seed gives the same file, another seed another estimate
run tid_again 0 --in "$TID" --out "$TMP/tid_a2.csv" --tyre-id apf -q
cmp -s "$TMP/tid_a.csv" "$TMP/tid_a2.csv" && ok "tid_again: byte-identical (seeded)" || bad "tid_again: differs"
printf 'tid_seed = 2\n' >"$TMP/seed2.par"
run tid_seed 0 --in "$TID" --out "$TMP/tid_s.csv" --tyre-id apf --params "$TMP/seed2.par" -q
grep -q '^# tid_seed = 2$' "$TMP/tid_s.csv" && ! cmp -s <(grep -v '^#' "$TMP/tid_a.csv") <(grep -v '^#' "$TMP/tid_s.csv") \
    && ok "tid_seed: tid_seed = 2 another estimate" || bad "tid_seed: same estimate or no key"
# sir; the flag sets tid_filter over a file; a file's tid_filter alone does not run it
run tid_sir 0 --in "$TID" --out "$TMP/tid_b.csv" --tyre-id sir -q
grep -q '^# tid_filter = sir$' "$TMP/tid_b.csv" && ! cmp -s <(grep -v '^#' "$TMP/tid_a.csv") <(grep -v '^#' "$TMP/tid_b.csv") \
    && ok "tid_sir: the bootstrap filter" || bad "tid_sir: $(grep tid_filter "$TMP/tid_b.csv")"
# sckf: the sigma-point filter (TYRE_ID.md §15): the same columns, the friction columns as
# without it, every sample accepted and updated (flag 1) but the first, named in the metadata,
# the JSON and the summary; deterministic (no seed)
run tid_sckf 0 --in "$TID" --out "$TMP/tid_k.csv" --tyre-id sckf --metrics "$TMP/tid_k.json"
[ "$(grep -v '^#' "$TMP/tid_k.csv" | head -1)" = "$H,$HT" ] && grep -q '^# tid_filter = sckf$' "$TMP/tid_k.csv" \
    && cmp -s <(grep -v '^#' "$TMP/tid_k.csv" | cut -d, -f1-14) <(grep -v '^#' "$TMP/tid_off.csv") \
    && ok "tid_sckf: the columns, tid_filter, the friction columns as without it" \
    || bad "tid_sckf: header or metadata $(grep 'tid_filter' "$TMP/tid_k.csv")"
res=$(awk -F, '/^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next}
    {st[$c["tid_status"]]++; f = $c["tid_flags"] + 0; if (f == 1) up++; if (f == 8) first++;
     if ($c["sd_mu_id_f"] + 0 <= 0 || $c["D_f"] + 0 <= 0) badv++}
    END {printf "%d %d %d %d", st[0], up, first, badv}' "$TMP/tid_k.csv")
set -- $res
[ "$1" -eq "$n" ] && [ "$2" -eq $((n - 1)) ] && [ "$3" -eq 1 ] && [ "$4" -eq 0 ] \
    && ok "tid_sckf: status 0 on all $n rows, the first the prior, $2 updates" \
    || bad "tid_sckf: status 0 on $1 of $n rows, $2 updates, $3 first, $4 non-positive sd or D"
grep -qF "\"tyre_id\": {\"filter\": \"sckf\"," "$TMP/tid_k.json" \
    && grep -qF "\"flag_counts\": {\"updated\": $2, \"resampled\": 0, \"held\": 0, \"first\": 1, \"lost\": 0}" "$TMP/tid_k.json" \
    && grep -Eq '^tyre identifier \(sckf, 20 cubature points\): at the end mu_id_f [0-9.]+ \(sd [0-9.]+\)' "$TMP/out" \
    && ok "tid_sckf: JSON and summary" || bad "tid_sckf: $(grep -A1 'tyre identifier' "$TMP/out")"
printf 'tid_seed = 2\n' >"$TMP/seed2.par"
run tid_sckf_seed 0 --in "$TID" --out "$TMP/tid_k2.csv" --tyre-id sckf --params "$TMP/seed2.par" -q
cmp -s <(grep -v '^#' "$TMP/tid_k.csv") <(grep -v '^#' "$TMP/tid_k2.csv") \
    && ok "tid_sckf_seed: deterministic, the seed unused" || bad "tid_sckf_seed: another seed, another estimate"
# The tyre identifier's estimate log $2 against the reference's golden $1 (first rows): prints
# "values over_bound times_differ", the bound 1e-10 of |value| + sd in mu and its sd per axle
# (test_tyre_id_golden_flt.c derives it).
tid_vs_golden() {
    awk -F, 'FNR == 1 {h = 0} /^#/ {next}
    !h {for (i = 1; i <= NF; i++) c[FILENAME, $i] = i; h = 1; next}
    FILENAME == ARGV[1] {k = FNR; t[++ng] = $c[FILENAME, "t"]; m[ng, 0] = $c[FILENAME, "mu_f"]; m[ng, 1] = $c[FILENAME, "mu_r"];
        s[ng, 0] = $c[FILENAME, "sd_mu_f"]; s[ng, 1] = $c[FILENAME, "sd_mu_r"]; next}
    { ++nr; if (nr > ng) next; if ($c[FILENAME, "t"] != t[nr]) tbad++;
      v[0] = $c[FILENAME, "mu_id_f"]; v[1] = $c[FILENAME, "mu_id_r"]; w[0] = $c[FILENAME, "sd_mu_id_f"]; w[1] = $c[FILENAME, "sd_mu_id_r"];
      for (a = 0; a < 2; a++) { sc = (m[nr, a] < 0 ? -m[nr, a] : m[nr, a]) + s[nr, a]; d = v[a] - m[nr, a]; if (d < 0) d = -d;
        e = w[a] - s[nr, a]; if (e < 0) e = -e; if (d > 1e-10 * sc || e > 1e-10 * s[nr, a]) over++; n2++ } }
    END {printf "%d %d %d", n2 + 0, over + 0, tbad + 0}' "$1" "$2"
}
# tid_golden_ok NAME GOLDEN RUN: at least 200 values, none beyond the bound, no time differing
tid_golden_ok() {
    set -- "$1" $(tid_vs_golden "$2" "$3")
    [ "$2" -ge 200 ] && [ "$3" -eq 0 ] && [ "$4" -eq 0 ] && ok "$1: the reference's golden within 1e-10 ($2 values)" \
        || bad "$1: $3 of $2 values beyond the bound, $4 times differ"
}
# the double replay is the library's: on the sine steer's first 200 rows it meets the
# reference's golden (scenarios/golden/tyre_id/sine_sckf.csv) within the bound
# test_tyre_id_golden_flt.c derives (1e-10 of |value| + sd) in mu and its sd per axle
run tid_sckf_double 0 --in "$TID" --out "$TMP/tid_kd.csv" --tyre-id sckf --real double -q
tid_golden_ok tid_sckf_double "$ROOT/scenarios/golden/tyre_id/sine_sckf.csv" "$TMP/tid_kd.csv"
# tid_delta_state_q (TYRE_ID.md §15.7) passed through to the library: the summary names the 22
# points, and the double replay on the low-mu ramp steer's first 200 rows meets the reference's
# golden (scenarios/golden/tyre_id/ramp_low_sckf_delta_state.csv) within the same 1e-10
printf 'tid_delta_state_q = 0.04\n' >"$TMP/dstate.par"
run tid_sckf_dstate 0 --in "$ROOT/scenarios/tyre_id/tid_ramp_steer_low_mu.csv" --out "$TMP/tid_ds.csv" \
    --tyre-id sckf --real double --params "$TMP/dstate.par"
grep -q '^tyre identifier (sckf, 22 cubature points, delta a state): at the end' "$TMP/out" \
    && grep -q '^# tid_delta_state_q = 0.04$' "$TMP/tid_ds.csv" \
    && ok "tid_sckf_dstate: 22 points in the summary, the key in the metadata" \
    || bad "tid_sckf_dstate: $(grep 'tyre identifier' "$TMP/out"; grep 'tid_delta_state_q' "$TMP/tid_ds.csv")"
tid_golden_ok tid_sckf_dstate "$ROOT/scenarios/golden/tyre_id/ramp_low_sckf_delta_state.csv" "$TMP/tid_ds.csv"
printf 'tid_delta_state_q = 0.04\ntid_delta_q = 0.05\n' >"$TMP/dboth.par"
run tid_dstate_with_delta_q 1 --in "$TID" --out "$TMP/tid_db.csv" --tyre-id sckf --params "$TMP/dboth.par" -q
printf 'tid_filter = sir\ntid_resample = systematic\n' >"$TMP/sir.par"
run tid_flag_beats_file 0 --in "$TID" --out "$TMP/tid_f.csv" --tyre-id apf --params "$TMP/sir.par" -q
grep -q '^# tid_filter = apf$' "$TMP/tid_f.csv" && grep -q '^# tid_resample = systematic$' "$TMP/tid_f.csv" \
    && ok "tid_flag_beats_file: apf, the file's resampling" || bad "tid_flag_beats_file: $(grep 'tid_filter\|tid_resample' "$TMP/tid_f.csv")"
run tid_file_without_flag 0 --in "$TID" --out "$TMP/tid_f2.csv" --params "$TMP/sir.par" -q
cmp -s "$TMP/tid_off.csv" <(sed '/^# param_file = /d' "$TMP/tid_f2.csv") \
    && ok "tid_file_without_flag: not run (off by default)" || bad "tid_file_without_flag: differs from the off run"
# double: round-trip values; behind the observer (a log without vx, vy, yaw_acc) after its columns
run tid_double 0 --in "$TID" --out "$TMP/tid_d.csv" --tyre-id apf --real double -q
grep -q '^# real = double$' "$TMP/tid_d.csv" && ok "tid_double: runs" || bad "tid_double: no double run"
run tid_observer 0 --in "$DATA/good_esc.csv" --out "$TMP/tid_v.csv" --tyre-id apf -q
grep -v '^#' "$TMP/tid_v.csv" | head -1 | grep -q ',sd_beta,mu_id_f,' && ok "tid_observer: after the observer's columns" \
    || bad "tid_observer: $(grep -v '^#' "$TMP/tid_v.csv" | head -1)"
# invalid keys: named with what refused them; a word not allowed; a combination: its rule
printf 'tid_seed = 1.5\n' >"$TMP/tid_bad.par"
run tid_bad_seed 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/tid_bad.par"
one_line tid_bad_seed "^mu_replay: .*tid_bad\.par:1: invalid parameter tid_seed = 1\.5 \(rejected by mu_replay: an integer 0 \.\. 2\^53, float run\)$"
printf 'tid_sd_r = 0\n' >"$TMP/tid_bad.par"
run tid_bad_key 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/tid_bad.par"
one_line tid_bad_key "^mu_replay: .*tid_bad\.par:1: invalid parameter tid_sd_r = 0 \(rejected by rfe_tyre_id_params_validate, float run\)$"
printf 'tid_filter = ekf\n' >"$TMP/tid_bad.par"
run tid_bad_word 1 --in "$TID" --out "$TMP/tid_x.csv" --params "$TMP/tid_bad.par"
one_line tid_bad_word "^mu_replay: .*tid_bad\.par:1:14: value of 'tid_filter': not one of the allowed words: 'ekf'$"
printf '# the resampling\ntid_resample = stratified\n' >"$TMP/tid_bad.par"
run tid_bad_resample 1 --in "$TID" --out "$TMP/tid_x.csv" --params "$TMP/tid_bad.par"
one_line tid_bad_resample "^mu_replay: .*tid_bad\.par:2:16: value of 'tid_resample': not one of the allowed words: 'stratified'$"
printf 'tid_n = 512\n' >"$TMP/tid_bad.par"
run tid_n_not_a_key 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/tid_bad.par"
one_line tid_n_not_a_key "^mu_replay: .*tid_bad\.par:1:1: unknown parameter key 'tid_n'$"
printf 'tid_C_hi = 1.2\n' >"$TMP/tid_bad.par"
run tid_combination 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/tid_bad.par"
one_line tid_combination "^mu_replay: .*estimator init failed: .*tyre identifier: tid_mu0, shape_Cy, cy and shape_Ey within their tid_\* bounds"
[ ! -e "$TMP/tid_x.csv" ] && ok "tid invalid parameters: nothing written" || bad "tid invalid parameters: estimate log written"
# the feed of the identified curve (tid_feed_sd_rel, TYRE_ID.md §14): off by default (the
# runs above have no cy_used); when on, the curve of each sample's step after the identifier's
# columns, the first row's the parameter file's (nothing identified yet), counted in the
# summary and the JSON; behind the observer, and negative, refused naming the key
grep -q 'cy_used' "$TMP/tid_a.csv" && bad "tid_feed: columns without the key" || ok "tid_feed: off by default"
grep -qF '"feed": {"sd_rel": 0, "evidence": 0, "ax_max": 0.5, "n_fed": 0, "refresh": 0, "outlier_k": 5, "n_reset": 0}}' "$TMP/tid_a.json" && ok "tid_feed: JSON off" \
    || bad "tid_feed: JSON $(grep -o '"feed": [^}]*}' "$TMP/tid_a.json")"
printf 'tid_feed_sd_rel = 0.05\n' >"$TMP/feed.par"
run tid_feed 0 --in "$TID" --out "$TMP/tid_fd.csv" --tyre-id apf --params "$TMP/feed.par" --metrics "$TMP/tid_fd.json" --real double
[ "$(grep -v '^#' "$TMP/tid_fd.csv" | head -1)" = "$H,$HT,cy_used,shape_Cy_used,shape_Ey_used,r_model_rel_used" ] \
    && ok "tid_feed: the columns" || bad "tid_feed: header $(grep -v '^#' "$TMP/tid_fd.csv" | head -1)"
res=$(awk -F, '/^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next}
    NR > 0 && !first {first = $c["cy_used"] "," $c["shape_Cy_used"] "," $c["shape_Ey_used"] "," $c["r_model_rel_used"]}
    {if (prev != "" && $c["cy_used"] != prev) ch++; prev = $c["cy_used"]}
    END {printf "%s %d", first, ch}' "$TMP/tid_fd.csv")
set -- $res
[ "$1" = "15,1.3,0,0.05" ] && [ "$2" -gt 0 ] && ok "tid_feed: the file's curve first, then $2 changes" \
    || bad "tid_feed: first curve $1, $2 changes"
fed=$(grep -o '"n_fed": [0-9]*, "refresh": 0, "outlier_k": 5, "n_reset": 0}}' "$TMP/tid_fd.json" | grep -o '"n_fed": [0-9]*' | grep -o '[0-9]*')
[ -n "$fed" ] && [ "$fed" -gt 0 ] && grep -qF '"feed": {"sd_rel": 0.05, "evidence": 0, "ax_max": 0.5, "n_fed": ' "$TMP/tid_fd.json" \
    && grep -Eq "^  lateral curve fed to the friction estimator at $fed samples \(tid_feed_sd_rel = 0\.05, tid_feed_evidence = 0 s, tid_feed_ax_max = 0\.5 m/s\^2\); its curve at the end cy " "$TMP/out" \
    && ok "tid_feed: $fed samples fed, JSON and summary" || bad "tid_feed: JSON/summary $(grep 'lateral curve' "$TMP/out")"
cmp -s <(grep -v '^#' "$TMP/tid_d.csv" | cut -d, -f1-14) <(grep -v '^#' "$TMP/tid_fd.csv" | cut -d, -f1-14) \
    && bad "tid_feed: the friction columns did not change" || ok "tid_feed: the friction columns change"
# tid_feed_evidence: the feed waits for the friction estimator's own evidence that its curve
# is wrong (time at a mu bound, status 1, or in model mismatch, status 4). On this log's
# first rows the estimator reports neither (checked here, so the check below can fail), so
# with any evidence required nothing is fed and the friction columns are the unfed run's;
# a negative value is refused, naming the key
printf 'tid_feed_sd_rel = 0.05\ntid_feed_evidence = 0.5\n' >"$TMP/feed_ev.par"
run tid_feed_evidence 0 --in "$TID" --out "$TMP/tid_fe.csv" --tyre-id apf --params "$TMP/feed_ev.par" --metrics "$TMP/tid_fe.json" --real double
wrong=$(awk -F, '/^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next} $c["status"] == 1 || $c["status"] == 4 {n++} END {print n + 0}' "$TMP/tid_d.csv")
[ "$wrong" -eq 0 ] && grep -qF '"feed": {"sd_rel": 0.05, "evidence": 0.5, "ax_max": 0.5, "n_fed": 0, "refresh": 0, "outlier_k": 5, "n_reset": 0}}' "$TMP/tid_fe.json" \
    && cmp -s <(grep -v '^#' "$TMP/tid_d.csv" | cut -d, -f1-14) <(grep -v '^#' "$TMP/tid_fe.csv" | cut -d, -f1-14) \
    && grep -q '^# tid_feed_evidence = 0.5$' "$TMP/tid_fe.csv" \
    && ok "tid_feed_evidence: no evidence ($wrong samples at a bound or in mismatch), nothing fed" \
    || bad "tid_feed_evidence: $wrong samples of evidence, JSON $(grep -o '"feed": [^}]*}' "$TMP/tid_fe.json")"
# wrong tyre data (true cy -30 %, C +30 %): the estimator's mismatch and bound statuses are the
# evidence; after 0.25 s of them the curve is fed, never before
printf 'tid_feed_sd_rel = 0.05\ntid_feed_evidence = 0.25\n' >"$TMP/feed_ev2.par"
WT="$ROOT/scenarios/wrong_tyre_data.mf.csv"
if [ -n "${RFE_TEST_LIGHT:-}" ] && [ "${RFE_TEST_LIGHT}" != 0 ]; then
    awk '/^#/ || !h {print; if (!/^#/) h = 1; next} n < 400 {print; n++}' "$WT" >"$TMP/wt_light.csv"
    WT="$TMP/wt_light.csv"
fi
run tid_feed_evidence_wrong 0 --in "$WT" --out "$TMP/tid_fw.csv" --tyre-id apf --params "$TMP/feed_ev2.par" --real double -q
res=$(awk -F, '/^#/ {next} !h {for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next}
    {if (have && (s == 1 || s == 4)) w += $c["t"] - tp; s = $c["status"] + 0; tp = $c["t"]; have = 1
     if (cy0 == "") cy0 = $c["cy_used"]; if (!ch && $c["cy_used"] != cy0) {ch = 1; wch = w}}
    END {printf "%d %.6f", ch, wch}' "$TMP/tid_fw.csv")
set -- $res
[ "$1" -eq 1 ] && awk -v w="$2" 'BEGIN {exit !(w >= 0.25)}' \
    && ok "tid_feed_evidence_wrong: first curve change after $2 s of evidence (>= 0.25)" \
    || bad "tid_feed_evidence_wrong: changed $1, after $2 s of evidence"
printf 'tid_feed_evidence = -1\n' >"$TMP/feed_ev_bad.par"
run tid_feed_evidence_negative 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/feed_ev_bad.par"
one_line tid_feed_evidence_negative "^mu_replay: .*feed_ev_bad\.par:1: invalid parameter tid_feed_evidence = -1 \(rejected by mu_replay: a time >= 0 s, float run\)$"
# tid_feed_ax_max (m/s^2, TYRE_ID.md §14: no curve fed after a sample braking or driving
# harder): in the metadata and the JSON; negative, or not a number, refused naming the key
printf 'tid_feed_sd_rel = 0.05\ntid_feed_ax_max = 2\n' >"$TMP/feed_ax.par"
run tid_feed_ax_max 0 --in "$TID" --out "$TMP/tid_fa.csv" --tyre-id apf --params "$TMP/feed_ax.par" --metrics "$TMP/tid_fa.json" --real double -q
grep -qF '"evidence": 0, "ax_max": 2, "n_fed": ' "$TMP/tid_fa.json" && grep -q '^# tid_feed_ax_max = 2$' "$TMP/tid_fa.csv" \
    && ok "tid_feed_ax_max: metadata and JSON" || bad "tid_feed_ax_max: JSON $(grep -o '"feed": [^}]*}' "$TMP/tid_fa.json")"
printf 'tid_feed_ax_max = -0.5\n' >"$TMP/feed_ax_bad.par"
run tid_feed_ax_max_negative 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/feed_ax_bad.par"
one_line tid_feed_ax_max_negative "^mu_replay: .*feed_ax_bad\.par:1: invalid parameter tid_feed_ax_max = -0\.5 \(rejected by mu_replay: a finite acceleration >= 0 m/s\^2, float run\)$"
# tid_feed_refresh and tid_feed_outlier_k (MONITOR.md §7: no curve fed after a held or
# implausible sample until the identifier has refreshed it): in the metadata and the JSON;
# negative refused naming the key
printf 'tid_feed_sd_rel = 0.05\ntid_feed_refresh = 1\ntid_feed_outlier_k = 4\n' >"$TMP/feed_rf.par"
run tid_feed_refresh 0 --in "$TID" --out "$TMP/tid_rf.csv" --tyre-id apf --params "$TMP/feed_rf.par" --metrics "$TMP/tid_rf.json" --real double -q
grep -qE '"refresh": 1, "outlier_k": 4, "n_reset": [0-9]+}}' "$TMP/tid_rf.json" && grep -q '^# tid_feed_refresh = 1$' "$TMP/tid_rf.csv" \
    && grep -q '^# tid_feed_outlier_k = 4$' "$TMP/tid_rf.csv" \
    && ok "tid_feed_refresh: metadata and JSON" || bad "tid_feed_refresh: JSON $(grep -o '"feed": [^}]*}' "$TMP/tid_rf.json")"
printf 'tid_feed_refresh = -1\n' >"$TMP/feed_rf_bad.par"
run tid_feed_refresh_negative 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/feed_rf_bad.par"
one_line tid_feed_refresh_negative "^mu_replay: .*feed_rf_bad\.par:1: invalid parameter tid_feed_refresh = -1 \(rejected by mu_replay: a finite time >= 0 s, float run\)$"
printf 'tid_feed_outlier_k = -1\n' >"$TMP/feed_ok_bad.par"
run tid_feed_outlier_k_negative 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/feed_ok_bad.par"
one_line tid_feed_outlier_k_negative "^mu_replay: .*feed_ok_bad\.par:1: invalid parameter tid_feed_outlier_k = -1 \(rejected by mu_replay: a finite multiple >= 0 of tid_sd_ay, float run\)$"
run tid_feed_observer 1 --in "$DATA/good_esc.csv" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/feed.par"
one_line tid_feed_observer "^mu_replay: .*feed\.par:1: invalid parameter tid_feed_sd_rel = 0\.05 \(rejected by mu_replay: a relative sd >= 0, and 0 behind the velocity observer, whose pipeline has no lateral tyre setter, float run\)$"
printf 'tid_feed_sd_rel = -1\n' >"$TMP/feed_bad.par"
run tid_feed_negative 1 --in "$TID" --out "$TMP/tid_x.csv" --tyre-id apf --params "$TMP/feed_bad.par"
one_line tid_feed_negative "^mu_replay: .*feed_bad\.par:1: invalid parameter tid_feed_sd_rel = -1 "
[ ! -e "$TMP/tid_x.csv" ] && ok "tid_feed refusals: nothing written" || bad "tid_feed refusals: estimate log written"

if [ -w /dev/full ]; then
    "$BIN" --in "$DATA/good_small.csv" --out "$TMP/s.csv" >/dev/full 2>"$TMP/err"
    [ $? -eq 1 ] && ok "stdout_full: exit 1" || bad "stdout_full: exit not 1"
    one_line stdout_full "^mu_replay: stdout: write failed$"
fi
run no_truth 0 --in "$DATA/good_notruth.csv" --out "$TMP/n.csv" --metrics="$TMP/n.json"
grep -q '^wheel ' "$TMP/out" && bad "no_truth: accuracy table without truth" || ok "no_truth: no accuracy table"
grep -q '"metrics": null' "$TMP/n.json" && ok "no_truth: metrics null" || bad "no_truth: metrics not null"

echo "cli: $PASS passed, $FAIL failed"
[ "$FAIL" -eq 0 ]
