#include "bake/cli/atlas_target.h"

#include <string>
#include <utility>
#include <vector>

#include "bake/cli/choice_option.h"
#include "bake/cli/commands.h"

namespace texbake::cli {
namespace fs = std::filesystem;

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
          "the whole background, alpha included (default: 8 at 2048, scaled with --size, at "
          "least 1, then push-pull of the colour over the rest of the background with alpha 0, "
          "so mipmaps never average in black; an explicit N is taken as is and leaves the rest "
          "transparent black, 0 = no dilation)")
      ->type_name("N|inf");
  add_choice_option<UvLayout>(
      bake, "--uv", flags.uv,
      "atlas target UV layout: auto (default: mesh if the mesh has UVs, else generate), "
      "mesh (its own UVs), generate (new non-overlapping charts) or proxy (the proxy's "
      "(u, v), cut at its seam; suits meshes that are star-shaped as seen from the proxy's "
      "centre, axis or plane: surfaces behind one another share texels, which are counted, "
      "warned about and take the visible surface's colour)");
  add_choice_option<AtlasFormat>(
      bake, "--format", flags.format,
      "atlas target image format: png8 (default), png16 or exr (.obj only)");
}

Expected<BakeTarget> resolve_target(const AtlasFlags& flags, const fs::path& output) {
  Expected<JobTarget> target = job_target(flags.target, output);
  if (!target) return target.error();
  return *target == JobTarget::kAtlas ? BakeTarget::kAtlas : BakeTarget::kVertex;
}

Expected<AtlasOptions> atlas_options(const AtlasFlags& flags, std::optional<int> samples,
                                     const VertexBakeOptions& shading, const fs::path& output) {
  AtlasOptions options;
  options.uv = flags.uv;
  AtlasBakeOptions& o = options.bake;
  o.shading = shading;
  o.size = flags.size;
  o.samples = samples.value_or(4);
  o.padding = kPaddingDefault;  // until --padding is parsed, after the other checks
  if (Status s = validate_options(options); !s) return s.error();
  Expected<int> padding = parse_padding(flags.padding);
  if (!padding) return padding.error();
  o.padding = *padding;
  if (Status s = validate_write(output, atlas_write_options(flags), /*atlas=*/true); !s) {
    return s.error();
  }
  return options;
}

WriteOptions atlas_write_options(const AtlasFlags& flags) {
  WriteOptions options;
  options.format = flags.format;
  return options;
}

}  // namespace texbake::cli
