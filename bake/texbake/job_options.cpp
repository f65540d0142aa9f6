// The bake job's option table and its one validation (texbake/job_options.h).
#include "texbake/job_options.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>
#include <utility>

#include "bake/util/timing.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/file_name.h"
#include "mesh_io/json_strict.h"
#include "texbake/geometry_options.h"

namespace texbake {

namespace fs = std::filesystem;
using namespace bakes;  // NOLINT(google-build-using-namespace): the masks, in this file only

namespace {

using T = JobOptionType;

// The rows before the proxy's geometry (which mapping/proxy_schema.h's
// table gives), then the rest. --help lists them in this order.
const JobOption kInputRows[] = {
    {"mesh", "", "", T::kPath, "MESH", "", "", kAll,
     "input mesh (.obj, .ply, .off, .stl, .glb, .gltf)"},
    {"texture", "--texture", "", T::kPath, "IMG", "", "", kProxy | kCamera,
     "image to bake (anything OpenImageIO reads); required unless --cameras"},
    {"output", "--output", "-o", T::kPath, "OUT", "", "", kAll,
     "output: .ply (vertex colours), .obj (atlas: + .mtl + atlas image beside it; vertex: v x y "
     "z r g b) or .glb (atlas embedded, or COLOR_0)"},
    {"proxy", "--proxy", "", T::kChoice, "KIND", "", "sphere|cylinder|cone|disk|quad|plane", kProxy,
     "proxy shape: sphere, cylinder, cone, disk, quad or plane"},
    {"proxy_file", "--proxy-file", "", T::kPath, "FILE", "", "", kProxy | kCamera,
     "read the proxy from a JSON file (as written by texbake fit) instead of --proxy and "
     "geometry flags; map, bake and render also take a camera (\"kind\":\"camera\", SPEC "
     "section 9)"},
};

const JobOption kUpRow = {
    "up",
    "--up",
    "",
    T::kChoice,
    "AXIS",
    "z",
    "x|y|z|-x|-y|-z",
    kAll,
    "the mesh's up axis: default pole/axis/normal, and for .glb output the axis the node matrix "
    "turns to glTF's +Y (vertex data unchanged); x, y, z, -x, -y or -z (default z)"};

const JobOption kOtherRows[] = {
    {"target", "--target", "", T::kChoice, "vertex|atlas", "by the output", "vertex|atlas", kAll,
     "vertex or atlas (default: vertex for .ply, atlas for .obj/.glb outputs)"},
    {"size", "--size", "", T::kInteger, "N", "2048", "1 .. 16384", kAtlas,
     "atlas target: width and height in texels (default 2048, 1..16384)"},
    {"padding", "--padding", "", T::kText, "N|inf", "8 at 2048, scaled with --size",
     "0 .. 16384|inf", kAtlas,
     "atlas target: texels of dilation into the gutter, or 'inf' for push-pull over the whole "
     "background, alpha included (default: 8 at 2048, scaled with --size, at least 1, then "
     "push-pull of the colour over the rest of the background with alpha 0, so mipmaps never "
     "average in black; an explicit N is taken as is and leaves the rest transparent black, 0 = "
     "no dilation)"},
    {"uv", "--uv", "", T::kChoice, "auto|mesh|generate|proxy", "auto", "auto|mesh|generate|proxy",
     kAtlas,
     "atlas target UV layout: auto (default: mesh if the mesh has UVs, else generate), mesh (its "
     "own UVs), generate (new non-overlapping charts) or proxy (the proxy's (u, v), cut at its "
     "seam; suits meshes that are star-shaped as seen from the proxy's centre, axis or plane: "
     "surfaces behind one another share texels, which are counted, warned about and take the "
     "visible surface's colour)"},
    {"format", "--format", "", T::kChoice, "png8|png16|exr", "png8", "png8|png16|exr", kAtlas,
     "atlas target image format: png8 (default), png16 or exr (.obj only)"},
    {"ascii", "--ascii", "", T::kFlag, "", "false", "", kVertex,
     "vertex target, .ply: ASCII instead of binary little-endian"},
    {"filter", "--filter", "", T::kChoice, "bilinear|area|ewa", "area (vertex), bilinear (atlas)",
     "bilinear|area|ewa", kProxy,
     "vertex: bilinear (sample at the vertex), area (average of --samples over the vertex's "
     "share of its triangles, default) or ewa (one elliptical weighted average over a MIP "
     "pyramid, sized by the vertex's share; a MIP-mapped texture file's own levels, as maketx "
     "writes them, are used); atlas: bilinear (default) or ewa (each supersample filtered by its "
     "footprint)"},
    {"samples", "--samples", "", T::kInteger, "N", "16 (vertex), 4 (atlas)",
     "1 .. 65536 (vertex), 1 .. 256 (atlas)", kProxy | kAtlas,
     "vertex: samples per vertex for --filter area (default 16, 1..65536); atlas: supersamples "
     "per texel (default 4, 1..256)"},
    {"visibility", "--visibility", "", T::kChoice, "first|all", "first", "first|all", kProxy,
     "first: only what the projector sees is coloured (default); all: no test"},
    {"occluded", "--occluded", "", T::kText, "fill|project|R,G,B[,A]", "fill",
     "fill|project|R,G,B[,A]", kAll,
     "occluded points: fill (smooth from visible neighbours, default), project (projected colour "
     "anyway) or a colour R,G,B[,A] in [0,1]"},
    {"outside", "--outside", "", T::kText, "clamp|R,G,B[,A]", "clamp", "clamp|R,G,B[,A]", kProxy,
     "points outside the proxy's (u,v) domain: clamp (edge texel, default) or a colour R,G,B[,A] "
     "in [0,1]"},
    {"wrap", "--wrap", "", T::kChoice, "clamp|repeat", "clamp", "clamp|repeat", kProxy,
     "plane proxy only: clamp (default) or repeat (tile)"},
    {"linear", "--linear", "", T::kFlag, "", "false", "", kProxy,
     "interpolate and average in linear light (an sRGB texture; a linear one always is)"},
    {"texture_colorspace", "--texture-colorspace", "", T::kChoice, "auto|srgb|linear", "auto",
     "auto|srgb|linear", kProxy | kCamera | kPhotos,
     "colour space of --texture: auto (default: as OpenImageIO reports it; untagged float/half "
     "files linear, 8/16-bit sRGB), srgb or linear (overrides the file)"},
    {"cache_mb", "--cache-mb", "", T::kInteger, "N", "1024", "1 .. 16777216", kProxy | kLayers,
     "memory budget for the texture (or each layer's texture and mask) in MiB (default 1024): a "
     "texture whose float RGBA copies would not fit, or larger than 16384 x 16384, is read in "
     "tiles on demand through OpenImageIO's ImageCache (same results, bit for bit)",
     "photos are read whole, at most 16384 x 16384 pixels"},
    {"cameras", "--cameras", "", T::kPath, "PATH", "", "", kPhotos,
     "bake from calibrated photos instead of --texture and a proxy: a COLMAP sparse model folder "
     "(cameras + images .txt or .bin) or a camera file, told by its content: a JSON camera "
     "list, a nerfstudio / instant-ngp transforms.json, a Metashape cameras.xml or a Meshroom / "
     "AliceVision cameras.sfm (vertex or atlas target)"},
    {"images", "--images", "", T::kPath, "DIR", "images/ beside sparse/", "", kPhotos,
     "--cameras: the photos' folder (default: a COLMAP workspace's images/ beside sparse/, or "
     "the camera file's folder)"},
    {"masks", "--masks", "", T::kPath, "DIR", "", "", kPhotos,
     "--cameras: the photos' masks in COLMAP's convention: DIR/<image name>.png (e.g. "
     "DIR/IMG_1.jpg.png, or DIR/IMG_1.png), 0 = masked out, any other value kept; a photo "
     "without a mask file is used whole (warning). A photo's own alpha always weighs its samples"},
    {"blend", "--blend", "", T::kChoice, "soft|best|mean", "soft", "soft|best|mean", kPhotos,
     "--cameras: soft (weights favouring the best views, default), best (one photo per point) "
     "or mean"},
    {"exposure", "--exposure", "", T::kChoice, "gain|none", "gain", "gain|none", kPhotos,
     "--cameras: gain (one gain per photo and channel, least squares, default) or none"},
    {"no_alignment_check", "--no-alignment-check", "", T::kFlag, "", "false", "", kPhotos | kLayers,
     "--cameras and --layers' \"cameras\": bake even when a COLMAP model's sparse points say it "
     "is not in the mesh's frame (default: an error; a doubtful model is a warning)"},
    {"strict_photos", "--strict-photos", "", T::kFlag, "", "false", "", kPhotos | kLayers,
     "--cameras and --layers' \"cameras\": a photo that cannot be read (missing, unreadable) is "
     "an error (default: a warning naming it; the photo is left out and listed in the report's "
     "photos_skipped)"},
    {"layers", "--layers", "", T::kPath, "LAYERS.json", "", "", kLayers,
     "bake several projections composited over a base from a layers file (SPEC section 10: "
     "base, and per layer proxy | proxy_file, texture, mask, opacity, mode, angle_fade, "
     "visibility, outside) instead of --texture and a proxy (vertex or atlas target; the atlas "
     "takes --size, --samples, --padding, --uv generate|mesh|auto, --format)"},
    {"report", "--report", "", T::kPath, "REPORT.json", "", "", kAll,
     "write what was done as JSON to this file"},
    {"threads", "--threads", "", T::kInteger, "N", "all cores", "1 .. 4096", kAll,
     "worker threads (default: all cores)"},
};

std::vector<JobOption> make_table() {
  std::vector<JobOption> rows(std::begin(kInputRows), std::end(kInputRows));
  for (const GeometryParam& p : geometry_params()) {
    const JobOptionType type = p.type == ParamType::kVec3     ? T::kVec3
                               : p.type == ParamType::kNumber ? T::kNumber
                                                              : T::kCorners;
    rows.push_back({p.key, p.flag, "", type, geometry_type_name(p.type), "fitted to the mesh", "",
                    kProxy, p.help});
  }
  rows.push_back(kUpRow);
  rows.insert(rows.end(), std::begin(kOtherRows), std::end(kOtherRows));
  return rows;
}

Error usage(std::string message) {
  return make_error(ErrorCode::kInvalidArgument, std::move(message));
}

// "--a" of an option (the mesh: "MESH").
std::string flag_of(const JobOption& o) {
  return o.flag.empty() ? std::string("MESH") : std::string(o.flag);
}

// A flag or a colour "R,G,B[,A]" (components in [0, 1]) after a keyword.
struct KeywordOrColor {
  std::string keyword;  // empty when a colour was given
  Rgba color{0, 0, 0, 1};
};

// The settings given, parsed: every option's typed value. An option not
// given has the table's default for the job's target (parse_settings), so
// no default is written here: the values below are placeholders.
struct Parsed {
  std::map<std::string, std::string, std::less<>> given;  // key -> text (flags: true only)
  std::string mesh, texture, output, report, layers, cameras, images, masks;
  GeometryFlags geometry;
  std::string target;
  int size = 0;
  std::string padding;  // "": its default in words (8 at 2048, scaled; parse_padding)
  UvLayout uv{};
  AtlasFormat format{};
  bool ascii = false;
  VertexFilter filter{};
  int samples = 0;
  Visibility visibility{};
  KeywordOrColor occluded;
  KeywordOrColor outside;
  WrapMode wrap{};
  bool linear = false;
  TextureColorSpace texture_colorspace{};
  std::size_t cache_mb = 0;
  PhotoBlend blend{};
  ExposureMode exposure{};
  bool strict_photos = false;
  bool no_alignment_check = false;
  int threads = 0;  // its default in words: all cores (0)

  bool has(std::string_view key) const { return given.find(key) != given.end(); }
};

Expected<long long> parse_integer(std::string_view text, const std::string& flag) {
  long long v = 0;
  const char* first = text.data();
  if (!text.empty() && text.front() == '+') ++first;
  const auto [end, ec] = std::from_chars(first, text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) {
    return usage(flag + ": '" + std::string(text) + "' is not an integer");
  }
  return v;
}

Expected<KeywordOrColor> keyword_or_color(std::string_view text, const std::string& flag,
                                          std::initializer_list<std::string_view> keywords) {
  for (std::string_view k : keywords) {
    if (text == k) return KeywordOrColor{std::string(k)};
  }
  Expected<Rgba> c = parse_color(text, flag);
  if (!c) return c.error();
  return KeywordOrColor{"", *c};
}

template <class E>
Status set_choice(std::string_view text, const std::string& flag, E& out) {
  Expected<E> v = parse_choice<E>(text, flag);
  if (!v) return v.error();
  out = *v;
  return ok_status();
}

// Parses one option's text into `p`.
Status parse_option(const JobOption& o, const std::string& text, Parsed& p) {
  const std::string flag = flag_of(o);
  const std::string_view k = o.key;
  if (o.type == T::kPath && text.empty()) return usage(flag + ": an empty path");
  if (o.type == T::kFlag) {
    if (text != "true") return usage(flag + ": '" + text + "' is not true or false (a flag)");
    if (k == "ascii") p.ascii = true;
    if (k == "linear") p.linear = true;
    if (k == "strict_photos") p.strict_photos = true;
    if (k == "no_alignment_check") p.no_alignment_check = true;
    return ok_status();
  }
  if (k == "mesh") p.mesh = text;
  if (k == "texture") p.texture = text;
  if (k == "output") p.output = text;
  if (k == "report") p.report = text;
  if (k == "layers") p.layers = text;
  if (k == "cameras") p.cameras = text;
  if (k == "images") p.images = text;
  if (k == "masks") p.masks = text;
  if (k == "target") {
    if (text != "vertex" && text != "atlas") {
      static const char* const kNames[] = {"vertex", "atlas"};
      return unknown_choice(flag, text, kNames);
    }
    p.target = text;
  }
  if (k == "padding") p.padding = text;
  if (k == "uv") return set_choice(text, flag, p.uv);
  if (k == "format") return set_choice(text, flag, p.format);
  if (k == "filter") return set_choice(text, flag, p.filter);
  if (k == "visibility") return set_choice(text, flag, p.visibility);
  if (k == "wrap") return set_choice(text, flag, p.wrap);
  if (k == "texture_colorspace") return set_choice(text, flag, p.texture_colorspace);
  if (k == "blend") return set_choice(text, flag, p.blend);
  if (k == "exposure") return set_choice(text, flag, p.exposure);
  if (k == "occluded" || k == "outside") {
    Expected<KeywordOrColor> v = k == "occluded" ? keyword_or_color(text, flag, {"fill", "project"})
                                                 : keyword_or_color(text, flag, {"clamp"});
    if (!v) return v.error();
    (k == "occluded" ? p.occluded : p.outside) = *v;
  }
  if (o.type == T::kInteger) {
    Expected<long long> n = parse_integer(text, flag);
    if (!n) return n.error();
    if (k == "size") {
      // The range is the atlas options' check (validate_options), as for a
      // value given through the API.
      if (Status s = check_range(flag, *n, INT32_MIN, INT32_MAX); !s) return s;
      p.size = static_cast<int>(*n);
    } else if (k == "samples") {
      // The vertex range; an atlas's smaller one is the atlas options'.
      if (Status s = check_range(flag, *n, 1, kMaxVertexSamples); !s) return s;
      p.samples = static_cast<int>(*n);
    } else if (k == "cache_mb") {
      if (Status s = check_cache_mb(*n); !s) return s;
      p.cache_mb = static_cast<std::size_t>(*n);
    } else if (k == "threads") {
      if (Status s = check_range(flag, *n, 1, kMaxThreads); !s) return s;
      p.threads = static_cast<int>(*n);
    }
  }
  if (k == "proxy" || k == "proxy_file" || k == "up" || o.type == T::kVec3 ||
      o.type == T::kNumber || o.type == T::kCorners) {
    return set_geometry_option(p.geometry, o.flag, text);
  }
  return ok_status();
}

Error unknown_key(std::string_view key) {
  std::string why = "is not an option of texbake bake";
  if (key == "quiet") {
    why = "is the batch's option (texbake batch --quiet), not a job's";
  } else if (std::string k(key); std::replace(k.begin(), k.end(), '-', '_'), find_job_option(k)) {
    why += " (did you mean '" + k + "'?)";
  }
  return usage("key '" + std::string(key) + "' " + why);
}

// "V (vertex), W (atlas)": the text for `target`; any other text as it is.
std::string_view default_for(std::string_view text, JobTarget target) {
  constexpr std::string_view kVertex = " (vertex), ", kAtlas = " (atlas)";
  const std::size_t v = text.find(kVertex);
  if (v == std::string_view::npos || !text.ends_with(kAtlas)) return text;
  if (target == JobTarget::kVertex) return text.substr(0, v);
  const std::size_t w = v + kVertex.size();
  return text.substr(w, text.size() - kAtlas.size() - w);
}

// Whether `text` is a value of `o` (not words that describe its default).
bool is_value(const JobOption& o, std::string_view text) {
  if (text.empty() || o.type == T::kPath) return false;
  if (o.type == T::kFlag) return text == "false";
  if (o.key == "padding") return static_cast<bool>(parse_padding(std::string(text)));
  Parsed scratch;
  return static_cast<bool>(parse_option(o, std::string(text), scratch));
}

// The settings, each checked and parsed, in the table's order (as the
// command line parses its flags), so the first bad value reported does not
// depend on the order they were given in; an option not given takes the
// table's default for the job's target (none while the target is unknown:
// make_job reports that). --up's is the proxy schema's, as a geometry flag
// given is more than its value (mapping/proxy_schema.h).
Expected<Parsed> parse_settings(std::span<const JobSetting> settings) {
  Parsed p;
  for (const JobSetting& s : settings) {
    const JobOption* o = find_job_option(s.key);
    if (!o) return unknown_key(s.key);
    if (p.given.count(s.key)) return usage(flag_of(*o) + " is given twice");
    if (o->type == T::kFlag && s.value != "true" && s.value != "false") {
      return usage(flag_of(*o) + ": '" + s.value + "' is not true or false (a flag)");
    }
    if (o->type == T::kFlag && s.value == "false") continue;  // not given
    p.given.emplace(s.key, s.value);
  }
  const auto given_text = [&p](std::string_view key) {
    const auto it = p.given.find(key);
    return it == p.given.end() ? std::string() : it->second;
  };
  const Expected<JobTarget> target = job_target(given_text("target"), given_text("output"));
  for (const JobOption& o : job_options()) {
    const auto it = p.given.find(o.key);
    std::string text;
    if (it != p.given.end()) {
      text = it->second;
    } else if (target && o.type != T::kFlag && o.key != "up") {
      text = job_option_default(o, *target);
      if (text.empty()) continue;
    } else {
      continue;
    }
    if (Status s = parse_option(o, text, p); !s) return s.error();
  }
  return p;
}

// ---- Which options apply to the bake ----

enum class Kind { kProxy, kCamera, kPhotos, kLayers };

unsigned bake_of(Kind kind, bool atlas) {
  switch (kind) {
    case Kind::kProxy:
      return atlas ? kProxyAtlas : kProxyVertex;
    case Kind::kCamera:
      return atlas ? kCameraAtlas : kCameraVertex;
    case Kind::kPhotos:
      return atlas ? kPhotosAtlas : kPhotosVertex;
    case Kind::kLayers:
      return atlas ? kLayersAtlas : kLayersVertex;
  }
  return 0;
}

unsigned both_targets(Kind kind) {
  return bake_of(kind, false) | bake_of(kind, true);
}

const char* what_of(Kind kind) {
  switch (kind) {
    case Kind::kProxy:
      return "a proxy";
    case Kind::kCamera:
      return "a camera --proxy-file";
    case Kind::kPhotos:
      return "--cameras";
    case Kind::kLayers:
      return "--layers";
  }
  return "";
}

const char* why_not(Kind kind) {
  switch (kind) {
    case Kind::kCamera:
      return "the photo is sampled bilinearly through the lens model, in linear light, visible "
             "along the segment to the camera";
    case Kind::kPhotos:
      return "the photos and their cameras are the projection";
    case Kind::kLayers:
      return "the layers file holds every projection and its options";
    case Kind::kProxy:
      break;
  }
  return "";
}

// "--cameras", "--cameras and --layers": the kinds (other than a proxy's) in `mask`.
std::string kinds_in(unsigned mask) {
  std::vector<std::string> names;
  if (mask & kCamera) names.emplace_back("a camera --proxy-file");
  if (mask & kPhotos) names.emplace_back("--cameras");
  if (mask & kLayers) names.emplace_back("--layers");
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    text += (i == 0 ? "" : (i + 1 == names.size() ? " and " : ", ")) + names[i];
  }
  return text;
}

// The first option given that does not apply to the bake, by the table:
// another kind's ("--filter does not apply to --cameras (why)", for a proxy
// bake "--blend applies to --cameras only") or the other target's ("--size
// applies to --target atlas only (this bake's target is vertex, writing
// OUT)"). With `kinds_only`, only whether it applies to some bake of
// `kinds`' (a mask of kinds), for before the kind is known.
Status check_applies(const Parsed& p, Kind kind, bool atlas, const std::string& output) {
  const unsigned bake = bake_of(kind, atlas);
  for (const JobOption& o : job_options()) {
    if (!p.has(o.key) || (o.bakes & bake)) continue;
    const std::string flag = flag_of(o);
    if (o.bakes & both_targets(kind)) {
      return usage(flag + " applies to --target " + (atlas ? "vertex" : "atlas") + " only" +
                   (kind == Kind::kProxy ? "" : std::string(" with ") + what_of(kind)) +
                   " (this bake's target is " + (atlas ? "atlas" : "vertex") + ", writing " +
                   output + ")");
    }
    if (kind == Kind::kProxy) return usage(flag + " applies to " + kinds_in(o.bakes) + " only");
    const std::string why = o.not_here.empty() ? why_not(kind) : std::string(o.not_here);
    return usage(flag + " does not apply to " + what_of(kind) + " (" + why + ")");
  }
  return ok_status();
}

// Options of photos or layers only, given without them: "--blend applies to --cameras only".
Status check_not_photo_options(const Parsed& p) {
  for (const JobOption& o : job_options()) {
    if (p.has(o.key) && !(o.bakes & (kProxy | kCamera))) {
      return usage(flag_of(o) + " applies to " + kinds_in(o.bakes) + " only");
    }
  }
  return ok_status();
}

// --uv proxy without a proxy.
Status check_uv_not_proxy(const Parsed& p, Kind kind) {
  if (p.uv != UvLayout::kProxy) return ok_status();
  return usage(std::string("--uv proxy needs a proxy, and ") + what_of(kind) +
               (kind == Kind::kCamera ? " is a camera" : " has none") +
               " (use --uv generate or --uv mesh)");
}

VertexBakeOptions shading_options(const Parsed& p) {
  VertexBakeOptions options;
  options.filter = p.filter;
  options.samples = p.samples;
  options.visibility = p.visibility;
  if (p.occluded.keyword == "fill") {
    options.occluded = OccludedMode::kFill;
  } else if (p.occluded.keyword == "project") {
    options.occluded = OccludedMode::kProject;
  } else {
    options.occluded = OccludedMode::kColor;
    options.occluded_color = p.occluded.color;
  }
  if (p.outside.keyword == "clamp") {
    options.outside = OutsideMode::kClamp;
  } else {
    options.outside = OutsideMode::kColor;
    options.outside_color = p.outside.color;
  }
  options.linear = p.linear;
  options.plane_wrap = p.wrap;
  return options;
}

WriteOptions write_options(const Parsed& p) {
  WriteOptions w;
  w.format = p.format;
  w.ascii = p.ascii;
  w.up = up_direction(p.geometry);  // a .glb's node matrix
  return w;
}

// The atlas options (checked: --size, --samples, --padding, the writer's).
Expected<AtlasOptions> atlas_options(const Parsed& p, const VertexBakeOptions& shading) {
  AtlasOptions options;
  options.uv = p.uv;
  AtlasBakeOptions& o = options.bake;
  o.shading = shading;
  o.size = p.size;
  o.samples = p.samples;
  o.padding = kPaddingDefault;  // until --padding is parsed, after the other checks
  if (Status s = validate_options(options); !s) return s.error();
  Expected<int> padding = parse_padding(p.padding);
  if (!padding) return padding.error();
  o.padding = *padding;
  WriteOptions w;
  w.format = p.format;
  if (Status s = validate_write(p.output, w, /*atlas=*/true); !s) return s.error();
  return options;
}

// The occluded colour of --occluded R,G,B[,A] into the photo or layers
// bake's options (a keyword keeps their default, fill).
template <class Options>
void set_occluded(const Parsed& p, Options& options) {
  if (p.occluded.keyword.empty()) {
    options.occluded = OccludedMode::kColor;
    options.occluded_color = p.occluded.color;
  }
}

// The job's common part: mesh, output, report, threads, cache, target, writer.
Job base_job(const Parsed& p, bool atlas) {
  Job job;
  job.mesh = p.mesh;
  job.output = p.output;
  job.report = p.report;
  job.threads = p.threads;
  job.cache_mb = p.cache_mb;
  job.target = atlas ? JobTarget::kAtlas : JobTarget::kVertex;
  job.write = write_options(p);
  job.naming = ParamNaming::kFlag;
  return job;
}

// Photos (cameras), or one photo through `camera` (a camera proxy_file).
Expected<Job> photos_job(const Parsed& p, bool atlas, const CameraProjector* camera) {
  const Kind kind = camera ? Kind::kCamera : Kind::kPhotos;
  if (Status s = check_applies(p, kind, atlas, p.output); !s) return s.error();
  Job job = base_job(p, atlas);
  PhotoBakeOptions& options = job.photo_options;
  options.blend = p.blend;
  options.exposure = p.exposure;
  options.strict_photos = p.strict_photos;
  if (camera) {
    job.proxy_file = *p.geometry.proxy_file;
    job.texture = p.texture;
    job.photo = Photo{fs::path(p.texture).filename().string(), *camera, p.texture, {}};
    options.exposure = ExposureMode::kNone;  // one photo: nothing to balance
    options.strict_photos = true;            // the texture itself: never left out
    options.color_space = p.texture_colorspace;
  } else {
    job.cameras = p.cameras;
    job.images = p.images;
    job.masks = p.masks;
    job.alignment_check = !p.no_alignment_check;
    options.color_space = p.texture_colorspace;
  }
  set_occluded(p, options);
  if (atlas) {
    if (Status s = check_uv_not_proxy(p, kind); !s) return s.error();
    Expected<AtlasOptions> a = atlas_options(p, VertexBakeOptions{});
    if (!a) return a.error();
    job.atlas = *a;
  }
  return job;
}

Expected<Job> layers_job(const Parsed& p, bool atlas) {
  if (Status s = check_applies(p, Kind::kLayers, atlas, p.output); !s) return s.error();
  Job job = base_job(p, atlas);
  job.layers = p.layers;
  job.alignment_check = !p.no_alignment_check;
  set_occluded(p, job.layers_options);
  job.layers_options.strict_photos = p.strict_photos;
  job.layers_options.consistency_warning = !p.no_alignment_check;
  if (atlas) {
    if (Status s = check_uv_not_proxy(p, Kind::kLayers); !s) return s.error();
    Expected<AtlasOptions> a = atlas_options(p, VertexBakeOptions{});
    if (!a) return a.error();
    job.atlas = *a;
    // Not given: the base texture's size (base "mesh"), else 2048.
    if (!p.has("size")) job.atlas.bake.size = 0;
  }
  return job;
}

// The geometry flags that make the proxy. --up also orients a .glb (its
// node matrix turns --up to glTF's +Y), so for a .glb output it is allowed
// where it is no geometry flag: with --proxy-file (the file holds the whole
// proxy) and with a kind without pole/axis/normal; there it is the GLB's
// alone. Elsewhere (a .ply or .obj) it stays the error it was.
GeometryFlags proxy_geometry(const GeometryFlags& flags, const fs::path& output) {
  GeometryFlags g = flags;
  if (lower_extension(output) != ".glb" || !g.up) return g;
  if (g.proxy_file) g.up.reset();
  if (g.kind) {
    const std::vector<std::string> allowed = flags_of_kind(*g.kind);
    if (std::find(allowed.begin(), allowed.end(), "--up") == allowed.end()) g.up.reset();
  }
  return g;
}

Status check_wrap(const Parsed& p, std::optional<ProxyKind> kind) {
  if (p.has("wrap") && kind && *kind != ProxyKind::kPlane) {
    return usage("--wrap applies to the plane proxy only (the others' wrap is fixed)");
  }
  return ok_status();
}

// An image through a proxy (given whole, by a file, or to be fitted).
Expected<Job> proxy_job(const Parsed& p, const GeometryFlags& geometry, bool atlas) {
  if (Status s = check_applies(p, Kind::kProxy, atlas, p.output); !s) return s.error();
  const WriteOptions write = write_options(p);
  if (!atlas) {
    if (Status s = validate_write(p.output, write, /*atlas=*/false); !s) return s.error();
  }
  if (atlas && p.has("filter") && p.filter == VertexFilter::kArea) {
    return usage(
        "--filter area applies to --target vertex only (the atlas takes bilinear or ewa; this "
        "bake's target is atlas, writing " +
        p.output + ")");
  }
  if (Status s = check_wrap(p, geometry.kind); !s) return s.error();
  VertexBakeOptions shading = shading_options(p);
  // The atlas's lookup: bilinear per supersample unless --filter ewa.
  if (atlas && shading.filter != VertexFilter::kEwa) shading.filter = VertexFilter::kBilinear;
  AtlasOptions atlas_opts;
  if (atlas) {
    Expected<AtlasOptions> a = atlas_options(p, shading);
    if (!a) return a.error();
    atlas_opts = *a;
  } else if (Status s = validate_options(shading); !s) {
    return s.error();
  }
  Job job = base_job(p, atlas);
  job.texture = p.texture;
  job.proxy_file = geometry.proxy_file.value_or("");
  // All geometry given (or a file): built and validated now, so a bad value
  // is reported before the long work. Otherwise the job fits it to the mesh.
  if (geometry.proxy_file || missing_geometry_flags(geometry, *geometry.kind).empty()) {
    Expected<Proxy> proxy = proxy_from_flags(geometry);
    if (!proxy) return proxy.error();
    if (Status s = check_wrap(p, kind_of(params_of(*proxy))); !s) return s.error();
    job.proxy = std::move(*proxy);
  } else {
    job.spec = spec_from_flags(geometry);
  }
  job.shading = shading;
  job.atlas = atlas_opts;
  job.texture_colorspace = p.texture_colorspace;
  return job;
}

Expected<Job> make_job(const Parsed& p) {
  if (p.mesh.empty()) return usage("MESH is required (the input mesh)");
  if (p.output.empty()) return usage("--output is required");
  Expected<JobTarget> target = job_target(p.target, p.output);
  if (!p.layers.empty()) {
    if (!target) return target.error();
    return layers_job(p, *target == JobTarget::kAtlas);
  }
  if (!p.cameras.empty()) {
    if (!target) return target.error();
    return photos_job(p, *target == JobTarget::kAtlas, nullptr);
  }
  if (Status s = check_not_photo_options(p); !s) return s.error();
  if (p.texture.empty()) {
    return usage("--texture is required (or --cameras to bake from photographs, or --layers)");
  }
  const GeometryFlags geometry = proxy_geometry(p.geometry, p.output);
  if (Status s = check_geometry_flags(geometry, /*require_proxy=*/true); !s) return s.error();
  // A camera proxy_file (SPEC section 9) bakes its photo like cameras with one photo.
  if (geometry.proxy_file) {
    Expected<Projector> projector = projector_from_flags(geometry);
    if (!projector) return projector.error();
    if (const CameraProjector* camera = as_camera(*projector)) {
      if (!target) return target.error();
      return photos_job(p, *target == JobTarget::kAtlas, camera);
    }
  }
  if (!target) return target.error();
  return proxy_job(p, geometry, *target == JobTarget::kAtlas);
}

}  // namespace

std::span<const JobOption> job_options() {
  static const std::vector<JobOption> table = make_table();
  return table;
}

std::string job_option_default(const JobOption& option, JobTarget target) {
  const std::string_view text = default_for(option.default_text, target);
  return is_value(option, text) ? std::string(text) : std::string();
}

const JobOption* find_job_option(std::string_view key) {
  for (const JobOption& o : job_options()) {
    if (o.key == key) return &o;
  }
  return nullptr;
}

Expected<Job> job_from_settings(std::span<const JobSetting> settings) {
  Expected<Parsed> parsed = parse_settings(settings);
  if (!parsed) return parsed.error();
  return make_job(*parsed);
}

JobFileNames job_file_names(const Job& job) {
  JobFileNames f;
  f.mesh = job.mesh;
  f.texture = job.texture;
  f.proxy_file = job.proxy_file;
  f.cameras = job.cameras;
  f.images = job.images;
  f.masks = job.masks;
  f.layers = job.layers;
  f.output = job.output;
  f.atlas = job.target == JobTarget::kAtlas;
  f.write = job.write;
  f.report = job.report;
  return f;
}

namespace {

using nlohmann::ordered_json;

// A JSON value as the text of an option's value: a string as it is, a
// number as JSON prints it, an array of numbers "x,y,z", an array of arrays
// "x,y,z;x,y,z;..." (corners). Error naming the key for other values.
Expected<std::string> value_text(const std::string& key, const ordered_json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number()) return v.dump();
  auto bad = [&] {
    return usage("key '" + key + "': " + v.dump() +
                 " is not a value of the command line (a string, a number, an array of numbers "
                 "or of arrays of numbers)");
  };
  if (!v.is_array() || v.empty()) return bad();
  std::string text;
  for (const ordered_json& e : v) {
    if (e.is_array()) {
      Expected<std::string> inner = value_text(key, e);
      if (!inner || inner->find(';') != std::string::npos) return bad();
      text += (text.empty() ? "" : ";") + *inner;
    } else if (e.is_number()) {
      text += (text.empty() ? "" : ",") + e.dump();
    } else {
      return bad();
    }
  }
  return text;
}

}  // namespace

Expected<std::vector<JobSetting>> job_settings_from_json(std::string_view object,
                                                         const std::string& source) {
  Expected<ordered_json> keys = parse_json_object<ordered_json>(object, source);
  if (!keys) return keys.error();
  std::vector<JobSetting> settings;
  for (const auto& [key, value] : keys->items()) {
    const JobOption* o = find_job_option(key);
    if (!o) return unknown_key(key);
    const bool is_flag = o->type == T::kFlag;
    if (is_flag != value.is_boolean()) {
      return usage("key '" + key + "': " + value.dump() +
                   (is_flag ? " is not true or false (a flag)"
                            : " is not a value of the command line (the option takes one, not a "
                              "flag's true or false)"));
    }
    if (is_flag) {
      settings.push_back({key, value.get<bool>() ? "true" : "false"});
      continue;
    }
    Expected<std::string> text = value_text(key, value);
    if (!text) return text.error();
    settings.push_back({key, std::move(*text)});
  }
  return settings;
}

namespace {

// Every output exists and none is older than any input (make's rule); false
// when an input is missing (the job runs and reports it).
bool up_to_date(const JobFileNames& names) {
  const std::vector<NamedFile> outputs = job_outputs(names);
  if (outputs.empty()) return false;
  std::error_code ec;
  fs::file_time_type newest_input = fs::file_time_type::min();
  for (const NamedFile& in : job_inputs(names)) {
    const fs::file_time_type t = fs::last_write_time(in.path, ec);
    if (ec) return false;
    newest_input = std::max(newest_input, t);
  }
  for (const NamedFile& out : outputs) {
    const fs::file_time_type t = fs::last_write_time(out.path, ec);
    if (ec || t < newest_input) return false;
  }
  return true;
}

// The job's line of the results file.
std::string result_line(const BatchJobResult& r) {
  const JobResult& job = r.result;
  ordered_json j;
  j["line"] = r.line;
  j["status"] = r.status;
  j["exit"] = job.exit_code;
  j["error"] = job.error ? ordered_json(job.error->message) : ordered_json();
  j["warnings"] = job.warnings;
  ordered_json outs = ordered_json::array();
  for (const fs::path& p : r.outputs) outs.push_back(p.string());
  j["outputs"] = outs;
  if (r.status == "ok" && !job.report.empty()) {
    const ordered_json report = ordered_json::parse(job.report);
    j["target"] = report["target"];
    j["counts"] = report["counts"];
    j["timings"] = report["timings"];
  } else {
    j["counts"] = ordered_json();
    j["timings"] = ordered_json();
  }
  j["seconds"] = job.seconds;
  // Paths and messages may hold bytes that are not UTF-8 (a photo's name):
  // those become U+FFFD rather than end the batch.
  return j.dump(-1, ' ', false, ordered_json::error_handler_t::replace);
}

// The results file: emptied at the start, then each job's line appended and
// flushed as the job ends.
class ResultsFile {
 public:
  Status open(const fs::path& path) {
    path_ = path;
    if (path.empty()) return ok_status();
    if (Status s = check_writable(path); !s) return s;
    out_.open(path, std::ios::binary | std::ios::trunc);
    if (!out_) return make_error(ErrorCode::kIo, "cannot write results " + path.string());
    return ok_status();
  }
  Status append(const std::string& line) {
    if (path_.empty()) return ok_status();
    out_ << line << '\n';
    out_.flush();
    if (!out_) return make_error(ErrorCode::kIo, "cannot write results " + path_.string());
    return ok_status();
  }

 private:
  fs::path path_;
  std::ofstream out_;
};

// One job of the batch: parsed, checked against the batch's files, skipped
// when up to date, or run.
BatchJobResult run_batch_job(const BatchJob& line, const BatchOptions& options,
                             const std::shared_ptr<JobCache>& cache) {
  BatchJobResult r;
  r.line = line.line;
  const auto start = Clock::now();
  Expected<Job> job = [&]() -> Expected<Job> {
    Expected<std::vector<JobSetting>> settings = job_settings_from_json(line.json, "");
    if (!settings) return settings.error();
    return job_from_settings(*settings);
  }();
  JobFileNames names;
  if (job) {
    if (job->threads == 0) job->threads = options.threads;
    job->cache = cache;
    names = job_file_names(*job);
    for (const NamedFile& out : job_outputs(names)) r.outputs.push_back(out.path);
    // No output may be an input: the jobs file is an input, the results
    // file an output, of every job.
    JobFileNames in_batch = names;
    in_batch.manifest = options.manifest;
    in_batch.results = options.results;
    if (Status s = check_job_files(in_batch); !s) job = s.error();
  }
  if (!job) {
    r.status = "failed";
    r.result.error = job.error();
    r.result.exit_code = exit_code(job.error());
  } else if (options.skip_existing && up_to_date(names)) {
    r.status = "skipped";
  } else {
    r.result = run_job(*job);
    r.status = r.result.ok() ? "ok" : "failed";
  }
  r.result.seconds = seconds_since(start);
  r.json = result_line(r);
  return r;
}

}  // namespace

BatchResult run_batch(std::span<const BatchJob> jobs, const BatchOptions& options) {
  const auto start = Clock::now();
  BatchResult batch;
  // The jobs file is an input, the results file an output, of every job.
  if (Status s =
          check_distinct_files({{"JOBS", options.manifest}}, {{"--results", options.results}});
      !s) {
    batch.error = s.error();
    return batch;
  }
  ResultsFile results;
  if (Status s = results.open(options.results); !s) {
    batch.error = s.error();
    return batch;
  }
  // The jobs share what they read (a mesh or texture of several jobs is read once).
  const auto cache = options.cache ? options.cache : std::make_shared<JobCache>();
  for (const BatchJob& line : jobs) {
    BatchJobResult r = run_batch_job(line, options, cache);
    ++(r.status == "ok" ? batch.ok : r.status == "skipped" ? batch.skipped : batch.failed);
    if (Status s = results.append(r.json); !s) {
      batch.error = s.error();
      batch.jobs.push_back(std::move(r));
      break;
    }
    if (options.on_job_end) options.on_job_end(r);
    const bool stop = options.fail_fast && r.status == "failed";
    batch.jobs.push_back(std::move(r));
    if (stop) break;
  }
  batch.not_run = jobs.size() - batch.jobs.size();
  batch.seconds = seconds_since(start);
  return batch;
}

}  // namespace texbake
