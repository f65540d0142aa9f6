"""Shared set-up of the Python tests (run by scripts/test.sh after ctest):
the module from TEXBAKE_BUILD/python (default build/python), the executable
TEXBAKE_BUILD/texbake, and the repository's data/ folder."""
import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("TEXBAKE_BUILD", ROOT / "build")).resolve()
DATA = ROOT / "data"
TEXBAKE = BUILD / "texbake"
sys.path.insert(0, str(BUILD / "python"))


def run_cli(*args, cwd=None):
    """Runs build/texbake with args; returns the CompletedProcess (text)."""
    return subprocess.run([str(TEXBAKE), *map(str, args)], capture_output=True, text=True,
                          cwd=cwd)


@pytest.fixture(scope="session")
def bunny():
    import texbake
    return texbake.read_mesh(DATA / "bunny00.off")


@pytest.fixture(scope="session")
def earth():
    import texbake
    return texbake.read_image(DATA / "earth.jpg")
