"""Shared set-up of the Python module's tests (tests/python, CTest label `python`).

CTest runs them with PYTHONPATH set to build/<preset>/python and
CAMDYN_BINARY to the `camdyn` executable of the same build. Run by hand:

    PYTHONPATH=build/ci/python CAMDYN_BINARY=build/ci/camdyn /usr/bin/python3 -m pytest -q tests/python
"""
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
if not any((Path(p) / "camdyn" / "__init__.py").exists() for p in sys.path if p):
    sys.path.insert(0, str(ROOT / "build" / "ci" / "python"))  # by hand, without PYTHONPATH

QUICKSTART = ROOT / "studies" / "quickstart.json"


@pytest.fixture
def root():
    return ROOT


@pytest.fixture
def quickstart():
    return QUICKSTART


@pytest.fixture
def camdyn_binary():
    binary = os.environ.get("CAMDYN_BINARY", str(ROOT / "build" / "ci" / "camdyn"))
    if not Path(binary).exists():
        pytest.fail(f"the camdyn executable {binary} is missing (set CAMDYN_BINARY)")
    return binary
