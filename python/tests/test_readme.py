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


def test_the_readmes_which_optimiser_is_pythons_default(root):
    """The README's "Which optimiser?" table (made by `metabezier list
    --markdown` from `optim::recommended`) is what `recommended`, and so
    `minimize`'s default, answers at each dimension and budget."""
    import metabezier

    text = (root / "README.md").read_text(encoding="utf-8")
    section = text.split("## Which optimiser?", 1)[1].split("\n## ", 1)[0]
    lines = [l for l in section.splitlines() if l.startswith("|")]
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    per_dim = [int(c.split("·")[0]) for c in header[1:]]
    assert per_dim == [100, 1000, 10000, 100000], header
    rows = [[c.strip() for c in l.strip("|").split("|")] for l in lines[2:]]
    assert len(rows) >= 5, section
    for row in rows:
        dim = int(row[0])
        for cell, b in zip(row[1:], per_dim):
            assert cell == f"`{metabezier.recommended(dim, b * dim)}`", (dim, b)
