"""The Python bakes' results name their figures as the command line's
--report does for the same job: each call's stats["counts"] equals the
report's "counts" (same keys, same values), its timings are the report's
stages by name, an atlas's stats["atlas"] is the report's atlas object
(size, samples_per_texel, padding, counts, uv ...), the photo bakes of either target
list the photos left out ("photos_skipped"), and so does each cameras layer
of a layers bake. An unreadable photo in the workspace leaves the atlas as
it is without that photo."""
import json
import shutil

import numpy as np
import pytest

import texbake
from conftest import DATA, run_cli

BUNNY = DATA / "bunny00.off"
EARTH = DATA / "earth.jpg"
SPHERE = dict(center=(0, 0, 0), radius=1, pole=(0, 1, 0), equator=(0, 0, 1))
SPHERE_FLAGS = ["--proxy", "sphere", "--center", "0,0,0", "--radius", "1", "--pole", "0,1,0",
                "--equator", "0,0,1"]


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    """Three unlit views of the bunny with the earth on it, as a COLMAP workspace."""
    ws = tmp_path_factory.mktemp("results") / "ws"
    r = run_cli("render", BUNNY, "--texture", EARTH, *SPHERE_FLAGS, "--up", "y", "--unlit",
                "--views", "3", "--size", "96x72", "--colmap", ws)
    assert r.returncode == 0, r.stderr
    return ws


@pytest.fixture(scope="module")
def mesh():
    return texbake.read_mesh(BUNNY)


def cli_report(tmp_path, *args):
    """Runs `texbake bake BUNNY ARGS --report R -o ...`; returns the report."""
    report = tmp_path / "r.json"
    r = run_cli("bake", *args, "-q", "--report", report)
    assert r.returncode == 0, r.stderr
    return json.loads(report.read_text())


def same_as_report(stats, report):
    """stats (a call's, or an atlas's) name their figures as the report:
    counts equal key for key, the timings are the report's stages (not the
    job's load, fit, write; total is the call's), an atlas's "atlas" object
    equals the report's less its timings, photos_skipped equal."""
    assert stats["counts"] == report["counts"]
    stages = [k for k in report["timings"] if k not in ("load", "fit", "write", "total")]
    assert list(stats["timings"]) == stages + ["total"]
    if "per_layer" in stages:
        assert len(stats["timings"]["per_layer"]) == len(report["timings"]["per_layer"])
    if "atlas" in report:
        assert stats["atlas"] == {k: v for k, v in report["atlas"].items() if k != "timings"}
    else:
        assert "atlas" not in stats
    if "photos_skipped" in report:
        assert stats["photos_skipped"] == report["photos_skipped"]


def camera_file(ws, tmp_path, name):
    """The camera of photo `name` as a camera proxy file (SPEC section 9),
    from the workspace's text model."""
    cams, sparse = {}, ws / "sparse" / "0"
    for line in (sparse / "cameras.txt").read_text().splitlines():
        if line and not line.startswith("#"):
            f = line.split()
            cams[f[0]] = {"model": f[1], "width": int(f[2]), "height": int(f[3]),
                          "params": [float(x) for x in f[4:]]}
    for line in (sparse / "images.txt").read_text().splitlines():
        f = line.split()
        if not line.startswith("#") and len(f) == 10 and f[9] == name:
            cam = dict(cams[f[8]], kind="camera",
                       pose={"q_wxyz": [float(x) for x in f[1:5]],
                             "t": [float(x) for x in f[5:8]]})
            path = tmp_path / "camera.json"
            path.write_text(json.dumps(cam))
            return path
    raise AssertionError(name)


def test_proxy_bakes_count_as_the_report(tmp_path, mesh, earth):
    proxy = texbake.Proxy.sphere(**SPHERE)
    report = cli_report(tmp_path, BUNNY, "--texture", EARTH, *SPHERE_FLAGS, "-o",
                        tmp_path / "v.ply")
    _, stats = texbake.bake_vertex(mesh, earth, proxy)
    same_as_report(stats, report)
    assert set(stats["counts"]) == {"vertices", "triangles", "degenerate_skipped",
                                    "unreferenced_vertices", "samples", "occluded",
                                    "undefined", "outside", "filled", "unfilled"}
    assert stats["counts"]["vertices"] == 37706 and stats["counts"]["occluded"] > 0
    report = cli_report(tmp_path, BUNNY, "--texture", EARTH, *SPHERE_FLAGS, "--size", "64",
                        "-o", tmp_path / "a.obj")
    atlas = texbake.bake_atlas(mesh, earth, proxy, size=64)
    same_as_report(atlas.stats, report)
    assert atlas.stats["atlas"]["padding"] == 1  # 8 at 2048, scaled to 64: at least 1
    assert atlas.stats["counts"]["texels"] > 0 and "filled" not in atlas.stats["counts"]


def test_photo_and_camera_bakes_count_as_the_report(tmp_path, mesh, workspace):
    sparse = workspace / "sparse" / "0"
    report = cli_report(tmp_path, BUNNY, "--cameras", sparse, "-o", tmp_path / "p.ply")
    _, stats, _ = texbake.bake_vertex_from_photos(mesh, cameras=sparse)
    same_as_report(stats, report)
    assert {"camera_samples", "unseen"} <= set(stats["counts"])
    assert stats["photos_skipped"] == report["photos_skipped"] == []
    report = cli_report(tmp_path, BUNNY, "--cameras", sparse, "--size", "64", "-o",
                        tmp_path / "p.obj")
    atlas, _ = texbake.bake_atlas_from_photos(mesh, cameras=sparse, size=64)
    same_as_report(atlas.stats, report)
    assert {"unseen", "unfilled_vertices"} <= set(atlas.stats["counts"])
    assert atlas.stats["photos_skipped"] == report["photos_skipped"] == []
    camera = camera_file(workspace, tmp_path, "view_01.png")
    photo = workspace / "images" / "view_01.png"
    report = cli_report(tmp_path, BUNNY, "--texture", photo, "--proxy-file", camera, "-o",
                        tmp_path / "c.ply")
    _, stats, _ = texbake.bake_vertex_from_camera(mesh, camera=camera, photo=photo)
    same_as_report(stats, report)
    report = cli_report(tmp_path, BUNNY, "--texture", photo, "--proxy-file", camera, "--size",
                        "64", "-o", tmp_path / "c.obj")
    atlas, _ = texbake.bake_atlas_from_camera(mesh, camera=camera, photo=photo, size=64)
    same_as_report(atlas.stats, report)


def test_layers_bakes_count_as_the_report(tmp_path):
    bottle, layers = DATA / "bottle.ply", DATA / "bottle_layers.json"
    mesh = texbake.read_mesh(bottle)
    report = cli_report(tmp_path, bottle, "--layers", layers, "-o", tmp_path / "l.ply")
    _, stats, _ = texbake.bake_vertex_from_layers(mesh, layers=layers)
    same_as_report(stats, report)
    assert set(stats["counts"]) == {"vertices", "triangles", "uncovered", "filled"}
    report = cli_report(tmp_path, bottle, "--layers", layers, "--size", "64", "-o",
                        tmp_path / "l.obj")
    atlas, _ = texbake.bake_atlas_from_layers(mesh, layers=layers, size=64)
    same_as_report(atlas.stats, report)
    # Without size: the report's size is the atlas's (the base texture's, else 2048).
    atlas, _ = texbake.bake_atlas_from_layers(mesh, layers=layers, size=None, samples=1)
    assert atlas.stats["atlas"]["size"] == atlas.image.shape[0] == 2048


def without_photo(ws, name, out):
    """A copy of the workspace's text model without photo `name` (its two
    lines of images.txt), its photos folder the workspace's."""
    sparse = out / "sparse" / "0"
    sparse.mkdir(parents=True)
    src = ws / "sparse" / "0"
    for f in src.iterdir():
        if f.name != "images.txt":
            (sparse / f.name).write_bytes(f.read_bytes())
    lines, kept, skip = (src / "images.txt").read_text().splitlines(), [], 0
    for line in lines:
        f = line.split()
        if skip:
            skip -= 1
        elif not line.startswith("#") and len(f) == 10 and f[9] == name:
            skip = 1  # and its 2D points' line
        else:
            kept.append(line)
    assert len(kept) == len(lines) - 2
    (sparse / "images.txt").write_text("\n".join(kept) + "\n")
    return sparse


def test_an_unreadable_photo_is_left_out_of_the_atlas(tmp_path, mesh, workspace):
    """The atlas from photos lists a photo that cannot be read (name and
    reason, as the vertex bake and the CLI's report), and equals the atlas
    of the model without that photo."""
    ws = tmp_path / "ws"
    shutil.copytree(workspace, ws)
    bad = ws / "images" / "view_01.png"
    bad.write_bytes(b"not a PNG file")
    atlas, cameras = texbake.bake_atlas_from_photos(mesh, cameras=ws / "sparse" / "0",
                                                    size=64, samples=1)
    skipped = atlas.stats["photos_skipped"]
    assert [(s["image"], s["path"]) for s in skipped] == [("view_01.png", str(bad))]
    assert skipped[0]["reason"].startswith(str(bad))
    assert atlas.stats["warnings"][0].startswith(
        "the photo of camera view_01.png is left out: " + str(bad))
    assert [c["image"] for c in cameras] == ["view_00.png", "view_02.png"]
    # The CLI's report lists it the same.
    report = cli_report(tmp_path, BUNNY, "--cameras", ws / "sparse" / "0", "--size", "64",
                        "--samples", "1", "-o", tmp_path / "cli.obj")
    assert report["photos_skipped"] == skipped
    # Without the photo in the model: the same atlas, cameras and counts.
    model = without_photo(workspace, "view_01.png", tmp_path / "two")
    alone, cameras2 = texbake.bake_atlas_from_photos(mesh, cameras=model,
                                                     images=workspace / "images", size=64,
                                                     samples=1)
    assert alone.stats["photos_skipped"] == []
    assert np.array_equal(atlas.image, alone.image)
    assert cameras == cameras2
    assert atlas.stats["counts"] == alone.stats["counts"]
    # The camera bake's atlas has the key too (its one photo is never left out).
    camera = camera_file(workspace, tmp_path, "view_00.png")
    one, _ = texbake.bake_atlas_from_camera(mesh, camera=camera,
                                            photo=workspace / "images" / "view_00.png", size=32)
    assert one.stats["photos_skipped"] == []


def test_a_cameras_layer_lists_its_photos_left_out(tmp_path, mesh, workspace):
    """A layers bake's cameras layer gives photos_skipped as the report's layer does."""
    ws = tmp_path / "ws"
    shutil.copytree(workspace, ws)
    missing = ws / "images" / "view_02.png"
    missing.unlink()
    layers = tmp_path / "layers.json"
    layers.write_text(json.dumps({"base": [0.5, 0.5, 0.5, 1],
                                  "layers": [{"cameras": "ws/sparse/0"}]}))
    report = cli_report(tmp_path, BUNNY, "--layers", layers, "-o", tmp_path / "l.ply")
    _, stats, per_layer = texbake.bake_vertex_from_layers(mesh, layers=layers)
    assert per_layer[0]["photos_skipped"] == report["layers"][0]["photos_skipped"] == [
        {"image": "view_02.png", "path": str(missing), "reason": f"{missing}: no such file"}]
    assert stats["counts"] == report["counts"]
    atlas, per_layer = texbake.bake_atlas_from_layers(mesh, layers=layers, size=32)
    assert per_layer[0]["photos_skipped"][0]["image"] == "view_02.png"


def test_atlas_filter_ewa_gives_the_cli_files(tmp_path, mesh):
    """bake_atlas takes --filter (bilinear, the table's atlas default, or
    ewa) and gives the CLI's bytes; area is the vertex bake's only."""
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    r = run_cli("bake", BUNNY, "--texture", EARTH, *SPHERE_FLAGS, "--filter", "ewa", "--size",
                "64", "-q", "-o", tmp_path / "cli" / "e.obj")
    assert r.returncode == 0, r.stderr
    atlas = texbake.bake_atlas(mesh, EARTH, texbake.Proxy.sphere(**SPHERE), filter="ewa",
                               size=64)
    texbake.write_atlas(tmp_path / "py" / "e.obj", atlas)
    for a, b in zip(texbake.atlas_files(tmp_path / "cli" / "e.obj"),
                    texbake.atlas_files(tmp_path / "py" / "e.obj")):
        assert open(a, "rb").read() == open(b, "rb").read(), (a, b)
    bilinear = texbake.bake_atlas(mesh, EARTH, texbake.Proxy.sphere(**SPHERE), size=64)
    assert not np.array_equal(bilinear.image, atlas.image)
    with pytest.raises(ValueError, match=r"^--filter area applies to --target vertex only"):
        texbake.bake_atlas(mesh, EARTH, texbake.Proxy.sphere(**SPHERE), filter="area")
