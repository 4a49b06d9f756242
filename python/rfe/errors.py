"""Typed exceptions of the rfe package, each carrying the library's status.

The C code reports a failed run as mu_replay does: an exit status (1 malformed input or a
failed run, 2 bad usage) and one line ``mu_replay: FILE:LINE:COL: message``. The exception
is chosen by the library status the message names (its rfe_status_str text, taken from the
C library, or the fixed-point range check's wording); ``status`` is that rfe_status_t value,
or None when the error is not the library's (a file that cannot be read, a malformed cell).
A run in memory (rfe.inmem) returns its status as a code instead, which picks the class
(BY_STATUS) without reading the message.
"""
from __future__ import annotations

import re

# rfe_status_t values (include/rfe/common.h).
RFE_ERR_NULL = 16
RFE_ERR_NONFINITE = 17
RFE_ERR_RANGE = 18
RFE_ERR_PARAM = 19
RFE_ERR_SIZE = 20
RFE_ERR_NOT_POSITIVE_DEFINITE = 21
RFE_ERR_NOT_INITIALISED = 22
RFE_ERR_ABI = 23


class RfeError(Exception):
    """Base of every rfe error.

    Attributes:
        message: the C code's message, without the ``mu_replay: FILE:LINE:COL:`` prefix.
        status: the library's rfe_status_t value, or None (not a library status).
        exit_code: mu_replay's exit status for the same input (1 or 2).
        file, line, col: where the C code located the problem (None when it did not).
    """

    def __init__(self, message: str, *, status: int | None = None, exit_code: int = 1,
                 file: str | None = None, line: int | None = None,
                 col: int | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.status = status
        self.exit_code = exit_code
        self.file = file
        self.line = line
        self.col = col

    def __str__(self) -> str:
        where = ":".join(str(x) for x in (self.file, self.line, self.col) if x)
        status = "" if self.status is None else f" [status {self.status}]"
        return f"{where}: {self.message}{status}" if where else f"{self.message}{status}"


class UsageError(RfeError, ValueError):
    """An option mu_replay would refuse as bad usage (its exit status 2)."""


class InputError(RfeError):
    """Malformed input or a failed run (mu_replay's exit status 1)."""


class NullError(InputError):
    """RFE_ERR_NULL (16)."""


class NonFiniteError(InputError):
    """RFE_ERR_NONFINITE (17): an input is NaN or infinite."""


class RangeError(InputError):
    """RFE_ERR_RANGE (18): an input or a parameter is outside its limits or Q format."""


class ParamError(InputError):
    """RFE_ERR_PARAM (19): a parameter is invalid."""


class SizeError(InputError):
    """RFE_ERR_SIZE (20)."""


class NotPositiveDefiniteError(InputError):
    """RFE_ERR_NOT_POSITIVE_DEFINITE (21)."""


class NotInitialisedError(InputError):
    """RFE_ERR_NOT_INITIALISED (22)."""


class AbiError(InputError):
    """RFE_ERR_ABI (23)."""


class RfeWarning(UserWarning):
    """A note or warning mu_replay prints on stderr during a successful run."""


BY_STATUS: dict[int, type[InputError]] = {
    RFE_ERR_NULL: NullError, RFE_ERR_NONFINITE: NonFiniteError, RFE_ERR_RANGE: RangeError,
    RFE_ERR_PARAM: ParamError, RFE_ERR_SIZE: SizeError,
    RFE_ERR_NOT_POSITIVE_DEFINITE: NotPositiveDefiniteError,
    RFE_ERR_NOT_INITIALISED: NotInitialisedError, RFE_ERR_ABI: AbiError,
}

_LINE = re.compile(r"^mu_replay: (?:(?P<file>.*?)(?::(?P<line>\d+))?(?::(?P<col>\d+))?: )?"
                   r"(?P<msg>.*)$")


# --strict: a bad cell of an estimator input (csv_log.c); without --strict it goes to the
# estimator as NaN/Inf, which rejects the sample with RFE_ERR_NONFINITE.
_BAD_CELL = re.compile(r"^column '[^']*': (empty field|nan/inf is not allowed|out of range)")


def from_cli(exit_code: int, stderr: str, status_text: dict[int, str]) -> RfeError:
    """The exception of a failed CLI run: its exit code, its stderr, and the library's
    status strings (``status_text``: rfe_status_t -> rfe_status_str)."""
    lines = [ln for ln in stderr.splitlines() if ln.startswith("mu_replay: ")]
    text = lines[0] if lines else (stderr.strip() or f"mu_replay exited with {exit_code}")
    m = _LINE.match(text)
    if exit_code == 2:
        msg = m.group("msg") if m else text
        # the usage reasons have no file part: "mu_replay: --real must be ..."
        msg = text[len("mu_replay: "):] if text.startswith("mu_replay: ") else msg
        return UsageError(msg, exit_code=2)
    file = m.group("file") if m else None
    line = int(m.group("line")) if m and m.group("line") else None
    col = int(m.group("col")) if m and m.group("col") else None
    msg = m.group("msg") if m else text
    status = None
    if _BAD_CELL.match(msg):
        status = RFE_ERR_NONFINITE  # what the estimator returns for it without --strict
    elif "does not fit the fixed-point formats" in msg:
        status = RFE_ERR_RANGE
    else:
        for code in sorted(BY_STATUS):
            if status_text[code] in msg:
                status = code
                break
    cls = BY_STATUS.get(status, InputError) if status is not None else InputError
    return cls(msg, status=status, exit_code=exit_code, file=file, line=line, col=col)
