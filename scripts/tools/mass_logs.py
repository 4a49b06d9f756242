"""The mass and grade logs every mass study reads: each CSV of scenarios/mass_grade/, so that a
log added there (make mass-grade-scenarios) enters every study's tables on its next run."""
import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MG_DIR = os.path.join(ROOT, "scenarios", "mass_grade")


def mass_grade_logs():
    """The mass and grade logs' file names (scenarios/mass_grade/*.csv), sorted."""
    return sorted(f for f in os.listdir(MG_DIR) if f.endswith(".csv"))


def mass_grade_names():
    """The same logs' names without the .csv, sorted."""
    return [f[:-4] for f in mass_grade_logs()]
