"""Names, units, scales and offsets of a recorded sensor log's columns (DATA.md "Units, scales
and names of a recorded log"): the Python side of src/host/log_units.c and csv_log.c's
column_meta, for every Python tool that reads a sensor log a car's logger wrote.

For each column of DATA.md's tables, the metadata may give ``column_<c>`` (the header name
it has in the log), ``unit_<c>`` (a unit word), ``scale_<c>`` and ``offset_<c>``; the value
read is SI = factor(unit) * (scale * value + offset), computed as C does:
(factor * scale) * value + factor * offset. Wheel speeds in a speed unit (the wheel's
circumferential speed) become spin by the rolling radius R. The errors are DATA.md's (a key
naming no column, a unit of another quantity, a scale of 0, wheel speeds of both kinds, an
alias naming a header column that is not there, one header column named for two columns).

Standard library only: the plotting tools use it without numpy.
"""

from __future__ import annotations

import math

WHEELS = ("fl", "fr", "rl", "rr")

# DATA.md's unit words per quantity and their factors to SI, as src/host/log_units.c (the
# first of each quantity is the SI unit).
UNITS: dict[str, dict[str, float]] = {
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0, "mrad": 1e-3},
    "rate": {"rad/s": 1.0, "deg/s": math.pi / 180.0, "rpm": 2.0 * math.pi / 60.0},
    "angular acceleration": {"rad/s^2": 1.0, "rad/s2": 1.0, "deg/s^2": math.pi / 180.0,
                             "deg/s2": math.pi / 180.0},
    "speed": {"m/s": 1.0, "km/h": 1.0 / 3.6, "kph": 1.0 / 3.6, "mph": 0.44704},
    "acceleration": {"m/s^2": 1.0, "m/s2": 1.0, "g": 9.80665},
    "pressure": {"MPa": 1.0, "kPa": 1e-3, "bar": 0.1, "Pa": 1e-6, "psi": 6.894757293168361e-3},
    "torque": {"N m": 1.0, "Nm": 1.0, "kN m": 1e3, "kNm": 1e3},
    "none": {"1": 1.0},
}

# The sensor-log columns of DATA.md and their quantity (csv_log.c's k_cols); "wheel": a rate
# (spin) or a speed (circumferential) unit.
COLUMNS: dict[str, str] = {
    "t": "time", "delta": "angle", "swa": "angle", "vx": "speed", "vy": "speed",
    "yaw_rate": "rate", "yaw_acc": "angular acceleration", "ax": "acceleration",
    "ay": "acceleration", "grade": "angle",
    **{f"omega_{w}": "wheel" for w in WHEELS}, **{f"mu_{w}": "none" for w in WHEELS},
    **{f"util_{w}": "none" for w in WHEELS}, **{f"p_{w}": "pressure" for w in WHEELS},
    **{f"torque_{w}": "torque" for w in WHEELS},
}
PREFIXES = ("unit_", "scale_", "offset_", "column_")


class UnitError(ValueError):
    """Metadata that DATA.md's column rules reject."""


def _number(meta: dict, key: str, default: float, where: str) -> float:
    if key not in meta:
        return default
    try:
        v = float(meta[key])
    except ValueError:
        raise UnitError(f"{where}: metadata '{key}': not a number: '{meta[key]}'") from None
    if not math.isfinite(v):
        raise UnitError(f"{where}: metadata '{key}': not finite: '{meta[key]}'")
    return v


def _factor(column: str, unit: str, where: str) -> tuple[float, bool]:
    """(factor to SI, circumferential) of @p unit for @p column."""
    quantity = COLUMNS[column]
    kinds = (("rate", False), ("speed", True)) if quantity == "wheel" else ((quantity, False),)
    for q, circumferential in kinds:
        if unit in UNITS[q]:
            return UNITS[q][unit], circumferential
    words = ", ".join(w for q, _ in kinds for w in UNITS[q])
    raise UnitError(f"{where}: metadata 'unit_{column}': '{unit}' is not a unit of column "
                    f"'{column}' (one of: {words})")


def column_rules(meta: dict, header: list[str], where: str = "log") -> dict[str, tuple]:
    """{DATA.md column: (header name, a, b, circumferential)} for each column the log has:
    SI = a * value + b (before the division by R of a circumferential wheel speed). Header
    columns that are no DATA.md column (extras, truth such as vx_true) are not in it."""
    for key in meta:
        for prefix in PREFIXES:
            if key.startswith(prefix) and key[len(prefix):] not in COLUMNS:
                raise UnitError(f"{where}: metadata '{key}': '{key[len(prefix):]}' is not a "
                                f"sensor-log column (DATA.md)")
    rules: dict[str, tuple] = {}
    named: dict[str, str] = {}
    wheel_kind = None
    for column in COLUMNS:
        alias = meta.get(f"column_{column}", "") or column
        factor, circumferential = 1.0, False
        if f"unit_{column}" in meta:
            factor, circumferential = _factor(column, meta[f"unit_{column}"], where)
        scale = _number(meta, f"scale_{column}", 1.0, where)
        if scale == 0.0:
            raise UnitError(f"{where}: metadata 'scale_{column}': a scale of 0 erases the column")
        offset = _number(meta, f"offset_{column}", 0.0, where)
        if COLUMNS[column] == "wheel":
            if wheel_kind is not None and circumferential != wheel_kind:
                raise UnitError(f"{where}: metadata: the wheel speeds mix spin (rad/s, rpm) and "
                                f"circumferential (km/h, m/s) units; give all four in one kind")
            wheel_kind = circumferential
        if alias != column and alias not in header:
            raise UnitError(f"{where}: missing column '{column}' (named '{alias}' by its "
                            f"column_{column} metadata)")
        if alias not in header:
            continue
        if alias in named:
            raise UnitError(f"{where}: column '{alias}' is named for both '{named[alias]}' and "
                            f"'{column}' (column_ metadata)")
        named[alias] = column
        rules[column] = (alias, factor * scale, factor * offset, circumferential)
    return rules


def to_si(meta: dict, columns: dict[str, list[float]], R: float | None = None,
          where: str = "log") -> dict[str, list[float]]:
    """@p columns (header name -> values, as read) with DATA.md's columns under their own
    names, in SI; the other header columns as they are. @p R: the rolling radius for wheel
    speeds in a speed unit (the log's `R` metadata when None; an error when neither)."""
    rules = column_rules(meta, list(columns), where)
    out = {name: values for name, values in columns.items()
           if name not in {rule[0] for rule in rules.values()}}
    for column, (alias, a, b, circumferential) in rules.items():
        values = columns[alias]
        if circumferential:
            radius = R if R is not None else _number(meta, "R", math.nan, where)
            if not radius > 0.0:
                raise UnitError(f"{where}: wheel speeds in a speed unit need the rolling radius "
                                f"R (metadata or parameters), > 0")
            out[column] = [(a * v + b) / radius for v in values]
        elif (a, b) == (1.0, 0.0):
            out[column] = values   # as read (no arithmetic: -0.0 stays -0.0)
        else:
            out[column] = [a * v + b for v in values]
    return out
