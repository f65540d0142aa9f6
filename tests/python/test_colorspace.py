"""Colour spaces in the Python module (README, Colour spaces): read_image
tags its array with the file's colour space, the bakes sample a linear
array in linear light, and their results equal the CLI's for the same
file. Expected values by hand: sRGB 128/255 = 0.50196 is linear
((0.50196 + 0.055) / 1.055) ** 2.4 = 0.2158605."""
import numpy as np
import pytest

from conftest import DATA, run_cli

SRGB = 128 / 255
LINEAR = ((SRGB + 0.055) / 1.055) ** 2.4


def test_read_image_tags_the_colour_space(tmp_path):
    import texbake
    earth = texbake.read_image(DATA / "earth.jpg")
    assert isinstance(earth, texbake.ImageArray) and earth.colorspace == "srgb"
    assert earth[1:5].colorspace == "srgb"  # views keep it
    texbake.write_image(tmp_path / "lin.exr", np.full((4, 8, 4), LINEAR, np.float32), bits=32)
    lin = texbake.read_image(tmp_path / "lin.exr")
    assert lin.colorspace == "linear"
    assert abs(float(lin[0, 0, 0]) - LINEAR) < 1e-6
    assert texbake.read_image(tmp_path / "lin.exr", colorspace="srgb").colorspace == "srgb"
    with pytest.raises(ValueError):
        texbake.read_image(tmp_path / "lin.exr", colorspace="gamma")
    with pytest.raises(ValueError):
        texbake.image(lin, "rec709")


def test_a_linear_array_bakes_like_its_srgb_twin(bunny):
    import texbake
    proxy = texbake.fit(bunny, "sphere", up="y")
    srgb = np.full((16, 32, 4), SRGB, np.float32)
    srgb[..., 3] = 1
    linear = texbake.image(np.where(np.arange(4) < 3, LINEAR, 1).astype(np.float32)
                           * np.ones((16, 32, 1), np.float32), "linear")
    a, _ = texbake.bake_vertex(bunny, srgb, proxy, occluded=(1, 0, 0))
    b, _ = texbake.bake_vertex(bunny, linear, proxy, occluded=(1, 0, 0))
    # Both are sRGB-encoded results of the same light: 128/255 wherever seen.
    seen = a[:, 1] > 0.1
    assert seen.sum() > 1000
    assert np.abs(a[seen, :3] - SRGB).max() < 1e-5
    assert np.abs(b[seen, :3] - SRGB).max() < 1e-5
    # The same linear values taken as sRGB give another colour: the tag matters.
    c, _ = texbake.bake_vertex(bunny, texbake.image(linear, "srgb"), proxy, occluded=(1, 0, 0))
    assert np.abs(c[seen, 0] - LINEAR).max() < 1e-5


def test_a_linear_exr_bakes_as_the_cli_does(tmp_path, bunny):
    import texbake
    values = np.zeros((64, 128, 4), np.float32)
    values[..., 0] = np.linspace(0, 1, 128)[None, :] ** 2.2
    values[..., 1] = np.linspace(0, 1, 64)[:, None]
    values[..., 2] = 0.05
    values[..., 3] = 1
    texbake.write_image(tmp_path / "ramp.exr", values, bits=32)
    proxy = texbake.fit(bunny, "sphere", up="y")
    proxy.write(tmp_path / "s.json")
    image = texbake.read_image(tmp_path / "ramp.exr")
    colors, _ = texbake.bake_vertex(bunny, image, proxy)
    texbake.write_vertex_colors(tmp_path / "py.ply", bunny, colors)
    r = run_cli("bake", DATA / "bunny00.off", "--texture", tmp_path / "ramp.exr",
                "--proxy-file", tmp_path / "s.json", "-q", "-o", tmp_path / "cli.ply")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
