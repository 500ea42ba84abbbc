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


def require_module(name):
    """Imports an optional module; skips without it, but fails under CAMDYN_CI
    (scripts/test.sh sets it): CI installs every optional tool, so a skip
    there would hide a test that never runs (tests/support/required_tool.h is
    the C++ twin)."""
    if os.environ.get("CAMDYN_CI"):
        try:
            return __import__(name)
        except ImportError as e:
            pytest.fail(f"{name} is not importable under CAMDYN_CI ({e}); scripts/setup.sh installs it")
    return pytest.importorskip(name)


@pytest.fixture
def pandas():
    return require_module("pandas")


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
