"""Tests of scripts/checks/check_layers.py on small trees made here: each dependency rule of
docs/LAYOUT.md fires on a file that breaks it, and a tree that keeps them passes."""

import os
import sys

import pytest

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)

import check_layers  # noqa: E402


def tree(tmp_path, files):
    for rel, text in files.items():
        p = tmp_path / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    return str(tmp_path)


GOOD = {
    "include/rfe/common.h": "#include <stdint.h>\n",
    "include/rfe/types.h": '#include "rfe/common.h"\n',
    "include/rfe/component/qr.h": '#include "rfe/types.h"\n',
    "include/rfe/component/qr_q31.h": '#include "rfe/common.h"\n',
    "include/rfe/component/tyre.h": '#include "rfe/types.h"\n',
    "include/rfe/friction.h": '#include "rfe/component/tyre.h"\n#include "rfe/component/qr.h"\n',
    "src/numerics/internal.h": "#include <math.h>\n#include \"rfe/types.h\"\n",
    "src/numerics/qr_flt.c": '#include "rfe/component/qr.h"\n#include "numerics/internal.h"\n',
    "src/numerics/qr_q31.c": '#include "rfe/component/qr_q31.h"\n#include <stddef.h>\n',
    "src/models/tyre_flt.c": '#include "rfe/component/tyre.h"\n#include "numerics/internal.h"\n',
    "src/estimators/friction/friction_flt.c": '#include "rfe/friction.h"\n',
    "src/host/cli.c": '#include "rfe/friction.h"\n#include "cli.h"\n#include <stdio.h>\n',
    "src/host/cli.h": "",
}


def run(tmp_path, extra):
    problems, _, _ = check_layers.check(tree(tmp_path, {**GOOD, **extra}))
    return problems


# REQ-QA-009
def test_a_tree_that_keeps_the_rules_passes(tmp_path, capsys):
    assert check_layers.main(["--root", tree(tmp_path, GOOD)]) == 0
    assert "no float header" in capsys.readouterr().out


# REQ-QA-009
@pytest.mark.parametrize("rel,text,expect", [
    ("src/numerics/chol_flt.c", '#include "rfe/component/tyre.h"\n', "numerics includes include/rfe/component/tyre.h (models)"),
    ("src/models/meas_flt.c", '#include "rfe/friction.h"\n', "models includes include/rfe/friction.h (estimators)"),
    ("src/models/meas2_flt.c", '#include "host/cli.h"\n', "models includes src/host/cli.h (host)"),
    ("src/numerics/chol_q31.c", '#include "rfe/types.h"\n', "fixed-point file includes the float header include/rfe/types.h"),
    ("src/numerics/fx_q31.c", "#include <math.h>\n", "fixed-point file includes <math.h>"),
    ("src/numerics/m_q31.c", '#include "numerics/internal.h"\n', "fixed-point file includes the float header src/numerics/internal.h"),
    ("src/models/x_flt.c", '#include "nowhere.h"\n', 'found in neither'),
    ("src/misc/x.c", "", "src/misc/x.c: no layer"),
    ("include/rfe/newthing.h", "", "include/rfe/newthing.h: no layer"),
])
def test_each_rule_fires(tmp_path, rel, text, expect):
    problems = run(tmp_path, {rel: text})
    assert len(problems) == 1 and expect in problems[0], problems


# REQ-QA-009
def test_the_repository_keeps_the_rules():
    problems, n_files, n_inc = check_layers.check(os.path.dirname(os.path.dirname(
        os.path.dirname(os.path.abspath(__file__)))))
    assert problems == [] and n_files > 50 and n_inc > 200
