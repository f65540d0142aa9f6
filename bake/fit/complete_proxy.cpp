// Completing a proxy spec by fitting (see complete_proxy.h).
#include "bake/fit/complete_proxy.h"

#include <utility>

namespace texbake {

FitOptions fit_options(const ProxySpec& spec) {
  FitOptions options;
  options.up = spec.up.value_or(Vec3{0, 0, 1});
  for (const ParamField& f : proxy_fields(spec.kind)) {
    const auto it = spec.values.find(f.key);
    const ParamValue* given = it == spec.values.end() ? nullptr : &it->second;
    const Vec3* vector = given ? std::get_if<Vec3>(given) : nullptr;
    switch (f.role) {
      case ParamRole::kAnchor:
        if (vector) options.anchor = *vector;
        break;
      case ParamRole::kConeHeight:
        if (given && std::holds_alternative<double>(*given))
          options.height = std::get<double>(*given);
        break;
      case ParamRole::kDirection:
      case ParamRole::kAxis:
        if (vector) {
          options.axis = *vector;
          options.keep_axis_sign = true;
        } else if (f.role == ParamRole::kAxis && spec.up) {
          // --up is the shorthand for the default axis (SPEC section 5).
          options.axis = *spec.up;
          options.keep_axis_sign = false;
        }
        break;
      case ParamRole::kEquator:
      case ParamRole::kExtent:
        break;  // replace the fitted values afterwards
    }
  }
  return options;
}

Expected<SpecCompletion> complete_spec(const ProxySpec& spec, const MeshData& mesh,
                                       ParamNaming naming) {
  if (missing_fields(spec).empty()) {
    Expected<ProxyParams> params = params_from_spec(spec, naming);
    if (!params) return params.error();
    Expected<Proxy> proxy = make_proxy(*params, naming);
    if (!proxy) return proxy.error();
    return SpecCompletion{std::move(*proxy), {}, 0};
  }
  if (Status s = check_given_values(spec, naming); !s) return s.error();

  const std::vector<Float3> points = fit_points(mesh);
  Expected<ProxyParams> fitted = fit_proxy(spec.kind, points, fit_options(spec));
  // The mesh's shape, not the given values, is at fault.
  if (!fitted) return make_error(ErrorCode::kParse, fitted.error().message);
  Expected<ProxyParams> merged = merge_spec(spec, std::move(*fitted), naming);
  if (!merged) return merged.error();
  Expected<Proxy> proxy = make_proxy(*merged, naming);
  if (!proxy) {
    return make_error(proxy.error().code, "the fitted " + std::string(to_string(spec.kind)) +
                                              " with the given " +
                                              (naming == ParamNaming::kFlag ? "flags" : "values") +
                                              " is invalid: " + proxy.error().message);
  }
  // Every field of the kind not given came from the fit (directions too).
  SpecCompletion done{std::move(*proxy), {}, points.size()};
  for (const ParamField& f : proxy_fields(spec.kind)) {
    if (!spec.values.contains(f.key)) done.fitted.emplace_back(f.key);
  }
  return done;
}

}  // namespace texbake
