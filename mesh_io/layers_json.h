// The layers file of `texbake bake MESH --layers LAYERS.json` (SPEC section
// 10): an ordered list of projections composited over a base, bottom first.
//   {"base": "mesh" | [r,g,b,a] | "none",
//    "layers": [{"proxy": {...} | "proxy_file": "p.json" | "cameras": "sparse/0",
//                "images": "photos/", "masks": "masks/", "texture": "label.png", "mask": "m.png",
//                "opacity": 1.0, "mode": "over" | "multiply" | "add" | "replace",
//                "angle_fade": [60, 80], "visibility": "first" | "all",
//                "outside": "transparent" | "clamp" | [r,g,b,a],
//                "filter": "bilinear" | "area" | "ewa", "samples": 16,
//                "wrap": "clamp" | "repeat"}]}
// Paths are relative to the layers file's folder (absolute ones stay). A
// layer's projector is exactly one of "proxy" (an inline proxy or camera
// object, mesh_io/proxy_json.h), "proxy_file" (a proxy or camera file) and
// "cameras" (a COLMAP model or a camera file, as --cameras, with optional "images"
// and "masks", as --images and --masks).
// "texture" is required unless the layer has "cameras" (whose photos are
// the images), where it is an error; a "cameras" layer takes no "mask", and
// only "outside" "transparent" and "visibility" "first". "filter" is the
// image's lookup as bake --filter names it: "bilinear" (the default),
// "area" (the vertex target; "samples" lookups per vertex, default 16, 1 ..
// 65536) and "ewa" (an analytic proxy, not a camera); a cameras layer takes
// "bilinear" only. "wrap" (a plane proxy only) is bake --wrap. Defaults:
// base "none", opacity 1, mode "over", no angle fade, visibility "first",
// outside "transparent", filter "bilinear", wrap "clamp".
//
// Errors are kParse (kIo when a file cannot be read) and start with the file
// and the key, e.g. "L.json: layers[1].opacity: must be a number in [0, 1]":
// unknown keys, missing or wrong-typed values, two projectors or none, an
// angle fade that is not 0 <= a0 < a1 <= 90, colours outside [0, 1], and the
// inline proxy's or proxy file's own errors.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/projector.h"

namespace texbake {

enum class LayerBase { kNone, kMesh, kColor };
enum class LayerMode { kOver, kMultiply, kAdd, kReplace };
enum class LayerVisibility { kFirst, kAll };
enum class LayerOutside { kTransparent, kClamp, kColor };
enum class LayerFilter { kBilinear, kArea, kEwa };

struct LayerSpec {
  std::optional<Projector> projector;  // "proxy" or "proxy_file"
  std::filesystem::path proxy_file;    // "proxy_file", resolved (empty otherwise)
  std::filesystem::path cameras;       // "cameras" (then projector is empty)
  std::filesystem::path images;        // "images" (with "cameras" only)
  std::filesystem::path masks;         // "masks" (with "cameras" only): COLMAP's mask folder
  std::filesystem::path texture;       // resolved against the layers file's folder
  std::filesystem::path mask;          // empty: none
  double opacity = 1;
  LayerMode mode = LayerMode::kOver;
  std::optional<std::array<double, 2>> angle_fade;  // degrees, a0 < a1
  LayerVisibility visibility = LayerVisibility::kFirst;
  LayerOutside outside = LayerOutside::kTransparent;
  Rgba outside_color{0, 0, 0, 0};  // sRGB-encoded RGB, straight alpha (kColor)
  LayerFilter filter = LayerFilter::kBilinear;
  int samples = 16;                  // kArea's lookups per vertex
  WrapMode wrap = WrapMode::kClamp;  // a plane proxy's "wrap"
};

struct LayersSpec {
  LayerBase base = LayerBase::kNone;
  Rgba base_color{0, 0, 0, 0};  // sRGB-encoded RGB, straight alpha (kColor)
  std::vector<LayerSpec> layers;
  std::string source;  // the file (or layers_from_json's source), for messages
};

const char* to_string(LayerMode mode);

// Parses `text` with relative paths resolved against `folder`.
Expected<LayersSpec> layers_from_json(std::string_view text, const std::filesystem::path& folder,
                                      const std::string& source = "layers JSON");
// Reads a layers file (a regular file, at most 16 MiB, like proxy files).
Expected<LayersSpec> read_layers_file(const std::filesystem::path& path);

}  // namespace texbake
