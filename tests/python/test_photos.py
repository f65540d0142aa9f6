"""texbake.bake_vertex_from_photos against the command line (SPEC sections 9, 11)."""
import json

import numpy as np
import pytest

import texbake
from conftest import DATA, read_model, run_cli


def test_photos_match_the_cli(tmp_path):
    bunny = DATA / "bunny00.off"
    ws = tmp_path / "ws"
    r = run_cli("render", bunny, "--texture", DATA / "earth.jpg", "--proxy", "sphere",
                "--center", "0,0,0", "--radius", "1", "--pole", "0,1,0", "--equator", "0,0,1",
                "--up", "y", "--unlit", "--views", "4", "--size", "320x240", "--colmap", ws)
    assert r.returncode == 0, r.stderr
    out = tmp_path / "cli.ply"
    r = run_cli("bake", bunny, "--cameras", ws / "sparse" / "0", "-q", "--occluded", "1,0,1",
                "-o", out)
    assert r.returncode == 0, r.stderr
    mesh = texbake.read_mesh(bunny)
    colors, stats, cameras = texbake.bake_vertex_from_photos(
        mesh, cameras=ws / "sparse" / "0", occluded=(1, 0, 1))
    assert colors.shape == (len(mesh.vertices), 4)
    py = tmp_path / "py.ply"
    texbake.write_vertex_colors(py, mesh, colors)
    assert py.read_bytes() == out.read_bytes()
    assert [c["image"] for c in cameras] == [f"view_0{k}.png" for k in range(4)]
    assert all(c["photo"] == (320, 240) for c in cameras)
    assert sum(c["weight_share"] for c in cameras) == pytest.approx(1, abs=1e-9)
    # Exposure gains multiply to 1 (geometric mean 1), channel by channel.
    gains = np.array([c["gain"] for c in cameras])
    assert np.prod(gains, axis=0) == pytest.approx([1, 1, 1], abs=1e-9)
    assert stats["counts"]["vertices"] == len(mesh.vertices)


def test_photo_errors_are_the_cli_messages(tmp_path, bunny):
    mesh = bunny
    with pytest.raises(OSError, match="missing"):
        texbake.bake_vertex_from_photos(mesh, cameras=tmp_path / "missing")
    with pytest.raises(ValueError, match="blend: unknown value 'sharp'"):
        texbake.bake_vertex_from_photos(mesh, cameras=tmp_path, blend="sharp")


def test_an_unreadable_photo_is_left_out(tmp_path):
    """A missing photo is left out with a warning and listed (as the CLI's
    --report photos_skipped); strict_photos=True makes it the CLI's
    --strict-photos error (OSError)."""
    bunny = DATA / "bunny00.off"
    ws = tmp_path / "ws"
    r = run_cli("render", bunny, "--views", "3", "--size", "64x48", "--colmap", ws)
    assert r.returncode == 0, r.stderr
    missing = ws / "images" / "view_01.png"
    missing.unlink()
    mesh = texbake.read_mesh(bunny)
    colors, stats, cameras = texbake.bake_vertex_from_photos(mesh, cameras=ws / "sparse" / "0")
    assert [c["image"] for c in cameras] == ["view_00.png", "view_02.png"]
    assert stats["photos_skipped"] == [
        {"image": "view_01.png", "path": str(missing), "reason": f"{missing}: no such file"}]
    assert stats["warnings"] == [
        f"the photo of camera view_01.png is left out: {missing}: no such file"]
    with pytest.raises(OSError, match="the photo of camera view_01.png: .*no such file"):
        texbake.bake_vertex_from_photos(mesh, cameras=ws / "sparse" / "0", strict_photos=True)


def test_layers_match_the_cli(tmp_path):
    """bake_vertex_from_layers gives the CLI's PLY bytes, here for the bundled
    bottle (label over the mesh's colours plus a decal), and the same per-layer
    counts as the CLI's report."""
    bottle, layers = DATA / "bottle.ply", DATA / "bottle_layers.json"
    out, report = tmp_path / "cli.ply", tmp_path / "r.json"
    r = run_cli("bake", bottle, "--layers", layers, "-q", "--report", report, "-o", out)
    assert r.returncode == 0, r.stderr
    mesh = texbake.read_mesh(bottle)
    colors, stats, per_layer = texbake.bake_vertex_from_layers(mesh, layers=layers)
    assert colors.shape == (len(mesh.vertices), 4)
    py = tmp_path / "py.ply"
    texbake.write_vertex_colors(py, mesh, colors)
    assert py.read_bytes() == out.read_bytes()
    cli = json.loads(report.read_text())["layers"]
    assert [(l["in_domain"], l["visible"], l["blended"]) for l in per_layer] == \
        [(l["in_domain"], l["visible"], l["blended"]) for l in cli]
    with pytest.raises(OSError, match="missing.json"):
        texbake.bake_vertex_from_layers(mesh, layers=tmp_path / "missing.json")
    with pytest.raises(ValueError, match="occluded"):
        texbake.bake_vertex_from_layers(mesh, layers=layers, occluded="paint")


def test_masks_as_the_cli_and_as_alpha(tmp_path):
    """masks= is --masks (COLMAP's DIR/<image name>.png, 0 = masked out): the
    same bytes as the CLI, and as the same masks put into the photos' alpha;
    check_cameras counts masked vertices; a missing folder is OSError."""
    bunny = DATA / "bunny00.off"
    ws = tmp_path / "ws"
    r = run_cli("render", bunny, "--texture", DATA / "earth.jpg", "--proxy", "sphere", "--up", "y",
                "--unlit", "--views", "3", "--size", "96x72", "--colmap", ws)
    assert r.returncode == 0, r.stderr
    masks, alpha = tmp_path / "masks", tmp_path / "alpha"
    masks.mkdir()
    alpha.mkdir()
    for k in range(3):
        name = f"view_0{k}.png"
        keep = np.ones((72, 96), bool)
        keep[:, 10 * k:10 * k + 40] = False
        grey = np.where(keep, 0.5, 0.0).astype(np.float32)  # 0.5: kept whole, COLMAP's rule
        texbake.write_image(masks / (name + ".png"), np.dstack([grey, grey, grey]))
        photo = np.array(texbake.read_image(ws / "images" / name))
        photo[..., 3] *= keep
        texbake.write_image(alpha / name, photo)
    mesh = texbake.read_mesh(bunny)
    model = ws / "sparse" / "0"
    by_masks, stats, cameras = texbake.bake_vertex_from_photos(mesh, cameras=model, masks=masks)
    by_alpha, _, _ = texbake.bake_vertex_from_photos(mesh, cameras=model, images=alpha)
    plain, _, _ = texbake.bake_vertex_from_photos(mesh, cameras=model)
    assert np.array_equal(by_masks, by_alpha)
    assert not np.array_equal(by_masks, plain)
    assert all(c["masked"] > 40 / 96 for c in cameras)
    out = tmp_path / "cli.ply"
    r = run_cli("bake", bunny, "--cameras", model, "--masks", masks, "-q", "-o", out)
    assert r.returncode == 0, r.stderr
    py = tmp_path / "py.ply"
    texbake.write_vertex_colors(py, mesh, by_masks)
    assert py.read_bytes() == out.read_bytes()
    checks = texbake.check_cameras(mesh, cameras=model, masks=masks)
    unmasked = texbake.check_cameras(mesh, cameras=model)
    for c, u in zip(checks, unmasked):
        assert c["has_mask"] and c["masked"] > 0 and c["inside"] == u["inside"]
        assert c["visible"] < u["visible"] and u["masked"] == 0
    with pytest.raises(OSError, match="masks .*nowhere: no such folder"):
        texbake.bake_vertex_from_photos(mesh, cameras=model, masks=tmp_path / "nowhere")


def test_refine_cameras_is_the_cli_and_keeps_true_poses(tmp_path):
    """refine_cameras returns the poses `cameras refine` writes (images.txt,
    read here with COLMAP's quaternion convention) and its report's figures,
    with another thread count. The photos: 160 x 120 renders at one sample
    per pixel of the Earth map, aliased, too coarse to pin a pose: the steps
    drift (measured: RMS 0.028 -> 0.155 over every photo's samples) and the
    refinement keeps the input poses, the true ones, with a warning."""
    bunny = DATA / "bunny00.off"
    ws = tmp_path / "ws"
    r = run_cli("render", bunny, "--texture", DATA / "earth.jpg", "--proxy", "sphere", "--up", "y",
                "--unlit", "--views", "4", "--size", "160x120", "--colmap", ws)
    assert r.returncode == 0, r.stderr
    model = ws / "sparse" / "0"
    out, report = tmp_path / "refined", tmp_path / "refine.json"
    r = run_cli("cameras", "refine", bunny, "--cameras", model, "-q", "--threads", "2",
                "--report", report, "-o", out)
    assert r.returncode == 0, r.stderr
    assert "the input poses are kept" in r.stderr, r.stderr
    mesh = texbake.read_mesh(bunny)
    photos, stats = texbake.refine_cameras(mesh, cameras=model, threads=1)
    assert any("did not make the photos agree better" in w for w in stats["warnings"])
    written, truth = read_model(out), read_model(model)
    assert [p["image"] for p in photos] == [f"view_0{k}.png" for k in range(4)]
    rep = json.loads(report.read_text())
    assert [p["image"] for p in rep["photos"]] == [p["image"] for p in photos]
    for p, q in zip(photos, rep["photos"]):
        R, t = written[p["image"]]
        np.testing.assert_allclose(np.array(p["R"]), R, atol=1e-9)
        np.testing.assert_allclose(np.array(p["t"]), t, atol=1e-9)
        R0, t0 = truth[p["image"]]
        np.testing.assert_allclose(R, R0, atol=1e-12)
        np.testing.assert_allclose(t, t0, atol=1e-12)
        assert p["rotation_change_deg"] < 1e-9 and p["translation_change"] < 1e-12
        assert not p["skipped"] and not p["clamped"]
        assert p["residual_after"] == p["residual_before"] == pytest.approx(q["residual_after"])
        assert p["iterations"] == 0  # the steps were dropped with the poses they found
    assert stats["points"] == rep["points"] and stats["levels"] == rep["levels"] == 2
    with pytest.raises(ValueError, match=r"--iterations 0 is out of range \(1 \.\. 1000\)"):
        texbake.refine_cameras(mesh, cameras=model, iterations=0)
    with pytest.raises(ValueError, match="--max-rotation must be in"):
        texbake.refine_cameras(mesh, cameras=model, max_rotation=0)
    with pytest.raises(OSError, match="missing"):
        texbake.refine_cameras(mesh, cameras=tmp_path / "missing")
    # COLMAP masks (masks=DIR, as --masks): all but view_00 masked out whole,
    # so no point is seen by two photos (exit 1 in the CLI: OSError).
    masks = tmp_path / "masks"
    masks.mkdir()
    for k in range(4):
        texbake.write_image(masks / f"view_0{k}.png.png",
                            np.full((120, 160, 3), 1.0 if k == 0 else 0.0, np.float32))
    with pytest.raises(OSError, match="no point of the mesh is seen by two photos"):
        texbake.refine_cameras(mesh, cameras=model, masks=masks)
    r = run_cli("cameras", "refine", bunny, "--cameras", model, "--masks", masks, "-q",
                "-o", tmp_path / "masked")
    assert r.returncode == 1 and "no point of the mesh is seen by two photos" in r.stderr
    assert not (tmp_path / "masked").exists()


def test_a_camera_files_notes_reach_every_result(tmp_path):
    """What a camera file's reader did (here a nerfstudio transforms.json's
    applied_transform undone) is a note, as the CLI prints it: in the photo
    bakes' stats (both targets), a layers bake's cameras layer, check_cameras
    and run_job. The file is written here from the COLMAP model by numpy
    (camera-to-world, OpenGL axes, the world re-framed by applied_transform
    as nerfstudio's colmap_to_json does: rows x, z, -y), so its bake must
    equal the model's."""
    bunny = DATA / "bunny00.off"
    ws = tmp_path / "ws"
    r = run_cli("render", bunny, "--texture", DATA / "earth.jpg", "--proxy", "sphere", "--up", "y",
                "--unlit", "--views", "3", "--size", "96x72", "--colmap", ws)
    assert r.returncode == 0, r.stderr
    cams = (ws / "sparse" / "0" / "cameras.txt").read_text().split("\n")
    w, h, fx, fy, cx, cy = next(l.split()[2:] for l in cams if l and l[0] != "#"
                                and l.split()[1] == "PINHOLE")
    applied = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]], float)
    frames = []
    for name, (rot, t) in sorted(read_model(ws / "sparse" / "0").items()):
        c2w = np.eye(4)
        c2w[:3, :3] = rot.T @ np.diag([1, -1, -1])  # OpenCV -> OpenGL axes
        c2w[:3, 3] = -rot.T @ t
        frames.append({"file_path": "images/" + name,
                       "transform_matrix": (applied @ c2w).tolist()})
    transforms = ws / "transforms.json"
    transforms.write_text(json.dumps({
        "camera_model": "OPENCV", "w": int(w), "h": int(h), "fl_x": float(fx), "fl_y": float(fy),
        "cx": float(cx), "cy": float(cy), "frames": frames,
        "applied_transform": applied[:3].tolist()}))
    note = f"{transforms}: the poses are taken back to the frame of the data they were made from"

    def noted(notes):
        return len(notes) == 1 and notes[0].startswith(note)

    mesh = texbake.read_mesh(bunny)
    colors, stats, _ = texbake.bake_vertex_from_photos(mesh, cameras=transforms)
    model_colors, model_stats, _ = texbake.bake_vertex_from_photos(
        mesh, cameras=ws / "sparse" / "0")
    assert np.abs(colors - model_colors).max() < 1e-4
    assert noted(stats["notes"]) and model_stats["notes"] == []
    atlas, _ = texbake.bake_atlas_from_photos(mesh, cameras=transforms, size=64)
    assert noted(atlas.stats["notes"])
    layers = tmp_path / "layers.json"
    layers.write_text(json.dumps({"base": [0.5, 0.5, 0.5, 1],
                                  "layers": [{"cameras": str(transforms)}]}))
    _, layer_stats, _ = texbake.bake_vertex_from_layers(mesh, layers=layers)
    assert noted(layer_stats["notes"])
    assert noted(texbake.check_cameras(mesh, cameras=transforms, photos=False).notes)
    job = texbake.run_job(bunny, tmp_path / "job.ply", cameras=str(transforms))
    assert noted(job["notes"]) and job["warnings"] == []
    # The CLI prints the same line (and --quiet drops it).
    r = run_cli("bake", bunny, "--cameras", transforms, "-o", tmp_path / "cli.ply")
    assert r.returncode == 0 and f"texbake: {note}" in r.stderr, r.stderr
