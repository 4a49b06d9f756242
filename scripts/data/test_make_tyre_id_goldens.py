"""Tests of the tyre identifier's goldens (scripts/data/make_tyre_id_goldens.py): the committed
files of scenarios/golden/tyre_id/ are exactly what the generator writes from the reference
today, byte for byte (the libm backend calls the platform's C library element by element, so
the figures do not depend on NumPy's SIMD kernels; the C tests compare the library with
these files bit for bit in double, so a hand edit or a change of the reference must show here
first). One case and the stream file, so the test stays near a second.
"""

from __future__ import annotations

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = [HERE, os.path.dirname(HERE)]
import make_tyre_id_goldens as gen  # noqa: E402

GOLDEN = os.path.join(ROOT, "scenarios", "golden", "tyre_id")


def _read(path):
    with open(path, encoding="utf-8") as fh:
        return fh.read()


# REQ-TID-002
def test_committed_golden_is_what_the_reference_writes(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    case, log, filt, scheme, start, count = gen.CASES[0]
    out = tmp_path / (case + ".csv")
    gen.write(str(out), *gen.golden(log, filt, scheme, start, count, 256))
    assert _read(str(out)) == _read(os.path.join(GOLDEN, case + ".csv"))


# REQ-TID-001
def test_committed_stream_is_what_the_reference_writes(tmp_path):
    out = tmp_path / "stream.csv"
    gen.write(str(out), *gen.stream_rows())
    assert _read(str(out)) == _read(os.path.join(GOLDEN, "stream.csv"))


def test_every_case_has_a_committed_golden():
    for case, *_ in gen.CASES:
        assert os.path.isfile(os.path.join(GOLDEN, case + ".csv")), case


# REQ-TID-009
def test_committed_ellipse_golden_is_what_the_reference_writes(tmp_path, monkeypatch):
    """The friction ellipse's particle-filter golden (tid_ellipse = 1 on brake_in_turn.mf):
    what the reference writes today, and its metadata says the key is on."""
    monkeypatch.chdir(ROOT)
    case, *spec = [c for c in gen.CASES if c[0] == "brake_apf_ellipse"][0]
    out = tmp_path / (case + ".csv")
    gen.write(str(out), *gen.golden(*spec[:5], 256, *spec[5:]))
    text = _read(os.path.join(GOLDEN, case + ".csv"))
    assert _read(str(out)) == text
    assert "# tid_ellipse = 1\n" in text


# REQ-TID-009
def test_ellipse_goldens_say_their_dead_band():
    """The goldens of the ellipse as first built set tid_ell_ax_min 0 (their rows unchanged by
    the key); the band's golden the default, and the band changes its rows (|ax| crosses it
    within the excerpt)."""
    first = _read(os.path.join(GOLDEN, "brake_apf_ellipse.csv"))
    band = _read(os.path.join(GOLDEN, "brake_apf_ellipse_band.csv"))
    assert "# tid_ell_ax_min = 0\n" in first
    assert "# tid_ell_ax_min = 0\n" in _read(os.path.join(GOLDEN, "brake_sckf_ellipse.csv"))
    assert "# tid_ell_ax_min = 0.6\n" in band
    rows = [ln for ln in first.splitlines() if not ln.startswith("#")]
    rows_band = [ln for ln in band.splitlines() if not ln.startswith("#")]
    assert rows[0] == rows_band[0] and len(rows) == len(rows_band)
    assert rows[1:] != rows_band[1:]


def test_every_sckf_case_has_a_committed_golden():
    for case, *_ in gen.SCKF_CASES:
        assert os.path.isfile(os.path.join(GOLDEN, case + ".csv")), case
