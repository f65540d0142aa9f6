"""texbake.map against the worked example of SPEC section 2 / the README."""
import math

import numpy as np
import pytest

import texbake


def test_worked_example():
    proxy = texbake.Proxy.sphere(center=(0, 0, 0), radius=1, pole=(0, 0, 1), equator=(1, 0, 0))
    points = np.array([[1, 1, 1], [1, -1, 1]]) / math.sqrt(3)
    uv, status, direction = texbake.map(proxy, points)
    # phi = acos(-Sn . Sp) = acos(-1/sqrt(3)) = 2.186276, v = phi / pi.
    v = math.acos(-1 / math.sqrt(3)) / math.pi
    assert abs(v - 0.695913) < 1e-6
    np.testing.assert_allclose(uv, [[0.125, v], [0.875, v]], rtol=0, atol=1e-12)
    assert [texbake.STATUS[s] for s in status] == ["ok", "ok"]
    np.testing.assert_allclose(direction, points, atol=1e-12)
    # In a 640 x 480 image: x = u W - 0.5 = 559.5, y = (1 - v) H - 0.5 = 145.46.
    x = uv[1, 0] * 640 - 0.5
    y = (1 - uv[1, 1]) * 480 - 0.5
    assert x == pytest.approx(559.5, abs=1e-9)
    assert y == pytest.approx(145.46162751265427, abs=1e-9)


def test_map_agrees_with_the_cli():
    from conftest import run_cli
    import json
    r = run_cli("map", "--proxy", "sphere", "--center", "0,0,0", "--radius", "1", "--pole",
                "0,0,1", "--equator", "1,0,0", "--dir", "1,-1,1", "--json")
    cli = json.loads(r.stdout)
    proxy = texbake.Proxy.from_json({"kind": "sphere", "center": [0, 0, 0], "radius": 1,
                                     "pole": [0, 0, 1], "equator": [1, 0, 0]})
    uv, _, _ = texbake.map(proxy, [[1 / math.sqrt(3), -1 / math.sqrt(3), 1 / math.sqrt(3)]])
    assert (uv[0, 0], uv[0, 1]) == (cli["u"], cli["v"])


def test_status_outside_and_undefined():
    disk = texbake.Proxy.disk(center=(0, 0, 0), radius=1, normal=(0, 0, 1))
    uv, status, direction = texbake.map(disk, [[0.5, 0, 0], [2, 0, 0]])
    assert list(status) == [0, 1]
    # v = r / radius, u = 0 on the equator (+X); d = the normal.
    np.testing.assert_allclose(uv, [[0, 0.5], [0, 2]], atol=1e-12)
    np.testing.assert_allclose(direction, [[0, 0, 1], [0, 0, 1]], atol=1e-12)
    sphere = texbake.Proxy.sphere()
    _, status, _ = texbake.map(sphere, [[0, 0, 0]])
    assert texbake.STATUS[status[0]] == "undefined"


def test_quad_and_plane_constructors():
    quad = texbake.Proxy.quad([(0, 0, 0), (2, 0, 0), (2, 1, 0), (0, 1, 0)])
    uv, status, _ = texbake.map(quad, [[0.5, 0.25, 3]])
    np.testing.assert_allclose(uv, [[0.25, 0.25]], atol=1e-12)
    plane = texbake.Proxy.plane(origin=(1, 0, 0), u_axis=(4, 0, 0), v_axis=(0, 2, 0))
    uv, _, _ = texbake.map(plane, [[3, 1, 0]])
    np.testing.assert_allclose(uv, [[0.5, 0.5]], atol=1e-12)
    d = texbake.Proxy.cylinder(base=(0, 0, 0), radius=1, height=2).to_dict()
    assert d["kind"] == "cylinder" and d["axis"] == [0, 0, 1] and d["height"] == 2
