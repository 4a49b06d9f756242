"""Run a generator's jobs one per process and print each job's line as it finishes: shared by
the scenario generators (make_scenarios.py, make_observer_scenarios.py,
make_mass_grade_scenarios.py, make_tyre_id_scenarios.py)."""

from __future__ import annotations

import multiprocessing
import time


def print_jobs(run_one, jobs: list, n_jobs: int, ordered: bool = False) -> float:
    """run_one(job) -> a line, for every job: in a pool of min(n_jobs, len(jobs)) processes
    when both exceed 1 (lines as the jobs finish; in the jobs' order when ordered), else in
    this process in order. Returns the seconds it took."""
    t0 = time.perf_counter()
    if n_jobs > 1 and len(jobs) > 1:
        with multiprocessing.Pool(min(n_jobs, len(jobs))) as pool:
            lines = pool.imap(run_one, jobs) if ordered else pool.imap_unordered(run_one, jobs)
            for line in lines:
                print(line, flush=True)
    else:
        for job in jobs:
            print(run_one(job), flush=True)
    return time.perf_counter() - t0
