"""Shared checks of the reference's tests (not collected by pytest: no test_ prefix)."""
from __future__ import annotations

from . import params


def assert_study_keys_off(keys) -> None:
    """Each key is a reference-only study option that is 0 by default and set by no preset,
    so the library's presets, goldens and every default run stay today's."""
    for key in keys:
        assert params.DEFAULTS[key] == 0.0, key
        assert key in params.REFERENCE_ONLY, key
        assert not any(key in pre for pre in params.PRESETS.values()), key
