"""The in-memory replay behind Estimator.run and Estimator.step (src/host/replay_mem.h).

Columns go to the C code as arrays of doubles, are read by the CSV reader's own rules
(column names and groups, unit_/scale_/offset_/column_ metadata, bad cells), the run is set
up by mu_replay's own code (its options, the parameter precedence, the checks) and stepped by
the replay core every other run uses, and the estimates come back as an array of doubles:
no file, no text, nothing printed. Each run owns its C state (allocated here with cffi, no
heap in C for it), so runs in several threads go side by side; cffi releases the GIL around
each C call.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from . import errors
from ._rfe import ffi, lib
from .replay import _fmt

COLS: list[str] = [ffi.string(lib.rfe_replay_mem_col(i)).decode()
                   for i in range(lib.RFE_MEM_COLS) if lib.rfe_replay_mem_col(i) != ffi.NULL]
_INT_COLS = {"valid_fl", "valid_fr", "valid_rl", "valid_rr", "status", "mg_status",
             "grade_walk", "mg_mismatch", "tid_status", "tid_flags"}
_VELOCITY = COLS[COLS.index("vx_est"):COLS.index("sd_beta") + 1]
# mg_mismatch came last to the C array (RFE_MEM_COLS) but follows grade_walk in the
# estimate log (csv_log.c), so the mass and grade group names it and the curve feed's stops
# before it.
_MASS_GRADE = COLS[COLS.index("mass_est"):COLS.index("grade_walk") + 1] + ["mg_mismatch"]
_TYRE_ID = COLS[COLS.index("mu_id_f"):COLS.index("tid_flags") + 1]
_TYRE_FEED = COLS[COLS.index("cy_used"):COLS.index("r_model_rel_used") + 1]
_BASE = COLS[:COLS.index("vx_est")]
REAL_WORDS = {"float": 0, "double": 1, "q31": 2}


def _error(code: int, err: Any) -> errors.RfeError:
    """The typed exception of a C return code: a library status (> 0) picks its class."""
    msg = ffi.string(err.msg).decode(errors="replace") or f"failed with code {code}"
    if code == lib.RFE_MEM_USAGE:
        return errors.UsageError(msg, exit_code=2)
    file = ffi.string(err.file).decode(errors="replace") if err.file != ffi.NULL else None
    where = dict(file=file, line=int(err.line) or None, col=int(err.col) or None)
    if code == lib.RFE_MEM_INPUT:
        return errors.InputError(msg, status=None, **where)
    return errors.BY_STATUS.get(code, errors.InputError)(msg, status=code, **where)


class _Block:
    """The C view of a block of samples: the metadata pairs and the columns (names and
    contiguous float64 values), kept alive as long as the block."""

    def __init__(self, columns: Mapping[str, Any], meta: Mapping[str, Any]) -> None:
        self._keep: list[Any] = []
        names = list(columns)
        n = {len(np.atleast_1d(np.asarray(columns[c]))) for c in names}
        if len(n) > 1:
            raise errors.UsageError("the columns have different lengths", exit_code=2)
        self.n_rows = n.pop() if n else 0
        self.cols = ffi.new("rfe_column_t[]", max(1, len(names)))
        for j, name in enumerate(names):
            self.cols[j].name = self._c(str(name))
            values = self._values(columns[name])
            self.cols[j].values = ffi.NULL if values is None else \
                ffi.cast("const double *", ffi.from_buffer(values))
        self.n_cols = len(names)
        self.meta = ffi.new("rfe_kv_t[]", max(1, len(meta)))
        for i, (k, v) in enumerate(meta.items()):
            self.meta[i].key = self._c(str(k))
            self.meta[i].value = self._c(_fmt(v))
        self.n_meta = len(meta)

    def _c(self, s: str) -> Any:
        b = ffi.new("char[]", s.encode())
        self._keep.append(b)
        return b

    def _values(self, col: Any) -> np.ndarray | None:
        """A column as contiguous doubles, or None when it holds no numbers (text): the C
        reader then treats it as a CSV column of text (an error if it is an input)."""
        try:
            a = np.ascontiguousarray(np.atleast_1d(np.asarray(col)), dtype=np.float64)
        except (TypeError, ValueError):
            return None
        self._keep.append(a)
        return a


class Run:
    """One replay: mu_replay's set-up on the first block of samples, then any number of
    blocks stepped in order (the state in C memory this object owns)."""

    def __init__(self, args: list[str], params_text: str | None,
                 columns: Mapping[str, Any], meta: Mapping[str, Any]) -> None:
        argv_keep = [ffi.new("char[]", a.encode()) for a in ["mu_replay", *args]]
        argv = ffi.new("char *[]", argv_keep)
        ptext = ffi.new("char[]", params_text.encode()) if params_text is not None else ffi.NULL
        real = REAL_WORDS.get(_option(args, "--real", "float"), 0)
        size = int(lib.rfe_replay_mem_state_size(real))
        self.mem = ffi.new("rfe_replay_mem_t *")
        # doubles, so the state is aligned as the C structs need (8 bytes)
        self.state = ffi.new("double[]", (size + 7) // 8)
        self.meta = dict(meta)
        block = _Block(columns, self.meta)
        err = ffi.new("rfe_io_error_t *")
        code = lib.rfe_mu_replay_open(self.mem, len(argv_keep), argv, ptext, block.meta,
                                      block.n_meta, block.cols, block.n_cols, block.n_rows,
                                      self.state, err)
        if code != 0:
            raise _error(code, err)
        names = _BASE + (_VELOCITY if self.mem.observer else []) + \
            (_MASS_GRADE if self.mem.mass_grade else []) + \
            (_TYRE_ID if self.mem.tyre_id else []) + (_TYRE_FEED if self.mem.tyre_feed else [])
        self.columns = names
        self._index = [COLS.index(c) for c in names]

    @property
    def dt_given(self) -> bool:
        return bool(self.mem.dt_given)

    @property
    def preset_vehicle(self) -> bool:
        return bool(self.mem.preset_vehicle)

    def feed(self, columns: Mapping[str, Any]) -> np.ndarray:
        """Steps a block; returns its estimate rows, RFE_MEM_COLS values each."""
        block = _Block(columns, self.meta)
        out = np.zeros((block.n_rows, lib.RFE_MEM_COLS), dtype=np.float64)
        err = ffi.new("rfe_io_error_t *")
        code = lib.rfe_replay_mem_feed(self.mem, block.meta, block.n_meta, block.cols,
                                       block.n_cols, block.n_rows,
                                       ffi.cast("double *", ffi.from_buffer(out)), err)
        if code != 0:
            raise _error(code, err)
        return out

    def frame(self, out: np.ndarray) -> pd.DataFrame:
        """The estimate rows as the estimate log's columns (integers as int64)."""
        data = {}
        for name, i in zip(self.columns, self._index):
            col = out[:, i]
            data[name] = col.astype(np.int64) if name in _INT_COLS else col
        return pd.DataFrame(data)

    def stats(self) -> dict[str, Any]:
        """The counters of the rows stepped: steps, statuses, gaps (mu_replay's summary)."""
        st = ffi.new("rfe_replay_q31_stats_t *")
        code = lib.rfe_replay_mem_stats(self.mem, st)
        if code != 0:
            raise _error(code, ffi.new("rfe_io_error_t *"))
        b = st.base
        out: dict[str, Any] = {
            "steps": int(b.n_steps),
            "status_counts": {str(s): int(b.status_count[s]) for s in range(32)
                              if b.status_count[s]},
            "gaps": {"count": int(b.n_gaps), "missed_periods": int(b.n_skipped)},
        }
        if self.mem.observer:
            out["gaps"]["observer_restarts"] = int(b.n_restarts)
        if self.mem.real == REAL_WORDS["q31"]:
            out["saturation"] = {"estimator_total": int(st.est_sat),
                                 "estimator_steps": int(st.est_sat_rows),
                                 "estimator_max_per_step": int(st.est_sat_max),
                                 "input_values": int(st.input_sat),
                                 "input_rows": int(st.input_sat_rows)}
        return out


def _option(args: list[str], flag: str, default: str) -> str:
    """The value of ``flag`` in an argument list (as mu_replay reads it), or ``default``."""
    for i, a in enumerate(args):
        if a == flag and i + 1 < len(args):
            return args[i + 1]
        if a.startswith(flag + "="):
            return a[len(flag) + 1:]
    return default


def columns_of(data: pd.DataFrame | Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """The columns and metadata of a DataFrame (``attrs["meta"]``) or of a mapping."""
    if isinstance(data, pd.DataFrame):
        return {str(c): data[c].to_numpy() for c in data.columns}, \
            dict(data.attrs.get("meta", {}) or {})
    return dict(data), {}
