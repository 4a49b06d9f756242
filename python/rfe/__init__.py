"""rfe: the road-friction estimator's C library from Python (docs/PYTHON.md).

    import rfe
    est = rfe.replay("scenarios/cruise.csv", real="double")   # mu_replay's estimate log
    rfe.metrics(est)                                           # its accuracy (the CLI's)
    python -m rfe --in LOG.csv --out EST.csv                   # mu_replay itself

Everything is computed by the C library and mu_replay's own C code, compiled into the
extension rfe._rfe; nothing is reimplemented in Python.
"""
from .errors import (AbiError, InputError, NonFiniteError, NotInitialisedError,
                     NotPositiveDefiniteError, NullError, ParamError, RangeError, RfeError,
                     RfeWarning, SizeError, UsageError)
from .mdf import MappingError, MissingChannelError, read_mdf, resample
from .parquet import read_parquet, write_parquet
from .plot import plot_estimates
from .replay import Estimator, metrics, read_log, replay, write_log

__version__ = "0.1.0"
__all__ = ["Estimator", "replay", "metrics", "read_log", "write_log", "read_mdf", "resample",
           "read_parquet", "write_parquet",
           "MappingError", "MissingChannelError", "plot_estimates", "RfeError", "UsageError",
           "InputError", "NullError", "NonFiniteError", "RangeError", "ParamError", "SizeError",
           "NotPositiveDefiniteError", "NotInitialisedError", "AbiError", "RfeWarning"]
