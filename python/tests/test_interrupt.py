"""Python that behaves like Python (issue 49): Ctrl-C stops minimize,
benchmark, run and fit within 2 s, a campaign stays resumable, the first
exception of an objective stops its run at once, a failing registered
problem prints no Rust panic text, and no finite value is no success."""

import math
import pathlib
import signal
import subprocess
import sys
import time

import pytest

import metabezier as mb

CHILD = pathlib.Path(__file__).with_name("interrupt_child.py")


def interrupt(case, out, after=0.6, ready=lambda: True):
    """Starts the child on ``case``, sends SIGINT ``after`` seconds after it
    is ready and once ``ready()`` holds (polled for up to 60 s), and returns
    (its output, seconds from the signal to its exit)."""
    p = subprocess.Popen(
        [sys.executable, str(CHILD), case, str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert p.stdout.readline().strip() == "ready"
        time.sleep(after)
        deadline = time.monotonic() + 60
        while not ready() and time.monotonic() < deadline:
            time.sleep(0.01)
        sent = time.monotonic()
        p.send_signal(signal.SIGINT)
        out_text, err_text = p.communicate(timeout=60)
    finally:
        p.kill()
    return out_text + err_text, time.monotonic() - sent


@pytest.mark.parametrize(
    "case", ["benchmark", "minimize", "minimize-builtin", "minimize-batch", "run", "fit"]
)
def test_sigint_raises_keyboard_interrupt_within_two_seconds(case, tmp_path):
    output, seconds = interrupt(case, tmp_path / "r")
    assert "KeyboardInterrupt" in output, output
    assert "panicked" not in output, output
    assert seconds < 2.0, (case, seconds)


def test_an_interrupted_campaign_resumes_to_the_uninterrupted_bits(tmp_path):
    journal = tmp_path / "cut" / "journal.csv"

    def two_runs_finished():
        return journal.exists() and journal.read_text().count("\n") >= 2

    output, _ = interrupt("run-resumable", tmp_path / "cut", after=0.0, ready=two_runs_finished)
    assert "KeyboardInterrupt" in output, output
    lines = journal.read_text().splitlines()
    assert 2 <= len(lines) < 6 and not (tmp_path / "cut" / "runs.csv").exists()
    # A seed edited in the journal: the resume warns, names it, and redoes the run.
    fields = lines[0].split(",")
    fields[7] = "12345"
    journal.write_text("\n".join([",".join(fields)] + lines[1:]) + "\n")
    from interrupt_child import SPEC

    spec = SPEC.format(budget=3 * 10**6)
    with pytest.warns(RuntimeWarning, match="field seed: 12345 is not the seed"):
        s = mb.run(spec, out=tmp_path / "cut", threads=1, resume=True)
    assert (s.reused, s.executed) == (len(lines) - 1, 6 - len(lines) + 1)
    mb.run(spec, out=tmp_path / "whole", threads=1)
    for name in ("runs.csv", "convergence.csv"):
        assert (tmp_path / "cut" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes()


@pytest.mark.parametrize("algorithm", ["hs", "cmaes", "lshade", "ga"])
@pytest.mark.parametrize("batch", [False, True])
def test_the_first_exception_stops_the_run_at_once(algorithm, batch):
    calls = []

    def fun(x):
        calls.append(1)
        if len(calls) == 10:
            raise KeyError("the tenth call")
        return 0.5

    def rows(X):
        fun(None)
        return [0.5] * len(X)

    started = time.monotonic()
    with pytest.raises(KeyError, match="the tenth call") as raised:
        mb.minimize(rows if batch else fun, [(-1, 1)] * 3, algorithm=algorithm, budget=10**9, batch=batch)
    assert time.monotonic() - started < 2.0
    assert len(calls) == 10, "no call after the exception"
    assert raised.traceback[-1].name == "fun", "raised with its traceback"


def test_a_failing_registered_problem_prints_no_rust_panic(tmp_path):
    script = f"""
import metabezier as mb
def bad(x):
    raise ArithmeticError("no value here")
mb.register_problem("bad_problem", bad, (-1.0, 1.0))
spec = '''[experiment]
name = "bad"
seed = 1
runs = 4
budget = 100
threshold = 1e-8

[[problem]]
function = "bad_problem"
dim = 2

[[algorithm]]
name = "hs"
'''
try:
    mb.run(spec, out={str(tmp_path / "bad")!r}, threads=2)
except RuntimeError as e:
    print("RuntimeError:", e, "| cause:", repr(e.__cause__))
"""
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert "ArithmeticError('no value here')" in p.stdout, p.stdout + p.stderr
    assert "panicked" not in p.stderr and "RUST_BACKTRACE" not in p.stderr, p.stderr


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: mb.minimize(sum, [(-1, 1)], budget=10**11), "budget = 100000000000"),
        (lambda: mb.minimize(sum, [(-1, 1)], budget=10**30), "budget = 10{30}"),
        (lambda: mb.minimize(sum, [(-1, 1)], budget=2.5), "budget = 2.5"),
        (lambda: mb.minimize(sum, [(-1, 1)], seed=-1), "seed = -1"),
        (lambda: mb.benchmark("sphere", 10**30), "dim = 10{30}"),
        (lambda: mb.benchmark("sphere", 3, budget=0), "budget = 0"),
        (lambda: mb.fit([(0, 0), (1, 0), (1, 1)], budget=10**20), "budget = 10{20}"),
        (lambda: mb.fit([(0, 0), (1, 0), (1, 1)], segments=True), "segments = True"),
        (lambda: mb.run("x.toml", threads=0), "threads = 0"),
    ],
)
def test_budgets_and_counts_are_capped_as_in_specs_with_the_parameter_named(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_no_finite_value_is_no_success():
    r = mb.minimize(lambda x: math.nan, [(-1, 1)] * 2, budget=50)
    assert not r.success and "no finite value" in r.message and r.nfev == 50
    r = mb.minimize(lambda x: -math.inf, [(-1, 1)] * 2, budget=50)
    assert not r.success and "-inf" in r.message
    r = mb.minimize(lambda x: x[0] if x[0] > 0 else math.nan, [(-1, 1)], budget=50)
    assert r.success and math.isfinite(r.fun)
