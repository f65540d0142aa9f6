// The option checks every client shares (texbake/texbake.h, "Option
// values"): the names of the enum options' values, the ranges, the colour
// and padding spellings, and validate_options for render, compare, photos
// and layers. One message per bad value, naming the CLI flag.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "texbake/texbake.h"

namespace texbake {

namespace {

template <class E, std::size_t N>
std::span<const Choice<E>> span_of(const Choice<E> (&table)[N]) {
  return {table, N};
}

Error usage(std::string message) {
  return make_error(ErrorCode::kInvalidArgument, std::move(message));
}

bool in_unit(double x) {
  return x >= 0 && x <= 1;
}

std::string not_a_color(std::string_view flag, std::string_view text, bool alpha) {
  return std::string(flag) + ": '" + std::string(text) + "' is not a colour " +
         (alpha ? "R,G,B[,A]" : "R,G,B") + " with components in [0, 1] (e.g. 1,0,0 for red)";
}

// The components as %g numbers separated by commas ("1,0,0.5").
std::string components_text(std::span<const double> c) {
  std::string text;
  for (std::size_t i = 0; i < c.size(); ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", c[i]);
    text += (i ? "," : "") + std::string(buf);
  }
  return text;
}

// The check of color_from_components, with `text` for the message.
Expected<Rgba> checked_color(std::span<const double> c, std::string_view text,
                             std::string_view flag, bool alpha) {
  const bool count_ok = c.size() == 3 || (alpha && c.size() == 4);
  bool values_ok = count_ok;
  for (double x : c) values_ok = values_ok && in_unit(x);
  if (!values_ok) return usage(not_a_color(flag, text, alpha));
  Rgba out{0, 0, 0, 1};
  for (std::size_t i = 0; i < c.size(); ++i) out[i] = static_cast<float>(c[i]);
  return out;
}

// An Rgba's first `n` components, checked as color_from_components.
Status check_rgba(const Rgba& c, std::size_t n, std::string_view flag) {
  const double d[4] = {c[0], c[1], c[2], c[3]};
  Expected<Rgba> checked = color_from_components({d, n}, flag, n == 4);
  if (!checked) return checked.error();
  return ok_status();
}

}  // namespace

std::span<const Choice<VertexFilter>> choices(VertexFilter) {
  static constexpr Choice<VertexFilter> kTable[] = {{"bilinear", VertexFilter::kBilinear},
                                                    {"area", VertexFilter::kArea},
                                                    {"ewa", VertexFilter::kEwa}};
  return span_of(kTable);
}

std::span<const Choice<Visibility>> choices(Visibility) {
  static constexpr Choice<Visibility> kTable[] = {{"first", Visibility::kFirst},
                                                  {"all", Visibility::kAll}};
  return span_of(kTable);
}

std::span<const Choice<WrapMode>> choices(WrapMode) {
  static constexpr Choice<WrapMode> kTable[] = {{"clamp", WrapMode::kClamp},
                                                {"repeat", WrapMode::kRepeat}};
  return span_of(kTable);
}

std::span<const Choice<UvLayout>> choices(UvLayout) {
  static constexpr Choice<UvLayout> kTable[] = {{"auto", UvLayout::kAuto},
                                                {"mesh", UvLayout::kMesh},
                                                {"generate", UvLayout::kGenerate},
                                                {"proxy", UvLayout::kProxy}};
  return span_of(kTable);
}

std::span<const Choice<AtlasFormat>> choices(AtlasFormat) {
  static constexpr Choice<AtlasFormat> kTable[] = {
      {"png8", AtlasFormat::kPng8}, {"png16", AtlasFormat::kPng16}, {"exr", AtlasFormat::kExr}};
  return span_of(kTable);
}

std::span<const Choice<PhotoBlend>> choices(PhotoBlend) {
  static constexpr Choice<PhotoBlend> kTable[] = {
      {"soft", PhotoBlend::kSoft}, {"best", PhotoBlend::kBest}, {"mean", PhotoBlend::kMean}};
  return span_of(kTable);
}

std::span<const Choice<ExposureMode>> choices(ExposureMode) {
  static constexpr Choice<ExposureMode> kTable[] = {{"gain", ExposureMode::kGain},
                                                    {"none", ExposureMode::kNone}};
  return span_of(kTable);
}

std::span<const Choice<TextureColorSpace>> choices(TextureColorSpace) {
  static constexpr Choice<TextureColorSpace> kTable[] = {{"auto", TextureColorSpace::kAuto},
                                                         {"srgb", TextureColorSpace::kSrgb},
                                                         {"linear", TextureColorSpace::kLinear}};
  return span_of(kTable);
}

Error unknown_choice(std::string_view flag, std::string_view text,
                     std::span<const char* const> names) {
  std::string expected;
  for (std::size_t i = 0; i < names.size(); ++i) {
    expected += std::string(i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + names[i];
  }
  return usage(std::string(flag) + ": unknown value '" + std::string(text) + "' (expected " +
               expected + ")");
}

Status check_range(std::string_view flag, long long value, long long lo, long long hi) {
  if (value >= lo && value <= hi) return ok_status();
  return usage(std::string(flag) + " " + std::to_string(value) + " is out of range (" +
               std::to_string(lo) + " .. " + std::to_string(hi) + ")");
}

Status check_cache_mb(long long cache_mb) {
  return check_range("--cache-mb", cache_mb, 1, static_cast<long long>(kMaxCacheMb));
}

Expected<Rgba> color_from_components(std::span<const double> components, std::string_view flag,
                                     bool alpha) {
  return checked_color(components, components_text(components), flag, alpha);
}

Expected<Rgba> parse_color(std::string_view text, std::string_view flag, bool alpha) {
  std::vector<double> c;
  std::size_t pos = 0;
  while (c.size() <= 4) {
    const std::size_t comma = text.find(',', pos);
    const std::string part(
        text.substr(pos, comma == std::string_view::npos ? text.npos : comma - pos));
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || std::isspace(static_cast<unsigned char>(part[0]))) {
      return usage(not_a_color(flag, text, alpha));
    }
    c.push_back(v);
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return checked_color(c, text, flag, alpha);
}

Expected<int> parse_padding(std::string_view text) {
  if (text.empty()) return kPaddingDefault;
  if (text == "inf") return kPaddingInfinite;
  const std::string s(text);
  char* end = nullptr;
  const long value = std::strtol(s.c_str(), &end, 10);
  if (!std::isdigit(static_cast<unsigned char>(s[0])) || *end != '\0' || value > kMaxAtlasSize) {
    return usage("--padding '" + s + "' is not a texel count (0 .. " +
                 std::to_string(kMaxAtlasSize) + ") or 'inf'");
  }
  return static_cast<int>(value);
}

Status validate_options(const RenderOptions& o) {
  if (o.width < 1 || o.height < 1 || o.width > kMaxRenderSize || o.height > kMaxRenderSize) {
    return usage("--size: expected WxH with positive integers up to " +
                 std::to_string(kMaxRenderSize) + ", got '" + std::to_string(o.width) + "x" +
                 std::to_string(o.height) + "'");
  }
  if (Status s = check_range("--views", o.views, 1, kMaxRenderViews); !s) return s;
  if (Status s = check_range("--samples", o.samples_per_pixel, 1, kMaxRenderSamples); !s) return s;
  if (!std::isfinite(o.azimuth_deg)) return usage("--view: azimuth must be finite");
  if (!(o.elevation_deg >= -90 && o.elevation_deg <= 90)) {
    return usage("--view: elevation must be in [-90, 90] degrees");
  }
  if (!is_finite(o.up) || length(o.up) == 0)
    return usage("--up: the up vector is zero or not finite");
  return check_rgba(o.background, 3, "--background");
}

Status validate_options(const CompareOptions& o) {
  return check_rgba(o.background, 3, "--background");
}

Status validate_options(const PhotoBakeOptions& o) {
  if (o.occluded == OccludedMode::kColor) {
    if (Status s = check_rgba(o.occluded_color, 4, "--occluded"); !s) return s;
  }
  if (!(o.max_view_angle_deg > 0 && o.max_view_angle_deg <= 90)) {
    return usage("max_view_angle_deg must be in (0, 90]");
  }
  return ok_status();
}

Status validate_options(const LayersBakeOptions& o) {
  // The engine's single-projection rule and shared scene are the proxy
  // bakes' (bake_vertex_colors): a layers job composites by coverage.
  if (o.alpha != ResultAlpha::kCoverage) {
    return usage("a layers bake takes the coverage as alpha (ResultAlpha::kCoverage)");
  }
  if (o.scene) return usage("a layers bake builds its own scene (scene must be null)");
  if (o.occluded == OccludedMode::kColor) {
    if (Status s = check_rgba(o.occluded_color, 4, "--occluded"); !s) return s;
  }
  if (o.base == LayerBase::kColor) return check_rgba(o.base_color, 4, "base");
  return ok_status();
}

}  // namespace texbake
