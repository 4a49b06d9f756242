"""Sensor and estimate logs as Parquet (docs/PYTHON.md "Parquet").

A Parquet file holds the log's columns as they are in the DataFrame (doubles as IEEE
doubles, so bit for bit; integers as int64) and the log's metadata, ``attrs["meta"]``, as
JSON under the file's key-value metadata key ``rfe.meta``. Needs pyarrow
(``pip install .[parquet]``).
"""
from __future__ import annotations

import json
import os
from typing import Any

import pandas as pd

from . import errors

META_KEY = b"rfe.meta"
SUFFIXES = (".parquet", ".pq")


def _pyarrow() -> Any:
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError as e:  # pragma: no cover
        raise ImportError("Parquet needs pyarrow: pip install rfe[parquet]") from e
    return pa, pq


def write_parquet(df: pd.DataFrame, path: str | os.PathLike) -> None:
    """Writes a sensor or estimate log's DataFrame, with ``attrs["meta"]``, as Parquet."""
    pa, pq = _pyarrow()
    table = pa.Table.from_pandas(df, preserve_index=False)
    meta = {str(k): v for k, v in (df.attrs.get("meta", {}) or {}).items()}
    schema_meta = dict(table.schema.metadata or {})
    schema_meta[META_KEY] = json.dumps(meta).encode("utf-8")
    pq.write_table(table.replace_schema_metadata(schema_meta), os.fspath(path))


def read_parquet(path: str | os.PathLike) -> pd.DataFrame:
    """Reads a log written by :func:`write_parquet` (or any Parquet table of DATA.md
    columns: without ``rfe.meta`` its metadata is empty); ``attrs["meta"]`` as written."""
    pa, pq = _pyarrow()
    where = os.fspath(path)
    try:
        table = pq.read_table(where)
    except (OSError, pa.ArrowInvalid) as e:
        raise errors.InputError(f"cannot read the Parquet file: {e}", file=where) from e
    raw = (table.schema.metadata or {}).get(META_KEY)
    df = table.to_pandas()
    df.attrs.clear()
    df.attrs["meta"] = json.loads(raw.decode("utf-8")) if raw else {}
    return df
