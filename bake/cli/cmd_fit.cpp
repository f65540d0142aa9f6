// texbake fit MESH --proxy KIND [--up x|y|z|-x|-y|-z] [geometry] [-o proxy.json]
// (SPEC sections 5 and 6): fits a proxy to the mesh's referenced vertices
// (bake/fit/fit_proxy.h; given geometry flags are kept, see proxy_for_mesh.h) and
// prints it as JSON on stdout, or writes it atomically for --proxy-file.
#include <iostream>
#include <memory>
#include <string>

#include "bake/cli/commands.h"
#include "bake/cli/geometry_flags.h"
#include "bake/cli/proxy_for_mesh.h"
#include "mesh_io/atomic_file.h"
#include "texbake/texbake.h"

namespace texbake::cli {
namespace {

struct FitCommandOptions {
  std::string mesh;
  GeometryFlags geometry;
  std::string output;  // empty: stdout
};

}  // namespace

RunFunction add_fit_command(CLI::App& app) {
  auto opts = std::make_shared<FitCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "fit",
      "Fit a proxy to a mesh (SPEC section 6) and print it as JSON (for --proxy-file).\n"
      "sphere: minimum enclosing sphere; cylinder, cone: principal axis (or --up/--axis), "
      "extents of the points; disk, quad, plane: best-fit plane, minimum enclosing circle or "
      "rectangle. Geometry flags given are kept and the rest is fitted around them (e.g. "
      "--center given: the radius encloses the mesh around it; likewise a cylinder's --base, a "
      "cone's --apex/--height, a plane's --origin); --up also fixes a cylinder's or cone's axis "
      "line, is the sphere's pole, and the hemisphere of a disk/quad/plane normal.");
  cmd->add_option("MESH", opts->mesh, "Mesh file (.obj, .ply, .off, .stl, .glb, .gltf)")
      ->required();
  add_geometry_flags(*cmd, opts->geometry);
  cmd->add_option("-o,--output", opts->output,
                  "Write the proxy JSON to this file (atomically) instead of stdout");

  return [opts]() -> int {
    if (opts->geometry.proxy_file) {
      return report_error(ErrorCode::kInvalidArgument,
                          "fit needs --proxy KIND (--proxy-file reads a proxy; fit writes one)");
    }
    if (Status s = check_geometry_flags(opts->geometry, /*require_proxy=*/true); !s) {
      return report_error(s.error());
    }
    if (!opts->output.empty()) {
      JobFileNames files;
      files.mesh = opts->mesh;
      files.output = opts->output;
      if (Status s = check_job_files(files); !s) return report_error(s.error());
      if (Status s = check_writable(opts->output); !s) return report_error(s.error());
    }
    Expected<LoadedMesh> loaded = read_mesh(opts->mesh);
    if (!loaded) return report_error(loaded.error());
    Expected<FlagsProxy> resolved =
        proxy_for_mesh(opts->geometry, loaded->mesh, opts->mesh, /*log=*/nullptr);
    if (!resolved) return report_error(resolved.error());
    if (opts->output.empty()) {
      std::cout << proxy_to_json(resolved->proxy, 2) << "\n";
      return 0;
    }
    if (Status s = write_proxy_file(opts->output, resolved->proxy); !s)
      return report_error(s.error());
    return 0;
  };
}

}  // namespace texbake::cli
