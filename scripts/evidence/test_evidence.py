"""Tests of the evidence gates: scripts/evidence/trace_requirements.py and scripts/evidence/evidence_coverage.py.

Each builds a miniature repository in a temporary folder (requirements, tagged tests, JUnit
XML, a Cobertura report, a justification table) and checks that the gate passes exactly when
it should and names what is wrong when it fails.
"""
import json
import os
import sys
import textwrap

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)
import evidence_coverage  # noqa: E402
import trace_requirements  # noqa: E402

REQS = """\
| ID | requirement | source | verification |
|---|---|---|---|
| REQ-A-001 | first | here | test |
| REQ-A-002 | second | here | test, make lib |
| REQ-B-001 | by a gate | here | make lib |
| REQ-B-002 | by a gate not defined yet | here | make not-yet |
"""

C_TEST = """\
/* a doc comment
 * REQ-A-001 */
static void test_one(void **state)
{
}

/* REQ-A-002, REQ-A-001 */
static void test_two(void **state)
{
}

static void test_untagged(void **state)
{
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_one),
        cmocka_unit_test(test_two),
        cmocka_unit_test(test_untagged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
"""

PY_TEST = """\
import pytest


# REQ-A-002
@pytest.mark.parametrize("x", [1, 2])
def test_py(x):
    pass
"""


def junit(cases):
    body = "".join(
        f'<testcase name="{n}" classname="{c}">' + ("<failure>boom</failure>" if r == "FAIL" else
                                                   "<skipped/>" if r == "SKIP" else "") + "</testcase>"
        for c, n, r in cases)
    return f'<?xml version="1.0"?><testsuites><testsuite name="tests">{body}</testsuite></testsuites>'


def make_repo(tmp_path, c_test=C_TEST, reqs=REQS, f32=None, py=None):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "REQUIREMENTS.md").write_text(reqs)
    (tmp_path / "test").mkdir()
    (tmp_path / "test" / "test_mod_flt.c").write_text(c_test)
    (tmp_path / "scripts").mkdir()
    (tmp_path / "scripts" / "test_tool.py").write_text(PY_TEST)
    (tmp_path / "Makefile").write_text("lib: x\n\tcc\n")
    res = tmp_path / "build" / "results"
    for tree in ("f32", "f64"):
        (res / tree).mkdir(parents=True)
        cases = f32 if (f32 is not None and tree == "f32") else \
            [("", "test_one", "PASS"), ("", "test_two", "PASS"), ("", "test_untagged", "PASS")]
        (res / tree / "test_mod_flt.xml").write_text(junit(cases))
    (res / "py").mkdir()
    (res / "py" / "pytest.xml").write_text(junit(py if py is not None else [
        ("scripts.test_tool", "test_py[1]", "PASS"), ("scripts.test_tool", "test_py[2]", "PASS")]))
    return tmp_path


def run_trace(root):
    rc = trace_requirements.main(["--root", str(root)])
    data = json.load(open(root / "build" / "trace" / "matrix.json"))
    return rc, data


# REQ-QA-007
def test_trace_passes_and_builds_the_matrix(tmp_path):
    root = make_repo(tmp_path)
    rc, data = run_trace(root)
    assert rc == 0, data["summary"]["errors"]
    status = {r["id"]: r["status"] for r in data["requirements"]}
    assert status == {"REQ-A-001": "PASS", "REQ-A-002": "PASS", "REQ-B-001": "BY TARGET",
                      "REQ-B-002": "PENDING"}
    a1 = next(r for r in data["requirements"] if r["id"] == "REQ-A-001")
    assert sorted(t["test"] for t in a1["tests"]) == ["test/test_mod_flt.c::test_one",
                                                       "test/test_mod_flt.c::test_two"]
    a2 = next(r for r in data["requirements"] if r["id"] == "REQ-A-002")
    assert "scripts/test_tool.py::test_py" in [t["test"] for t in a2["tests"]]
    assert data["untagged_tests"] == ["test/test_mod_flt.c::test_untagged"]
    assert any("not-yet" in w for w in data["summary"]["warnings"])


# REQ-QA-007
def test_trace_fails_on_unknown_requirement(tmp_path):
    root = make_repo(tmp_path, c_test=C_TEST.replace("REQ-A-002, REQ-A-001", "REQ-A-001 REQ-Z-999"))
    rc, data = run_trace(root)
    assert rc == 1
    assert any("unknown requirement REQ-Z-999" in e for e in data["summary"]["errors"])


# REQ-QA-007
def test_trace_fails_when_a_requirement_has_no_passing_test(tmp_path):
    # test_one fails in the f32 run: REQ-A-001 still has test_two, REQ-A-002 has the pytest
    # test; failing test_two as well leaves REQ-A-001 without a passing test.
    root = make_repo(tmp_path, f32=[("", "test_one", "FAIL"), ("", "test_two", "FAIL")])
    rc, data = run_trace(root)
    assert rc == 1
    status = {r["id"]: r["status"] for r in data["requirements"]}
    assert status["REQ-A-001"] == "FAIL"
    assert any(e.startswith("REQ-A-001:") for e in data["summary"]["errors"])


# REQ-QA-007
def test_trace_fails_on_a_requirement_no_test_names(tmp_path):
    root = make_repo(tmp_path, reqs=REQS + "| REQ-C-001 | orphan | here | test |\n")
    rc, data = run_trace(root)
    assert rc == 1
    assert any(e == "REQ-C-001: no test names it" for e in data["summary"]["errors"])


# REQ-QA-007
def test_trace_fails_on_duplicate_id_and_skipped_only(tmp_path):
    root = make_repo(tmp_path, reqs=REQS + "| REQ-A-001 | again | here | test |\n",
                     py=[("scripts.test_tool", "test_py[1]", "SKIP")])
    rc, data = run_trace(root)
    assert rc == 1
    errs = data["summary"]["errors"]
    assert any("REQ-A-001 defined twice" in e for e in errs)
    tests = {t["test"]: t["result"] for r in data["requirements"] for t in r["tests"]}
    assert tests["scripts/test_tool.py::test_py"] == "SKIP"


COBERTURA = """<?xml version="1.0"?>
<coverage><packages><package name="src"><classes>
<class name="m" filename="src/m_flt.c"><lines>
<line number="3" hits="5"/><line number="4" hits="0"/><line number="8" hits="0"/>
</lines></class></classes></package></packages></coverage>
"""

SRC = """\
rfe_status_t rfe_m_do(int a)
{
    if (a > 0) {
        return RFE_ERR_RANGE; /* defensive */
    }
    return RFE_OK;
}
static int helper(void) { return 0; }
"""


def cov_repo(tmp_path, rows):
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "m_flt.c").write_text(SRC)
    (tmp_path / "cov.xml").write_text(COBERTURA)
    (tmp_path / "J.md").write_text("| file | function | marker | kind | justification |\n|---|---|---|---|---|\n" + rows)
    return ["--root", str(tmp_path), "--cobertura", str(tmp_path / "cov.xml"),
            "--justifications", str(tmp_path / "J.md"), "--out", str(tmp_path / "out.md")]


# REQ-QA-005
def test_coverage_justify_passes_when_every_line_has_a_row(tmp_path, capsys):
    args = cov_repo(tmp_path, textwrap.dedent("""\
        | src/m_flt.c | rfe_m_do | `return RFE_ERR_RANGE;` | line | unreachable: a > 0 is rejected earlier |
        | src/m_flt.c | * | `static int helper` | line, mcdc | unused helper kept for the q31 twin |
        | src/m_flt.c | rfe_m_do | `no such text` | line | stale |
        """))
    assert evidence_coverage.main(args) == 0
    out = capsys.readouterr().out
    assert "row matches nothing" in out and "no such text" in out
    report = (tmp_path / "out.md").read_text()
    assert "`src/m_flt.c:4` | rfe_m_do" in report and "unreachable" in report


# REQ-QA-005
def test_coverage_justify_fails_on_an_unjustified_line(tmp_path, capsys):
    # the row names the wrong function: line 4 (in rfe_m_do) stays unjustified
    args = cov_repo(tmp_path, textwrap.dedent("""\
        | src/m_flt.c | helper | `return RFE_ERR_RANGE;` | line | wrong function |
        | src/m_flt.c | helper | `static int helper` | line | unused helper |
        """))
    assert evidence_coverage.main(args) == 1
    out = capsys.readouterr().out
    assert "src/m_flt.c:4 (rfe_m_do)" in out and "NOT JUSTIFIED" in out
