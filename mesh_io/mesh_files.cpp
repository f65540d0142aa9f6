#include "mesh_io/mesh_files.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <system_error>

#include "mesh_io/file_name.h"
#include "mesh_io/json_strict.h"
#include "mesh_io/regular_file.h"
#include "mesh_io/text_scan.h"

namespace texbake {

namespace {

namespace fs = std::filesystem;

// Calls fn(rest) for each line of the file whose first token is `keyword`,
// with the rest of the line trimmed (OBJ and MTL names may hold spaces, and
// OpenMesh takes the whole rest). Reads in blocks, so that an OBJ of
// gigabytes is scanned without holding it.
template <class Fn>
void for_each_keyword_line(const fs::path& path, std::string_view keyword, Fn&& fn) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return;
  constexpr std::size_t kBlock = std::size_t{1} << 20;
  std::string buffer(kBlock, '\0');
  std::string carry;  // the start of a line cut by the block's end
  auto line_of = [&](std::string_view line) {
    const std::string_view t = read_detail::trim(line);
    if (t.size() > keyword.size() && t.substr(0, keyword.size()) == keyword &&
        (t[keyword.size()] == ' ' || t[keyword.size()] == '\t')) {
      fn(read_detail::trim(t.substr(keyword.size())));
    }
  };
  while (true) {
    const std::size_t n = std::fread(buffer.data(), 1, kBlock, f.get());
    if (n == 0) break;
    std::string_view block(buffer.data(), n);
    while (!block.empty()) {
      const char* nl = static_cast<const char*>(std::memchr(block.data(), '\n', block.size()));
      if (!nl) {
        // A line longer than any name texbake reads is not one of these.
        if (carry.size() < 65536) carry.append(block);
        break;
      }
      const std::size_t len = static_cast<std::size_t>(nl - block.data());
      if (carry.empty()) {
        line_of(block.substr(0, len));
      } else {
        carry.append(block.substr(0, len));
        line_of(carry);
        carry.clear();
      }
      block.remove_prefix(len + 1);
    }
  }
  if (!carry.empty()) line_of(carry);
}

bool file_exists(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

// read_obj.cpp's rules: OpenMesh opens a library as FOLDER/NAME; the
// texture is NAME if absolute, else relative to the OBJ's folder.
std::vector<fs::path> obj_files(const fs::path& obj) {
  std::vector<fs::path> files;
  // A device or a FIFO would be read forever (read_mesh refuses it).
  if (!check_regular_file(obj, "a mesh file")) return files;
  const std::string dir = obj.has_parent_path() ? obj.parent_path().string() : ".";
  std::vector<fs::path> libraries;
  for_each_keyword_line(obj, "mtllib", [&](std::string_view name) {
    const fs::path lib = dir + "/" + std::string(name);
    if (file_exists(lib)) libraries.push_back(lib);
  });
  for (const fs::path& lib : libraries) {
    files.push_back(lib);
    if (!check_text_file(lib, "a material library")) continue;  // not read: names nothing
    for_each_keyword_line(lib, "map_Kd", [&](std::string_view name) {
      const fs::path p(name);
      const fs::path texture = p.is_absolute() ? p : obj.parent_path() / p;
      if (file_exists(texture)) files.push_back(texture.lexically_normal());
    });
  }
  return files;
}

// A glTF document's buffers[].uri and images[].uri that are not data:
// URIs, as given and percent-decoded, beside the file (read_gltf.cpp
// refuses any other, so those name no file it opens).
std::vector<fs::path> uri_files(std::string_view json, const fs::path& file) {
  std::vector<fs::path> files;
  Expected<nlohmann::json> doc = parse_json_object<nlohmann::json>(json, file.string());
  if (!doc) return files;
  for (const char* key : {"buffers", "images"}) {
    const auto list = doc->find(key);
    if (list == doc->end() || !list->is_array()) continue;
    for (const nlohmann::json& item : *list) {
      if (!item.is_object()) continue;
      const auto uri = item.find("uri");
      if (uri == item.end() || !uri->is_string()) continue;
      const std::string& u = uri->get_ref<const std::string&>();
      if (u.rfind("data:", 0) == 0) continue;
      std::vector<std::string> names{u};
      if (std::string decoded = read_detail::percent_decode(u); decoded != u)
        names.push_back(decoded);
      for (const std::string& name : names) {
        const fs::path p = file.parent_path() / fs::u8path(name);
        if (file_exists(p)) files.push_back(p.lexically_normal());
      }
    }
  }
  return files;
}

std::vector<fs::path> gltf_files(const fs::path& gltf) {
  if (!check_text_file(gltf, "a glTF file")) return {};
  std::ifstream in(gltf, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  return uri_files(text, gltf);
}

// A .glb's JSON chunk (the binary glTF container: a 12-byte header "glTF",
// version, length; then the first chunk's length, type "JSON" and bytes);
// a file that is not one, or a chunk longer than the file, names nothing
// (read_mesh reports it).
std::vector<fs::path> glb_files(const fs::path& glb) {
  if (!check_regular_file(glb, "a mesh file")) return {};
  std::ifstream in(glb, std::ios::binary);
  unsigned char header[20];
  if (!in.read(reinterpret_cast<char*>(header), sizeof header)) return {};
  auto u32 = [&](int at) {
    return std::uint32_t{header[at]} | std::uint32_t{header[at + 1]} << 8 |
           std::uint32_t{header[at + 2]} << 16 | std::uint32_t{header[at + 3]} << 24;
  };
  if (std::memcmp(header, "glTF", 4) != 0 || std::memcmp(header + 16, "JSON", 4) != 0) return {};
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(glb, ec);
  const std::uint32_t chunk = u32(12);
  if (ec || chunk > size - sizeof header) return {};
  std::string json(chunk, '\0');
  if (!in.read(json.data(), chunk)) return {};
  return uri_files(json, glb);
}

}  // namespace

std::vector<fs::path> mesh_named_files(const fs::path& mesh) {
  const std::string ext = lower_extension(mesh);
  if (ext == ".obj") return obj_files(mesh);
  if (ext == ".gltf") return gltf_files(mesh);
  if (ext == ".glb") return glb_files(mesh);
  return {};
}

}  // namespace texbake
