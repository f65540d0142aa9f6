// Proxies as JSON (SPEC section 2), e.g.
//   {"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,1],"equator":[1,0,0]}
// Keys per kind (all required except "equator", which defaults as in
// mapping/proxy.h):
//   sphere   center, radius, pole, equator
//   cylinder base, axis, equator, radius, height
//   cone     apex, axis, equator, height, radius
//   disk     center, normal, equator, radius
//   quad     corners: [[x,y,z] x 4] as p00, p10, p11, p01
//   plane    origin, u_axis, v_axis
// Vectors are arrays of 3 numbers, scalars numbers.
//
// Errors are kParse (exit 1: a file's content is wrong) or kIo (the file
// cannot be read or written); messages start with the file name (or the
// `source` name given for a string) and name the key: unknown key, missing
// key, wrong type, non-finite number, unknown kind, and make_proxy's geometry
// errors (zero vectors, non-convex quad, ...). Duplicate keys are an error too
// (JSON leaves them undefined; nlohmann would silently keep the last).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "mapping/error.h"
#include "mapping/projector.h"
#include "mapping/proxy.h"

namespace texbake {

// Parses and validates (make_proxy) a proxy from JSON text.
Expected<Proxy> proxy_from_json(std::string_view text, const std::string& source = "proxy JSON");

// Parses without geometric validation: the user's parameters as written.
Expected<ProxyParams> proxy_params_from_json(std::string_view text,
                                             const std::string& source = "proxy JSON");

// Reads and validates a proxy file. A camera file ("kind":"camera") is an
// error here (kParse): the commands that take cameras read proxy files with
// read_projector_file.
Expected<Proxy> read_proxy_file(const std::filesystem::path& path);

// A proxy file that holds an analytic proxy or a camera (SPEC section 9,
// mesh_io/camera_json.h): "kind":"camera" is read by camera_from_json, any
// other kind by proxy_from_json, with their errors.
Expected<Projector> projector_from_json(std::string_view text,
                                        const std::string& source = "proxy JSON");
Expected<Projector> read_projector_file(const std::filesystem::path& path);

// The proxy's parameters (params_of: equator filled in) as a JSON object;
// numbers are printed so that they read back exactly. indent < 0: one line;
// otherwise pretty-printed with that many spaces.
std::string proxy_to_json(const Proxy& proxy, int indent = -1);
std::string proxy_params_to_json(const ProxyParams& params, int indent = -1);

// Writes proxy_to_json(proxy, 2) and a newline through write_atomically.
Status write_proxy_file(const std::filesystem::path& path, const Proxy& proxy);

}  // namespace texbake
