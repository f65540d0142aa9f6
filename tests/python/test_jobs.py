"""Every job of the command line has a Python call giving the same bytes
(issue #29 item 4): the atlas from photos, the atlas from layers, the
camera proxy bakes (vertex and atlas) and cameras check. Each test runs the
CLI's job and the Python call, writes the Python result with the library's
writer under the same file name in another folder, and compares the files
byte for byte (an atlas: OBJ, MTL and PNG)."""
import json

import numpy as np
import pytest

import texbake
from conftest import DATA, run_cli

BUNNY = DATA / "bunny00.off"


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    """Four unlit views of the bunny with the earth projected on it, as a COLMAP workspace."""
    ws = tmp_path_factory.mktemp("jobs") / "ws"
    r = run_cli("render", BUNNY, "--texture", DATA / "earth.jpg", "--proxy", "sphere",
                "--center", "0,0,0", "--radius", "1", "--pole", "0,1,0", "--equator", "0,0,1",
                "--up", "y", "--unlit", "--views", "4", "--size", "320x240", "--colmap", ws)
    assert r.returncode == 0, r.stderr
    return ws


def same_files(cli_out, py_out):
    """The atlas file set of each (atlas_files) exists and is byte-identical."""
    cli_files, py_files = texbake.atlas_files(cli_out), texbake.atlas_files(py_out)
    assert len(cli_files) == 3
    for a, b in zip(cli_files, py_files):
        with open(a, "rb") as fa, open(b, "rb") as fb:
            assert fa.read() == fb.read(), (a, b)


def test_atlas_from_photos_gives_the_cli_files(tmp_path, workspace):
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    cli_out, py_out = tmp_path / "cli" / "a.obj", tmp_path / "py" / "a.obj"
    r = run_cli("bake", BUNNY, "--cameras", workspace / "sparse" / "0", "--size", "128",
                "--occluded", "1,0,1", "-q", "--threads", "2", "-o", cli_out)
    assert r.returncode == 0, r.stderr
    mesh = texbake.read_mesh(BUNNY)
    atlas, cameras = texbake.bake_atlas_from_photos(mesh, cameras=workspace / "sparse" / "0",
                                                    size=128, occluded=(1, 0, 1), threads=1)
    assert atlas.image.shape == (128, 128, 4)
    assert atlas.uv_layout["used"] == "generate"  # the bunny has no UVs
    texbake.write_atlas(py_out, atlas)
    same_files(cli_out, py_out)
    assert [c["image"] for c in cameras] == [f"view_0{k}.png" for k in range(4)]
    assert sum(c["weight_share"] for c in cameras) == pytest.approx(1, abs=1e-9)


def test_atlas_from_layers_gives_the_cli_files(tmp_path):
    bottle, layers = DATA / "bottle.ply", DATA / "bottle_layers.json"
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    cli_out, py_out = tmp_path / "cli" / "b.obj", tmp_path / "py" / "b.obj"
    report = tmp_path / "r.json"
    r = run_cli("bake", bottle, "--layers", layers, "--size", "128", "-q", "--report", report,
                "-o", cli_out)
    assert r.returncode == 0, r.stderr
    atlas, per_layer = texbake.bake_atlas_from_layers(texbake.read_mesh(bottle), layers=layers,
                                                      size=128)
    texbake.write_atlas(py_out, atlas)
    same_files(cli_out, py_out)
    cli = json.loads(report.read_text())["layers"]
    assert [(l["in_domain"], l["visible"], l["blended"]) for l in per_layer] == \
        [(l["in_domain"], l["visible"], l["blended"]) for l in cli]


def test_atlas_from_layers_without_size_is_the_cli_default(tmp_path):
    """size=None is the CLI without --size: 2048 for a base that is not a texture."""
    bottle = DATA / "bottle.ply"
    atlas, _ = texbake.bake_atlas_from_layers(texbake.read_mesh(bottle),
                                              layers=DATA / "bottle_layers.json", samples=1)
    assert atlas.image.shape == (2048, 2048, 4)


def camera_file(ws, tmp_path, k):
    """The camera of view k of the workspace as a camera proxy file (SPEC
    section 9: kind camera, COLMAP's model, params and world-to-camera pose),
    read from the workspace's text model."""
    cams = {}
    for line in (ws / "sparse" / "0" / "cameras.txt").read_text().splitlines():
        if line and not line.startswith("#"):
            f = line.split()
            cams[f[0]] = {"model": f[1], "width": int(f[2]), "height": int(f[3]),
                          "params": [float(x) for x in f[4:]]}
    for line in (ws / "sparse" / "0" / "images.txt").read_text().splitlines():
        f = line.split()  # a pose line: ID QW QX QY QZ TX TY TZ CAMERA_ID NAME
        if not line.startswith("#") and len(f) == 10 and f[9] == f"view_0{k}.png":
            cam = dict(cams[f[8]], kind="camera")
            cam["pose"] = {"q_wxyz": [float(x) for x in f[1:5]],
                           "t": [float(x) for x in f[5:8]]}
            path = tmp_path / f"view_0{k}.json"
            path.write_text(json.dumps(cam))
            return path, ws / "images" / f[9]
    raise AssertionError(f"view_0{k}.png not in images.txt")


def test_vertex_from_camera_gives_the_cli_ply(tmp_path, workspace):
    camera, photo = camera_file(workspace, tmp_path, 1)
    cli_out, py_out = tmp_path / "cli.ply", tmp_path / "py.ply"
    r = run_cli("bake", BUNNY, "--texture", photo, "--proxy-file", camera, "-q", "-o", cli_out)
    assert r.returncode == 0, r.stderr
    mesh = texbake.read_mesh(BUNNY)
    colors, stats, cameras = texbake.bake_vertex_from_camera(mesh, camera=camera, photo=photo)
    texbake.write_vertex_colors(py_out, mesh, colors)
    assert py_out.read_bytes() == cli_out.read_bytes()
    # One photo: no exposure balance (gain 1), all the weight.
    assert len(cameras) == 1 and cameras[0]["gain"] == (1, 1, 1)
    assert cameras[0]["weight_share"] == pytest.approx(1)
    assert stats["counts"]["vertices"] == len(mesh.vertices)


def test_atlas_from_camera_gives_the_cli_files(tmp_path, workspace):
    camera, photo = camera_file(workspace, tmp_path, 2)
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    cli_out, py_out = tmp_path / "cli" / "c.glb", tmp_path / "py" / "c.glb"
    r = run_cli("bake", BUNNY, "--texture", photo, "--proxy-file", camera, "--size", "64",
                "--padding", "inf", "-q", "-o", cli_out)
    assert r.returncode == 0, r.stderr
    atlas, cameras = texbake.bake_atlas_from_camera(texbake.read_mesh(BUNNY), camera=camera,
                                                    photo=photo, size=64, padding="inf")
    texbake.write_atlas(py_out, atlas)
    assert py_out.read_bytes() == cli_out.read_bytes()


def test_camera_proxy_errors(tmp_path, bunny):
    sphere = tmp_path / "s.json"
    texbake.Proxy.sphere().write(sphere)
    with pytest.raises(ValueError, match="holds an analytic proxy, not a camera"):
        texbake.bake_vertex_from_camera(bunny, camera=sphere, photo=DATA / "earth.jpg")
    with pytest.raises(OSError, match="missing.json"):
        texbake.bake_vertex_from_camera(bunny, camera=tmp_path / "missing.json",
                                        photo=DATA / "earth.jpg")


def test_check_cameras_gives_the_cli_table(tmp_path, workspace):
    """check_cameras is `cameras check`: the --json rows (photo agreement
    columns included), the table's agreement line, the bake's own agreement
    figures (stats), and --no-photos as photos=False."""
    model = workspace / "sparse" / "0"
    r = run_cli("cameras", "check", BUNNY, "--cameras", model, "--json")
    assert r.returncode == 0, r.stderr
    cli = json.loads(r.stdout)
    for c in cli:
        c["gain"] = tuple(c["gain"])
    mesh = texbake.read_mesh(BUNNY)
    checks = texbake.check_cameras(mesh, cameras=model)
    assert isinstance(checks, texbake.CameraChecks) and isinstance(checks, list)
    assert checks == cli
    # Renders framed on the bunny see all of it in front and inside.
    assert all(c["in_front"] == 1 and c["inside"] == 1 for c in checks)
    assert all(0 < c["visible"] < 1 for c in checks)
    # The agreement: the photo bake's own figures; the table's line.
    _, stats, _ = texbake.bake_vertex_from_photos(mesh, cameras=model, occluded=(0, 0, 0))
    assert checks.photo_agreement == stats["photo_agreement"]
    a = checks.photo_agreement
    # An unlit render: the views agree but for resampling (measured 89.8 %).
    assert a["vertices"] > 1000 and a["agreeing"] > 0.8
    r = run_cli("cameras", "check", BUNNY, "--cameras", model)
    assert r.returncode == 0, r.stderr
    line = [l for l in r.stdout.splitlines() if l.startswith("photo agreement: ")][0]
    assert f"{100 * a['agreeing']:.0f} % of {a['vertices']} vertices" in line, line
    assert checks.alignment is None  # the render writes no sparse points
    assert checks.agreement_note == "" and list(checks.warnings) == []
    # --no-photos: the geometric figures only.
    plain = texbake.check_cameras(mesh, cameras=model, photos=False)
    r = run_cli("cameras", "check", BUNNY, "--cameras", model, "--json", "--no-photos")
    assert plain == json.loads(r.stdout)
    assert plain.photo_agreement is None and "shared" not in plain[0]
    # No photo readable: the geometric figures and a note saying why.
    empty = tmp_path / "empty"
    empty.mkdir()
    loose = texbake.check_cameras(mesh, cameras=model, images=empty)
    assert loose.photo_agreement is None and "view_00.png" in loose.agreement_note
    assert [c["visible"] for c in loose] == [c["visible"] for c in checks]
    # A model outside a workspace needs no photo folder (as the CLI).
    import shutil
    bare = tmp_path / "bare"
    shutil.copytree(model, bare)
    r = run_cli("cameras", "check", BUNNY, "--cameras", bare, "--json")
    assert r.returncode == 0, r.stderr
    alone = texbake.check_cameras(mesh, cameras=bare)
    assert alone == json.loads(r.stdout) == plain
    assert alone.photo_agreement is None and alone.agreement_note != ""


def test_new_calls_release_the_gil_and_report_progress(tmp_path, workspace):
    stages = set()
    texbake.bake_atlas_from_photos(texbake.read_mesh(BUNNY), cameras=workspace / "sparse" / "0",
                                   size=32, progress=lambda s, f: stages.add(s))
    assert {"uv_layout", "photos"} <= stages
    with pytest.raises(texbake.Cancelled):
        texbake.bake_atlas_from_layers(texbake.read_mesh(DATA / "bottle.ply"),
                                       layers=DATA / "bottle_layers.json", size=32,
                                       progress=lambda s, f: False)


@pytest.mark.parametrize("name", ["p.ply", "p.obj"])
def test_run_job_from_photos_gives_the_cli_files(tmp_path, workspace, name):
    """texbake.run_job with cameras= is `texbake bake --cameras`, either target."""
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    size = ["--size", "64"] if name.endswith(".obj") else []
    r = run_cli("bake", BUNNY, "--cameras", workspace / "sparse" / "0", *size, "--blend", "best",
                "-q", "--threads", "2", "-o", tmp_path / "cli" / name)
    assert r.returncode == 0, r.stderr
    extra = dict(size=64) if name.endswith(".obj") else {}
    result = texbake.run_job(BUNNY, tmp_path / "py" / name, cameras=workspace / "sparse" / "0",
                             blend="best", threads=1, **extra)
    assert result["report"]["counts"]
    keys = {o["key"] for o in texbake.JOB_OPTIONS}
    assert set(result["report"]["inputs"]["options"]) <= keys
    assert result["report"]["inputs"]["options"]["blend"] == "best"
    for a, b in zip(sorted((tmp_path / "cli").iterdir()), sorted((tmp_path / "py").iterdir())):
        assert a.name == b.name  # an OBJ names its MTL by the same name: equal too
        assert a.read_bytes() == b.read_bytes(), a.name


def test_run_job_through_a_camera_proxy_gives_the_cli_ply(tmp_path, workspace):
    camera, photo = camera_file(workspace, tmp_path, 1)
    cli_out, py_out = tmp_path / "cli.ply", tmp_path / "py.ply"
    r = run_cli("bake", BUNNY, "--texture", photo, "--proxy-file", camera, "-q", "-o", cli_out)
    assert r.returncode == 0, r.stderr
    texbake.run_job(BUNNY, py_out, texture=photo, proxy_file=camera)
    assert cli_out.read_bytes() == py_out.read_bytes()
    # A flag that does not apply to a camera: the command line's refusal.
    with pytest.raises(ValueError, match="--filter does not apply to a camera --proxy-file"):
        texbake.run_job(BUNNY, py_out, texture=photo, proxy_file=camera, filter="ewa")
