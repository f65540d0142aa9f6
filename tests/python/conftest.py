"""Shared set-up of the Python tests (run by scripts/test.sh after ctest):
the module from TEXBAKE_BUILD/python (default build/python), the executable
TEXBAKE_BUILD/texbake, and the repository's data/ folder."""
import os
import pathlib
import subprocess
import sys

import numpy as np
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


def read_model(folder):
    """{name: (R world-to-camera, t)} of a text model's images.txt (numpy, independent of texbake)."""
    poses = {}
    lines = [l for l in (folder / "images.txt").read_text().splitlines() if l and l[0] != "#"]
    for line in lines:
        f = line.split()
        if len(f) != 10:
            continue
        qw, qx, qy, qz = map(float, f[1:5])
        n = np.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
        qw, qx, qy, qz = qw / n, qx / n, qy / n, qz / n
        r = np.array([[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)],
                      [2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx)],
                      [2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)]])
        poses[f[9]] = (r, np.array(list(map(float, f[5:8]))))
    return poses
