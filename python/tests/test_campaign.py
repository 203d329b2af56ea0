"""run, report and load: the CLI's runs.csv byte for byte, threads and
resume, Python problems in a campaign, and their errors."""

import filecmp
import subprocess

import pytest

import metabezier as mb

FILES = ["runs.csv", "convergence.csv", "hits.csv"]


def test_quick_spec_gives_the_cli_bytes(root, cli, tmp_path):
    spec = root / "experiments" / "quick.toml"
    subprocess.run([str(cli), "run", str(spec), "--out", str(tmp_path / "cli"), "-q"], check=True)
    s = mb.run(spec, out=tmp_path / "py", threads=2)
    assert s.complete and s.total == 75 and s.executed == 75
    for name in FILES:
        a, b = tmp_path / "cli" / name, tmp_path / "py" / name
        assert a.read_bytes() == b.read_bytes(), name
    # The spec as text gives the same runs.
    mb.run(spec.read_text(), out=tmp_path / "text", threads=1)
    assert filecmp.cmp(tmp_path / "cli" / "runs.csv", tmp_path / "text" / "runs.csv", shallow=False)
    # resume reuses every run
    again = mb.run(spec, out=tmp_path / "py", resume=True)
    assert again.reused == 75 and again.executed == 0
    path = mb.report(tmp_path / "py")
    assert path.endswith("report.md")
    assert "## Summary" in (tmp_path / "py" / "report.md").read_text()


def test_load_gives_columns(root, tmp_path):
    mb.run(root / "experiments" / "quick.toml", out=tmp_path / "q")
    d = mb.load(tmp_path / "q", pandas=False)
    runs = d["runs"]
    assert set(d) >= {"runs", "convergence", "hits"}
    assert len(runs["best"]) == 75 and all(isinstance(v, float) for v in runs["best"])
    assert isinstance(runs["seed"][0], int)
    assert sorted(set(runs["algorithm"])) == ["GA", "GHS", "HS", "MHS", "PSO"]
    with pytest.raises(ValueError, match="no runs.csv"):
        mb.load(tmp_path)
    # With pandas (installed by make test-python), the same columns as DataFrames.
    frames = mb.load(tmp_path / "q")
    df = frames["runs"]
    assert list(df.columns) == list(runs) and len(df) == 75
    assert df["best"].tolist() == runs["best"]
    assert frames["convergence"].shape[0] == len(d["convergence"]["evaluations"])


def styblinski_tang(x):
    return 0.5 * sum(v ** 4 - 16 * v * v + 5 * v for v in x)


SPEC = """[experiment]
name = "python_problem"
seed = 7
runs = 4
budget = 4000
threshold = 1e-6

[[problem]]
function = "py_styblinski_tang"
dim = [2, 3]

[[algorithm]]
name = "mhs"

[[algorithm]]
name = "ga"
"""


def test_a_python_problem_in_a_campaign_one_and_two_threads(tmp_path):
    mb.register_problem("py_styblinski_tang", styblinski_tang, (-5.0, 5.0), optimum=-39.16616570377142)
    one = mb.run(SPEC.replace('"py_styblinski_tang"', '"py_styblinski_tang"'), out=tmp_path / "1", threads=1)
    two = mb.run(SPEC, out=tmp_path / "2", threads=2)
    assert one.total == two.total == 16
    for name in FILES:
        assert (tmp_path / "1" / name).read_bytes() == (tmp_path / "2" / name).read_bytes(), name
    with pytest.raises(ValueError, match="py_styblinski_tang"):
        mb.register_problem("py_styblinski_tang", styblinski_tang, (-5.0, 5.0))


def test_builtin_names_and_bad_specs_are_refused(tmp_path):
    with pytest.raises(ValueError, match="sphere"):
        mb.register_problem("sphere", lambda x: 0.0, (-1.0, 1.0))
    with pytest.raises(ValueError, match=r"problem\[1\].function.*did you mean"):
        mb.run(SPEC.replace("py_styblinski_tang", "py_styblinski_tnag"), out=tmp_path / "x")
    with pytest.raises(ValueError, match="threads"):
        mb.run(SPEC, out=tmp_path / "y", threads=0)


def test_an_exception_in_a_campaign_names_the_run_and_keeps_the_cause(tmp_path):
    calls = {"n": 0}

    def fragile(x):
        calls["n"] += 1
        if calls["n"] > 3000:
            raise ArithmeticError("the user's function failed")
        return sum(v * v for v in x)

    mb.register_problem("py_fragile", fragile, (-1.0, 1.0))
    spec = SPEC.replace('"py_styblinski_tang"', '"py_fragile"').replace("dim = [2, 3]", "dim = 2")
    with pytest.raises(RuntimeError) as info:
        mb.run(spec, out=tmp_path / "f", threads=1)
    assert "py_fragile" in str(info.value)
    assert isinstance(info.value.__cause__, ArithmeticError)
