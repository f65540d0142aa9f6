// Meshes shared by the benchmarks: the data meshes of data and the
// armadillo subdivided twice (832k triangles), built once per process.
#pragma once

#include <string>

#include "mapping/proxy.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"

namespace texbake::bench {

// Prints "texbake_bench: <what>" and exits 1 (a benchmark cannot go on
// without its input).
[[noreturn]] void die(const std::string& what);

// Reads data/<file> with read_mesh, or dies.
MeshData load_shared_mesh(const std::string& file);

// One round of 1-to-4 midpoint subdivision of mesh.triangles (positions only;
// every edge's midpoint is shared by its two triangles), triangulated.
MeshData subdivide(const MeshData& mesh);

// data/bunny00.off (75k triangles), loaded once.
const MeshData& bunny();

// data/armadillo.off subdivided twice: 416,002 vertices, 832,000
// triangles; built once.
const MeshData& armadillo_832k();

// data/earth.jpg, loaded once.
const Image& earth();

// A sphere around the mesh's bounding box (what `fit` would roughly give),
// pole +Y, equator +Z.
Proxy sphere_around(const MeshData& mesh);

}  // namespace texbake::bench
