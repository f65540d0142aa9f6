// The writers: write_vertex_colors, write_atlas (atlas_files) and write_image.
#include "bake/python/common.h"

namespace texbake::python {

namespace {

void write_colors(py::handle path, const LoadedMesh& mesh, py::handle colors, bool ascii,
                  py::handle up) {
  const std::filesystem::path p = path_arg(path, "path");
  Array<double> c = rows<double>(colors, "colors", 0);
  if (c.shape(1) != 3 && c.shape(1) != 4) usage("colors must have shape (n, 3) or (n, 4)");
  check_float_rows(c, "colors");
  std::vector<Rgba> rgba(c.shape(0));
  for (py::ssize_t i = 0; i < c.shape(0); ++i) {
    const double* q = c.data() + c.shape(1) * i;
    rgba[i] = {static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2]),
               c.shape(1) == 4 ? static_cast<float>(q[3]) : 1.0f};
  }
  WriteOptions o;
  o.ascii = ascii;
  o.up = vec3_arg(up, "up");
  py::gil_scoped_release release;
  check(write_vertex_colors(p, mesh.mesh, rgba, o));
}

void write_atlas_files(py::handle path, py::handle atlas_obj, py::handle format, py::handle up) {
  const std::filesystem::path p = path_arg(path, "path");
  if (!py::isinstance<Atlas>(atlas_obj)) {
    usage("atlas must be a texbake.Atlas, not " +
          std::string(py::str(py::type::handle_of(atlas_obj).attr("__name__"))));
  }
  const Atlas& atlas = atlas_obj.cast<const Atlas&>();
  WriteOptions o;
  o.up = vec3_arg(up, "up");
  o.format = choice_arg<AtlasFormat>(format, "--format");
  check(validate_write(p, o, /*atlas=*/true));
  py::gil_scoped_release release;
  check(write_atlas(p, atlas, o));
}

void write_image_file(py::handle path, py::handle image, py::handle bits, py::handle compression) {
  const std::filesystem::path p = path_arg(path, "path");
  ImageWriteOptions o;
  const long long level = int_arg(compression, "compression");
  if (level < 0 || level > 9) usage("compression must be in 0..9");
  o.png_compression = static_cast<int>(level);
  const long long depth = int_arg(bits, "bits");
  if (depth != 8 && depth != 16 && depth != 32) {
    usage("bits: unknown value '" + std::to_string(depth) + "' (expected 8, 16 or 32)");
  }
  o.bit_depth = depth == 8    ? ImageBitDepth::k8
                : depth == 16 ? ImageBitDepth::k16
                              : ImageBitDepth::kFloat;
  ImageArg img = image_arg(image, "image");
  py::gil_scoped_release release;
  check(write_image(p, img.view, o));
}

}  // namespace

void bind_writers(py::module_& m) {
  m.def("write_vertex_colors", &write_colors);
  m.def("write_atlas", &write_atlas_files);
  m.def("atlas_files", [](py::handle path, py::handle format) {
    WriteOptions o;
    o.format = choice_arg<AtlasFormat>(format, "--format");
    std::vector<std::string> out;
    for (const auto& p : atlas_files(path_arg(path, "path"), o)) out.push_back(p.string());
    return out;
  });
  m.def("write_image", &write_image_file);
}

}  // namespace texbake::python
