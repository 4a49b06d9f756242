"""Tests of scripts/checks/check_names.py on archives compiled here from small sources: a
symbol without its suffix, or whose full name no header writes out, fails; the library's
own pattern (a short name mapped to the full one in a header block) passes."""

import os
import shutil
import subprocess
import sys

import pytest

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__))]

import check_names  # noqa: E402

HEADER = """#if defined(RFE_REAL_DOUBLE)
#define rfe_x_get rfe_x_get_f64
#else
#define rfe_x_get rfe_x_get_f32
#endif
int rfe_x_get(int a);
"""
pytestmark = pytest.mark.skipif(shutil.which("gcc") is None or shutil.which("ar") is None,
                                reason="needs gcc and ar (binutils), as the library build does")


def archive(tmp_path, name, source, double=False):
    (tmp_path / "include" / "rfe").mkdir(parents=True, exist_ok=True)
    (tmp_path / "include" / "rfe" / "x.h").write_text(HEADER)
    c = tmp_path / f"{name}.c"
    c.write_text('#include "rfe/x.h"\n' + source)
    o = tmp_path / f"{name}.o"
    a = tmp_path / f"{name}.a"
    flags = ["-DRFE_REAL_DOUBLE"] if double else []
    subprocess.run(["gcc", "-c", *flags, "-I", str(tmp_path / "include"), str(c), "-o", str(o)],
                   check=True)
    subprocess.run(["ar", "rcs", str(a), str(o)], check=True)
    return str(a)


def run(tmp_path, *libs):
    return check_names.main([*(f"--lib={lib}" for lib in libs), "--root", str(tmp_path)])


# REQ-QA-012
def test_mapped_short_names_pass_in_both_precisions(tmp_path, capsys):
    src = "int rfe_x_get(int a) { return a; }\nstatic int helper(void) { return 0; }\n"
    f32 = archive(tmp_path, "f32", src)
    f64 = archive(tmp_path, "f64", src, double=True)
    assert run(tmp_path, f32 + ":_f32", f64 + ":_f64") == 0
    assert "2 public symbols" in capsys.readouterr().out


# REQ-QA-012
def test_a_symbol_without_the_suffix_fails(tmp_path, capsys):
    f32 = archive(tmp_path, "f32", "int rfe_x_get(int a) { return a; }\n")
    assert run(tmp_path, f32 + ":_f64") == 1
    assert "rfe_x_get_f32: does not end with _f64" in capsys.readouterr().out


# REQ-QA-012
def test_a_full_name_no_header_writes_fails(tmp_path, capsys):
    # a public function pasted together by a macro: the symbol exists, no header spells it
    src = "#define PASTE(n) n##_f32\nint PASTE(rfe_y_put)(int a) { return a; }\n"
    f32 = archive(tmp_path, "f32", src)
    assert run(tmp_path, f32 + ":_f32") == 1
    assert "rfe_y_put_f32: its full name is written in no header" in capsys.readouterr().out


# REQ-QA-012
def test_an_empty_suffix_checks_only_the_headers(tmp_path):
    f32 = archive(tmp_path, "q31", "int rfe_x_get_q31(int a) { return a; }\n")
    assert run(tmp_path, f32 + ":") == 1          # rfe_x_get_q31 is in no header
    (tmp_path / "include" / "rfe" / "x_q31.h").write_text("int rfe_x_get_q31(int a);\n")
    assert run(tmp_path, f32 + ":") == 0


# REQ-QA-012
def test_a_missing_archive_is_a_usage_error(tmp_path):
    assert run(tmp_path, str(tmp_path / "none.a") + ":_f32") == 2
