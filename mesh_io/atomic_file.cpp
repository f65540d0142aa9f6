// Atomic output files and sets of files (see atomic_file.h). POSIX calls
// where the standard library has no equivalent: stat (file kinds, modes,
// inodes), access, fsync, kill(pid, 0) and async-signal-safe unlink/rename.
#include "mesh_io/atomic_file.h"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <system_error>

namespace texbake {
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kPrefix = ".texbake-";
constexpr std::string_view kJournalExtension = ".commit";
// Extensions longer than this are replaced by ".tmp" in temporary names, so
// a temporary's name stays short whatever the target's.
constexpr std::size_t kMaxKeptExtension = 16;

// ---- Temporaries in progress, for the signal handler. ---------------------
// A fixed table (no allocation in the handler): a slot's path is written
// before it is marked used, and the handler only reads used slots.
constexpr int kSlots = 64;
struct PendingSlot {
  std::atomic<int> used{0};
  char path[PATH_MAX];
};
PendingSlot g_pending[kSlots];
std::atomic<int> g_committing{0};       // commits in progress: signals wait
std::atomic<int> g_deferred_signal{0};  // a signal that arrived meanwhile

int register_pending(const fs::path& path) {
  const std::string& s = path.native();
  if (s.size() >= PATH_MAX) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_pending[i].used.compare_exchange_strong(expected, 2)) {  // 2: being filled
      std::memcpy(g_pending[i].path, s.c_str(), s.size() + 1);
      g_pending[i].used.store(1, std::memory_order_release);
      return i;
    }
  }
  return -1;  // table full: this temporary is not removed on a signal
}

void unregister_pending(int slot) {
  if (slot >= 0) g_pending[slot].used.store(0, std::memory_order_release);
}

void remove_pending_from_handler() {
  for (PendingSlot& slot : g_pending) {
    if (slot.used.load(std::memory_order_acquire) == 1) ::unlink(slot.path);
  }
}

void cleanup_signal_handler(int sig) {
  if (g_committing.load() > 0) {
    // Renames in progress: let them finish; the committing thread re-raises.
    g_deferred_signal.store(sig);
    return;
  }
  remove_pending_from_handler();
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void raise_deferred_signal() {
  const int sig = g_deferred_signal.exchange(0);
  if (sig != 0 && g_committing.load() == 0) {
    remove_pending_from_handler();
    ::signal(sig, SIG_DFL);
    ::raise(sig);
  }
}

// ---- Names. ------------------------------------------------------------------

std::string host_tag() {
  static const std::string tag = [] {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) name[0] = '\0';
    uint32_t h = 2166136261u;  // FNV-1a
    for (const char* c = name; *c; ++c) h = (h ^ static_cast<unsigned char>(*c)) * 16777619u;
    char hex[9];
    std::snprintf(hex, sizeof hex, "%08x", h);
    return std::string(hex);
  }();
  return tag;
}

fs::path folder_of(const fs::path& target) {
  fs::path dir = target.parent_path();
  return dir.empty() ? fs::path(".") : dir;
}

// ".texbake-<host>-<pid>-<counter>-<random><ext>".
fs::path temp_path_for(const fs::path& target, std::string_view extension) {
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  std::string ext = target.extension().string();
  if (ext.size() > kMaxKeptExtension) ext = ".tmp";
  if (!extension.empty()) ext = extension;
  const std::string name = std::string(kPrefix) + host_tag() + "-" + std::to_string(::getpid()) +
                           "-" + std::to_string(counter.fetch_add(1)) + "-" +
                           std::to_string(rd() % 1000000) + ext;
  return folder_of(target) / name;
}

// The pid of a temporary of this host ("" host mismatch or not ours: 0).
pid_t stale_candidate_pid(const std::string& name) {
  if (name.rfind(kPrefix, 0) != 0) return 0;
  const std::string rest = name.substr(kPrefix.size());
  const std::string host = host_tag();
  if (rest.size() < host.size() + 2 || rest.compare(0, host.size(), host) != 0 ||
      rest[host.size()] != '-') {
    return 0;
  }
  const char* p = rest.c_str() + host.size() + 1;
  char* end = nullptr;
  const long pid = std::strtol(p, &end, 10);
  if (end == p || *end != '-' || pid <= 0) return 0;
  return static_cast<pid_t>(pid);
}

bool process_is_gone(pid_t pid) {
  return pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

// Completes an interrupted commit: every temporary the journal names that
// still exists is renamed over its target.
void roll_forward(const fs::path& journal) {
  std::ifstream in(journal);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t tab = line.find('\t');
    if (tab == std::string::npos) continue;
    const std::string temp = line.substr(0, tab), target = line.substr(tab + 1);
    if (temp.empty()) {
      ::unlink(target.c_str());  // a staged removal
    } else if (::access(temp.c_str(), F_OK) == 0) {
      ::rename(temp.c_str(), target.c_str());
    }
  }
  in.close();
  ::unlink(journal.c_str());
}

// Once per folder and process: finish the commits of texbake processes of
// this host that were killed, then remove their temporaries.
void clean_stale_temporaries(const fs::path& folder) {
  static std::mutex mutex;
  static std::set<std::string> cleaned;
  std::error_code ec;
  const fs::path key = fs::absolute(folder, ec);
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (!cleaned.insert(key.string()).second) return;
  }
  std::vector<fs::path> journals, temps;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const pid_t pid = stale_candidate_pid(name);
    if (pid == 0 || !process_is_gone(pid)) continue;
    const bool journal = name.size() > kJournalExtension.size() &&
                         name.compare(name.size() - kJournalExtension.size(),
                                      kJournalExtension.size(), kJournalExtension) == 0;
    (journal ? journals : temps).push_back(it->path());
  }
  for (const fs::path& j : journals) roll_forward(j);
  for (const fs::path& t : temps) fs::remove(t, ec);
}

// ---- Targets. ---------------------------------------------------------------

// Follows symbolic links (at most 40, like the kernel) to the path that
// will really be written.
fs::path resolve_links(const fs::path& target) {
  fs::path p = target;
  std::error_code ec;
  for (int i = 0; i < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++i) {
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) break;
    p = link.is_absolute() ? link : folder_of(p) / link;
  }
  return p;
}

enum class TargetKind { kNew, kRegular, kDirect };

struct ResolvedTarget {
  fs::path path;  // after links
  TargetKind kind = TargetKind::kNew;
  mode_t mode = 0;  // kRegular: the permission bits to keep
};

Error cannot_write(const fs::path& target, const std::string& why) {
  return make_error(ErrorCode::kIo, "cannot write " + target.string() + ": " + why);
}

Expected<ResolvedTarget> resolve_target(const fs::path& target) {
  ResolvedTarget r;
  r.path = resolve_links(target);
  const fs::path dir = folder_of(r.path);
  struct stat st {};
  if (::stat(r.path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return cannot_write(target, "it is a folder");
    if (S_ISREG(st.st_mode)) {
      if (::access(r.path.c_str(), W_OK) != 0 || (st.st_mode & 0222) == 0) {
        return cannot_write(target, "it is read-only");
      }
      r.kind = TargetKind::kRegular;
      r.mode = st.st_mode & 07777;
    } else if (S_ISCHR(st.st_mode)) {
      r.kind = TargetKind::kDirect;
      return r;
    } else if (S_ISFIFO(st.st_mode)) {
      // Opening a FIFO for writing blocks until it has a reader: ask first.
      const int fd = ::open(r.path.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd < 0) {
        return cannot_write(target, errno == ENXIO ? "it is a FIFO with no reader"
                                                   : std::string(std::strerror(errno)));
      }
      ::close(fd);
      r.kind = TargetKind::kDirect;
      return r;
    } else {
      return cannot_write(target, "it is not a regular file");
    }
  }
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    return cannot_write(target, "folder " + dir.string() + " does not exist");
  }
  if (::access(dir.c_str(), W_OK) != 0) {
    return cannot_write(
        target, "folder " + dir.string() + " is not writable (" + std::strerror(errno) + ")");
  }
  return r;
}

void fsync_path(const fs::path& path, int flags) {
  if (int fd = ::open(path.c_str(), flags); fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

// ---- AtomicFileSet. -----------------------------------------------------------

void (*g_after_commit_rename_for_tests)(std::size_t index) = nullptr;

struct AtomicFileSet::Impl {
  struct Entry {
    fs::path target;  // as given (for messages)
    fs::path real;    // after links
    fs::path temp;    // empty for direct writes and removals
    int slot = -1;
    bool remove = false;  // a staged removal (stage_removal)
  };
  std::vector<Entry> entries;
  bool committed = false;

  void remove_temporaries(std::size_t from) {
    std::error_code ec;
    for (std::size_t i = from; i < entries.size(); ++i) {
      if (!entries[i].temp.empty()) fs::remove(entries[i].temp, ec);
      unregister_pending(entries[i].slot);
      entries[i].slot = -1;
    }
  }
};

AtomicFileSet::AtomicFileSet() : impl_(std::make_unique<Impl>()) {}

AtomicFileSet::~AtomicFileSet() {
  if (!impl_->committed) impl_->remove_temporaries(0);
}

Status AtomicFileSet::stage(const fs::path& target, const WriteFunction& write) {
  Expected<ResolvedTarget> resolved = resolve_target(target);
  if (!resolved) return resolved.error();
  Impl::Entry entry{target, resolved->path, {}, -1};
  if (resolved->kind == TargetKind::kDirect) {
    // A device or FIFO: written in place, never replaced or removed.
    try {
      if (Status s = write(resolved->path); !s) return s;
    } catch (const std::exception& e) {
      return cannot_write(target, e.what());
    }
    impl_->entries.push_back(entry);
    return ok_status();
  }
  clean_stale_temporaries(folder_of(resolved->path));
  entry.temp = temp_path_for(resolved->path, {});
  entry.slot = register_pending(entry.temp);
  auto fail = [&](Status s) {
    std::error_code ec;
    fs::remove(entry.temp, ec);
    unregister_pending(entry.slot);
    return s;
  };
  Status result = ok_status();
  try {
    result = write(entry.temp);
  } catch (const std::exception& e) {
    return fail(cannot_write(target, e.what()));
  }
  if (!result) return fail(result);
  if (resolved->kind == TargetKind::kRegular) ::chmod(entry.temp.c_str(), resolved->mode);
  // Flush the data before the rename makes it visible under the target's
  // name, so a power cut cannot leave an empty file there.
  fsync_path(entry.temp, O_RDONLY);
  impl_->entries.push_back(std::move(entry));
  return ok_status();
}

Status AtomicFileSet::stage_removal(const fs::path& target) {
  struct stat st {};
  if (::lstat(target.c_str(), &st) != 0) return ok_status();  // nothing to remove
  if (S_ISDIR(st.st_mode)) {
    return make_error(ErrorCode::kIo, "cannot replace " + target.string() + ": it is a folder");
  }
  const fs::path dir = folder_of(target);
  if (::access(dir.c_str(), W_OK) != 0) {
    return make_error(ErrorCode::kIo, "cannot remove " + target.string() + ": folder " +
                                          dir.string() + " is not writable (" +
                                          std::strerror(errno) + ")");
  }
  clean_stale_temporaries(dir);
  Impl::Entry entry{target, target, {}, -1, true};
  impl_->entries.push_back(std::move(entry));
  return ok_status();
}

Status AtomicFileSet::commit() {
  std::vector<Impl::Entry>& entries = impl_->entries;
  // Removals first: a reader then sees the old set, or the new one, never
  // a stale file beside new ones.
  std::stable_partition(entries.begin(), entries.end(),
                        [](const Impl::Entry& e) { return e.remove; });
  std::size_t renamed = 0;
  std::size_t to_rename = 0;
  for (const Impl::Entry& e : entries) to_rename += e.temp.empty() && !e.remove ? 0 : 1;
  fs::path journal;
  g_committing.fetch_add(1);
  if (to_rename >= 2) {
    // The journal: one "temporary<TAB>target" line per rename, in order,
    // after one "<TAB>target" line per removal.
    for (const Impl::Entry& e : entries) {
      if (journal.empty() && (!e.temp.empty() || e.remove)) {
        journal = temp_path_for(e.real, kJournalExtension);
      }
    }
    std::ostringstream text;
    for (const Impl::Entry& e : entries) {
      if (!e.temp.empty() || e.remove) {
        text << (e.remove ? std::string() : fs::absolute(e.temp).string()) << '\t'
             << fs::absolute(e.real).string() << '\n';
      }
    }
    std::ofstream out(journal, std::ios::binary);
    out << text.str();
    out.close();
    if (!out) {
      g_committing.fetch_sub(1);
      std::error_code ec;
      fs::remove(journal, ec);
      impl_->remove_temporaries(0);
      raise_deferred_signal();
      return cannot_write(entries.front().target,
                          "cannot write the commit journal " + journal.string());
    }
    fsync_path(journal, O_RDONLY);
  }
  Status result = ok_status();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    Impl::Entry& e = entries[i];
    if (e.remove) {
      if (::unlink(e.real.c_str()) != 0 && errno != ENOENT) {
        result = make_error(ErrorCode::kIo,
                            "cannot remove " + e.target.string() + ": " + std::strerror(errno));
        impl_->remove_temporaries(i);
        break;
      }
      continue;
    }
    if (e.temp.empty()) continue;
    std::error_code ec;
    fs::rename(e.temp, e.real, ec);
    if (ec) {
      result = cannot_write(e.target, ec.message());
      impl_->remove_temporaries(i);
      break;
    }
    unregister_pending(e.slot);
    e.slot = -1;
    e.temp.clear();
    if (g_after_commit_rename_for_tests) g_after_commit_rename_for_tests(renamed);
    ++renamed;
  }
  if (renamed > 0) fsync_path(folder_of(entries.back().real), O_RDONLY | O_DIRECTORY);
  if (!journal.empty()) {
    std::error_code ec;
    fs::remove(journal, ec);
  }
  impl_->committed = true;
  g_committing.fetch_sub(1);
  raise_deferred_signal();
  return result;
}

Status write_atomically(const fs::path& target, const WriteFunction& write) {
  AtomicFileSet set;
  if (Status s = set.stage(target, write); !s) return s;
  return set.commit();
}

Status stage_or_write(AtomicFileSet* set, const fs::path& target, const WriteFunction& write) {
  return set ? set->stage(target, write) : write_atomically(target, write);
}

Status check_writable(const fs::path& target) {
  Expected<ResolvedTarget> resolved = resolve_target(target);
  if (!resolved) return resolved.error();
  return ok_status();
}

bool same_file(const fs::path& a, const fs::path& b) {
  struct stat sa {
  }, sb{};
  if (::stat(a.c_str(), &sa) != 0 || ::stat(b.c_str(), &sb) != 0) return false;
  return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

void install_signal_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction action {};
    action.sa_handler = cleanup_signal_handler;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &action, nullptr);
  });
}

std::vector<fs::path> list_texbake_temporaries(const fs::path& folder) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().filename().string().rfind(kPrefix, 0) == 0) out.push_back(it->path());
  }
  return out;
}

}  // namespace texbake
