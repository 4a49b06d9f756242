"""Every relative markdown link `](path)` of the README, docs/*.md, docs/spec/*.md and
test/README.md names a file or folder that exists, so moving a page or a source cannot leave a
dead link behind (http and mailto links and #anchors are not checked)."""

import glob
import os
import re

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LINK_RE = re.compile(r"\]\(([^)\s]+)\)")


def pages():
    files = [os.path.join(ROOT, "README.md"), os.path.join(ROOT, "test", "README.md")]
    files += sorted(glob.glob(os.path.join(ROOT, "docs", "*.md")))
    files += sorted(glob.glob(os.path.join(ROOT, "docs", "spec", "*.md")))
    return [f for f in files if os.path.isfile(f)]


def broken(path):
    """(line, target) of each relative link of one page whose target does not exist."""
    out = []
    with open(path, encoding="utf-8") as fh:
        for n, line in enumerate(fh, 1):
            for tgt in LINK_RE.findall(line):
                if re.match(r"^[a-z][a-z0-9+.-]*:", tgt) or tgt.startswith("#"):
                    continue
                if not os.path.exists(os.path.join(os.path.dirname(path), tgt.split("#", 1)[0])):
                    out.append((n, tgt))
    return out


# REQ-QA-011
def test_checker_finds_a_dead_link(tmp_path):
    page = tmp_path / "p.md"
    (tmp_path / "there.md").write_text("x")
    page.write_text("[a](there.md) [b](gone.md#x) [c](https://example.org) [d](#top)\n")
    assert broken(str(page)) == [(1, "gone.md#x")]


# REQ-QA-011
def test_every_relative_link_resolves():
    dead = [f"{os.path.relpath(p, ROOT)}:{n}: {t}" for p in pages() for n, t in broken(p)]
    assert len(pages()) >= 10 and not dead, "\n".join(dead)
