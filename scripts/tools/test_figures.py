"""The figure functions of scripts/tools/figures.py (and the ones it reuses from
mass_grade_results.py and tyre_id_results.py) on small synthetic inputs: each gives a valid
SVG with the drawn lines, and the same bytes twice (make figures must not churn the files)."""

import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]

import figures as F  # noqa: E402
import mass_grade_results as M  # noqa: E402
import tyre_id_results as TI  # noqa: E402

SVG_NS = "{http://www.w3.org/2000/svg}"


def _svg(make, tmp_path, name):
    """Save make() twice; return the parsed root of the first and both files' bytes."""
    a, b = tmp_path / f"{name}.a.svg", tmp_path / f"{name}.b.svg"
    F.save_svg(make(), a)
    F.save_svg(make(), b)
    return ET.parse(a).getroot(), a.read_bytes(), b.read_bytes()


def _texts(root):
    return [t.text for t in root.iter(SVG_NS + "text") if t.text]


def test_beta_figure_is_a_deterministic_svg(tmp_path):
    t = np.linspace(0.0, 2.0, 201)
    beta = 0.05 * np.sin(t)
    root, a, b = _svg(lambda: F.beta_figure(t, beta, beta + 0.01, np.full_like(t, 0.02),
                                            t > 1.0, "synthetic"), tmp_path, "beta")
    assert root.tag == SVG_NS + "svg"
    assert a == b
    assert b"Date" not in a                       # no date in the metadata
    assert "synthetic" in _texts(root)            # text kept as text (svg.fonttype none)


def test_tyre_curves_figure_draws_truth_and_identified_per_axle(tmp_path):
    n = 50
    alpha = np.linspace(0.0, 0.1, n)              # rad, the slip range "excited"
    c, out = {}, {}
    for a, D in (("f", 4000.0), ("r", 3500.0)):
        c[f"alpha_{a}_true"] = alpha
        c.update({f"D_{a}_true": np.full(n, D), f"C_{a}_true": np.full(n, 1.3),
                  f"B_{a}_true": np.full(n, 10.0), f"E_{a}_true": np.full(n, 0.0)})
        # identified: D 10 % low, K = B C D at the truth's
        out.update({f"D_{a}": np.full(n, 0.9 * D), f"C_{a}": np.full(n, 1.3),
                    f"K_{a}": np.full(n, 10.0 * 1.3 * D), f"E_{a}": np.full(n, 0.0)})
    root, a, b = _svg(lambda: TI.plot_curves([("synthetic", c, out, 0)]), tmp_path, "tyre")
    assert a == b
    labels = _texts(root)
    for want in ("front, truth", "front, identified", "rear, truth", "rear, identified"):
        assert want in labels


def test_curves_peak_is_the_truth_d():
    # the curves() helper behind the figure and the curve RMSE: with C = 1.3, B = 10, E = 0
    # the truth's force over tan(alpha) in [0, 0.2] reaches D sin(1.3 atan(2)) = 0.955 D
    # (atan 2 = 1.107 rad, 1.3 * 1.107 = 1.439 rad, sin = 0.9913; max at the end of the range)
    n = 10
    c = {"alpha_f_true": np.full(n, np.arctan(0.2)), "D_f_true": np.full(n, 1000.0),
         "C_f_true": np.full(n, 1.3), "B_f_true": np.full(n, 10.0), "E_f_true": np.zeros(n)}
    out = {"D_f": [1000.0], "C_f": [1.3], "K_f": [13000.0], "E_f": [0.0]}
    grid, truth, ident, D, t_max = TI.curves(c, out, 0, 0)
    assert abs(t_max - 0.2) < 1e-12
    expected = 1000.0 * np.sin(1.3 * np.arctan(2.0))
    assert abs(truth[-1] - expected) < 1e-9       # the same formula, rounding only
    assert np.allclose(ident, truth, rtol=0, atol=1e-9)   # identified = truth here


def test_mass_error_figure_has_one_panel_per_configuration(tmp_path):
    t = np.linspace(0.0, 10.0, 101)
    logs = {"synthetic_log": {"mass_true": np.full(t.size, 2000.0)}}
    runs = {("synthetic_log", g, cfg): {"t": t, "mass": 2000.0 * (1.0 + g * np.exp(-t))}
            for g in M.GUESSES for cfg in ("AUKF", "UKF + ax")}
    panels = [("synthetic_log", ("AUKF",)), ("synthetic_log", ("UKF + ax",))]
    root, a, b = _svg(lambda: M.plot_mass_error(runs, logs, panels, every=2), tmp_path, "mass")
    assert a == b
    labels = _texts(root)
    assert "synthetic_log: AUKF" in labels and "synthetic_log: UKF + ax" in labels
    assert "UKF + ax, start +50 %" in labels
