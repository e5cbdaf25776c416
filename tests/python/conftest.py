"""Shared fixtures of the Python tests (run by CTest `python.pytest`, or by hand:
PYTHONPATH=build/python ALLANLOT_BINARY=build/allanlot python3 -m pytest tests/python)."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data"


def read_column(path):
    """The numbers of a single-column text file (Stable32's and AllanTools' data files)."""
    values = []
    for line in open(path, encoding="ascii"):
        line = line.strip()
        if line and not line.startswith("#"):
            values.append(float(line.split()[0]))
    return np.array(values)


def read_stable32_table(path):
    """Rows (AF, Tau, #, Alpha, Min Sigma, Sigma, Max Sigma) of a Stable32 table; '-' as NaN."""
    rows = []
    for line in open(path, encoding="latin-1"):
        if line.startswith("#") or not line.strip():
            continue
        fields = line.split()
        rows.append([float("nan") if f == "-" else float(f) for f in fields[:7]])
    return np.array(rows)


@pytest.fixture(scope="session")
def phase_dat():
    return read_column(DATA / "stable32" / "phasedat" / "PHASE.DAT")


@pytest.fixture(scope="session")
def binary():
    path = os.environ.get("ALLANLOT_BINARY", str(REPO / "build" / "allanlot"))
    if not os.access(path, os.X_OK):
        pytest.fail("no allanlot binary at %s (set ALLANLOT_BINARY)" % path)
    return path


def run(binary, *args, check=True):
    proc = subprocess.run([binary, *map(str, args)], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, timeout=600)
    if check and proc.returncode != 0:
        raise AssertionError("allanlot %s: exit %d\n%s%s" % (" ".join(map(str, args)),
                                                             proc.returncode, proc.stdout,
                                                             proc.stderr))
    return proc
