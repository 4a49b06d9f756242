"""Tests of scripts/codegen/twins.py: the committed C files hold exactly what the templates
make, a hand edit inside a region is reported (file, line, function, how to fix), and a change
to a template reaches every twin it serves."""

import os
import shutil
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import twins  # noqa: E402

FILES = sorted({path for _, path, _, _ in twins.TWINS})


def copy_tree(tmp_path):
    """The C files with regions and the templates, copied under tmp_path."""
    root = tmp_path / "repo"
    for rel in FILES:
        dst = root / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(os.path.join(twins.ROOT, rel), dst)
    templates = tmp_path / "templates"
    shutil.copytree(twins.TEMPLATES, templates)
    return str(root), str(templates)


def read(root, rel):
    with open(os.path.join(root, rel), encoding="utf-8") as fh:
        return fh.read()


def write(root, rel, text):
    with open(os.path.join(root, rel), "w", encoding="utf-8") as fh:
        fh.write(text)


def edit(root, rel, old, new):
    """Replaces the one occurrence of old in root/rel (a C file or a template) by new."""
    text = read(root, rel)
    assert text.count(old) == 1, (rel, old)
    write(root, rel, text.replace(old, new))
    return text


def test_committed_files_match_the_templates():
    assert twins.run() == []
    assert twins.main(["--check"]) == 0


def test_every_template_is_used_and_every_region_is_known():
    used = {t for t, _, _, _ in twins.TWINS}
    assert used == {f for f in os.listdir(twins.TEMPLATES) if f.endswith(".c.in")}
    for rel in FILES:
        names = [n for n, _, _ in twins.regions(read(twins.ROOT, rel), rel)]
        want = [twins.region_name(t) for t, p, _, _ in twins.TWINS if p == rel]
        assert sorted(names) == sorted(want), rel


def test_each_region_is_one_twin_of_a_pair():
    """Every template serves a float and a fixed-point file (the point of generating it)."""
    for template in {t for t, _, _, _ in twins.TWINS}:
        kinds = {tw for t, _, tw, _ in twins.TWINS if t == template}
        assert kinds == {"flt", "q31"}, template


def test_a_hand_edit_inside_a_region_is_reported_and_make_twins_repairs_it(tmp_path, capsys):
    root, templates = copy_tree(tmp_path)
    rel = "src/estimators/friction/friction_q31.c"
    old = "    backup_q31(est, 0);\n    st = gap_update_q31(est, missed);\n"
    text = edit(root, rel, old, "    st = gap_update_q31(est, missed);\n")
    problems = twins.run(root, templates)
    assert len(problems) == 1
    msg = problems[0]
    line = text[:text.index(old)].count("\n") + 1
    assert msg.startswith("%s:%d: rfe_friction_skip_q31 (region friction_skip)" % (rel, line))
    assert "scripts/codegen/templates/friction_skip.c.in" in msg and "make twins" in msg
    assert twins.main(["--check", "--root", root, "--templates", templates]) == 1
    assert "friction_skip" in capsys.readouterr().err
    # make twins writes the template's function back; the rest of the file is untouched
    assert twins.main(["--root", root, "--templates", templates]) == 0
    assert read(root, rel) == text
    assert twins.run(root, templates) == []


def test_an_edit_outside_the_regions_is_not_the_generators_business(tmp_path):
    root, templates = copy_tree(tmp_path)
    edit(root, "src/estimators/friction/friction_flt.c", "#define NM ((size_t)RFE_N_MAX)\n",
         "#define NM ((size_t)RFE_N_MAX) /* edited */\n")
    assert twins.run(root, templates) == []


def test_a_template_change_reaches_both_twins(tmp_path):
    root, templates = copy_tree(tmp_path)
    marker = "    size_t i;\n"
    edit(templates, "friction_backup.c.in", marker, marker + "    /* a new line, written once */\n")
    problems = twins.run(root, templates)
    assert sorted(p.split(":")[0] for p in problems) == [
        "src/estimators/friction/friction_flt.c", "src/estimators/friction/friction_q31.c"]
    assert "backup (region friction_backup)" in problems[0]
    assert "backup_q31 (region friction_backup)" in problems[1]
    assert twins.run(root, templates, write=True) == []
    for rel in ("src/estimators/friction/friction_flt.c",
                "src/estimators/friction/friction_q31.c"):
        assert read(root, rel).count("    /* a new line, written once */\n") == 1
    assert twins.run(root, templates) == []


def test_the_clamp_template_serves_four_functions(tmp_path):
    root, templates = copy_tree(tmp_path)
    edit(templates, "filter_clamp.c.in", "    return RFE_OK;\n}",
         "    /* once */\n    return RFE_OK;\n}")
    assert twins.run(root, templates, write=True) == []
    for kind in ("sckf", "ckf"):
        for tw in ("flt", "q31"):
            assert "    /* once */\n" in read(root, "src/filters/%s_%s.c" % (kind, tw))


def test_missing_and_stale_regions_are_reported(tmp_path):
    root, templates = copy_tree(tmp_path)
    rel = "src/models/meas_flt.c"
    begin = twins.begin_line("meas_input_slot.c.in")
    edit(root, rel, begin, begin.replace("meas_input_slot", "meas_old_slot"))
    problems = twins.run(root, templates)
    assert any("region meas_old_slot is not in" in p for p in problems)
    assert any(p.startswith(rel + ": no region for meas_input_slot.c.in (input_slot)")
               for p in problems)


def test_an_unclosed_region_is_an_error(tmp_path):
    root, templates = copy_tree(tmp_path)
    rel = "src/filters/ckf_flt.c"
    write(root, rel, read(root, rel).replace(twins.END_LINE + "\n", "", 1))
    with pytest.raises(twins.TemplateError, match="has no"):
        twins.run(root, templates)
    assert twins.main(["--check", "--root", root, "--templates", templates]) == 2


# ---- the template language ----------------------------------------------------------------

def test_render_keeps_each_twins_block_and_fills_placeholders():
    text = ("int f@sfx@(void)\n{\n@{flt}\n    a();\n@{q31}\n    b();\n    c();\n@{end}\n"
            "    return @zero@;\n}\n")
    assert twins.render(text, "flt", {"sfx": "", "zero": "RFE_R(0.0)"}) == (
        "int f(void)\n{\n    a();\n    return RFE_R(0.0);\n}\n")
    assert twins.render(text, "q31", {"sfx": "_q31", "zero": "0"}) == (
        "int f_q31(void)\n{\n    b();\n    c();\n    return 0;\n}\n")


def test_render_aligns_continuations_after_the_open_parenthesis():
    text = "    st = g@sfx@(a, h(b),\n         @^c);\n"
    assert twins.render(text, "flt", {"sfx": ""}) == "    st = g(a, h(b),\n           c);\n"
    assert twins.render(text, "q31", {"sfx": "_q31"}) == (
        "    st = g_q31(a, h(b),\n               c);\n")


@pytest.mark.parametrize("text,match", [
    ("x = @nope@;\n", "unknown placeholder @nope@"),
    ("@{q31}\nx;\n", "not closed"),
    ("x;\n@^y;\n", "without an open"),
    ("x = a @ b;\n", "stray"),
])
def test_render_rejects_malformed_templates(text, match):
    with pytest.raises(twins.TemplateError, match=match):
        twins.render(text, "flt", {"sfx": ""})
