"""Interop with Open3D (python3-open3d): read with Open3D, bake with texbake,
set vertex_colors, write with Open3D, read back and compare."""
import numpy as np
import pytest

import texbake
from conftest import DATA

o3d = pytest.importorskip("open3d")


def test_open3d_round_trip(tmp_path, earth):
    mesh = o3d.io.read_triangle_mesh(str(DATA / "bunny00.off"))
    vertices = np.asarray(mesh.vertices)
    faces = np.asarray(mesh.triangles)
    assert vertices.shape == (37706, 3) and faces.shape == (75408, 3)
    proxy = texbake.Proxy.sphere(center=(0, 0, 0), radius=1, pole=(0, 1, 0), equator=(0, 0, 1))
    colors, _ = texbake.bake_vertex(vertices, faces, earth, proxy)
    # Open3D read the same vertices in the same order as texbake.
    ours = texbake.read_mesh(DATA / "bunny00.off")
    np.testing.assert_array_equal(vertices.astype(np.float32), ours.vertices.astype(np.float32))
    expected, _ = texbake.bake_vertex(ours, earth, proxy)
    np.testing.assert_array_equal(colors, expected)

    mesh.vertex_colors = o3d.utility.Vector3dVector(colors[:, :3].astype(np.float64))
    out = tmp_path / "o3d.ply"
    assert o3d.io.write_triangle_mesh(str(out), mesh)
    back = o3d.io.read_triangle_mesh(str(out))
    got = np.asarray(back.vertex_colors)
    # PLY stores uchar: within half a step of 1/255.
    assert got.shape == (37706, 3)
    assert np.max(np.abs(got - colors[:, :3])) <= 0.5 / 255 + 1e-6
    # texbake reads Open3D's file and finds the same colours.
    again = texbake.read_mesh(out)
    np.testing.assert_allclose(again.colors[:, :3], got, atol=1e-6)
