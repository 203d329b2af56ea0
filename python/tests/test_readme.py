"""The README's Python example, run as written (its one ```python block
under "## Use it from Python")."""

import contextlib
import io
import pathlib
import re


def test_the_readme_example_runs(root, tmp_path, monkeypatch):
    text = (root / "README.md").read_text(encoding="utf-8")
    section = text.split("## Use it from Python", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert len(blocks) == 1, "expected one python block in the section"
    monkeypatch.chdir(tmp_path)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(blocks[0], "README.md", "exec"), {"__name__": "readme"})
    printed = out.getvalue()
    assert re.search(r"^hs: median f - f\* = \S+ over 5 runs$", printed, flags=re.M), printed
    assert re.search(r"^mhs: median f - f\* = \S+ over 5 runs$", printed, flags=re.M), printed
    assert "10 runs; report in results-st/report.md" in printed, printed
    png = pathlib.Path("convergence.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "results-st" / "report.md").read_text().startswith("#")
