#include "bake/cli/atlas_target.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "bake/atlas/atlas_raster.h"
#include "bake/atlas/dilate.h"
#include "bake/cli/choice_option.h"
#include "bake/util/timing.h"
#include "bake/uv/uv_generate.h"
#include "bake/uv/uv_proxy.h"
#include "mesh_io/file_name.h"
#include "mesh_io/write_textured.h"

namespace texbake::cli {
namespace fs = std::filesystem;

namespace {

// Charts need at least two empty texels between them: each chart's
// conservative coverage reaches one texel further than the packer's (texel
// squares), and two charts must never share a texel.
constexpr int kMinGutter = 2;

}  // namespace

void add_atlas_flags(CLI::App& bake, AtlasFlags& flags) {
  add_choice_option<std::string>(
      bake, "--target", flags.target, {{"vertex", "vertex"}, {"atlas", "atlas"}},
      "vertex or atlas (default: vertex for .ply, atlas for .obj/.glb outputs)");
  bake.add_option("--size", flags.size,
                  "atlas target: width and height in texels (default 2048, 1..16384)")
      ->type_name("N");
  bake.add_option(
          "--padding", flags.padding,
          "atlas target: texels of dilation into the gutter, or 'inf' for push-pull over "
          "the whole background (default: 8 at 2048, scaled with --size, at least 1; an explicit "
          "N is taken as is, 0 = no dilation)")
      ->type_name("N|inf");
  add_choice_option(
      bake, "--uv", flags.uv,
      {{"auto", UvSource::kAuto},
       {"mesh", UvSource::kMesh},
       {"generate", UvSource::kGenerate},
       {"proxy", UvSource::kProxy}},
      "atlas target UV layout: auto (default: mesh if the mesh has UVs, else generate), "
      "mesh (its own UVs), generate (new non-overlapping charts) or proxy (the proxy's "
      "(u, v), cut at its seam)");
  add_choice_option(
      bake, "--format", flags.format,
      {{"png8", ImageBitDepth::k8}, {"png16", ImageBitDepth::k16}, {"exr", ImageBitDepth::kFloat}},
      "atlas target image format: png8 (default), png16 or exr (.obj only)");
}

Expected<BakeTarget> resolve_target(const AtlasFlags& flags, const fs::path& output) {
  const std::string ext = lower_extension(output);
  if (ext != ".ply" && ext != ".obj" && ext != ".glb") {
    return make_error(ErrorCode::kInvalidArgument,
                      "-o " + output.string() + ": unknown output format '" + ext +
                          "' (texbake bake writes .ply, .obj and .glb)");
  }
  if (flags.target == "atlas" && ext == ".ply") {
    return make_error(ErrorCode::kUnsupported,
                      "--target atlas cannot write " + output.string() +
                          ": PLY has no standard texture (use .obj or .glb)");
  }
  if (flags.target == "vertex") return BakeTarget::kVertex;
  if (flags.target == "atlas") return BakeTarget::kAtlas;
  return ext == ".ply" ? BakeTarget::kVertex : BakeTarget::kAtlas;
}

Expected<AtlasBakeOptions> atlas_options(const AtlasFlags& flags, std::optional<int> samples,
                                         const VertexBakeOptions& shading, const fs::path& output) {
  AtlasBakeOptions o;
  o.shading = shading;
  if (flags.size < 1 || flags.size > kMaxAtlasSize) {
    return make_error(ErrorCode::kInvalidArgument, "--size " + std::to_string(flags.size) +
                                                       " is out of range (1 .. " +
                                                       std::to_string(kMaxAtlasSize) + ")");
  }
  o.size = flags.size;
  o.samples = samples.value_or(4);
  if (o.samples < 1 || o.samples > kMaxAtlasSamples) {
    return make_error(ErrorCode::kInvalidArgument, "--samples " + std::to_string(o.samples) +
                                                       " is out of range for an atlas (1 .. " +
                                                       std::to_string(kMaxAtlasSamples) + ")");
  }
  if (flags.padding.empty()) {
    o.padding = kPaddingDefault;
  } else if (flags.padding == "inf") {
    o.padding = kPaddingInfinite;
  } else {
    std::size_t used = 0;
    int value = -1;
    try {
      value = std::stoi(flags.padding, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != flags.padding.size() || value < 0 || value > kMaxAtlasSize) {
      return make_error(
          ErrorCode::kInvalidArgument,
          "--padding '" + flags.padding + "' is not a texel count (0 .. 16384) or 'inf'");
    }
    o.padding = value;
  }
  if (flags.format == ImageBitDepth::kFloat && lower_extension(output) == ".glb") {
    return make_error(ErrorCode::kUnsupported, "--format exr cannot be embedded in " +
                                                   output.string() +
                                                   " (glTF embeds PNG: use png8 or png16)");
  }
  return o;
}

Expected<AtlasJobReport> run_atlas_job(const MeshData& mesh, const ImageView& image,
                                       const Proxy& proxy, const AtlasFlags& flags,
                                       const AtlasBakeOptions& options, const fs::path& output,
                                       Progress* progress) {
  AtlasJobReport report;
  auto t0 = Clock::now();
  UvSource source = flags.uv;
  if (source == UvSource::kAuto) source = mesh.has_uvs() ? UvSource::kMesh : UvSource::kGenerate;

  MeshData generated;
  const MeshData* layout = &mesh;
  bool repeat_u = false;
  switch (source) {
    case UvSource::kMesh: {
      report.uv_source = "mesh";
      if (!mesh.has_uvs()) {
        return make_error(ErrorCode::kInvalidArgument,
                          "--uv mesh: the mesh has no UV coordinates (use --uv generate or "
                          "--uv proxy)");
      }
      const MeshUvCheck check = check_mesh_uvs(mesh, options.size);
      report.uv_corners_outside = check.corners_outside;
      report.uv_overlap_texels = check.overlap_texels;
      if (check.corners_outside > 0) {
        report.warnings.push_back(std::to_string(check.corners_outside) +
                                  " UV corners lie outside [0, 1]; their texels are not baked");
      }
      if (check.overlap_texels > 0) {
        report.warnings.push_back(std::to_string(check.overlap_texels) +
                                  " atlas texels are covered by overlapping UV triangles; "
                                  "overlapping parts share colours");
      }
      break;
    }
    case UvSource::kProxy: {
      report.uv_source = "proxy";
      Expected<ProxyUvLayout> cut = proxy_uv_layout(mesh, proxy);
      if (!cut) return cut.error();
      report.cut_triangles = cut->stats.cut_triangles;
      if (cut->stats.wide_triangles > 0) {
        report.warnings.push_back(std::to_string(cut->stats.wide_triangles) +
                                  " triangles contain a pole of the proxy and are stretched "
                                  "across the atlas");
      }
      generated = std::move(cut->mesh);
      layout = &generated;
      repeat_u = wrap_u(proxy) == WrapMode::kRepeat;
      break;
    }
    case UvSource::kGenerate:
    case UvSource::kAuto: {
      report.uv_source = "generate";
      UvGenerateOptions go;
      go.atlas_size = options.size;
      const int pad = options.padding >= 0 ? options.padding : default_padding(options.size);
      go.padding = std::max(pad, kMinGutter);
      Expected<UvAtlas> atlas = generate_uv_atlas(mesh, go);
      if (!atlas) return atlas.error();
      report.chart_count = atlas->chart_count;
      report.utilisation = atlas->utilisation;
      report.stretch_l2 = atlas->stretch_l2;
      generated = mesh_with_triangle_uvs(mesh, atlas->uvs, atlas->triangle_uvs);
      layout = &generated;
      break;
    }
  }
  report.timings.uv_layout = seconds_since(t0);

  Expected<AtlasBakeResult> baked = bake_atlas(*layout, image, proxy, options, progress);
  if (!baked) return baked.error();
  report.counts = baked->counts;
  report.timings.rasterize = baked->timings.rasterize;
  report.timings.scene_build = baked->timings.scene_build;
  report.timings.sample = baked->timings.sample;
  report.timings.fill = baked->timings.fill;
  report.timings.pad = baked->timings.pad;

  t0 = Clock::now();
  TexturedWriteOptions wo;
  wo.bit_depth = flags.format;
  wo.repeat_u = repeat_u;
  if (Status s = write_textured_mesh(output, *layout, baked->atlas.view(), wo); !s) {
    return s.error();
  }
  report.timings.write = seconds_since(t0);
  return report;
}

std::string atlas_report_json(const AtlasJobReport& r, const AtlasBakeOptions& o) {
  nlohmann::ordered_json j;
  j["uv"] = r.uv_source;
  j["size"] = o.size;
  j["samples_per_texel"] = o.samples;
  if (o.padding == kPaddingInfinite) {
    j["padding"] = "inf";
  } else {
    j["padding"] = o.padding == kPaddingDefault ? default_padding(o.size) : o.padding;
  }
  j["counts"] = {{"texels", r.counts.texels},
                 {"samples", r.counts.samples},
                 {"border_samples", r.counts.border_samples},
                 {"occluded", r.counts.occluded},
                 {"undefined", r.counts.undefined},
                 {"outside", r.counts.outside},
                 {"padded", r.counts.padded}};
  if (r.uv_source == "mesh") {
    j["uv_check"] = {{"corners_outside", r.uv_corners_outside},
                     {"overlap_texels", r.uv_overlap_texels}};
  } else if (r.uv_source == "proxy") {
    j["cut_triangles"] = r.cut_triangles;
  } else {
    j["charts"] = r.chart_count;
    j["utilisation"] = r.utilisation;
    j["stretch_l2"] = r.stretch_l2;
  }
  j["timings"] = {{"uv_layout", r.timings.uv_layout},
                  {"rasterize", r.timings.rasterize},
                  {"scene_build", r.timings.scene_build},
                  {"sample", r.timings.sample},
                  {"fill", r.timings.fill},
                  {"pad", r.timings.pad},
                  {"write", r.timings.write}};
  return j.dump(2);
}

}  // namespace texbake::cli
