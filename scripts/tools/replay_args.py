"""The command line the study tools that run mu_replay share: --mu-replay (the binary, default
build/mu_replay), --page (the docs page whose generated region to rewrite; empty: print only)
and, for those that run logs side by side, --jobs; a missing binary stops the tool with a
message that names it and says to build it first."""
from __future__ import annotations

import argparse
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def replay_args(doc: str, who: str, jobs: int | None = None, argv=None,
                extra=None) -> argparse.Namespace:
    """Parse the shared options; doc's first paragraph is the description, who names the tool
    in the error, jobs (when given) is --jobs's default; extra (when given) adds the tool's own
    options to the parser."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--mu-replay", default=os.path.join(ROOT, "build", "mu_replay"))
    ap.add_argument("--page", default="")
    if jobs is not None:
        ap.add_argument("--jobs", type=int, default=jobs)
    if extra is not None:
        extra(ap)
    a = ap.parse_args(argv)
    if not os.access(a.mu_replay, os.X_OK):
        raise SystemExit(f"{who}: {a.mu_replay} not found: run make first")
    return a
