#include "mesh_io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <random>
#include <system_error>

namespace texbake {
namespace fs = std::filesystem;

namespace {

fs::path folder_of(const fs::path& target) {
  fs::path dir = target.parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

// ".texbake-<pid>-<counter>-<random>.<name>" beside the target: unique across
// processes and threads, hidden, and keeps the target's extension last.
fs::path temp_path_for(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  std::string name = ".texbake-" + std::to_string(::getpid()) + "-" +
                     std::to_string(counter.fetch_add(1)) + "-" + std::to_string(rd() % 1000000) +
                     "-" + target.filename().string();
  return folder_of(target) / name;
}

}  // namespace

Status check_writable(const fs::path& target) {
  const fs::path dir = folder_of(target);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    return make_error(ErrorCode::kIo, "cannot write " + target.string() + ": folder " +
                                          dir.string() + " does not exist");
  }
  if (fs::is_directory(target, ec)) {
    return make_error(ErrorCode::kIo, "cannot write " + target.string() + ": it is a folder");
  }
  if (::access(dir.c_str(), W_OK) != 0) {
    return make_error(ErrorCode::kIo, "cannot write " + target.string() + ": folder " +
                                          dir.string() + " is not writable (" +
                                          std::strerror(errno) + ")");
  }
  return ok_status();
}

Status write_atomically(const fs::path& target,
                        const std::function<Status(const fs::path& temp)>& write) {
  if (Status s = check_writable(target); !s) return s;
  const fs::path temp = temp_path_for(target);
  auto cleanup = [&] {
    std::error_code ignored;
    fs::remove(temp, ignored);
  };
  Status result = ok_status();
  try {
    result = write(temp);
  } catch (const std::exception& e) {
    cleanup();
    return make_error(ErrorCode::kIo, "cannot write " + target.string() + ": " + e.what());
  }
  if (!result) {
    cleanup();
    return result;
  }
  // Flush the data to disk before the rename makes it visible under the
  // target's name, so a power cut cannot leave an empty file there.
  if (int fd = ::open(temp.c_str(), O_RDONLY); fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    cleanup();
    return make_error(ErrorCode::kIo, "cannot write " + target.string() + ": " + ec.message());
  }
  return ok_status();
}

}  // namespace texbake
