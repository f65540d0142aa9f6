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
    assert "texbake cameras align" in r.stderr
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


def test_align_brings_a_moved_model_back(tmp_path, workspace):
    """The workspace's model moved away by a known similarity (cameras align
    --transform; its centres checked against numpy's), refused by the bake,
    then brought back by cameras align's own fit: it bakes as the original."""
    model = workspace / "sparse" / "0"
    write_points(workspace, texbake.read_mesh(BUNNY).vertices)
    original = tmp_path / "original.ply"
    r = run_cli("bake", BUNNY, "--cameras", model, "-q", "-o", original)
    assert r.returncode == 0, r.stderr

    # Scale 3, a quarter turn about +x (y -> z, z -> -y), then (4, -1, 2).
    m = np.array([[3, 0, 0, 4], [0, 0, -3, -1], [0, 3, 0, 2], [0, 0, 0, 1]], float)
    away = tmp_path / "away"
    r = run_cli("cameras", "align", BUNNY, "--cameras", model, "--transform",
                ",".join(str(v) for v in m.ravel()), "-o", away)
    assert r.returncode == 0, r.stderr
    before, after = read_model(model), read_model(away)
    assert before.keys() == after.keys()
    for name, (rc, tc) in before.items():
        centre = -rc.T @ tc
        moved_r, moved_t = after[name]
        np.testing.assert_allclose(-moved_r.T @ moved_t, m[:3, :3] @ centre + m[:3, 3], atol=1e-9)
    # Moved away, the model no longer bakes onto the bunny.
    r = run_cli("bake", BUNNY, "--cameras", away, "--images", workspace / "images", "-o",
                tmp_path / "away.ply")
    assert r.returncode == 1 and "not in the frame of" in r.stderr, r.stderr

    back = tmp_path / "back"
    r = run_cli("cameras", "align", BUNNY, "--cameras", away, "-o", back)
    assert r.returncode == 0, r.stderr
    assert "after: " in r.stdout and "100.0 % of them within 1 %" in r.stdout, r.stdout
    printed = [l for l in r.stdout.splitlines() if l.startswith("transform: ")][0]
    found = np.array([float(v) for v in printed.split()[1].split(",")]).reshape(4, 4)
    np.testing.assert_allclose(found @ m, np.eye(4), atol=2e-3)
    baked = tmp_path / "back.ply"
    r = run_cli("bake", BUNNY, "--cameras", back, "--images", workspace / "images", "-q", "-o",
                baked)
    assert r.returncode == 0, r.stderr
    a = texbake.read_mesh(original).colors
    b = texbake.read_mesh(baked).colors
    assert np.abs(a - b).max() <= 2 / 255, np.abs(a - b).max()


def test_align_refusals(tmp_path, workspace):
    model = workspace / "sparse" / "0"
    (model / "points3D.txt").write_text("# no points\n")
    r = run_cli("cameras", "align", BUNNY, "--cameras", model, "-o", tmp_path / "o")
    assert r.returncode == 2 and "at least 20 are needed" in r.stderr, r.stderr
    r = run_cli("cameras", "align", BUNNY, "--cameras", model, "--transform", "1,0,0", "-o",
                tmp_path / "o")
    assert r.returncode == 2 and "expected 16 numbers" in r.stderr, r.stderr
    r = run_cli("cameras", "align", BUNNY, "--cameras", model, "-o", model)
    assert r.returncode == 2, r.stderr  # the output is the input
    assert not (tmp_path / "o").exists()
