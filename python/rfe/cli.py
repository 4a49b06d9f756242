"""mu_replay's own main, compiled into the extension (rfe._rfe.lib.rfe_mu_replay_main).

``python -m rfe ARGS`` is ``mu_replay ARGS``: the same C function on the same arguments,
writing to the same stdout and stderr, returning the same exit status.
"""
from __future__ import annotations

import os
import sys
import tempfile
import threading
from collections.abc import Sequence

from ._rfe import ffi, lib

# The captured runs redirect the process's stdout and stderr (file descriptors 1 and 2):
# one at a time. The C call itself runs without the GIL (cffi releases it).
_CAPTURE = threading.Lock()


def main(argv: Sequence[str]) -> int:
    """Runs mu_replay's main with ``argv`` (without the program name) on this process's
    stdout and stderr; returns its exit status (0, 1 input or run failed, 2 bad usage)."""
    sys.stdout.flush()
    sys.stderr.flush()
    keep = [ffi.new("char[]", os.fsencode(a)) for a in ["mu_replay", *argv]]
    args = ffi.new("char *[]", keep + [ffi.NULL])
    rc = int(lib.rfe_mu_replay_main(len(keep), args))
    lib.fflush(ffi.NULL)
    return rc


def run_captured(argv: Sequence[str]) -> tuple[int, str, str]:
    """As main, with the C code's stdout and stderr captured: (exit status, stdout, stderr)."""
    with _CAPTURE, tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        sys.stdout.flush()
        sys.stderr.flush()
        saved = os.dup(1), os.dup(2)
        try:
            os.dup2(out.fileno(), 1)
            os.dup2(err.fileno(), 2)
            keep = [ffi.new("char[]", os.fsencode(a)) for a in ["mu_replay", *argv]]
            args = ffi.new("char *[]", keep + [ffi.NULL])
            rc = int(lib.rfe_mu_replay_main(len(keep), args))
            lib.fflush(ffi.NULL)
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
        out.seek(0)
        err.seek(0)
        return rc, out.read().decode(), err.read().decode()


def console_main() -> None:
    """Entry point of ``python -m rfe`` and the ``rfe-replay`` script."""
    sys.exit(main(sys.argv[1:]))
