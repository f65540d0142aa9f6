"""The module's bakes equal the command line's, byte for byte (issue #15)."""
import numpy as np
import pytest

import texbake
from conftest import DATA, run_cli

# The README's sphere on the bunny, given completely (nothing fitted).
SPHERE_FLAGS = ["--proxy", "sphere", "--center", "0,0,0", "--radius", "1",
                "--pole", "0,1,0", "--equator", "0,0,1"]


def sphere():
    return texbake.Proxy.sphere(center=(0, 0, 0), radius=1, pole=(0, 1, 0), equator=(0, 0, 1))


def test_vertex_bake_writes_the_cli_bytes(tmp_path, bunny, earth):
    cli = tmp_path / "cli.ply"
    r = run_cli("bake", DATA / "bunny00.off", "--texture", DATA / "earth.jpg", *SPHERE_FLAGS,
                "-q", "-o", cli)
    assert r.returncode == 0, r.stderr
    colors, stats = texbake.bake_vertex(bunny, earth, sphere())
    assert colors.shape == (37706, 4) and colors.dtype == np.float32
    out = tmp_path / "py.ply"
    texbake.write_vertex_colors(out, bunny, colors)
    assert out.read_bytes() == cli.read_bytes()
    # The CLI's uchar colours are the module's to within rounding.
    back = texbake.read_mesh(cli).colors
    assert np.max(np.abs(back - colors)) <= 0.5 / 255 + 1e-6
    assert stats["counts"]["vertices"] == 37706
    assert stats["counts"]["occluded"] > 0


def test_vertex_bake_from_arrays_equals_the_mesh_object(bunny, earth):
    a, _ = texbake.bake_vertex(bunny, earth, sphere(), filter="bilinear", threads=1)
    b, _ = texbake.bake_vertex(bunny.vertices, bunny.faces, earth, sphere(), filter="bilinear",
                               threads=2)
    np.testing.assert_array_equal(a, b)


def test_fitted_bake_equals_the_cli_with_fit(tmp_path, bunny, earth):
    cli = tmp_path / "cli.ply"
    r = run_cli("bake", DATA / "bunny00.off", "--texture", DATA / "earth.jpg", "--proxy",
                "sphere", "--up", "y", "--visibility", "all", "--samples", "4", "-q", "-o", cli)
    assert r.returncode == 0, r.stderr
    proxy = texbake.fit(bunny, "sphere", up="y")
    assert proxy.fitted == ["center", "radius", "pole", "equator"]
    colors, _ = texbake.bake_vertex(bunny, earth, proxy, visibility="all", samples=4)
    out = tmp_path / "py.ply"
    texbake.write_vertex_colors(out, bunny, colors)
    assert out.read_bytes() == cli.read_bytes()


def test_atlas_bake_writes_the_cli_png(tmp_path, bunny, earth):
    cli = tmp_path / "cli.obj"
    r = run_cli("bake", DATA / "bunny00.off", "--texture", DATA / "earth.jpg", *SPHERE_FLAGS,
                "--uv", "proxy", "--size", "256", "-q", "-o", cli)
    assert r.returncode == 0, r.stderr
    atlas = texbake.bake_atlas(bunny, earth, sphere(), uv="proxy", size=256)
    image, uvs, face_uvs, stats = atlas
    assert image.shape == (256, 256, 4) and image.dtype == np.float32
    assert uvs.shape[1] == 2 and face_uvs.shape[1] == 3
    assert stats["counts"]["texels"] > 0
    out = tmp_path / "py.obj"
    texbake.write_atlas(out, atlas)
    assert texbake.atlas_files(out) == [str(out), str(tmp_path / "py.mtl"),
                                        str(tmp_path / "py.png")]
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    # The OBJ differs only in the names of its MTL and image.
    obj = out.read_text().replace("py.mtl", "cli.mtl")
    assert obj == cli.read_text()
    # The atlas image written alone holds the same pixels (the atlas writer
    # uses another zlib level).
    alone = tmp_path / "alone.png"
    texbake.write_image(alone, image)
    np.testing.assert_array_equal(texbake.read_image(alone),
                                  texbake.read_image(tmp_path / "cli.png"))


def test_input_image_of_other_layouts(bunny, earth):
    # uint8 RGB is scaled by 1/255 as read_image does: same colours.
    rgb8 = np.round(earth[:, :, :3] * 255).astype(np.uint8)
    a, _ = texbake.bake_vertex(bunny, earth, sphere(), filter="bilinear", visibility="all")
    b, _ = texbake.bake_vertex(bunny, rgb8, sphere(), filter="bilinear", visibility="all")
    np.testing.assert_array_equal(a, b)


def test_render_and_compare(tmp_path, bunny, earth):
    cli = tmp_path / "cli.png"
    r = run_cli("render", DATA / "bunny00.off", "--texture", DATA / "earth.jpg", *SPHERE_FLAGS,
                "--size", "64x48", "--up", "y", "-o", cli)
    assert r.returncode == 0, r.stderr
    image, _ = texbake.render(bunny, texture=earth, proxy=sphere(), size=(64, 48), up="y")
    assert image.shape == (48, 64, 4)
    out = tmp_path / "py.png"
    texbake.write_image(out, image)
    assert out.read_bytes() == cli.read_bytes()
    same = texbake.compare(out, cli)
    assert same["psnr"] == float("inf") and same["max_difference"] == 0
    grey, _ = texbake.render(bunny, size=(64, 48), up="y")
    diff = texbake.compare(grey, image)
    assert 0 < diff["max_difference"] <= 1


def test_mesh_uvs_from_a_file_and_from_arrays(tmp_path, earth):
    # suzanne_uv.obj: 1968 quads with a vt per corner.
    suzanne = texbake.read_mesh(DATA / "suzanne_uv.obj")
    assert suzanne.faces.shape == (1968, 4)
    assert suzanne.corner_uvs.shape == (4 * 1968,) and suzanne.uvs.shape[1] == 2
    cli = tmp_path / "cli.obj"
    r = run_cli("bake", DATA / "suzanne_uv.obj", "--texture", DATA / "earth.jpg", "--proxy",
                "sphere", "--center", "0,0,0", "--radius", "2", "--uv", "mesh", "--size", "128",
                "-q", "-o", cli)
    assert r.returncode == 0, r.stderr
    proxy = texbake.Proxy.sphere(radius=2)
    # The same mesh rebuilt from its arrays (quads, per-corner UVs) bakes the same atlas.
    rebuilt = texbake.Mesh(suzanne.vertices, suzanne.faces, uvs=suzanne.uvs,
                           face_uvs=suzanne.corner_uvs.reshape(-1, 4))
    for mesh in (suzanne, rebuilt):
        atlas = texbake.bake_atlas(mesh, earth, proxy, uv="mesh", size=128)
        assert atlas.uv_layout["used"] == "mesh"
        out = tmp_path / "py.obj"
        texbake.write_atlas(out, atlas)
        assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    with pytest.raises(ValueError, match="--uv mesh"):
        texbake.bake_atlas(suzanne.vertices, suzanne.faces, earth, proxy, uv="mesh")


@pytest.mark.parametrize("up", [None, "y"])
def test_glb_writes_the_cli_bytes_with_its_up(tmp_path, earth, up):
    mesh = texbake.read_mesh(DATA / "mushroom.off")
    cli = tmp_path / "cli.glb"
    r = run_cli("bake", DATA / "mushroom.off", "--texture", DATA / "earth.jpg", *SPHERE_FLAGS,
                *(["--up", up] if up else []), "--target", "vertex", "-q", "-o", cli)
    assert r.returncode == 0, r.stderr
    colors, _ = texbake.bake_vertex(mesh, earth, sphere())
    out = tmp_path / "py.glb"
    texbake.write_vertex_colors(out, mesh, colors, up=up or "z")
    assert out.read_bytes() == cli.read_bytes()
    if up:  # the node matrix differs from the Z-up one
        texbake.write_vertex_colors(tmp_path / "z.glb", mesh, colors)
        assert (tmp_path / "z.glb").read_bytes() != cli.read_bytes()


def test_ewa_vertex_bake_writes_the_cli_bytes(tmp_path, bunny, earth):
    # --filter ewa (issue #16 item 2): the module's filter="ewa" is the CLI's.
    cli = tmp_path / "cli.ply"
    r = run_cli("bake", DATA / "bunny00.off", "--texture", DATA / "earth.jpg", *SPHERE_FLAGS,
                "--filter", "ewa", "--visibility", "all", "-q", "-o", cli)
    assert r.returncode == 0, r.stderr
    colors, stats = texbake.bake_vertex(bunny, earth, sphere(), filter="ewa", visibility="all")
    out = tmp_path / "py.ply"
    texbake.write_vertex_colors(out, bunny, colors)
    assert out.read_bytes() == cli.read_bytes()
    assert stats["counts"]["samples"] == 37706  # one lookup per vertex


def test_an_image_path_is_read_through_the_cache_with_the_same_colours(tmp_path, bunny, earth):
    # earth.jpg (2048 x 1024) is 32 MiB as float RGBA: cache_mb=4 reads it
    # in tiles through OpenImageIO's ImageCache (issue #16), with the very
    # values of the array read whole; so does the CLI with --cache-mb 4.
    path = DATA / "earth.jpg"
    whole, _ = texbake.bake_vertex(bunny, earth, sphere(), linear=True)
    cached, _ = texbake.bake_vertex(bunny, path, sphere(), linear=True, cache_mb=4)
    np.testing.assert_array_equal(cached, whole)
    cli = tmp_path / "cli.ply"
    r = run_cli("bake", DATA / "bunny00.off", "--texture", path, *SPHERE_FLAGS, "--linear",
                "--cache-mb", "4", "-q", "-o", cli)
    assert r.returncode == 0, r.stderr
    out = tmp_path / "py.ply"
    texbake.write_vertex_colors(out, bunny, cached)
    assert out.read_bytes() == cli.read_bytes()
    a = texbake.bake_atlas(bunny, earth, sphere(), uv="proxy", size=128)
    b = texbake.bake_atlas(bunny, str(path), sphere(), uv="proxy", size=128, cache_mb=4)
    np.testing.assert_array_equal(a.image, b.image)
    # --filter ewa's MIP levels (10.7 MiB) do not fit 4 MiB: ValueError, as the CLI's exit 2.
    with pytest.raises(ValueError, match="--filter ewa keeps the MIP levels"):
        texbake.bake_vertex(bunny, path, sphere(), filter="ewa", cache_mb=4)
    with pytest.raises(OSError):
        texbake.bake_vertex(bunny, tmp_path / "missing.png", sphere())
