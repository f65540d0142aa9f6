#!/usr/bin/python3
"""Writes box_open3d.glb beside this script: an independent glTF writer's
file for tests/mesh_io/read_gltf_test.cpp (Open3D 0.16, python3-open3d).

Open3D's create_box(1, 2, 3): 8 vertices, 12 outward triangles; vertex i
gets the colour (i / 7, 0.5, 1 - i / 7), which Open3D stores in COLOR_0 as
given (float VEC3; glTF reads COLOR_0 as linear light). Open3D puts the
buffer in a data: URI (no BIN chunk) and POSITION and COLOR_0 in one
bufferView with byteStride 12.

Run: /usr/bin/python3 tests/data/gltf/make_box_open3d.py
"""
import os

import numpy as np
import open3d as o3d

mesh = o3d.geometry.TriangleMesh.create_box(1, 2, 3)
mesh.vertex_colors = o3d.utility.Vector3dVector(
    np.array([[i / 7, 0.5, 1 - i / 7] for i in range(8)]))
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "box_open3d.glb")
if not o3d.io.write_triangle_mesh(out, mesh):
    raise SystemExit("open3d could not write " + out)
print(out)
print("vertices:", np.asarray(mesh.vertices).tolist())
