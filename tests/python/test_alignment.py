"""A photo bake checks that a COLMAP model is in the mesh's frame before it
bakes (SPEC section 9, "Alignment"): the model's sparse points against the
mesh's surface. Four views of the bunny rendered as a COLMAP workspace get a
points3D.txt by hand: the bunny's own vertices (in its frame: every point on
the surface), or the same points scaled by 3 and moved by 10 (a raw model in
its own frame: none near the surface)."""
import numpy as np
import pytest

import texbake
from conftest import DATA, run_cli

BUNNY = DATA / "bunny00.off"


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    ws = tmp_path_factory.mktemp("align") / "ws"
    r = run_cli("render", BUNNY, "--texture", DATA / "earth.jpg", "--proxy", "sphere",
                "--center", "0,0,0", "--radius", "1", "--pole", "0,1,0", "--up", "y", "--unlit",
                "--views", "4", "--size", "160x120", "--colmap", ws)
    assert r.returncode == 0, r.stderr
    return ws


def write_points(ws, points):
    lines = ["# 3D point list with one line of data per point:"]
    lines += [f"{i + 1} {x!r} {y!r} {z!r} 128 128 128 0.5" for i, (x, y, z) in enumerate(points)]
    (ws / "sparse" / "0" / "points3D.txt").write_text("\n".join(lines) + "\n")


def test_a_model_in_the_mesh_frame_bakes_and_says_so(tmp_path, workspace):
    write_points(workspace, texbake.read_mesh(BUNNY).vertices)
    r = run_cli("bake", BUNNY, "--cameras", workspace / "sparse" / "0", "-o", tmp_path / "o.ply")
    assert r.returncode == 0, r.stderr
    assert "is in the mesh's frame" in r.stderr
    assert "100.0 % of them within 1 % of its size of the surface" in r.stderr
    c = run_cli("cameras", "check", BUNNY, "--cameras", workspace / "sparse" / "0")
    assert c.returncode == 0, c.stderr
    assert "model alignment: aligned:" in c.stdout


def test_a_model_in_its_own_frame_is_an_error(tmp_path, workspace):
    points = texbake.read_mesh(BUNNY).vertices * 3 + np.array([10.0, 0, 0])
    write_points(workspace, points)
    out = tmp_path / "o.ply"
    r = run_cli("bake", BUNNY, "--cameras", workspace / "sparse" / "0", "-o", out)
    assert r.returncode == 1, r.stderr
    assert "the model is not in the frame of" in r.stderr
    assert "0 of " in r.stderr and "--no-alignment-check" in r.stderr
    assert not out.exists()
    # The way out: bake anyway.
    r = run_cli("bake", BUNNY, "--cameras", workspace / "sparse" / "0", "--no-alignment-check",
                "-q", "-o", out)
    assert r.returncode == 0, r.stderr
    assert out.exists()
    # The same job from Python: the error is an OSError (the input is at fault).
    with pytest.raises(OSError, match="not in the frame of"):
        texbake.run_job(BUNNY, tmp_path / "p.ply", cameras=workspace / "sparse" / "0")
    texbake.run_job(BUNNY, tmp_path / "p.ply", cameras=workspace / "sparse" / "0",
                    no_alignment_check=True)
    assert (tmp_path / "p.ply").read_bytes() == out.read_bytes()
    # cameras check prints the figures and warns.
    c = run_cli("cameras", "check", BUNNY, "--cameras", workspace / "sparse" / "0")
    assert c.returncode == 0, c.stderr
    assert "model alignment: misaligned: 0 of" in c.stdout
    assert "the model is not in the frame of" in c.stderr


def test_a_model_without_points_is_not_checked(tmp_path, workspace):
    (workspace / "sparse" / "0" / "points3D.txt").write_text("# no points\n")
    r = run_cli("bake", BUNNY, "--cameras", workspace / "sparse" / "0", "-o", tmp_path / "o.ply")
    assert r.returncode == 0, r.stderr
    assert "frame" not in r.stderr
