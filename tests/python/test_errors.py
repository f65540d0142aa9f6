"""Errors map to ValueError / OSError / RuntimeError / texbake.Cancelled with
the command line's messages."""
import json

import numpy as np
import pytest

import texbake
from conftest import DATA, run_cli


def cli_error(*args):
    r = run_cli(*args)
    errors = [l for l in r.stderr.splitlines() if l.startswith("texbake: error: ")]
    assert len(errors) == 1, r.stderr
    return r.returncode, errors[0][len("texbake: error: "):]


@pytest.mark.parametrize("missing_mesh", [True, False])
def test_missing_file_is_oserror_with_the_cli_message(tmp_path, missing_mesh):
    missing = tmp_path / ("missing.off" if missing_mesh else "missing.png")
    mesh = missing if missing_mesh else DATA / "bunny00.off"
    image = DATA / "earth.jpg" if missing_mesh else missing
    code, message = cli_error("bake", mesh, "--texture", image, "--proxy", "sphere", "-o",
                              tmp_path / "o.ply")
    assert code == 1 and message == f"{missing}: no such file"
    with pytest.raises(OSError) as e:
        (texbake.read_mesh if missing_mesh else texbake.read_image)(missing)
    assert str(e.value) == message


def test_bad_proxy_file_is_oserror_with_the_cli_message(tmp_path):
    bad = tmp_path / "p.json"
    bad.write_text('{"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,1],"colour":1}')
    code, message = cli_error("map", "--proxy-file", bad, "--point", "1,0,0")
    assert code == 1 and "colour" in message
    with pytest.raises(OSError) as e:
        texbake.Proxy.from_json(bad)
    assert str(e.value) == message


def test_usage_errors_are_valueerror(bunny, earth):
    sphere = texbake.Proxy.sphere()
    with pytest.raises(ValueError, match="--samples"):
        texbake.bake_vertex(bunny, earth, sphere, samples=0)
    with pytest.raises(ValueError, match=r"filter: unknown value 'box' \(expected bilinear, area or ewa\)"):
        texbake.bake_vertex(bunny, earth, sphere, filter="box")
    with pytest.raises(ValueError, match="--size"):
        texbake.bake_atlas(bunny, earth, sphere, size=0)
    with pytest.raises(ValueError, match=r"vertices must have shape \(n, 3\), got \(4, 2\)"):
        texbake.bake_vertex(np.zeros((4, 2)), [[0, 1, 2]], earth, sphere)
    with pytest.raises(ValueError, match="faces: index 7"):
        texbake.Mesh(np.zeros((3, 3)), [[0, 1, 7]])
    with pytest.raises(ValueError, match="sphere: pole is the zero vector"):
        texbake.Proxy.sphere(pole=(0, 0, 0))
    with pytest.raises(ValueError, match="image"):
        texbake.bake_vertex(bunny, np.zeros((0, 4, 4), np.float32), sphere)


def test_degenerate_mesh_is_oserror_as_the_cli(tmp_path, earth):
    # Three collinear points: the CLI says "MESH: all 1 triangles are degenerate".
    off = tmp_path / "flat.off"
    off.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n")
    code, message = cli_error("bake", off, "--texture", DATA / "earth.jpg", *[
        "--proxy", "sphere", "--center", "0,0,0", "--radius", "1"], "-o", tmp_path / "o.ply")
    assert code == 1
    with pytest.raises(OSError) as e:
        texbake.bake_vertex(texbake.read_mesh(off), earth, texbake.Proxy.sphere())
    assert message == f"{off}: {e.value}"


def test_cancel_raises_cancelled(bunny, earth):
    seen = []

    def stop(stage, fraction):
        seen.append(stage)
        return False

    with pytest.raises(texbake.Cancelled):
        texbake.bake_vertex(bunny, earth, texbake.Proxy.sphere(), progress=stop)
    assert seen and seen[0] == "bake"
    with pytest.raises(texbake.Cancelled):
        texbake.bake_atlas(bunny, earth, texbake.Proxy.sphere(), uv="proxy", size=64,
                           progress=stop)


def test_callback_exception_propagates(bunny, earth):
    def boom(stage, fraction):
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        texbake.bake_vertex(bunny, earth, texbake.Proxy.sphere(), progress=boom)


def test_progress_runs_to_the_end(bunny, earth):
    seen = {}

    def note(stage, fraction):
        seen.setdefault(stage, []).append(fraction)
        return True

    texbake.bake_vertex(bunny, earth, texbake.Proxy.sphere(), progress=note)
    assert seen["bake"][-1] == 1.0 and sorted(seen["bake"]) == seen["bake"]


def test_gil_is_released_while_baking(bunny, earth):
    # A Python thread counts while the bake runs: without the GIL released it
    # could not run at all until the bake returned.
    import threading
    import time
    ticks = []
    running = threading.Event()

    def count():
        running.set()
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.001)

    done = threading.Event()
    t = threading.Thread(target=count)
    t.start()
    running.wait()
    start = len(ticks)
    texbake.bake_vertex(bunny, earth, texbake.Proxy.sphere(), samples=64, threads=1)
    during = len(ticks) - start
    done.set()
    t.join()
    assert during > 5
