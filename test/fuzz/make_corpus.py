#!/usr/bin/env python3
"""Write the committed libFuzzer seed corpus (test/fuzz/corpus/), deterministic.

    python3 test/fuzz/make_corpus.py [--scenarios scenarios] [--out test/fuzz/corpus]

fuzz_step/ (both step harnesses; format in fuzz_input.h): stretches of real scenario logs
(every field as its float32 bit pattern), each configuration byte, the operating corners
(standstill from mu_min, braking to a stop and reversing, locked and spinning wheels,
every field at its limit) and bad values between good samples.
fuzz_mass_grade/, fuzz_tyre_id/ (their harnesses; parameters as fuzz_params.h decodes them):
stretches of the bundled mass-and-grade and tyre-identification logs mapped onto the
harness's fields, every configuration byte, perturbed and garbage parameters, restarts, gaps
and bad values, and the inputs of every finding.
fuzz_csv/ (fuzz_csv.c): byte 0 '0' sensor log, '1' parameter file, '2' number; the head
of a real log and the malformed-input cases of test/host/test_cli.sh, parameter files,
numbers.  Regenerate after changing the input format; the files are small (< 20 kB each).
"""

import argparse
import os
import struct

FIELDS = ("delta", "vx", "vy", "yaw_rate", "yaw_acc", "ax", "ay",
          "omega_fl", "omega_fr", "omega_rl", "omega_rr")


def cfg(preset_default=0, ckf=0, toggle_tyre=0, mu0=0):
    return bytes([preset_default | ckf << 1 | toggle_tyre << 2 | mu0 << 3])


def f32(v):
    return bytes([4]) + struct.pack("<f", v)


def special(idx):
    return bytes([3, idx])


def sample(values):
    """op 0: a new sample, each value a float32 bit pattern (or bytes for a special)."""
    out = bytes([0])
    for v in values:
        out += v if isinstance(v, bytes) else f32(v)
    return out


def repeat(n):
    """op 1: the current sample n times (1..64)."""
    return bytes([1 | (n - 1) << 2])


def ramp(n, values):
    """op 3: n steps (1..64) to the target sample."""
    out = bytes([3 | (n - 1) << 2])
    for v in values:
        out += v if isinstance(v, bytes) else f32(v)
    return out


def set_field(field, value):
    return bytes([2, field]) + (value if isinstance(value, bytes) else f32(value))


def gap(missed):
    """op 2 with a field byte >= 128: a gap of `missed` periods (rfe_friction_skip)."""
    return bytes([2, 128]) + int(missed).to_bytes(4, "little")


def read_rows(path, first, count):
    with open(path, encoding="utf-8") as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    head = lines[0].strip().split(",")
    idx = [head.index(c) for c in FIELDS]
    rows = []
    for ln in lines[1 + first:1 + first + count]:
        cells = ln.strip().split(",")
        rows.append([float(cells[i]) for i in idx])
    return rows


def drive(v, kappa=0.0, delta=0.0, ax=0.0, ay=0.0):
    w = (1.0 + kappa) * v / 0.325
    return [delta, v, 0.0, v * delta / 3.05, 0.0, ax, ay, w, w, w, w]


def step_seeds(scen):
    s = {}
    for name, c, log, first, n in [
            ("log_hard_brake_low_mu_paper", cfg(0), "hard_brake_low_mu.mf.csv", 80, 220),
            ("log_sine_steer_default", cfg(1), "sine_steer_low_mu.mf.csv", 100, 250),
            ("log_mu_step_ckf", cfg(0, ckf=1), "mu_step_hard_brake.csv", 250, 200),
            ("log_split_mu_default_paper_tyre", cfg(1, toggle_tyre=1), "split_mu_hard_brake.mf.csv", 80, 200),
            ("log_brake_in_turn_absolute", cfg(0, toggle_tyre=1), "brake_in_turn.csv", 150, 200)]:
        s[name] = c + b"".join(sample(r) for r in read_rows(os.path.join(scen, log), first, n))
    for b in range(32):  # every configuration byte, one plausible sample
        s[f"config_{b:02d}"] = bytes([b]) + sample(drive(20.0, -0.05, 0.01, -3.0))
    # Standstill after braking, from mu_min and mu_max (the estimate sits on a bound).
    for mu0, tag in ((1, "mu_min"), (2, "mu_max")):
        for pd in (0, 1):
            s[f"standstill_{tag}_{'default' if pd else 'paper'}"] = (
                cfg(pd, mu0=mu0) + sample(drive(20.0, -0.1, 0.0, -6.0)) + repeat(30)
                + ramp(64, drive(0.0, 0.0, 0.0, -6.0)) + sample([0.0] * 11)
                + repeat(64) * 20)
    # Braking to a stop, reversing, forwards again (vx through 0 and v_min).
    s["stop_reverse_go"] = (cfg(1) + sample(drive(15.0, -0.05, 0.0, -4.0)) + ramp(64, drive(0.0))
                            + ramp(64, drive(-5.0, 0.0, -0.3)) + repeat(40) + ramp(64, drive(0.0))
                            + ramp(64, drive(10.0, 0.1, 0.05, 2.0)) + repeat(64))
    lock = drive(20.0, -0.1, 0.0, -7.0)
    lock[7] = 0.0
    s["locked_front_left_paper"] = cfg(0) + sample(lock) + repeat(64) * 4 + set_field(8, 0.0) + repeat(64) * 4
    s["locked_all_default"] = cfg(1) + sample(drive(25.0, -1.0, 0.0, -8.0)) + repeat(64) * 8
    spin = drive(4.0, 0.0, 0.0, 3.0)
    spin[7] = spin[8] = 60.0
    s["spinning_absolute"] = cfg(0, toggle_tyre=1) + sample(spin) + repeat(64) * 6
    s["limits_all"] = b"".join(
        cfg(pd, ckf=ck) + sample([special(2 + (k % 2)) for k in range(11)]) + repeat(64)
        for pd, ck in ((0, 0), (0, 1), (1, 0)))
    bad = b""
    for k, idx in enumerate((6, 7, 8, 4, 5, 9, 11, 13)):  # NaN, +-Inf, beyond limit, huge, tiny
        bad += sample(drive(20.0, -0.05, 0.0, -3.0)) + set_field(k % 11, special(idx))
    s["bad_values_between_good"] = cfg(1) + bad + sample(drive(20.0, -0.05, 0.0, -3.0)) + repeat(10)
    s["ckf_hard_samples"] = cfg(0, ckf=1) + sample(drive(19.8, -1.0, -0.95, -50.0, -50.0)) + repeat(64)
    # Gaps while braking (a dropped frame, a logger's second, the longest count), both filters.
    for pd, ck, tag in ((1, 0, "default"), (0, 1, "paper_ckf")):
        s[f"gaps_braking_{tag}"] = (cfg(pd, ckf=ck) + sample(drive(20.0, -0.08, 0.0, -4.0))
                                    + repeat(30) + gap(2) + repeat(10) + gap(100) + repeat(20)
                                    + gap(0xFFFFFFFF) + repeat(64) + gap(0) + repeat(5))
    return s


LOG_HEAD = ("t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n")
ROW = "{t},0.01,20,0.1,0.02,0.01,-3,0.5,60,60.1,60.2,60.3\n"


def csv_seeds(scen):
    s = {}
    with open(os.path.join(scen, "hard_brake_low_mu.mf.csv"), encoding="utf-8") as fh:
        lines = fh.readlines()
    hdr = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    s["log_real_head"] = "0" + "".join(lines[:hdr + 40])
    s["log_real_rows_only"] = "0" + "".join(lines[hdr:hdr + 60])
    rows = "".join(ROW.format(t=k * 0.01) for k in range(5))
    s["log_minimal"] = "0" + LOG_HEAD + rows
    s["log_crlf_padded"] = "0" + (LOG_HEAD + rows).replace(",", " , ").replace("\n", "\r\n")
    s["log_meta_params"] = "0# m = 1650\n# mu_max = 1.5\n# tyre = paper\n# dt = 0.02\n# junk\n" + LOG_HEAD + rows
    s["log_meta_bad_value"] = "0# m = heavy\n" + LOG_HEAD + rows
    # found by make fuzz (fuzz_csv): a huge prior sd moves the mean in one held step
    s["log_meta_huge_prior_regression"] = ("0# sd0 = 077777777777777770\n# v_est_min = 0\n" + LOG_HEAD
                                           + "0.0,0.0101,20,0.1,0.02,0.01,-3,0.5,60,60.1,60.2,60.3\n")
    # found by make fuzz (fuzz_csv): sd0_common / sd0 = 1e11 makes the prior singular in float:
    # init returns RFE_ERR_NOT_POSITIVE_DEFINITE (now documented in friction.h)
    s["log_meta_prior_ratio_regression"] = "0# sd0_common = 1e10\n# mu_min = 1e-300\n# v_est_min = 0\n" + LOG_HEAD + rows
    s["log_meta_extreme"] = "0# sd0_common = 1e30\n# mu_min = 1e-300\n# v_est_min = 0\n" + LOG_HEAD + rows
    s["log_truth_partial"] = "0" + LOG_HEAD.strip() + ",mu_fl,mu_fr\n" + rows.replace("\n", ",0.5,0.5\n")
    s["log_truth_full"] = "0" + LOG_HEAD.strip() + ",mu_fl,mu_fr,mu_rl,mu_rr,extra\n" + rows.replace("\n", ",0.3,0.3,0.3,0.3,x\n")
    s["log_missing_column"] = "0" + LOG_HEAD.replace(",ay", "") + rows
    s["log_duplicate_column"] = "0" + LOG_HEAD.strip() + ",ax\n" + rows.replace("\n", ",1\n")
    s["log_nan_field"] = "0" + LOG_HEAD + rows.replace("-3", "nan", 1)
    s["log_hex_float"] = "0" + LOG_HEAD + rows.replace("-3", "0x1p3", 1)
    s["log_overflow"] = "0" + LOG_HEAD + rows.replace("-3", "1e999", 1)
    s["log_t_not_increasing"] = "0" + LOG_HEAD + ROW.format(t=1) + ROW.format(t=1)
    s["log_wrong_field_count"] = "0" + LOG_HEAD + rows + "5,1,2\n"
    s["log_header_only"] = "0" + LOG_HEAD
    s["log_empty_fields"] = "0" + LOG_HEAD + ",,,,,,,,,,,\n"
    s["log_out_of_limits"] = "0" + LOG_HEAD + rows.replace("-3", "-80")
    s["log_nul_byte"] = "0" + LOG_HEAD + "0\x00,1\n"
    s["log_long_line"] = "0" + LOG_HEAD + "1" * 3000 + "\n"
    s["par_full"] = ("1# parameters\nm = 1830\nLf = 1.4\nLr = 1.65\nmu0 = 0.5   # comment\n"
                     "tyre = absolute\nfilter = ckf\nstructure = sides\nsd_valid = 0.15\n\n")
    s["par_unknown_key"] = "1mass = 1830\n"
    s["par_duplicate"] = "1m = 1\nm = 2\n"
    s["par_no_equals"] = "1m 1830\n"
    s["par_bad_word"] = "1tyre = pirelli\n"
    s["par_bad_number"] = "1q_mu = 1e-3x\n"
    s["par_empty_value"] = "1q_mu =\n"
    for k, v in enumerate(("1e308", "1e309", "-0", "0x1p3", "nan", ".5", "5.", "+1.5e-3",
                           " 7 ", "1e-400", "--1", "")):
        s[f"num_{k:02d}"] = "2" + v
    return s


def log_rows(path, first, count, step=1):
    """Rows of a DATA.md log as dicts of floats (every step-th from first)."""
    with open(path, encoding="utf-8") as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    head = lines[0].strip().split(",")
    out = []
    for ln in lines[1 + first:1 + first + count * step:step]:
        out.append(dict(zip(head, (float(c) for c in ln.strip().split(",")))))
    return out


# fuzz_mass_grade_flt.c's fields: dt = 0.01 v1, v = 0.2 omega_fl, torque = 1e4 yaw_rate,
# p_brake = 1e4 yaw_acc, ax, gear = omega_fr / 50, brake = omega_rl - 58, has ^= omega_rr - 58,
# vy >= 25 restarts.
def mg_sample(dt, v, torque=0.0, p_brake=0.0, ax=0.0, gear=1, brake=0, has_xor=0, restart=False):
    return sample([0.0, dt / 0.01, 30.0 if restart else 0.0, torque / 1e4, p_brake / 1e4, ax, 0.0,
                   v / 0.2, gear * 50.0 + 1.0, 58.0 + brake, 58.0 + has_xor])


def mg_params(mode, perturb=()):
    """fuzz_params.h: mode 0 preset, 1 (field, class, byte...) perturbations, 2 garbage."""
    if mode != 1:
        return bytes([mode])
    out = bytes([1, len(perturb) - 1])
    for field, value in perturb:
        out += bytes([field]) + value
    return out


def f32_value(v):
    return bytes([4]) + struct.pack("<f", v)


def mass_grade_seeds(scen):
    s = {}
    # cfg: bit 0 truck, bit 1 seed configuration, bits 2-3 the optional inputs (2: ax, brake, pressure)
    for name, log, cfg in (("log_stop_and_go_car", "car_stop_and_go.csv", 2 << 2),
                           ("log_grade_step_seed", "car_grade_step.csv", 2 | 2 << 2),
                           ("log_gear_shift_all", "car_gear_shift.csv", 3 << 2),
                           ("log_truck_seed", "truck_graded_drive.csv", 1 | 2 | 2 << 2)):
        rows = log_rows(os.path.join(scen, "mass_grade", log), 0, 300, 5)
        body = b""
        for k, r in enumerate(rows):
            dt = 0.0 if k == 0 else r["t"] - rows[k - 1]["t"]
            v = 0.325 * (r["omega_fl"] + r["omega_fr"] + r["omega_rl"] + r["omega_rr"]) / 4.0
            body += mg_sample(dt, v, r["drive_torque"], r["brake_pressure"], r["ax"],
                              int(r["gear"]), int(r["brake"]))
        s[name] = bytes([cfg]) + mg_params(0) + body
    for b in range(16):
        s[f"config_{b:02d}"] = bytes([b]) + mg_params(0) + mg_sample(0.02, 15.0, 500.0, 0.0, 0.3) + repeat(64)
    cruise = mg_sample(0.02, 20.0, 400.0, 0.0, 0.2)
    # perturbed parameters: each real field (0..30) halved, negated, 0, NaN, huge; the flags
    for field in range(33):
        for tag, value in (("x16", bytes([0, 64])), ("neg", bytes([2])), ("zero", bytes([6])),
                           ("nan", special(6)), ("huge", bytes([7, 40]))):
            s[f"param_{field:02d}_{tag}"] = bytes([4]) + mg_params(1, [(field, value)]) + cruise + repeat(32)
    s["param_garbage"] = bytes([4]) + bytes([2]) + b"".join(f32_value(1.0) for _ in range(31)) + b"\x01\x00" + cruise
    # holds, restarts, a gap beyond dt_max, unknown has bits, bad values between good ones
    s["brake_shift_restart"] = (bytes([3 << 2]) + mg_params(0) + cruise + repeat(20)
                                + mg_sample(0.02, 18.0, 0.0, 2e5, -3.0, 1, 1) + repeat(30)
                                + mg_sample(0.02, 18.0, 300.0, 0.0, 0.1, 2) + repeat(60)
                                + mg_sample(0.02, 18.0, 300.0, 0.0, 0.1, 2, restart=True)
                                + mg_sample(2.0, 1.0, 0.0) + mg_sample(0.02, 15.0, 300.0) + repeat(40))
    bad = b""
    for k, idx in enumerate((6, 7, 8, 4, 5, 9, 11, 13)):
        bad += cruise + set_field((1, 3, 5, 7, 10)[k % 5], special(idx))
    s["bad_values_between_good"] = bytes([4]) + mg_params(0) + bad + cruise + repeat(10)
    s["unknown_has_bits"] = bytes([4]) + mg_params(0) + cruise + mg_sample(0.02, 20.0, 400.0, 0.0, 0.2, has_xor=16) + cruise
    return s


# fuzz_tyre_id_flt.c's fields: delta, dt = 0.001 vx-field, yaw_rate, ax, ay, vx = 0.2 omega_fl.
def tid_sample(dt, delta, vx, r, ay, ax=0.0):
    return sample([delta, dt / 0.001, 0.0, r, 0.0, ax, ay, vx / 0.2, 58.0, 58.0, 58.0])


def tid_head(cfg=0, seed=1, tp=b"\x00", veh=b"\x00"):
    return bytes([cfg]) + int(seed).to_bytes(8, "little") + tp + veh


def tyre_id_seeds(scen):
    s = {}
    for name, log, cfg, first in (("log_sine_steer_apf", "tid_sine_steer.csv", 0, 100),
                                  ("log_ramp_high_mu_sir", "tid_ramp_steer_high_mu.csv", 1, 500),
                                  ("log_dlc_low_mu_systematic", "tid_dlc_low_mu.csv", 2, 200),
                                  ("log_straight_substeps", "tid_straight.csv", 4, 0)):
        rows = log_rows(os.path.join(scen, "tyre_id", log), first, 120)
        body = b""
        for k, r in enumerate(rows):
            dt = 0.01 if k == 0 else r["t"] - rows[k - 1]["t"]
            body += tid_sample(dt, r["delta"], r["vx"], r["yaw_rate"], r["ay"], r["ax"])
        s[name] = tid_head(cfg, 7) + body
    for b in range(32):
        s[f"config_{b:02d}"] = tid_head(b, b) + tid_sample(0.01, 0.02, 20.0, 0.1, 2.0) + repeat(16)
    drive = tid_sample(0.01, 0.03, 18.0, 0.15, 2.5, -0.5)
    for field in range(31):  # the identifier's 28 reals and 3 integers
        for tag, value in (("x16", bytes([0, 64])), ("neg", bytes([2])), ("zero", bytes([6])),
                           ("huge", bytes([7, 40]))):
            p = bytes([1, 0, field]) + (value if field < 28 else bytes([3]) + (7).to_bytes(4, "little"))
            s[f"param_{field:02d}_{tag}"] = tid_head(tp=p) + drive + repeat(8)
    for field in range(10):  # the vehicle's
        for tag, value in (("tiny", bytes([7, 0])), ("huge", bytes([7, 40]))):
            s[f"vehicle_{field:02d}_{tag}"] = tid_head(veh=bytes([1, 0, field]) + value) + drive + repeat(8)
    s["held_then_driving"] = (tid_head() + tid_sample(0.01, 0.0, 2.0, 0.0, 0.0) + repeat(10)
                              + ramp(40, [0.0, 10.0, 0.0, 0.1, 0.0, 0.0, 1.0, 90.0, 58.0, 58.0, 58.0])
                              + repeat(30))
    bad = b""
    for k, idx in enumerate((6, 7, 8, 4, 5, 9, 11, 13)):
        bad += drive + set_field((0, 1, 3, 5, 6, 7)[k % 6], special(idx))
    s["bad_values_between_good"] = tid_head() + bad + drive + repeat(4)
    s["axle_lifted_ax"] = tid_head() + drive + set_field(5, f32_value(49.0)) + set_field(5, f32_value(-49.0)) + drive
    return s


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenarios", default=os.path.join(repo, "scenarios"))
    ap.add_argument("--out", default=os.path.join(here, "corpus"))
    a = ap.parse_args(argv)
    for sub, seeds in (("fuzz_step", step_seeds(a.scenarios)), ("fuzz_csv", csv_seeds(a.scenarios)),
                       ("fuzz_mass_grade", mass_grade_seeds(a.scenarios)),
                       ("fuzz_tyre_id", tyre_id_seeds(a.scenarios))):
        d = os.path.join(a.out, sub)
        os.makedirs(d, exist_ok=True)
        for old in os.listdir(d):
            if not old.startswith("found_"):  # the inputs of findings stay (see ROBUSTNESS.md)
                os.remove(os.path.join(d, old))
        for name, data in seeds.items():
            with open(os.path.join(d, name), "wb") as fh:
                fh.write(data if isinstance(data, bytes) else data.encode("latin-1"))
        print(f"{sub}: {len(seeds)} seeds")


if __name__ == "__main__":
    main()
