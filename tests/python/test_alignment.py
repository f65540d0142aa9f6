"""A photo bake checks that a COLMAP model is in the mesh's frame before it
bakes (SPEC section 9, "Alignment"): the model's sparse points against the
mesh's surface. Four views of the bunny rendered as a COLMAP workspace get a
points3D.txt by hand: the bunny's own vertices (in its frame: every point on
the surface), or the same points scaled by 3 and moved by 10 (a raw model in
its own frame: none near the surface)."""
import numpy as np
import pytest

import texbake
from conftest import DATA, read_model, run_cli

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


def _pairs_file(path, model_points, mesh_points, header=True):
    lines = ["model_x,model_y,model_z,mesh_x,mesh_y,mesh_z"] if header else []
    lines += [",".join(repr(float(v)) for v in (*a, *b)) for a, b in zip(model_points, mesh_points)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_align_from_point_pairs(tmp_path, workspace):
    """A model without sparse points, moved away by a known similarity, comes
    back from five point pairs (--correspondences: the moved and the true
    positions of five bunny vertices): its camera centres are the original's
    (numpy), the pairs' RMS is printed; a mistyped pair is a warning naming
    its line; too few pairs, pairs on a line and --transform with
    --correspondences are refused."""
    model = workspace / "sparse" / "0"
    (model / "points3D.txt").write_text("# no points\n")
    m = np.array([[0, -2, 0, 1], [2, 0, 0, 2], [0, 0, 2, 3], [0, 0, 0, 1]], float)
    away = tmp_path / "away"
    r = run_cli("cameras", "align", BUNNY, "--cameras", model, "--transform",
                ",".join(str(v) for v in m.ravel()), "-o", away)
    assert r.returncode == 0, r.stderr
    vertices = texbake.read_mesh(BUNNY).vertices.astype(float)
    picked = vertices[[0, 100, 200, 300, 400]]
    moved = picked @ m[:3, :3].T + m[:3, 3]
    pairs = _pairs_file(tmp_path / "pairs.csv", moved, picked)
    back = tmp_path / "back"
    r = run_cli("cameras", "align", BUNNY, "--cameras", away, "--correspondences", pairs,
                "-o", back)
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    line = [l for l in r.stdout.splitlines() if l.startswith("correspondences: ")][0]
    assert line.startswith("correspondences: 5 pairs, RMS "), line
    assert float(line.split("RMS ")[1].split()[0]) < 1e-6, line
    original, restored = read_model(model), read_model(back)
    assert original.keys() == restored.keys()
    for name, (rc, tc) in original.items():
        r2, t2 = restored[name]
        np.testing.assert_allclose(-r2.T @ t2, -rc.T @ tc, atol=1e-5)
        np.testing.assert_allclose(r2, rc, atol=1e-6)

    # The fourth pair (line 5, after the header) mistyped: a warning names it.
    typo = picked.copy()
    typo[3] += 0.05
    r = run_cli("cameras", "align", BUNNY, "--cameras", away, "--correspondences",
                _pairs_file(tmp_path / "typo.csv", moved, typo), "-o", tmp_path / "typo")
    assert r.returncode == 0, r.stderr
    assert "the pairs do not agree on one similarity" in r.stderr, r.stderr
    assert "at line 5" in r.stderr, r.stderr

    r = run_cli("cameras", "align", BUNNY, "--cameras", away, "--correspondences",
                _pairs_file(tmp_path / "two.csv", moved[:2], picked[:2]), "-o", tmp_path / "o")
    assert r.returncode == 1 and "2 point pairs: at least 3 are needed" in r.stderr, r.stderr
    line_pts = np.array([[0, 0, 0], [1, 1, 1], [2, 2, 2]], float)
    r = run_cli("cameras", "align", BUNNY, "--cameras", away, "--correspondences",
                _pairs_file(tmp_path / "line.csv", line_pts, picked[:3]), "-o", tmp_path / "o")
    assert r.returncode == 1 and "the model's points lie on one line" in r.stderr, r.stderr
    r = run_cli("cameras", "align", BUNNY, "--cameras", away, "--correspondences", pairs,
                "--transform", ",".join(str(v) for v in np.eye(4).ravel()), "-o", tmp_path / "o")
    assert r.returncode == 2, r.stderr
    assert not (tmp_path / "o").exists()
    # The pairs file where the output's images.txt would go: exit 2, untouched.
    inside = tmp_path / "inside"
    inside.mkdir()
    kept = _pairs_file(inside / "images.txt", moved, picked)
    text = kept.read_text()
    r = run_cli("cameras", "align", BUNNY, "--cameras", away, "--correspondences", kept,
                "-o", inside)
    assert r.returncode == 2 and "--correspondences" in r.stderr, r.stderr
    assert kept.read_text() == text
