"""The README's "Which optimiser?" table, held to Python's default (the
guide's Python blocks run in test_guide.py)."""


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
