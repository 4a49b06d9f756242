"""The examples of the integrator's headers (the @code blocks of include/rfe/*.h) compile as
C99 with the library's strict warnings, in the float and the double build, so the example
a newcomer copies cannot drift from the API."""

import glob
import os
import re
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HEADERS = sorted(glob.glob(os.path.join(ROOT, "include", "rfe", "*.h")))
FLAGS = ["-std=c99", "-pedantic", "-Wall", "-Wextra", "-Wconversion", "-Wshadow", "-Werror"]


def examples():
    for h in HEADERS:
        with open(h, encoding="utf-8") as fh:
            text = fh.read()
        for i, m in enumerate(re.finditer(r"@code(.*?)@endcode", text, re.S)):
            code = "\n".join(re.sub(r"^ \* ?", "", line) for line in m.group(1).split("\n"))
            yield pytest.param(code, id=f"{os.path.basename(h)}#{i}")


def test_the_integrator_header_has_an_example():
    assert any("friction.h" in p.id for p in examples())


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc, as the library build")
@pytest.mark.parametrize("code", list(examples()))
@pytest.mark.parametrize("precision", [[], ["-DRFE_REAL_DOUBLE"]], ids=["f32", "f64"])
def test_header_example_compiles(code, precision, tmp_path):
    src = tmp_path / "example.c"
    src.write_text(code)
    r = subprocess.run(["gcc", *FLAGS, *precision, "-I", os.path.join(ROOT, "include"), "-c",
                        str(src), "-o", str(tmp_path / "example.o")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
