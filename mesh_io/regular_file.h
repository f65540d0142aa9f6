// Input files must be regular files (issue #12 item 6): a FIFO given as a
// mesh, texture, proxy or material file makes open() block forever, and a
// device (a link to /dev/zero) is read until memory runs out. Every reader
// calls one of these before it opens its file (read_mesh for every format
// and the OBJ's mtllib, read_image; read_proxy_file is meant to). The check
// follows symbolic links and opens nothing, so it cannot block; a file
// swapped for a FIFO between the check and the open is not caught.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "mapping/error.h"

namespace texbake {

// The largest text input texbake reads whole that has no size check of its
// own: a proxy JSON file or an OBJ's material library (MTL), 16 MiB. (The
// mesh text formats check their declared counts against the file's size.)
inline constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{16} << 20;

// OK if `path` (after following links) is a regular file. Else kIo, with
// `what` the file's role and its article ("a mesh file", "an image"):
//   "PATH: no such file"                    (also a dangling link)
//   "PATH: is a folder, not WHAT"
//   "PATH: is not a regular file (a FIFO), cannot be read as WHAT"
//                                           (a character device, a block
//                                           device, a socket, ...)
//   "PATH: cannot access (REASON)"          (stat failed otherwise)
Status check_regular_file(const std::filesystem::path& path, std::string_view what);

// check_regular_file, then the size: a file larger than kMaxTextFileBytes is
// kParse "PATH: is N bytes, more than the 16 MiB texbake reads as WHAT".
Status check_text_file(const std::filesystem::path& path, std::string_view what);

// check_text_file, then the whole file. Errors: check_text_file's, kIo
// "PATH: cannot open" and "PATH: read error".
Expected<std::string> read_text_file(const std::filesystem::path& path, std::string_view what);

}  // namespace texbake
