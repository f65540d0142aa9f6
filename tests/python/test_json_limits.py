"""JSON inputs nested too deep or holding numbers beyond double's range are
errors with the command line's message (they crashed the interpreter: the
value was converted recursively), through every reader the module calls."""
import pytest

import texbake
from conftest import DATA, run_cli


def cli_error(*args):
    r = run_cli(*args)
    errors = [l for l in r.stderr.splitlines() if l.startswith("texbake: error: ")]
    assert len(errors) == 1, r.stderr
    return r.returncode, errors[0][len("texbake: error: "):]


def test_a_layers_file_nested_90000_deep_is_an_error(tmp_path):
    # Line 2 starts with {"proxy":{"kind":"sphere","center": (35 characters);
    # root, "layers", the layer and "proxy" are levels 1-4, so the 125th '['
    # of "center" is level 129.
    layers = tmp_path / "L.json"
    layers.write_text('{"layers":[\n{"proxy":{"kind":"sphere","center":' + "[" * 90000)
    code, message = cli_error("bake", DATA / "bottle.ply", "--layers", layers, "-o",
                              tmp_path / "o.ply")
    assert code == 1
    assert message == (f"{layers}: key 'layers.proxy.center' nests deeper than 128 levels "
                       "(line 2, column 160)")
    mesh = texbake.read_mesh(DATA / "bottle.ply")
    with pytest.raises(OSError) as e:
        texbake.bake_vertex_from_layers(mesh, layers=layers)
    assert str(e.value) == message


@pytest.mark.parametrize("text, says", [
    ('{"kind":"sphere","center":' + "[" * 100000, "key 'center' nests deeper than 128 levels"),
    ('{"kind":"sphere","center":[0,0,0],"radius":1e999,"pole":[0,0,1]}',
     "key 'radius' holds a number that is not finite (1e999 at line 1, column 44)"),
])
def test_a_proxy_file_nested_too_deep_or_out_of_range_is_an_error(tmp_path, text, says):
    bad = tmp_path / "p.json"
    bad.write_text(text)
    code, message = cli_error("map", "--proxy-file", bad, "--point", "1,0,0")
    assert code == 1 and message.startswith(f"{bad}: {says}"), message
    with pytest.raises(OSError) as e:
        texbake.Proxy.from_json(bad)
    assert str(e.value) == message
