#include "bake/cli/geometry_flags.h"

namespace texbake::cli {

namespace {

// Sets `flag` through the library, a CLI::ValidationError with its message
// on a bad value.
void set_or_throw(GeometryFlags& flags, const std::string& flag, const std::string& text) {
  if (Status s = set_geometry_option(flags, flag, text); !s) {
    throw CLI::ValidationError(s.error().message);
  }
}

}  // namespace

Vec3 parse_vec3_flag(std::string_view text, const std::string& flag) {
  Expected<Vec3> v = parse_vec3_option(text, flag);
  if (!v) throw CLI::ValidationError(v.error().message);
  return *v;
}

void add_geometry_flags(CLI::App& command, GeometryFlags& flags) {
  CLI::Option* kind = command.add_option_function<std::string>(
      "--proxy", [&flags](const std::string& name) { set_or_throw(flags, "--proxy", name); },
      "proxy shape: sphere, cylinder, cone, disk, quad or plane");
  kind->type_name("KIND");
  CLI::Option* file = command.add_option_function<std::string>(
      "--proxy-file",
      [&flags](const std::string& path) { set_or_throw(flags, "--proxy-file", path); },
      "read the proxy from a JSON file (as written by texbake fit) instead of --proxy and "
      "geometry flags; map, bake and render also take a camera (\"kind\":\"camera\", SPEC "
      "section 9)");
  file->type_name("FILE");
  file->excludes(kind);

  for (const GeometryParam& p : geometry_params()) {
    const std::string name(p.flag);
    command
        .add_option_function<std::string>(
            name, [&flags, name](const std::string& s) { set_or_throw(flags, name, s); },
            std::string(p.help))
        ->type_name(geometry_type_name(p.type));
  }
  command
      .add_option_function<std::string>(
          "--up", [&flags](const std::string& s) { set_or_throw(flags, "--up", s); },
          "default pole/axis/normal: x, y, z, -x, -y or -z (default z)")
      ->type_name("AXIS");
}

}  // namespace texbake::cli
