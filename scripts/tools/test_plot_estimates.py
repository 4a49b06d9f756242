"""Tests of scripts/tools/plot_estimates.py (pytest, a few seconds; matplotlib Agg).

Small synthetic logs in tmp_path: a sensor log (with or without truth, optionally with a
text column or bad cells) and estimate logs whose valid flags are 0 for the first half; and
a bundled car-format log (scenarios/car_format/), converted to SI by hand here.
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import plot_estimates as pe  # noqa: E402

N = 50
WHEELS = pe.WHEELS


def write_csv(path: Path, cols: dict) -> Path:
    names = list(cols)
    lines = ["# generator = test", ",".join(names)]
    lines += [",".join(str(cols[n][i]) for n in names) for i in range(N)]
    path.write_text("\n".join(lines) + "\n")
    return path


def sensor_log(tmp_path: Path, truth: bool = True, text_column: bool = False) -> Path:
    t = [0.01 * i for i in range(N)]
    cols = {"t": t, "delta": [0.02] * N, "vx": [20.0 - 0.1 * i for i in range(N)],
            "ax": [-3.0] * N, "ay": [0.5] * N}
    if text_column:
        cols["driver"] = ["alice"] * N
    if truth:
        cols.update({f"mu_{w}": [0.8] * N for w in WHEELS})
    return write_csv(tmp_path / "sensor.csv", cols)


def estimate_log(tmp_path: Path, name: str, mu: float, valid_from: int = N // 2) -> Path:
    cols = {"t": [0.01 * i for i in range(N)]}
    cols.update({f"mu_{w}": [mu] * N for w in WHEELS})
    cols.update({f"sd_{w}": [0.05] * N for w in WHEELS})
    cols.update({f"valid_{w}": [int(i >= valid_from) for i in range(N)] for w in WHEELS})
    return write_csv(tmp_path / f"{name}.csv", cols)


@pytest.fixture
def three(tmp_path):
    """Three estimates with the same mu, as the paper's SCKF and CKF are."""
    return [estimate_log(tmp_path, n, 0.7) for n in ("default", "sckf", "ckf")], \
        ["default", "paper SCKF", "paper CKF"]


def legend_labels(fig) -> list[str]:
    return [t.get_text() for t in fig.legends[0].get_texts()]


def test_read_csv_ignores_text_columns(tmp_path):
    cols = pe.read_csv(sensor_log(tmp_path, text_column=True))
    assert "driver" not in cols
    assert cols["vx"][0] == 20.0 and len(cols["t"]) == N


def test_cli_plots_a_log_with_a_text_column(tmp_path, three):
    files, labels = three
    out = tmp_path / "fig.png"
    argv = ["--sensor", str(sensor_log(tmp_path, text_column=True)), "--out", str(out)]
    for f, lab in zip(files, labels):
        argv += ["--estimate", str(f), "--label", lab]
    assert pe.main(argv) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_title_says_true_only_with_truth(tmp_path, three):
    files, labels = three
    with_truth = pe.figure(sensor_log(tmp_path, truth=True), files, labels)
    without = pe.figure(sensor_log(tmp_path, truth=False), files, labels)
    assert "true" in with_truth._suptitle.get_text()
    assert "true" not in without._suptitle.get_text()
    assert "true μ" not in legend_labels(without)
    plt.close("all")


def test_coinciding_estimates_differ_in_colour_and_style(tmp_path, three):
    files, labels = three
    fig = pe.figure(sensor_log(tmp_path), files, labels)
    lines = {ln.get_label(): ln for ln in fig.axes[0].lines}
    est = [lines[f"{lab} μ̂"] for lab in labels]
    for i in range(len(est)):
        for j in range(i + 1, len(est)):
            a, b = est[i], est[j]
            assert a.get_color() != b.get_color()
            assert (a.get_linestyle(), a.get_linewidth(), a.get_marker()) != \
                   (b.get_linestyle(), b.get_linewidth(), b.get_marker())
    # SCKF and CKF (the pair the paper compares) in different dashes, not only widths
    assert est[1].get_linestyle() != est[2].get_linestyle()
    plt.close(fig)


def test_not_valid_is_shaded_per_estimate_apart_from_the_sd_band(tmp_path, three):
    files, labels = three
    fig = pe.figure(sensor_log(tmp_path), files, labels)
    names = legend_labels(fig)
    for lab in labels:
        assert f"{lab} not valid" in names
    assert "default ±2 sd" in names
    patches = {c.get_label(): c for c in fig.axes[0].collections}
    band, shade = patches["default ±2 sd"], patches["default not valid"]
    assert shade.get_hatch() and not band.get_hatch()
    # the lane covers only the not-valid half of the log (valid from t = 0.25 s)
    xmax = max(p.vertices[:, 0].max() for p in shade.get_paths())
    assert xmax < 0.01 * (N // 2) + 1e-9
    plt.close(fig)


def test_no_shading_when_every_sample_is_valid(tmp_path):
    f = estimate_log(tmp_path, "ok", 0.7, valid_from=0)
    fig = pe.figure(sensor_log(tmp_path), [f], ["ok"])
    assert not any("not valid" in lab for lab in legend_labels(fig))
    plt.close(fig)


def test_manoeuvre_panel_shows_speed_steering_and_accelerations(tmp_path, three):
    files, labels = three
    fig = pe.figure(sensor_log(tmp_path), files, labels)
    drawn = {ln.get_label(): ln for ax in fig.axes for ln in ax.lines}
    for name in ("vx", "δ", "ax", "ay"):
        assert name in drawn, name
    assert list(drawn["vx"].get_ydata())[:2] == [20.0, 19.9]
    assert drawn["δ"].get_ydata()[0] == pytest.approx(0.02 * 180 / 3.141592653589793)
    # below the wheels: the manoeuvre axes share the time axis with the mu panels
    mu_ax, man_ax = fig.axes[0], drawn["ax"].axes
    assert man_ax.get_position().y1 < min(a.get_position().y0 for a in fig.axes[:4])
    assert man_ax.get_shared_x_axes().joined(man_ax, mu_ax)
    plt.close(fig)


# ---- a car's logger's log (DATA.md "Units, scales and names of a recorded log") ----------
CAR_LOG = Path(__file__).resolve().parents[2] / "scenarios" / "car_format" / "dlc_mu035.csv"


def raw_rows(path: Path) -> tuple[dict, list[dict]]:
    """(metadata, rows as {header: text}) with no interpretation, for the hand conversion."""
    meta, body = {}, []
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("#"):
            key, _, value = line[1:].partition(" = ")
            meta[key.strip()] = value.strip()
        else:
            body.append(line.split(","))
    return meta, [dict(zip(body[0], r)) for r in body[1:]]


def test_a_car_format_log_is_plotted_in_si(tmp_path):
    meta, rows = raw_rows(CAR_LOG)
    # the log declares ms, deg, g, km/h and the SAE lateral sense: the trap this guards
    assert meta["unit_t"] == "ms" and meta["unit_ay"] == "g" and meta["scale_ay"] == "-1.0"
    est = estimate_log(tmp_path, "est", 0.4)
    out = tmp_path / "car.png"
    assert pe.main(["--sensor", str(CAR_LOG), "--estimate", str(est), "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    fig = pe.figure(CAR_LOG, [est], ["est"])
    drawn = {ln.get_label(): ln for ax in fig.axes for ln in ax.lines}
    g, kmh, ratio = 9.80665, 1 / 3.6, float(meta["obs_steer_ratio"])
    for i in (1, 200):   # two rows, converted here by hand
        r = rows[i]
        t = float(r["Time_ms"]) * 1e-3
        ax = float(r["LongAccel"]) * g
        ay = -float(r["LatAccel_SAE"]) * g
        v = sum(float(r[f"WheelSpeed_{w.upper()}"]) for w in WHEELS) / 4 * kmh
        delta_deg = float(r["SteeringWheelAngle"]) / ratio
        # 1e-12 relative: the reader computes (factor*scale)*x + factor*offset and divides
        # a wheel speed by R to spin and multiplies it back, the hand conversion in another
        # order; the two differ by a few ulps (1e-16 each), far below any unit error
        # (the smallest, km/h against m/s, is a factor 3.6)
        assert drawn["ax"].get_xdata()[i] == pytest.approx(t, rel=1e-12, abs=1e-15)
        assert drawn["ax"].get_ydata()[i] == pytest.approx(ax, rel=1e-12, abs=1e-15)
        assert drawn["ay"].get_ydata()[i] == pytest.approx(ay, rel=1e-12, abs=1e-15)
        assert drawn["wheels ω̄·R"].get_ydata()[i] == pytest.approx(v, rel=1e-12)
        assert drawn["δ"].get_ydata()[i] == pytest.approx(delta_deg, rel=1e-12, abs=1e-15)
    # the row-200 values are not zero, so the comparisons above tell units apart
    assert abs(float(rows[200]["LatAccel_SAE"])) > 0.05
    assert abs(float(rows[200]["SteeringWheelAngle"])) > 5
    plt.close("all")


def test_a_unit_metadata_typo_is_an_error_not_a_wrong_plot(tmp_path):
    bad = tmp_path / "typo.csv"
    text = CAR_LOG.read_text(encoding="utf-8")
    bad.write_text(text.replace("# unit_yaw_rate = deg/s", "# unit_yawrate = deg/s"),
                   encoding="utf-8")
    with pytest.raises(SystemExit, match="'yawrate' is not a sensor-log column"):
        pe.read_csv(bad)


# ---- bad cells (issue 18): empty, nan and inf cells are gaps, not a reason to drop a column
def test_empty_nan_and_inf_cells_are_nan_and_keep_their_column(tmp_path):
    path = tmp_path / "cells.csv"
    path.write_text("# generator = test\n"
                    "t,ay,ax,note\n"
                    "0,0.5,1,a\n"
                    "0.01,,nan,\n"          # an empty ay cell (the CLI: a bad cell) and nan
                    "0.02,inf,-inf,b\n"
                    "0.03, 0.7 ,2,c\n", encoding="utf-8")
    cols = pe.read_csv(path)
    assert "note" not in cols                 # a text column stays out
    assert cols["t"] == [0.0, 0.01, 0.02, 0.03]
    ay, ax = cols["ay"], cols["ax"]
    assert ay[0] == 0.5 and ay[3] == 0.7 and ax[0] == 1.0 and ax[3] == 2.0
    assert all(v != v for v in (ay[1], ay[2], ax[1], ax[2]))   # NaN: not equal to itself


def test_a_column_with_one_text_cell_is_still_left_out(tmp_path):
    path = tmp_path / "mixed.csv"
    path.write_text("t,ay,driver\n0,0.5,\n0.01,0.6,alice\n", encoding="utf-8")
    cols = pe.read_csv(path)
    assert "driver" not in cols and cols["ay"] == [0.5, 0.6]


def test_an_empty_ay_cell_keeps_the_ay_trace(tmp_path, three):
    files, labels = three
    path = sensor_log(tmp_path)
    lines = path.read_text().splitlines()
    header = lines[1].split(",")
    cells = lines[5].split(",")
    cells[header.index("ay")] = ""
    lines[5] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    fig = pe.figure(path, files, labels)
    drawn = {ln.get_label(): ln for ax in fig.axes for ln in ax.lines}
    y = list(drawn["ay"].get_ydata())
    assert len(y) == N and y[3] != y[3] and y[0] == 0.5   # sample 3 (file line 6) is the gap
    plt.close(fig)
