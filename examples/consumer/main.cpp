// texbake_consumer: a program outside texbake that uses it through the
// installed package alone (find_package(texbake), <texbake/texbake.h>).
//
//   texbake_consumer DATA_DIR OUTPUT_DIR
//
// Reads DATA_DIR/bunny00.off and DATA_DIR/earth.jpg, fits a sphere proxy
// (pole +y) to the bunny, then bakes the Earth map
//   1. into vertex colours, written to OUTPUT_DIR/bunny.ply, and
//   2. into a 512 x 512 atlas on generated UV charts, written to
//      OUTPUT_DIR/bunny.obj (+ bunny.mtl + bunny.png), and
//   3. into vertex colours again through the job front door
//      (<texbake/job.h>, run_job: read, fit, bake, write), written to
//      OUTPUT_DIR/bunny_job.ply, which must hold the bytes of bunny.ply,
// checks the results (every vertex colour finite; the atlas covers texels
// and took samples) and prints one line per output. Exit status: 0 on
// success, 2 on a usage error (wrong arguments, or an error of category
// kUsage), 1 otherwise; errors go to stderr as "texbake_consumer: error: ...".
#include <texbake/job.h>
#include <texbake/texbake.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace {

namespace fs = std::filesystem;

int fail(const texbake::Error& error) {
  std::fprintf(stderr, "texbake_consumer: error: %s\n", error.message.c_str());
  return texbake::category(error) == texbake::ErrorCategory::kUsage ? 2 : 1;
}

int fail(const std::string& message) {
  std::fprintf(stderr, "texbake_consumer: error: %s\n", message.c_str());
  return 1;
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool all_finite(const std::vector<texbake::Rgba>& colors) {
  for (const texbake::Rgba& c : colors) {
    for (float channel : c) {
      if (!std::isfinite(channel)) return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: texbake_consumer DATA_DIR OUTPUT_DIR\n");
    return 2;
  }
  const fs::path data = argv[1];
  const fs::path out = argv[2];
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) return fail(out.string() + ": " + ec.message());

  auto mesh = texbake::read_mesh(data / "bunny00.off");
  if (!mesh) return fail(mesh.error());
  auto image = texbake::read_image(data / "earth.jpg");
  if (!image) return fail(image.error());

  // A sphere with only its kind and pole given: centre and radius are fitted.
  texbake::ProxySpec spec;
  spec.kind = texbake::ProxyKind::kSphere;
  spec.up = texbake::Vec3{0, 1, 0};
  auto proxy = texbake::complete_proxy(spec, mesh->mesh);
  if (!proxy) return fail(proxy.error());

  // 1. Vertex colours.
  auto colors = texbake::bake_vertex_colors(mesh->mesh, image->view(), proxy->proxy);
  if (!colors) return fail(colors.error());
  if (colors->colors.size() != mesh->mesh.vertex_count()) {
    return fail("vertex bake: " + std::to_string(colors->colors.size()) + " colours for " +
                std::to_string(mesh->mesh.vertex_count()) + " vertices");
  }
  if (!all_finite(colors->colors)) return fail("vertex bake: a colour is not finite");
  const fs::path ply = out / "bunny.ply";
  if (auto written = texbake::write_vertex_colors(ply, mesh->mesh, colors->colors); !written) {
    return fail(written.error());
  }
  std::printf("%s: %zu vertex colours (%zu occluded, %zu filled)\n", ply.string().c_str(),
              colors->colors.size(), colors->stats.counts.occluded, colors->stats.counts.filled);

  // 2. A texture atlas on generated UV charts.
  texbake::AtlasOptions atlas_options;
  atlas_options.uv = texbake::UvLayout::kGenerate;
  atlas_options.bake.size = 512;
  auto atlas = texbake::bake_atlas_texture(mesh->mesh, image->view(), proxy->proxy, atlas_options);
  if (!atlas) return fail(atlas.error());
  const texbake::Counts& counts = atlas->stats.counts;
  if (counts.texels == 0 || counts.samples == 0) {
    return fail("atlas bake: " + std::to_string(counts.texels) + " texels covered, " +
                std::to_string(counts.samples) + " samples");
  }
  const fs::path obj = out / "bunny.obj";
  if (auto written = texbake::write_atlas(obj, *atlas); !written) return fail(written.error());
  std::string files;  // "bunny.obj + bunny.mtl + bunny.png"
  for (const fs::path& file : texbake::atlas_files(obj)) {
    files += (files.empty() ? "" : " + ") + file.string();
  }
  std::printf("%s: %dx%d atlas, %zu charts, %zu texels covered\n", files.c_str(),
              atlas->image.width, atlas->image.height, atlas->uv.charts, counts.texels);

  // 3. The same vertex bake as one job: run_job reads, fits, bakes and writes.
  texbake::Job job;
  job.mesh = data / "bunny00.off";
  job.texture = data / "earth.jpg";
  job.spec = spec;
  job.output = out / "bunny_job.ply";
  const texbake::JobResult result = texbake::run_job(job);
  if (!result.ok()) return fail(*result.error);
  if (file_bytes(job.output) != file_bytes(ply)) {
    return fail(job.output.string() + " differs from " + ply.string());
  }
  std::printf("%s\n", result.summary.c_str());
  return 0;
}
