"""Shared fixtures of the predvs Python tests (run by CTest `python_module`, see python/CMakeLists.txt).

Environment (set by CTest): PYTHONPATH=<build>/python, PREDVS_CLI (the predvs binary),
PREDVS_PY_REFERENCE (python/tests/reference_run.cpp), PREDVS_SOURCE_DIR.
"""
import os
import subprocess

import numpy as np
import pytest


def _env_path(name):
    value = os.environ.get(name)
    if not value or not os.path.exists(value):
        pytest.skip(f"{name} not set or missing (run through CTest: ctest -R python_module)")
    return value


@pytest.fixture(scope="session")
def cli():
    return _env_path("PREDVS_CLI")


@pytest.fixture(scope="session")
def reference_exe():
    return _env_path("PREDVS_PY_REFERENCE")


@pytest.fixture(scope="session")
def source_dir():
    return _env_path("PREDVS_SOURCE_DIR")


# One generated maneuvering track (t,u,v,u_true,v_true; an empty u,v = dropped frame), 8 s at 30 Hz.
TRACK_ARGS = ["--kind", "turns", "--rate-hz", "30", "--noise-px", "1.5", "--duration-s", "8", "--drop", "0.05",
              "--seed", "7"]


@pytest.fixture(scope="session")
def track_csv(cli, tmp_path_factory):
    path = tmp_path_factory.mktemp("track") / "track.csv"
    subprocess.run([cli, "make-track", *TRACK_ARGS, "--out", str(path)], check=True, capture_output=True)
    return path


def read_track(path):
    """(t, z) of a make-track CSV: z (frames, 2) = u, v with NaN where the cell is empty."""
    a = np.genfromtxt(path, delimiter=",", names=True)
    return np.asarray(a["t"], dtype=float), np.column_stack([a["u"], a["v"]]).astype(float)
