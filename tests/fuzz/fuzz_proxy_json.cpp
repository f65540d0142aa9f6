// libFuzzer target for the proxy JSON reader (mesh_io/proxy_json.h). Besides
// the sanitizers it checks a round trip: a proxy that parses is written with
// proxy_to_json, which must parse again to the same proxy. "Same" allows a
// relative 1e-12 per number: reading normalises the directions again (and
// re-orthogonalises the equator), which may move an already unit vector by
// an ulp (the fuzzer found pole [2,0,1]: equator x 0.4472135954999579 ->
// 0.447213595499958); everything else (keys, kinds) must match exactly.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string_view>

#include "mesh_io/proxy_json.h"

namespace {

bool same(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    return std::abs(x - y) <= 1e-12 * std::max({1.0, std::abs(x), std::abs(y)});
  }
  if (a.type() != b.type() || a.size() != b.size()) return false;
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (!b.contains(it.key()) || !same(it.value(), b.at(it.key()))) return false;
    }
    return true;
  }
  if (a.is_array()) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!same(a[i], b[i])) return false;
    }
    return true;
  }
  return a == b;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)texbake::proxy_params_from_json(text, "fuzz.json");
  texbake::Expected<texbake::Proxy> proxy = texbake::proxy_from_json(text, "fuzz.json");
  if (!proxy) {
    if (proxy.error().message.rfind("fuzz.json", 0) != 0) {
      std::fprintf(stderr, "error does not name the source: %s\n", proxy.error().message.c_str());
      std::abort();
    }
    return 0;
  }
  const std::string once = texbake::proxy_to_json(*proxy);
  texbake::Expected<texbake::Proxy> again = texbake::proxy_from_json(once, "round trip");
  if (!again) {
    std::fprintf(stderr, "written proxy does not read back: %s\n%s\n",
                 again.error().message.c_str(), once.c_str());
    std::abort();
  }
  const std::string twice = texbake::proxy_to_json(*again);
  if (!same(nlohmann::json::parse(once), nlohmann::json::parse(twice))) {
    std::fprintf(stderr, "round trip changed the proxy:\n%s\n%s\n", once.c_str(), twice.c_str());
    std::abort();
  }
  return 0;
}
