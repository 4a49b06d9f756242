"""``python -m rfe ARGS``: mu_replay ARGS (the same C main; docs/PYTHON.md)."""
from .cli import console_main

console_main()
