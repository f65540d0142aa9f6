// The proxy kinds' parameter tables and the conversions they drive (see
// proxy_schema.h). Each kind's table is bound to its Params struct by
// members() below, checked at compile time field by field (count, type,
// optional equator), so the tables and mapping/proxy.h cannot drift apart.
#include "mapping/proxy_schema.h"

#include <cmath>
#include <sstream>
#include <tuple>
#include <type_traits>
#include <utility>

#include "mapping/azimuth.h"

namespace texbake {

namespace {

// ---- The parameters, each once (the --help order, see geometry_params). ----

constexpr GeometryParam kCenter{"center", "--center", ParamType::kVec3, "sphere/disk centre"};
constexpr GeometryParam kPole{"pole", "--pole", ParamType::kVec3,
                              "sphere pole: v = 1 at its tip (default: --up)"};
constexpr GeometryParam kEquator{
    "equator", "--equator", ParamType::kVec3,
    "direction of u = 0 (default: first of +X, +Y, +Z not parallel to the pole/axis/normal)"};
constexpr GeometryParam kAxis{
    "axis", "--axis", ParamType::kVec3,
    "cylinder axis (base -> top) or cone axis (base -> apex) (default: --up)"};
constexpr GeometryParam kApex{"apex", "--apex", ParamType::kVec3, "cone apex (v = 1)"};
constexpr GeometryParam kBase{"base", "--base", ParamType::kVec3, "cylinder base centre (v = 0)"};
constexpr GeometryParam kNormal{"normal", "--normal", ParamType::kVec3,
                                "disk normal, towards the projector (default: --up)"};
constexpr GeometryParam kOrigin{"origin", "--origin", ParamType::kVec3,
                                "plane point of (u, v) = (0, 0)"};
constexpr GeometryParam kUAxis{"u_axis", "--u-axis", ParamType::kVec3,
                               "plane: origin + u-axis is (u, v) = (1, 0)"};
constexpr GeometryParam kVAxis{"v_axis", "--v-axis", ParamType::kVec3,
                               "plane: origin + v-axis is (u, v) = (0, 1)"};
constexpr GeometryParam kRadius{"radius", "--radius", ParamType::kNumber,
                                "sphere/cylinder/disk radius, cone base radius"};
constexpr GeometryParam kHeight{"height", "--height", ParamType::kNumber,
                                "cylinder height, cone height (apex to base plane)"};
constexpr GeometryParam kCorners{
    "corners", "--corners", ParamType::kCorners,
    "quad corners p00;p10;p11;p01 (u runs p00 -> p10, v runs p00 -> p01; convex, planar)"};

constexpr GeometryParam kParams[] = {kCenter, kPole,  kEquator, kAxis,   kApex,   kBase,   kNormal,
                                     kOrigin, kUAxis, kVAxis,   kRadius, kHeight, kCorners};

constexpr ParamField field(const GeometryParam& p, ParamRole role, bool required) {
  return {p.key, p.flag, p.type, role, required, p.help};
}

using R = ParamRole;

// ---- One table per kind, SPEC section 2's order. ---------------------------

constexpr ParamField kSphereFields[] = {
    field(kCenter, R::kAnchor, true),
    field(kRadius, R::kExtent, true),
    field(kPole, R::kDirection, false),
    field(kEquator, R::kEquator, false),
};
constexpr ParamField kCylinderFields[] = {
    field(kBase, R::kAnchor, true),      field(kAxis, R::kAxis, false),
    field(kEquator, R::kEquator, false), field(kRadius, R::kExtent, true),
    field(kHeight, R::kExtent, true),
};
constexpr ParamField kConeFields[] = {
    field(kApex, R::kAnchor, true),      field(kAxis, R::kAxis, false),
    field(kEquator, R::kEquator, false), field(kHeight, R::kConeHeight, true),
    field(kRadius, R::kExtent, true),
};
constexpr ParamField kDiskFields[] = {
    field(kCenter, R::kAnchor, true),
    field(kNormal, R::kDirection, false),
    field(kEquator, R::kEquator, false),
    field(kRadius, R::kExtent, true),
};
constexpr ParamField kQuadFields[] = {field(kCorners, R::kExtent, true)};
constexpr ParamField kPlaneFields[] = {
    field(kOrigin, R::kAnchor, true),
    field(kUAxis, R::kExtent, true),
    field(kVAxis, R::kExtent, true),
};

// ---- Each table bound to its Params struct, member by member. -------------

auto members(SphereParams& p) {
  return std::tie(p.center, p.radius, p.pole, p.equator);
}
auto members(CylinderParams& p) {
  return std::tie(p.base, p.axis, p.equator, p.radius, p.height);
}
auto members(ConeParams& p) {
  return std::tie(p.apex, p.axis, p.equator, p.height, p.radius);
}
auto members(DiskParams& p) {
  return std::tie(p.center, p.normal, p.equator, p.radius);
}
auto members(QuadParams& p) {
  return std::tie(p.corners);
}
auto members(PlaneParams& p) {
  return std::tie(p.origin, p.u_axis, p.v_axis);
}

// The variants list the kinds in ProxyKind's order, so the table of the
// variant's alternative I is kTables[I].
constexpr std::span<const ParamField> kTables[] = {kSphereFields, kCylinderFields, kConeFields,
                                                   kDiskFields,   kQuadFields,     kPlaneFields};

template <class P, std::size_t I = 0>
constexpr std::size_t alternative_index() {
  if constexpr (std::is_same_v<std::variant_alternative_t<I, ProxyParams>, P>) {
    return I;
  } else {
    return alternative_index<P, I + 1>();
  }
}
template <class P>
constexpr std::span<const ParamField> table_of() {
  return kTables[alternative_index<P>()];
}

// The ParamType of a Params member's type (and whether it is optional).
template <class M>
struct MemberType;
template <>
struct MemberType<Vec3> {
  static constexpr ParamType type = ParamType::kVec3;
  static constexpr bool optional = false;
};
template <>
struct MemberType<std::optional<Vec3>> {
  static constexpr ParamType type = ParamType::kVec3;
  static constexpr bool optional = true;
};
template <>
struct MemberType<double> {
  static constexpr ParamType type = ParamType::kNumber;
  static constexpr bool optional = false;
};
template <>
struct MemberType<std::array<Vec3, 4>> {
  static constexpr ParamType type = ParamType::kCorners;
  static constexpr bool optional = false;
};

template <class P>
using Members = decltype(members(std::declval<P&>()));

template <class P, std::size_t I>
using MemberTypeOf = MemberType<std::remove_cvref_t<std::tuple_element_t<I, Members<P>>>>;

// Table and struct agree: as many fields as members, each of the member's
// type, exactly the equator optional, and directions (which default to `up`)
// plain vectors.
template <class P, std::size_t... I>
constexpr bool table_matches(std::index_sequence<I...>) {
  constexpr std::span<const ParamField> t = table_of<P>();
  return t.size() == sizeof...(I) &&
         ((t[I].type == MemberTypeOf<P, I>::type &&
           (t[I].role == ParamRole::kEquator) == MemberTypeOf<P, I>::optional &&
           (!is_direction(t[I].role) ||
            (t[I].type == ParamType::kVec3 && !MemberTypeOf<P, I>::optional))) &&
          ...);
}
template <class P>
constexpr bool table_matches() {
  return table_matches<P>(std::make_index_sequence<std::tuple_size_v<Members<P>>>{});
}
static_assert(table_matches<SphereParams>());
static_assert(table_matches<CylinderParams>());
static_assert(table_matches<ConeParams>());
static_assert(table_matches<DiskParams>());
static_assert(table_matches<QuadParams>());
static_assert(table_matches<PlaneParams>());

// Calls f(field, member) for every field of p's kind, in table order.
template <class P, class F>
void for_each_member(P& p, F&& f) {
  auto m = members(p);
  constexpr std::span<const ParamField> t = table_of<P>();
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(t[I], std::get<I>(m)), ...);
  }
  (std::make_index_sequence<std::tuple_size_v<Members<P>>>{});
}

// Default-constructed params of `kind`.
ProxyParams default_params(ProxyKind kind) {
  ProxyParams params;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    ((static_cast<std::size_t>(kind) == I ? (void)params.emplace<I>() : (void)0), ...);
  }
  (std::make_index_sequence<std::variant_size_v<ProxyParams>>{});
  return params;
}

// The value of a member as a ParamValue; nullopt for an absent equator.
std::optional<ParamValue> value_of(const Vec3& v) {
  return ParamValue{v};
}
std::optional<ParamValue> value_of(const std::optional<Vec3>& v) {
  if (!v) return std::nullopt;
  return ParamValue{*v};
}
std::optional<ParamValue> value_of(double x) {
  return ParamValue{x};
}
std::optional<ParamValue> value_of(const std::array<Vec3, 4>& c) {
  return ParamValue{c};
}

// Writes a value (of the member's type: checked by check_spec_keys) into it.
void assign(Vec3& member, const ParamValue& v) {
  member = std::get<Vec3>(v);
}
void assign(std::optional<Vec3>& member, const ParamValue& v) {
  member = std::get<Vec3>(v);
}
void assign(double& member, const ParamValue& v) {
  member = std::get<double>(v);
}
void assign(std::array<Vec3, 4>& member, const ParamValue& v) {
  member = std::get<std::array<Vec3, 4>>(v);
}

Error invalid(ProxyKind kind, const std::string& what) {
  return make_error(ErrorCode::kInvalidArgument, std::string(to_string(kind)) + ": " + what);
}

// "center, radius": the names of the fields that pass `keep`.
template <class Keep>
std::string field_list(ProxyKind kind, ParamNaming naming, Keep keep) {
  std::string list;
  for (const ParamField& f : proxy_fields(kind)) {
    if (keep(f)) list += (list.empty() ? "" : ", ") + std::string(field_name(f, naming));
  }
  return list;
}

const char* type_text(ParamType type) {
  switch (type) {
    case ParamType::kVec3:
      return "a vector x,y,z";
    case ParamType::kNumber:
      return "a number";
    case ParamType::kCorners:
      return "four corners x,y,z";
  }
  return "?";
}

// As mapping/proxy.cpp prints a rejected number (17 significant digits).
std::string number_text(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

// What make_proxy would reject in this value on its own (see
// check_given_values).
std::optional<Error> value_error(ProxyKind kind, const ParamField& f, const ParamValue& value,
                                 ParamNaming naming) {
  const std::string name(field_name(f, naming));
  if (const double* x = std::get_if<double>(&value)) {
    if (!std::isfinite(*x) || *x <= 0) {
      return invalid(kind, name + " must be a finite number > 0 (got " + number_text(*x) + ")");
    }
  } else if (const Vec3* v = std::get_if<Vec3>(&value)) {
    if (f.role == ParamRole::kAnchor) {
      if (!is_finite(*v)) return invalid(kind, name + " is not finite");
    } else if (Expected<Vec3> unit = unit_vector(*v, name); !unit) {
      return invalid(kind, unit.error().message);
    }
  } else {
    for (const Vec3& c : std::get<std::array<Vec3, 4>>(value)) {
      if (!is_finite(c)) return invalid(kind, name + " contain a non-finite coordinate");
    }
  }
  return std::nullopt;
}

std::optional<Error> up_error(const ProxySpec& spec, ParamNaming naming) {
  if (!spec.up) return std::nullopt;
  Expected<Vec3> unit = unit_vector(*spec.up, naming == ParamNaming::kKey ? "up" : "--up");
  if (!unit) return invalid(spec.kind, unit.error().message);
  return std::nullopt;
}

}  // namespace

std::span<const ParamField> proxy_fields(ProxyKind kind) {
  return kTables[static_cast<std::size_t>(kind)];
}

std::span<const GeometryParam> geometry_params() {
  return kParams;
}

const ParamField* find_field(ProxyKind kind, std::string_view key) {
  for (const ParamField& f : proxy_fields(kind)) {
    if (f.key == key) return &f;
  }
  return nullptr;
}

std::string_view field_name(const ParamField& field, ParamNaming naming) {
  return naming == ParamNaming::kKey ? field.key : field.flag;
}

bool holds_type(const ParamValue& value, ParamType type) {
  switch (type) {
    case ParamType::kVec3:
      return std::holds_alternative<Vec3>(value);
    case ParamType::kNumber:
      return std::holds_alternative<double>(value);
    case ParamType::kCorners:
      return std::holds_alternative<std::array<Vec3, 4>>(value);
  }
  return false;
}

std::vector<std::string> missing_fields(const ProxySpec& spec) {
  std::vector<std::string> missing;
  for (const ParamField& f : proxy_fields(spec.kind)) {
    if (f.required && !spec.values.contains(f.key)) missing.emplace_back(f.key);
  }
  return missing;
}

Status check_spec_keys(const ProxySpec& spec, ParamNaming naming) {
  for (const auto& [key, value] : spec.values) {
    const ParamField* f = find_field(spec.kind, key);
    if (!f) {
      // Another kind's parameter is shown as its flag when flags are named.
      std::string shown = "'" + key + "'";
      for (const GeometryParam& p : kParams) {
        if (p.key == key && naming == ParamNaming::kFlag) shown = p.flag;
      }
      return invalid(spec.kind, "unknown parameter " + shown + " (expected " +
                                    field_list(spec.kind, naming, [](auto&) { return true; }) +
                                    ")");
    }
    if (!holds_type(value, f->type)) {
      return invalid(spec.kind,
                     std::string(field_name(*f, naming)) + " must be " + type_text(f->type));
    }
  }
  return ok_status();
}

Status check_given_values(const ProxySpec& spec, ParamNaming naming) {
  if (Status s = check_spec_keys(spec, naming); !s) return s;
  for (const ParamField& f : proxy_fields(spec.kind)) {
    const auto it = spec.values.find(f.key);
    if (it == spec.values.end()) continue;
    if (auto e = value_error(spec.kind, f, it->second, naming)) return *e;
  }
  if (auto e = up_error(spec, naming)) return *e;
  return ok_status();
}

Expected<ProxyParams> params_from_spec(const ProxySpec& spec, ParamNaming naming) {
  if (Status s = check_spec_keys(spec, naming); !s) return s.error();
  const std::vector<std::string> missing = missing_fields(spec);
  if (!missing.empty()) {
    const ParamField& first = *find_field(spec.kind, missing.front());
    return invalid(
        spec.kind,
        "missing " + std::string(field_name(first, naming)) + " (needs " +
            field_list(spec.kind, naming, [](const ParamField& f) { return f.required; }) + ")");
  }
  const Vec3 up = spec.up.value_or(Vec3{0, 0, 1});
  std::optional<Error> error;
  ProxyParams params = default_params(spec.kind);
  std::visit(
      [&](auto& p) {
        for_each_member(p, [&](const ParamField& f, auto& member) {
          const auto it = spec.values.find(f.key);
          if (it != spec.values.end()) {
            assign(member, it->second);
          } else if (is_direction(f.role)) {
            if (!error) error = up_error(spec, naming);
            assign(member, ParamValue{up});
          }
        });
      },
      params);
  if (error) return *error;
  return params;
}

ProxySpec spec_from_params(const ProxyParams& params) {
  ProxySpec spec;
  spec.kind = kind_of(params);
  ProxyParams copy = params;  // members() binds mutable references
  std::visit(
      [&](auto& p) {
        for_each_member(p, [&](const ParamField& f, const auto& member) {
          if (std::optional<ParamValue> v = value_of(member)) spec.values.emplace(f.key, *v);
        });
      },
      copy);
  return spec;
}

Expected<ProxyParams> merge_spec(const ProxySpec& spec, ProxyParams params, ParamNaming naming) {
  if (kind_of(params) != spec.kind) {
    return invalid(spec.kind,
                   std::string("cannot merge into a ") + to_string(kind_of(params)) + "'s values");
  }
  if (Status s = check_spec_keys(spec, naming); !s) return s.error();
  std::visit(
      [&](auto& p) {
        for_each_member(p, [&](const ParamField& f, auto& member) {
          const auto it = spec.values.find(f.key);
          if (it != spec.values.end()) assign(member, it->second);
        });
      },
      params);
  return params;
}

}  // namespace texbake
