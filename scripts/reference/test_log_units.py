"""Tests of reference/log_units.py, the Python tools' reader of DATA.md's column names,
units, scales and offsets (the rules src/host/log_units.c and csv_log.c apply in mu_replay):
the formula SI = factor(unit) * (scale * value + offset), the wheel speeds' two kinds, and
each error DATA.md lists instead of a guess."""

import math

import pytest

from . import log_units as lu


def test_scale_then_offset_in_the_column_unit_then_the_factor():
    meta = {"column_ay": "LatAcc", "unit_ay": "g", "scale_ay": "-1", "offset_ay": "0.01",
            "unit_t": "ms"}
    cols = lu.to_si(meta, {"t": [0.0, 20.0], "LatAcc": [0.1, -0.2], "note": [1.0, 2.0]})
    assert cols["t"] == [0.0, 0.02]
    # 1e-15 absolute: two roundings of numbers below 2 (ulp 2.2e-16)
    assert cols["ay"] == pytest.approx([9.80665 * (-0.1 + 0.01), 9.80665 * (0.2 + 0.01)],
                                       abs=1e-15)
    assert "LatAcc" not in cols and cols["note"] == [1.0, 2.0]


def test_wheel_speeds_as_spin_or_circumferential_speed():
    # all four in one kind (a wheel without unit_ is in rad/s, spin), as mu_replay demands
    def units(word):
        return {f"unit_omega_{w}": word for w in lu.WHEELS}

    # pytest.approx's default 1e-6 relative: any wrong factor is off by far more
    spin = lu.to_si(units("rpm"), {"omega_fl": [60.0]})
    assert spin["omega_fl"] == [pytest.approx(2 * math.pi)]      # 1 rev/s
    speed = lu.to_si({**units("km/h"), "R": "0.3"}, {"omega_fl": [36.0]})
    assert speed["omega_fl"] == [pytest.approx(10.0 / 0.3)]      # 10 m/s on a 0.3 m wheel
    assert lu.to_si(units("km/h"), {"omega_fl": [36.0]}, R=0.5)["omega_fl"] == \
        [pytest.approx(20.0)]                                    # R given by the caller
    with pytest.raises(lu.UnitError, match="rolling radius"):
        lu.to_si(units("km/h"), {"omega_fl": [36.0]})


def test_unconverted_values_are_the_values_read():
    cols = lu.to_si({}, {"ax": [-0.0]})
    assert math.copysign(1.0, cols["ax"][0]) == -1.0


@pytest.mark.parametrize("meta, header, message", [
    ({"unit_yawrate": "deg/s"}, ["yaw_rate"], "'yawrate' is not a sensor-log column"),
    ({"unit_ax": "deg"}, ["ax"], "'deg' is not a unit of column 'ax'"),
    ({"scale_ay": "0"}, ["ay"], "a scale of 0 erases the column"),
    ({"offset_ay": "zero"}, ["ay"], "not a number"),
    ({"column_t": "Time_ms"}, ["t"], "missing column 't' \\(named 'Time_ms'"),
    ({"column_vy": "vx"}, ["vx"], "'vx' is named for both 'vx' and 'vy'"),
    ({"unit_omega_fl": "rad/s", "unit_omega_fr": "km/h", "R": "0.3"},
     ["omega_fl", "omega_fr"], "mix spin"),
])
def test_what_data_md_calls_an_error_is_one(meta, header, message):
    with pytest.raises(lu.UnitError, match=message):
        lu.to_si(meta, {h: [1.0] for h in header})
