"""Paths shared by the Python test suites (set by ctest; defaults for a run from the
source tree after scripts/build.sh: PYTHONPATH=build/python /usr/bin/python3 -m pytest tests/python)."""
import os

import pytest

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN_DIR = os.environ.get("NCP_BIN_DIR", os.path.join(SOURCE_DIR, "build", "bin"))


@pytest.fixture(scope="session")
def source_dir():
    return SOURCE_DIR


@pytest.fixture(scope="session")
def bin_dir():
    return BIN_DIR
