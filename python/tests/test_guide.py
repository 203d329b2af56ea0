"""The guide's Python blocks, run as written: every ```python block of
README.md, docs/FAQ.md and docs/guide/*.md (tests/house/code_blocks.rs
holds the other kinds of block; this file is the Python half)."""

import contextlib
import io
import re


def python_blocks(root):
    files = [root / "README.md", root / "docs" / "FAQ.md"]
    files += sorted((root / "docs" / "guide").glob("*.md"))
    for f in files:
        text = f.read_text(encoding="utf-8")
        for m in re.finditer(r"^```python\n(.*?)^```", text, flags=re.S | re.M):
            line = text.count("\n", 0, m.start()) + 1
            yield f"{f.relative_to(root)}:{line}", m.group(1)


def run_block(name, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, name, "exec"), {"__name__": "guide"})
    return out.getvalue()


def test_every_python_block_runs(root, tmp_path, monkeypatch):
    """Each block in a directory of its own, in one process (a problem a
    block registers stays registered, so each block runs once); then what
    the one block of docs/guide/python.md says it does: two algorithms over
    five seeds, a convergence plot, a campaign with its report."""
    blocks = list(python_blocks(root))
    assert blocks, "no python block in the documents"
    printed = {}
    for k, (name, code) in enumerate(blocks):
        d = tmp_path / f"block{k}"
        d.mkdir()
        printed[name] = (d, run_block(name, code, d, monkeypatch))
    example = [n for n in printed if n.startswith("docs/guide/python.md")]
    assert len(example) == 1, list(printed)
    d, out = printed[example[0]]
    assert re.search(r"^hs: median f - f\* = \S+ over 5 runs$", out, flags=re.M), out
    assert re.search(r"^mhs: median f - f\* = \S+ over 5 runs$", out, flags=re.M), out
    assert "10 runs; report in results-st/report.md" in out, out
    assert (d / "convergence.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (d / "results-st" / "report.md").read_text().startswith("#")
