"""Run by `make wheel` in a fresh venv holding only NumPy and the built
wheel, with no Rust toolchain on PATH: the wheel imports, runs an optimiser
on a Python function and a built-in function, and reproduces by seed."""

import shutil
import sys

import numpy as np

import metabezier as mb

assert shutil.which("cargo") is None and shutil.which("rustc") is None, "a Rust toolchain is on PATH"
r = mb.minimize(lambda x: float((x * x).sum()), [(-5, 5)] * 4, budget=3000, seed=11)
again = mb.minimize(lambda x: float((x * x).sum()), [(-5, 5)] * 4, budget=3000, seed=11)
assert isinstance(r.x, np.ndarray) and list(r.x) == list(again.x) and r.fun < 1e-3, r
b = mb.benchmark("rastrigin", 5, algorithm="mhs", budget=2000, seed=3)
assert b.nfev == 2000 and b.success
print(f"wheel {mb.__version__} on Python {sys.version.split()[0]}: {r.algorithm} {r.fun:.3g}, mhs {b.fun:.3g}")
