"""observer_results.py's "beyond 2 sd" share on logs written here (no replay run)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import observer_results as orr  # noqa: E402


def _write(path: Path, cols: dict) -> Path:
    names = list(cols)
    rows = zip(*(cols[n] for n in names))
    path.write_text(",".join(names) + "\n" + "".join(",".join(repr(v) for v in r) + "\n"
                                                     for r in rows))
    return path


def test_beyond_2sd_counts_only_errors_past_twice_the_sd_at_speed(tmp_path):
    # five samples: errors 0.1, 0.3, 0.25, 0.5 (vx 2 m/s: below BETA_MIN_VX, left out), -0.5
    # against sd 0.1 (2 sd = 0.2, so 0.3 and -0.5 are beyond, 0.1 is not) and 0.125 (0.25
    # against 2 sd = 0.25: not beyond, the rule is strict)
    log = _write(tmp_path / "log.csv", {"beta_true": [0.0] * 5,
                                        "vx_true": [10.0, 10.0, 10.0, 2.0, 10.0]})
    est = _write(tmp_path / "est.csv", {"beta_est": [0.1, 0.3, 0.25, 0.5, -0.5],
                                        "sd_beta": [0.1, 0.1, 0.125, 0.1, 0.1]})
    assert orr.beyond_2sd(est, log) == 2 / 4


def test_beyond_2sd_is_none_without_a_sample_at_speed(tmp_path):
    log = _write(tmp_path / "log.csv", {"beta_true": [0.0, 0.0], "vx_true": [1.0, 2.9]})
    est = _write(tmp_path / "est.csv", {"beta_est": [1.0, 1.0], "sd_beta": [0.1, 0.1]})
    assert orr.beyond_2sd(est, log) is None
    assert orr.pct(orr.beyond_2sd(est, log)) == "–"


def test_replay_passes_the_params_file_and_keeps_its_outputs_apart(tmp_path):
    # a stand-in for mu_replay that records its arguments and writes empty metrics: the
    # --params option must reach the command, and its stem the output names (so runs with
    # different files in one --out directory do not overwrite each other)
    fake = tmp_path / "fake_replay"
    argv = tmp_path / "argv.txt"
    fake.write_text("#!/bin/sh\n"
                    f"echo \"$@\" > {argv}\n"
                    "while [ $# -gt 0 ]; do [ \"$1\" = --metrics ] && "
                    "echo '{\"metrics\": {}}' > \"$2\"; shift; done\n")
    fake.chmod(0o755)
    log = tmp_path / "observer" / "spin.csv"
    log.parent.mkdir()
    log.write_text("t\n0\n")
    par = tmp_path / "k25.par"
    par.write_text("obs_vydot_rerr = 25\n")
    info = orr.replay(fake, log, tmp_path, "observer", "float", par)
    args = argv.read_text().split()
    assert args[args.index("--params") + 1] == str(par)
    assert info["estimate"].name == "observer.spin.observer.float.k25.csv"
    orr.replay(fake, log, tmp_path, "observer", "float")
    assert "--params" not in argv.read_text().split()
