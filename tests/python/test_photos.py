"""texbake.bake_vertex_from_photos against the command line (SPEC sections 9, 11)."""
import numpy as np
import pytest

import texbake
from conftest import DATA, run_cli


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
    import json
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
