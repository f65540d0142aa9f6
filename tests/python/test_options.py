"""Bad arguments raise ValueError with the command line's message for the same
flag (issue #28 item 17): the library checks both clients' values with one
function per option, so each case runs the CLI with the flag and compares
its `texbake: error:` line with the Python exception's text."""
import math
import warnings

import numpy as np
import pytest

import texbake
from conftest import DATA, run_cli

BUNNY = DATA / "bunny00.off"
EARTH = DATA / "earth.jpg"
SPHERE = ["--proxy", "sphere", "--center", "0,0,0", "--radius", "1"]


def cli_usage(*args):
    """Runs the CLI; returns its one error message, asserting exit 2 (usage)."""
    r = run_cli(*args)
    errors = [l for l in r.stderr.splitlines() if l.startswith("texbake: error: ")]
    assert r.returncode == 2 and len(errors) == 1, (r.returncode, r.stderr)
    return errors[0][len("texbake: error: "):]


def py_usage(call):
    with pytest.raises(ValueError) as e:
        call()
    return str(e.value)


@pytest.fixture(scope="module")
def sphere():
    return texbake.Proxy.sphere()


# (CLI flags after `bake BUNNY --texture EARTH SPHERE -o OUT`, bake_vertex keywords)
VERTEX_CASES = [
    (["--cache-mb", "0"], {"cache_mb": 0}),
    (["--cache-mb", "16777217"], {"cache_mb": 16777217}),
    (["--occluded", "1,1,1,7"], {"occluded": (1, 1, 1, 7)}),
    (["--occluded", "nan,0,0"], {"occluded": (math.nan, 0, 0)}),
    (["--outside", "2,0,0"], {"outside": (2, 0, 0)}),
    (["--outside", "1,0"], {"outside": (1, 0)}),
    (["--filter", "box"], {"filter": "box"}),
    (["--visibility", "some"], {"visibility": "some"}),
    (["--samples", "0"], {"samples": 0}),
]


@pytest.mark.parametrize("flags, keywords", VERTEX_CASES)
def test_vertex_bake_options_fail_as_the_cli(tmp_path, bunny, earth, sphere, flags, keywords):
    message = cli_usage("bake", BUNNY, "--texture", EARTH, *SPHERE, *flags, "-o",
                        tmp_path / "o.ply")
    assert py_usage(lambda: texbake.bake_vertex(bunny, earth, sphere, **keywords)) == message


ATLAS_CASES = [
    (["--padding", "1.5"], {"padding": 1.5}),
    (["--padding=-1"], {"padding": -1}),
    (["--padding", "16385"], {"padding": 16385}),
    (["--padding", "infinity"], {"padding": "infinity"}),
    (["--size", "0"], {"size": 0}),
    (["--samples", "257"], {"samples": 257}),
    (["--uv", "charts"], {"uv": "charts"}),
]


@pytest.mark.parametrize("flags, keywords", ATLAS_CASES)
def test_atlas_bake_options_fail_as_the_cli(tmp_path, bunny, earth, sphere, flags, keywords):
    message = cli_usage("bake", BUNNY, "--texture", EARTH, *SPHERE, *flags, "-o",
                        tmp_path / "o.obj")
    assert py_usage(lambda: texbake.bake_atlas(bunny, earth, sphere, **keywords)) == message


RENDER_CASES = [
    (["--views", "1000000"], {"views": 10**6}),
    (["--views", "0"], {"views": 0}),
    (["--samples", "0"], {"samples": 0}),
    (["--samples", "1025"], {"samples": 1025}),
    (["--size", "0x10"], {"size": (0, 10)}),
    (["--size", "40000x10"], {"size": (40000, 10)}),
    (["--view", "0,95"], {"view": (0, 95)}),
    (["--background", "5,0,0"], {"background": (5, 0, 0)}),
    (["--background", "nan,0,0"], {"background": (math.nan, 0, 0)}),
    (["--background=-1,0,0"], {"background": (-1, 0, 0)}),
    (["--texture", EARTH, "--proxy", "sphere", "--outside", "1,2,0"],
     {"texture": "EARTH", "proxy": "SPHERE", "outside": (1, 2, 0)}),
]


@pytest.mark.parametrize("flags, keywords", RENDER_CASES)
def test_render_options_fail_as_the_cli(tmp_path, bunny, earth, sphere, flags, keywords):
    message = cli_usage("render", BUNNY, *flags, "-o", tmp_path / "r.png")
    keywords = {k: {"EARTH": earth, "SPHERE": sphere}.get(v, v) if isinstance(v, str) else v
                for k, v in keywords.items()}
    assert py_usage(lambda: texbake.render(bunny, **keywords)) == message


@pytest.mark.parametrize("background", [(5, 0, 0), (math.nan, 0, 0)])
def test_compare_background_fails_as_the_cli(background):
    text = ",".join(repr(float(x)) if math.isnan(x) else str(x) for x in background)
    message = cli_usage("compare", EARTH, EARTH, "--background", text)
    assert py_usage(lambda: texbake.compare(EARTH, EARTH, background=background)) == message


def test_the_messages_are_the_ranges_of_the_library():
    """The texts themselves, worked out from the flags' documented ranges."""
    img = np.zeros((2, 2, 4), np.float32)
    mesh = texbake.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    assert py_usage(lambda: texbake.bake_vertex(mesh, img, texbake.Proxy.sphere(), cache_mb=0)) \
        == "--cache-mb 0 is out of range (1 .. 16777216)"
    assert py_usage(lambda: texbake.render(mesh, views=10**6)) \
        == "--views 1000000 is out of range (1 .. 64)"
    assert py_usage(lambda: texbake.render(mesh, background=(5, 0, 0))) == (
        "--background: '5,0,0' is not a colour R,G,B with components in [0, 1] "
        "(e.g. 1,0,0 for red)")
    assert py_usage(lambda: texbake.bake_atlas(mesh, img, texbake.Proxy.sphere(), padding=1.5)) \
        == "--padding '1.5' is not a texel count (0 .. 16384) or 'inf'"


def test_photo_and_layer_options_fail_as_the_cli(tmp_path, bunny):
    # The occluded colour is checked before any file is read, as the CLI's flag.
    message = cli_usage("bake", BUNNY, "--cameras", tmp_path, "--occluded", "1,1,1,7", "-o",
                        tmp_path / "o.ply")
    for call in (texbake.bake_vertex_from_photos, texbake.bake_atlas_from_photos):
        assert py_usage(lambda: call(bunny, cameras=tmp_path, occluded=(1, 1, 1, 7))) == message
    for call in (texbake.bake_vertex_from_layers, texbake.bake_atlas_from_layers):
        assert py_usage(lambda: call(bunny, layers=DATA / "bottle_layers.json",
                                     occluded=(1, 1, 1, 7))) == message
    message = cli_usage("bake", BUNNY, "--cameras", tmp_path, "--blend", "sharp", "-o",
                        tmp_path / "o.ply")
    assert py_usage(lambda: texbake.bake_vertex_from_photos(bunny, cameras=tmp_path,
                                                            blend="sharp")) == message
    message = cli_usage("bake", BUNNY, "--layers", DATA / "bottle_layers.json", "--cache-mb", "0",
                        "-o", tmp_path / "o.ply")
    assert py_usage(lambda: texbake.bake_vertex_from_layers(
        bunny, layers=DATA / "bottle_layers.json", cache_mb=0)) == message


@pytest.mark.parametrize("call, match", [
    (lambda m, i, p: texbake.bake_vertex(m, i, None), "proxy must be a texbake.Proxy, not NoneType"),
    (lambda m, i, p: texbake.bake_atlas(m, i, "sphere"), "proxy must be a texbake.Proxy, not str"),
    (lambda m, i, p: texbake.bake_vertex(m, i, p, samples=1.5), "--samples: '1.5' is not an integer"),
    (lambda m, i, p: texbake.bake_vertex(m, i, p, samples="4"), "--samples: '4' is not an integer"),
    (lambda m, i, p: texbake.bake_vertex(m, i, p, threads=-1),
     r"--threads -1 is out of range \(0 .. 4096\)"),
    (lambda m, i, p: texbake.bake_vertex(m, i, p, filter=3), r"--filter: unknown value '3'"),
    (lambda m, i, p: texbake.bake_atlas(m, i, p, padding=True), "--padding 'True'"),
    (lambda m, i, p: texbake.compare(DATA / "earth.jpg", 5), "b must be a file path"),
    (lambda m, i, p: texbake.compare(str(DATA / "earth.jpg"), None), "b must be a file path"),
    (lambda m, i, p: texbake.render(m, size=512), r"--size: expected \(width, height\)"),
    (lambda m, i, p: texbake.render(m, view=("a", 0)), "--view: 'a' is not a number"),
    (lambda m, i, p: texbake.render(m, texture=i), "--texture needs --proxy"),
    (lambda m, i, p: texbake.read_image(DATA / "earth.jpg", colorspace="rgb"),
     "--texture-colorspace: unknown value 'rgb'"),
    (lambda m, i, p: texbake.write_atlas("x.obj", None), "atlas must be a texbake.Atlas, not NoneType"),
])
def test_wrong_types_are_valueerror(bunny, earth, sphere, call, match):
    with pytest.raises(ValueError, match=match):
        call(bunny, earth, sphere)


@pytest.mark.parametrize("value, what", [(math.nan, "is not finite (nan)"),
                                         (math.inf, "is not finite (inf)"),
                                         (1e39, "is beyond float range (1e+39)")])
def test_nonfinite_geometry_is_valueerror_naming_array_and_row(value, what):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    f = [[0, 1, 2]]
    bad = v.copy()
    bad[2, 1] = value
    with pytest.raises(ValueError, match=r"^vertices: row 2 " + what.replace("(", r"\(")
                       .replace(")", r"\)").replace("+", r"\+") + "$"):
        texbake.Mesh(bad, f)
    uvs = np.array([[0, 0], [1, 0], [0, 1]], float)
    uvs[1, 0] = value
    with pytest.raises(ValueError, match=r"^uvs: row 1 "):
        texbake.Mesh(v, f, uvs=uvs, face_uvs=f)
    colors = np.ones((3, 4))
    colors[0, 3] = value
    with pytest.raises(ValueError, match=r"^colors: row 0 "):
        texbake.Mesh(v, f, colors=colors)
    with pytest.raises(ValueError, match=r"^colors: row 0 "):
        texbake.write_vertex_colors("never.ply", texbake.Mesh(v, f), colors)


def test_nonfinite_texels_read_as_zero_with_the_cli_warning(bunny, sphere):
    """An image with NaN and inf texels bakes as the same image with 0 there,
    and warns as the CLI warns for a texture file."""
    image = np.full((8, 16, 4), 0.5, np.float32)
    image[2, 3, 0] = np.nan
    image[5, 9, 1:3] = np.inf
    zeroed = np.nan_to_num(image, nan=0, posinf=0)
    with pytest.warns(RuntimeWarning, match=r"^image: 3 NaN or infinite values read as 0$"):
        colors, _ = texbake.bake_vertex(bunny, image, sphere, filter="bilinear")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        expected, _ = texbake.bake_vertex(bunny, zeroed, sphere, filter="bilinear")
    assert np.isfinite(colors).all()
    assert np.array_equal(colors, expected)
    # A uint8 image has no NaN; a float64 one is converted, NaN included.
    with pytest.warns(RuntimeWarning, match="texture: 3 NaN"):
        texbake.render(bunny, texture=image.astype(np.float64), proxy=sphere, size=(8, 8))
