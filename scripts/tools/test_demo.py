"""Tests of scripts/tools/demo.py and its modules demo_tables.py, md_tables.py, demo_index.py.

The demo tests run build/mu_replay (make build/mu_replay; skipped without it) on a copy of
one bundled scenario in its three variants (cruise: default noise, noise-free, Magic Formula
truth), about 5 s; matplotlib on the Agg backend.
"""

import re
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import pytest  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import demo  # noqa: E402
import demo_tables  # noqa: E402
from demo_index import write_index  # noqa: E402
from md_tables import CONSOLE_WIDTH, console_table, markdown_doc  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
REPLAY = REPO / "build" / "mu_replay"
SCENARIO = "cruise"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """One demo run (--trust, as make demo): (output directory, console text)."""
    if not REPLAY.is_file():
        pytest.skip("needs build/mu_replay (make build/mu_replay)")
    scen = tmp_path_factory.mktemp("scenarios")
    for suffix in ("", ".nf", ".mf"):
        name = f"{SCENARIO}{suffix}.csv"
        (scen / name).write_bytes((REPO / "scenarios" / name).read_bytes())
    out = tmp_path_factory.mktemp("demo")
    import contextlib
    import io
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert demo.main(["--replay", str(REPLAY), "--scenarios", str(scen), "--out", str(out),
                          "--trust"]) == 0
    return out, buf.getvalue()


# ---- item 1: the Magic Formula logs are plotted with the default preset ----------------
def test_mf_logs_are_plotted_with_the_default_preset(run):
    out, _ = run
    assert (out / f"{SCENARIO}.mf.png").is_file()
    assert (out / f"{SCENARIO}.mf.default.sckf.float.csv").is_file()
    assert (out / f"{SCENARIO}.png").is_file() and (out / f"{SCENARIO}.nf.png").is_file()


def test_mf_logs_stay_out_of_the_accuracy_table(run):
    # the accuracy table (docs/RESULTS.md) is the paper configuration on the Dugoff truth
    out, _ = run
    rows = [ln for ln in (out / "accuracy.md").read_text().splitlines()
            if ln.startswith(f"| {SCENARIO}")]
    assert len(rows) == 2 and not any(".mf" in r for r in rows)


# ---- item 4: titled tables with column legends; console at most ~120 wide ------------
def test_table_files_have_a_title_and_a_column_legend(run):
    out, _ = run
    for name, (title, _, legend) in demo_tables.TABLE_DOCS.items():
        text = (out / f"{name}.md").read_text()
        assert text.startswith(f"# {title}\n"), name
        assert "Columns:" in text and all(f"*{col}*" in text for col, _ in legend), name


def test_console_lines_fit_the_width(run):
    out, console = run
    # (lines naming files are as long as the output path, short under make demo's build/demo)
    lines = [ln for ln in console.splitlines() if str(out) not in ln]
    assert max(len(ln) for ln in lines) <= CONSOLE_WIDTH
    for _, (title, _, _) in demo_tables.TABLE_DOCS.items():
        assert title in console


def test_console_table_splits_wide_tables_and_keeps_every_cell():
    head = "| key | " + " | ".join(f"column number {i}" for i in range(12)) + " |"
    lines = [head, "|" + "---|" * 13, "| row-a | " + " | ".join(f"a{i}" for i in range(12)) + " |",
             "", "A closing sentence " * 12]
    out = console_table("wide", lines, width=80)
    assert max(len(ln) for ln in out) <= 80
    text = "\n".join(out)
    for i in range(12):
        assert f"column number {i}" in text and f"a{i}" in text
    # the key column heads every group, so each row stays identifiable
    assert sum(ln.startswith("key ") for ln in out) >= 2
    assert sum(ln.startswith("row-a ") for ln in out) >= 2


def test_markdown_doc_keeps_the_table_verbatim():
    lines = ["| a | b |", "|---|---|", "| 1 | 2 |"]
    doc = markdown_doc("T", lines, [("a", "first"), ("b", "second")])
    assert doc.startswith("# T\n") and "\n".join(lines) in doc
    assert "- *b*: second" in doc


# ---- item 5: index of every plot and table, closing summary ----------------------------
def test_index_links_every_plot_and_table_relatively(run):
    out, _ = run
    index = (out / "index.md").read_text()
    links = re.findall(r"\]\(<([^>]+)>\)", index)
    assert links and not any(Path(link).is_absolute() for link in links)
    assert all((out / link).is_file() for link in links)
    written = {p.name for p in out.glob("*.png")} | {p.name for p in out.glob("*.md")} - {"index.md"}
    assert set(links) == written


def test_closing_summary_names_counts_and_index(run):
    out, console = run
    last = console.strip().splitlines()[-1]
    assert "3 plots" in last and "4 tables" in last
    assert str(out / "index.md") in last


def test_index_lists_only_this_runs_files(tmp_path):
    (tmp_path / "old.png").write_bytes(b"")
    table = tmp_path / "t.md"
    table.write_text("x")
    index = write_index(tmp_path, [("T", table)], []).read_text()
    assert "(<t.md>)" in index and "old.png" not in index


# issue 18: the Magic Formula truth plot of a scenario beside its paper-truth (Dugoff) plots
def test_index_groups_each_scenarios_plots_magic_formula_first(run):
    out, _ = run
    index = (out / "index.md").read_text()
    section = index.split(f"### {SCENARIO}\n\n", 1)[1].split("\n\n", 1)[0].splitlines()
    assert [line.split("(<", 1)[1].split(">)")[0] for line in section] == [
        f"{SCENARIO}.mf.png", f"{SCENARIO}.png", f"{SCENARIO}.nf.png"]
