#include "mesh_io/regular_file.h"

#include <fstream>
#include <string>

namespace texbake {
namespace fs = std::filesystem;

namespace {

Error io_error(const fs::path& path, const std::string& what) {
  return make_error(ErrorCode::kIo, path.string() + ": " + what);
}

const char* kind_of(fs::file_type type) {
  switch (type) {
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "of an unknown type";
  }
}

}  // namespace

Status check_regular_file(const fs::path& path, std::string_view what) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows links
  if (st.type() == fs::file_type::not_found) return io_error(path, "no such file");
  if (ec) return io_error(path, "cannot access (" + ec.message() + ")");
  if (fs::is_regular_file(st)) return ok_status();
  if (fs::is_directory(st)) return io_error(path, "is a folder, not " + std::string(what));
  return io_error(path, std::string("is not a regular file (") + kind_of(st.type()) +
                            "), cannot be read as " + std::string(what));
}

Status check_text_file(const fs::path& path, std::string_view what) {
  if (Status s = check_regular_file(path, what); !s) return s;
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) return io_error(path, "cannot access (" + ec.message() + ")");
  if (size > kMaxTextFileBytes) {
    return make_error(ErrorCode::kParse, path.string() + ": is " + std::to_string(size) +
                                             " bytes, more than the " +
                                             std::to_string(kMaxTextFileBytes >> 20) +
                                             " MiB texbake reads as " + std::string(what));
  }
  return ok_status();
}

Expected<std::string> read_text_file(const fs::path& path, std::string_view what) {
  if (Status s = check_text_file(path, what); !s) return s.error();
  std::ifstream f(path, std::ios::binary);
  if (!f) return make_error(ErrorCode::kIo, path.string() + ": cannot open");
  // Read to the end, checking each read (operator<< of a stream buffer
  // would stop at a read error silently and hand on part of the file).
  std::string text;
  char buf[1 << 16];
  while (f.read(buf, sizeof buf) || f.gcount() > 0) {
    text.append(buf, static_cast<std::size_t>(f.gcount()));
    if (text.size() > kMaxTextFileBytes) {  // it grew since the check
      return make_error(ErrorCode::kParse, path.string() + ": is more than the " +
                                               std::to_string(kMaxTextFileBytes >> 20) +
                                               " MiB texbake reads as " + std::string(what));
    }
  }
  if (f.bad()) return make_error(ErrorCode::kIo, path.string() + ": read error");
  return text;
}

}  // namespace texbake
