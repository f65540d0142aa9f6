// texbake map: the inverse mapping as a calculator (SPEC section 5, issue #2).
//   texbake map --proxy KIND [geometry] (--point x,y,z | --dir x,y,z) [--image WxH] [--json]
//   texbake map --proxy-file CAMERA.json --point x,y,z [--json]
// A camera (SPEC section 9) prints the photo pixel (x, y) in COLMAP's
// convention as well as (u, v); behind the camera x, y, u and v are null.
// --point is a world point for every proxy. --dir is for the sphere only: it
// is the normal Sn itself (the point center + dir); for the other proxies a
// direction alone does not fix a point, so it is a usage error there.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "bake/cli/commands.h"
#include "bake/cli/geometry_flags.h"
#include "mapping/image_view.h"

namespace texbake::cli {

namespace {

struct MapOptions {
  GeometryFlags geometry;
  std::optional<Vec3> point, dir;
  std::optional<std::pair<int, int>> image;  // width, height
  bool json = false;
};

// "640x480": two positive integers.
std::pair<int, int> parse_image_size(const std::string& text) {
  const std::size_t x = text.find_first_of("xX");
  int w = 0, h = 0;
  const char* end = text.data() + text.size();
  bool ok = x != std::string::npos;
  if (ok) {
    const auto [wend, wec] = std::from_chars(text.data(), text.data() + x, w);
    const auto [hend, hec] = std::from_chars(text.data() + x + 1, end, h);
    ok = wec == std::errc() && hec == std::errc() && wend == text.data() + x && hend == end &&
         x > 0 && w > 0 && h > 0;
  }
  if (!ok) {
    throw CLI::ValidationError(
        "--image", "expected WxH with positive integers (e.g. 640x480), got '" + text + "'");
  }
  return {w, h};
}

const char* status_name(MapStatus s) {
  switch (s) {
    case MapStatus::kOk:
      return "ok";
    case MapStatus::kOutside:
      return "outside";
    case MapStatus::kUndefined:
      return "undefined";
  }
  return "undefined";
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x + 0.0);  // + 0.0: no "-0"
  return buf;
}

std::string vector_text(Vec3 v) {
  return number(v.x) + ", " + number(v.y) + ", " + number(v.z);
}

const char* outside_reason(CameraOutside o) {
  switch (o) {
    case CameraOutside::kNone:
      return "";
    case CameraOutside::kBehind:
      return "behind the camera";
    case CameraOutside::kFolded:
      return "past the distortion's turning point";
    case CameraOutside::kOffPhoto:
      return "outside the photo";
  }
  return "";
}

// A camera (SPEC section 9): the photo pixel (x, y) in COLMAP's convention
// and (u, v) = (x / width, 1 - y / height).
int run_map_camera(const MapOptions& options, const CameraProjector& camera) {
  if (options.dir) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--dir applies only to a sphere (it gives the normal Sn); use --point "
                        "for a camera");
  }
  if (options.image) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--image does not apply to a camera (its photo's size is the camera's; "
                        "x and y are always printed)");
  }
  const Vec3 point = *options.point;
  const CameraProjection proj = camera.project(point);
  const MapResult r = camera.inverse_map(point);
  const bool in_front = proj.outside != CameraOutside::kBehind;
  if (options.json) {
    nlohmann::ordered_json out;
    if (in_front) {
      out["u"] = proj.uv.u;
      out["v"] = proj.uv.v;
    } else {
      out["u"] = nullptr;
      out["v"] = nullptr;
    }
    out["status"] = proj.inside ? "ok" : "outside";
    if (!proj.inside) out["reason"] = outside_reason(proj.outside);
    if (in_front) {
      out["x"] = proj.pixel.x;
      out["y"] = proj.pixel.y;
    } else {
      out["x"] = nullptr;
      out["y"] = nullptr;
    }
    out["depth"] = proj.depth;
    std::printf("%s\n", out.dump().c_str());
    return 0;
  }
  const CameraSpec& spec = camera.spec();
  std::printf("proxy    camera (%s, %d x %d)\n", std::string(camera_model_name(spec.model)).c_str(),
              spec.width, spec.height);
  std::printf("point    %s\n", vector_text(point).c_str());
  if (in_front) {
    std::printf("u        %s\n", number(proj.uv.u).c_str());
    std::printf("v        %s\n", number(proj.uv.v).c_str());
  }
  if (proj.inside) {
    std::printf("status   ok\n");
  } else {
    std::printf("status   outside (%s)\n", outside_reason(proj.outside));
  }
  std::printf("depth    %s (z in camera axes)\n", number(proj.depth).c_str());
  std::printf("d(P)     %s (towards the camera centre %s)\n", vector_text(r.to_projector).c_str(),
              vector_text(camera.centre()).c_str());
  if (in_front) {
    std::printf(
        "pixel    x %s, y %s in the %d x %d photo (COLMAP: the top-left pixel's centre is "
        "0.5, 0.5)\n",
        number(proj.pixel.x).c_str(), number(proj.pixel.y).c_str(), spec.width, spec.height);
  }
  return 0;
}

int run_map(const MapOptions& options) {
  if (!options.point && !options.dir) {
    return report_error(ErrorCode::kInvalidArgument, "missing --point X,Y,Z or --dir X,Y,Z");
  }
  Expected<Projector> projector = projector_from_flags(options.geometry);
  if (!projector) return report_error(projector.error());
  if (const CameraProjector* camera = as_camera(*projector))
    return run_map_camera(options, *camera);
  const Expected<Proxy> proxy = *as_proxy(*projector);

  Vec3 point;
  if (options.dir) {
    const Sphere* sphere = std::get_if<Sphere>(&*proxy);
    if (!sphere) {
      return report_error(ErrorCode::kInvalidArgument,
                          std::string("--dir applies only to a sphere (it gives the normal Sn); "
                                      "use --point for a ") +
                              to_string(kind_of(*proxy)));
    }
    if (*options.dir == Vec3{}) {
      return report_error(ErrorCode::kInvalidArgument, "--dir is the zero vector");
    }
    // The direction is Sn itself; its length is irrelevant to (u, v).
    point = sphere->center + *options.dir;
  } else {
    point = *options.point;
  }

  const MapResult r = inverse_map(*proxy, point);
  std::optional<PixelPos> pixel;
  if (options.image) pixel = pixel_from_uv(r.uv, options.image->first, options.image->second);

  if (options.json) {
    // Exactly one object; nlohmann prints doubles so they read back exactly.
    nlohmann::ordered_json out;
    out["u"] = r.uv.u;
    out["v"] = r.uv.v;
    out["status"] = status_name(r.status);
    if (pixel) {
      out["x"] = pixel->x;
      out["y"] = pixel->y;
    }
    std::printf("%s\n", out.dump().c_str());
    return 0;
  }
  std::printf("proxy    %s\n", to_string(kind_of(*proxy)));
  std::printf("point    %s\n", vector_text(point).c_str());
  std::printf("u        %s\n", number(r.uv.u).c_str());
  std::printf("v        %s\n", number(r.uv.v).c_str());
  std::printf("status   %s%s\n", status_name(r.status),
              r.status == MapStatus::kOutside ? " (outside the proxy's (u, v) domain; unclamped)"
              : r.status == MapStatus::kUndefined ? " (no mapping at this point)"
                                                  : "");
  std::printf("d(P)     %s (towards the projector)\n", vector_text(r.to_projector).c_str());
  if (pixel) {
    std::printf(
        "pixel    x %s, y %s in a %d x %d image (texel centres at integers, y down from "
        "the top row)\n",
        number(pixel->x).c_str(), number(pixel->y).c_str(), options.image->first,
        options.image->second);
  }
  return 0;
}

}  // namespace

RunFunction add_map_command(CLI::App& app) {
  auto options = std::make_shared<MapOptions>();
  CLI::App* cmd = app.add_subcommand(
      "map",
      "Print the proxy's inverse mapping (u, v) of a point: the inverse-mapping calculator.\n"
      "Example (SPEC section 2's worked example):\n"
      "  texbake map --proxy sphere --center 0,0,0 --radius 1 --pole 0,0,1 --equator 1,0,0 "
      "--dir 1,1,1 --json\n"
      "A camera file (--proxy-file CAM.json, \"kind\":\"camera\") prints the photo pixel x, y "
      "(COLMAP's convention: the top-left pixel's centre is 0.5, 0.5) as well as u, v.");
  add_geometry_flags(*cmd, options->geometry);
  CLI::Option* point =
      cmd->add_option_function<std::string>(
             "--point",
             [options](const std::string& s) { options->point = parse_vec3_flag(s, "--point"); },
             "world point P to map")
          ->type_name("X,Y,Z");
  CLI::Option* dir =
      cmd->add_option_function<std::string>(
             "--dir",
             [options](const std::string& s) { options->dir = parse_vec3_flag(s, "--dir"); },
             "sphere only: the normal Sn (any length), i.e. the point center + dir")
          ->type_name("X,Y,Z");
  point->excludes(dir);
  cmd->add_option_function<std::string>(
         "--image", [options](const std::string& s) { options->image = parse_image_size(s); },
         "also print the pixel position in a W x H image (SPEC section 1)")
      ->type_name("WxH");
  cmd->add_flag("--json", options->json,
                "print one JSON object {\"u\",\"v\",\"status\"[,\"x\",\"y\"]} (a camera: "
                "u, v, status, reason when outside, x, y, depth)");
  return [options] { return run_map(*options); };
}

}  // namespace texbake::cli
