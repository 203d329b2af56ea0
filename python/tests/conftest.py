"""Shared fixtures: the repository root and the command-line binary the
identity tests compare against (``METABEZIER_BIN``, else the release build
of the repository; a missing binary fails, it is not skipped)."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    path = pathlib.Path(os.environ.get("METABEZIER_BIN", ROOT / "target" / "release" / "metabezier"))
    if not path.is_file():
        pytest.fail(
            f"{path}: no metabezier binary to compare with; build it with "
            "`cargo build --release --locked` or set METABEZIER_BIN"
        )
    return path
