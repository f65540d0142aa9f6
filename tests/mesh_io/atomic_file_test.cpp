// write_atomically and AtomicFileSet: targets appear only complete, failures
// and interruptions leave nothing, special targets are never replaced.
#include "mesh_io/atomic_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

namespace texbake {
namespace {
namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_atomic_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add);
    fs::remove_all(dir_);
  }
  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static Status write_text(const fs::path& p, const std::string& text) {
    std::ofstream out(p, std::ios::binary);
    out << text;
    return out ? ok_status() : make_error(ErrorCode::kIo, "write failed");
  }
  std::size_t entries() const {
    return std::distance(fs::directory_iterator(dir_), fs::directory_iterator());
  }
  fs::path dir_;
};

TEST_F(AtomicFileTest, WritesTargetAndLeavesNoTemporary) {
  const fs::path target = dir_ / "out.ply";
  fs::path seen_temp;
  Status s = write_atomically(target, [&](const fs::path& temp) {
    seen_temp = temp;
    EXPECT_EQ(temp.parent_path(), target.parent_path());
    EXPECT_EQ(temp.extension(), ".ply") << "the real extension must stay last";
    EXPECT_FALSE(fs::exists(target)) << "target must not exist before the rename";
    return write_text(temp, "hello");
  });
  ASSERT_TRUE(s);
  EXPECT_EQ(read(target), "hello");
  EXPECT_FALSE(fs::exists(seen_temp));
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, FailedWriteKeepsPreviousFileAndRemovesTemporary) {
  const fs::path target = dir_ / "out.png";
  ASSERT_TRUE(write_text(target, "previous"));
  Status s = write_atomically(target, [&](const fs::path& temp) -> Status {
    EXPECT_TRUE(write_text(temp, "half"));
    return make_error(ErrorCode::kIo, "disk full");
  });
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().message, "disk full");
  EXPECT_EQ(read(target), "previous");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, ThrowingWriterBecomesAnErrorNamingTheTarget) {
  const fs::path target = dir_ / "out.obj";
  Status s = write_atomically(target, [&](const fs::path& temp) -> Status {
    EXPECT_TRUE(write_text(temp, "x"));
    throw std::runtime_error("boom");
  });
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find(target.string()), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find("boom"), std::string::npos);
  EXPECT_EQ(entries(), 0u);
}

TEST_F(AtomicFileTest, MissingFolderIsAnErrorBeforeWriting) {
  bool called = false;
  Status s = write_atomically(dir_ / "nope" / "out.ply", [&](const fs::path&) {
    called = true;
    return ok_status();
  });
  ASSERT_FALSE(s);
  EXPECT_FALSE(called);
  EXPECT_EQ(s.error().code, ErrorCode::kIo);
  EXPECT_NE(s.error().message.find("does not exist"), std::string::npos) << s.error().message;
}

TEST_F(AtomicFileTest, UnwritableFolderIsAnError) {
  if (::geteuid() == 0) {
    // root bypasses permission bits; check the folder-is-a-file case instead.
    Status s = check_writable(dir_);
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("is a folder"), std::string::npos) << s.error().message;
    return;
  }
  fs::permissions(dir_, fs::perms::owner_write, fs::perm_options::remove);
  Status s = check_writable(dir_ / "out.ply");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("not writable"), std::string::npos) << s.error().message;
}

TEST_F(AtomicFileTest, TemporaryNamesAreUnique) {
  fs::path a, b;
  ASSERT_TRUE(write_atomically(dir_ / "x.ply", [&](const fs::path& t) {
    a = t;
    return write_text(t, "1");
  }));
  ASSERT_TRUE(write_atomically(dir_ / "x.ply", [&](const fs::path& t) {
    b = t;
    return write_text(t, "2");
  }));
  EXPECT_NE(a, b);
  EXPECT_EQ(read(dir_ / "x.ply"), "2");
}

// ---- Issue #12: names, permissions, special files, sets, stale files. ----

TEST_F(AtomicFileTest, LongestLegalNameIsWritable) {
  // 255 bytes is NAME_MAX; the temporary's name must not be longer than
  // what fits (it used to be the target's name plus a 30-byte prefix).
  const fs::path target = dir_ / (std::string(251, 'n') + ".ply");
  ASSERT_EQ(target.filename().string().size(), 255u);
  Status s = write_atomically(target, [&](const fs::path& t) {
    EXPECT_LE(t.filename().string().size(), 64u);
    return write_text(t, "long");
  });
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_EQ(read(target), "long");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, ReadOnlyTargetIsRefusedAndKept) {
  const fs::path target = dir_ / "ro.ply";
  ASSERT_TRUE(write_text(target, "keep"));
  fs::permissions(target, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  bool called = false;
  Status s = write_atomically(target, [&](const fs::path& t) {
    called = true;
    return write_text(t, "new");
  });
  ASSERT_FALSE(s);
  EXPECT_FALSE(called);
  EXPECT_EQ(s.error().code, ErrorCode::kIo);
  EXPECT_NE(s.error().message.find("read-only"), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find(target.string()), std::string::npos);
  EXPECT_FALSE(check_writable(target));
  EXPECT_EQ(read(target), "keep");
  EXPECT_EQ(fs::status(target).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, ReplacedFileKeepsItsPermissions) {
  const fs::path target = dir_ / "private.json";
  ASSERT_TRUE(write_text(target, "old"));
  fs::permissions(target, fs::perms::owner_read | fs::perms::owner_write);
  ASSERT_TRUE(write_atomically(target, [&](const fs::path& t) { return write_text(t, "new"); }));
  EXPECT_EQ(read(target), "new");
  EXPECT_EQ(fs::status(target).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
}

TEST_F(AtomicFileTest, SymbolicLinkIsWrittenThroughAndKept) {
  fs::create_directories(dir_ / "real");
  const fs::path real = dir_ / "real" / "out.ply";
  ASSERT_TRUE(write_text(real, "old"));
  const fs::path link = dir_ / "link.ply";
  fs::create_symlink(fs::path("real") / "out.ply", link);
  ASSERT_TRUE(write_atomically(link, [&](const fs::path& t) {
    EXPECT_EQ(t.parent_path(), dir_ / "real") << "the temporary goes beside the real file";
    return write_text(t, "new");
  }));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(read(real), "new");
  EXPECT_TRUE(list_texbake_temporaries(dir_ / "real").empty());
}

TEST_F(AtomicFileTest, CharacterDeviceIsWrittenInPlaceNeverReplaced) {
  // A private copy of /dev/null (major 1, minor 3), so a failure here can
  // never touch the system's own.
  const fs::path node = dir_ / "null";
  ASSERT_EQ(::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)), 0)
      << "mknod needs root (the suite runs as root in CI): " << std::strerror(errno);
  fs::path written;
  ASSERT_TRUE(check_writable(node));
  Status s = write_atomically(node, [&](const fs::path& t) {
    written = t;
    return write_text(t, "discarded");
  });
  ASSERT_TRUE(s) << s.error().message;
  EXPECT_EQ(written, node) << "a device is written directly, not through a temporary";
  EXPECT_TRUE(fs::is_character_file(node));
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, FifoWithoutReaderIsAnErrorNotAHang) {
  const fs::path fifo = dir_ / "pipe.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  bool called = false;
  Status s = write_atomically(fifo, [&](const fs::path&) {
    called = true;
    return ok_status();
  });
  ASSERT_FALSE(s);
  EXPECT_FALSE(called);
  EXPECT_NE(s.error().message.find("FIFO with no reader"), std::string::npos) << s.error().message;
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST_F(AtomicFileTest, FifoWithReaderReceivesTheData) {
  const fs::path fifo = dir_ / "pipe.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  // The reader holds the FIFO open (O_RDWR never blocks) and drains it after.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  ASSERT_TRUE(write_atomically(fifo, [&](const fs::path& t) { return write_text(t, "piped"); }));
  char buf[16] = {};
  const ssize_t n = ::read(reader, buf, sizeof buf);
  ::close(reader);
  EXPECT_EQ(std::string(buf, n > 0 ? n : 0), "piped");
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST_F(AtomicFileTest, SetIsInvisibleUntilCommitAndAFailureKeepsTheOldSet) {
  const fs::path a = dir_ / "m.png", b = dir_ / "m.obj";
  ASSERT_TRUE(write_text(a, "old png"));
  ASSERT_TRUE(write_text(b, "old obj"));
  {
    AtomicFileSet set;
    ASSERT_TRUE(set.stage(a, [&](const fs::path& t) { return write_text(t, "new png"); }));
    EXPECT_EQ(read(a), "old png") << "staged, not yet visible";
    Status s = set.stage(b, [&](const fs::path& t) {
      EXPECT_TRUE(write_text(t, "half"));
      return make_error(ErrorCode::kIo, "disk full");
    });
    ASSERT_FALSE(s);
  }  // destroyed without commit
  EXPECT_EQ(read(a), "old png");
  EXPECT_EQ(read(b), "old obj");
  EXPECT_TRUE(list_texbake_temporaries(dir_).empty());
  {
    AtomicFileSet set;
    ASSERT_TRUE(set.stage(a, [&](const fs::path& t) { return write_text(t, "new png"); }));
    ASSERT_TRUE(set.stage(b, [&](const fs::path& t) { return write_text(t, "new obj"); }));
    ASSERT_TRUE(set.commit());
  }
  EXPECT_EQ(read(a), "new png");
  EXPECT_EQ(read(b), "new obj");
  EXPECT_EQ(entries(), 2u) << "no temporary and no journal left";
}

// Runs `child` in a forked process that must die by SIGKILL; returns when it has.
void run_killed_child(const std::function<void()>& child) {
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    child();
    ::_exit(3);  // child() should not return
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "status " << status;
}

TEST_F(AtomicFileTest, NextWriteRemovesTheTemporariesOfAKilledProcess) {
  const fs::path target = dir_ / "atlas.png";
  ASSERT_TRUE(write_text(target, "old"));
  run_killed_child([&] {
    (void)write_atomically(target, [&](const fs::path& t) {
      (void)write_text(t, "partial");
      ::kill(::getpid(), SIGKILL);
      return ok_status();
    });
  });
  ASSERT_EQ(list_texbake_temporaries(dir_).size(), 1u) << "the killed write left its temporary";
  EXPECT_EQ(read(target), "old");
  // Any later write into the folder cleans it.
  ASSERT_TRUE(
      write_atomically(dir_ / "other.ply", [&](const fs::path& t) { return write_text(t, "x"); }));
  EXPECT_TRUE(list_texbake_temporaries(dir_).empty());
  EXPECT_EQ(read(target), "old");
}

TEST_F(AtomicFileTest, CommitKilledBetweenRenamesIsCompletedByTheNextWrite) {
  const fs::path png = dir_ / "m.png", mtl = dir_ / "m.mtl", obj = dir_ / "m.obj";
  for (const fs::path& p : {png, mtl, obj}) ASSERT_TRUE(write_text(p, "old"));
  run_killed_child([&] {
    g_after_commit_rename_for_tests = [](std::size_t index) {
      if (index == 0) ::kill(::getpid(), SIGKILL);  // after the image, before MTL and OBJ
    };
    AtomicFileSet set;
    for (const fs::path& p : {png, mtl, obj}) {
      (void)set.stage(p, [&](const fs::path& t) { return write_text(t, "new"); });
    }
    (void)set.commit();
  });
  EXPECT_EQ(read(png), "new");
  EXPECT_EQ(read(obj), "old") << "killed before the OBJ's rename";
  EXPECT_FALSE(list_texbake_temporaries(dir_).empty()) << "temporaries and the journal remain";
  ASSERT_TRUE(
      write_atomically(dir_ / "other.ply", [&](const fs::path& t) { return write_text(t, "x"); }));
  EXPECT_EQ(read(png), "new");
  EXPECT_EQ(read(mtl), "new");
  EXPECT_EQ(read(obj), "new") << "the next write completes the interrupted set";
  EXPECT_TRUE(list_texbake_temporaries(dir_).empty());
}

TEST_F(AtomicFileTest, StagedRemovalsGoWithTheCommit) {
  // A COLMAP model's other form: cameras.bin goes when cameras.txt comes.
  const fs::path bin = dir_ / "cameras.bin", txt = dir_ / "cameras.txt";
  ASSERT_TRUE(write_text(bin, "stale"));
  {
    AtomicFileSet set;
    ASSERT_TRUE(set.stage_removal(bin));
    ASSERT_TRUE(set.stage_removal(dir_ / "absent.bin"));  // nothing to remove: fine
    ASSERT_TRUE(set.stage(txt, [&](const fs::path& t) { return write_text(t, "new"); }));
    EXPECT_TRUE(fs::exists(bin)) << "staged, not yet removed";
  }  // destroyed without commit: nothing changes
  EXPECT_EQ(read(bin), "stale");
  EXPECT_FALSE(fs::exists(txt));
  {
    AtomicFileSet set;
    ASSERT_TRUE(set.stage(txt, [&](const fs::path& t) { return write_text(t, "new"); }));
    ASSERT_TRUE(set.stage_removal(bin));
    ASSERT_TRUE(set.commit());
  }
  EXPECT_FALSE(fs::exists(bin));
  EXPECT_EQ(read(txt), "new");
  EXPECT_EQ(entries(), 1u) << "no temporary and no journal left";
  // A folder cannot be removed in its place: an error before anything.
  fs::create_directories(dir_ / "images.bin");
  AtomicFileSet set;
  const Status s = set.stage_removal(dir_ / "images.bin");
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().message,
            "cannot replace " + (dir_ / "images.bin").string() + ": it is a folder");
}

TEST_F(AtomicFileTest, ACommitWithRemovalsKilledBetweenRenamesIsCompleted) {
  const fs::path stale = dir_ / "images.bin", a = dir_ / "cameras.txt", b = dir_ / "images.txt";
  ASSERT_TRUE(write_text(stale, "stale"));
  run_killed_child([&] {
    g_after_commit_rename_for_tests = [](std::size_t index) {
      if (index == 0) ::kill(::getpid(), SIGKILL);  // removal and first rename done
    };
    AtomicFileSet set;
    (void)set.stage(a, [&](const fs::path& t) { return write_text(t, "new"); });
    (void)set.stage(b, [&](const fs::path& t) { return write_text(t, "new"); });
    (void)set.stage_removal(stale);
    (void)set.commit();
  });
  EXPECT_FALSE(fs::exists(stale)) << "removed before the renames";
  EXPECT_EQ(read(a), "new");
  EXPECT_FALSE(fs::exists(b));
  ASSERT_TRUE(
      write_atomically(dir_ / "other.ply", [&](const fs::path& t) { return write_text(t, "x"); }));
  EXPECT_EQ(read(b), "new") << "the next write completes the interrupted set";
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(list_texbake_temporaries(dir_).empty());
}

TEST_F(AtomicFileTest, SigtermDuringAWriteRemovesTheTemporary) {
  const fs::path target = dir_ / "atlas.png";
  ASSERT_TRUE(write_text(target, "old"));
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    install_signal_cleanup();
    (void)write_atomically(target, [&](const fs::path& t) {
      (void)write_text(t, "partial");
      ::kill(::getpid(), SIGTERM);
      ::pause();
      return ok_status();
    });
    ::_exit(3);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  EXPECT_TRUE(list_texbake_temporaries(dir_).empty());
  EXPECT_EQ(read(target), "old");
}

TEST_F(AtomicFileTest, SameFileFollowsLinksAndHardLinks) {
  const fs::path a = dir_ / "a.ply", b = dir_ / "b.ply";
  ASSERT_TRUE(write_text(a, "a"));
  ASSERT_TRUE(write_text(b, "a"));
  fs::create_symlink(a, dir_ / "sym.ply");
  fs::create_hard_link(a, dir_ / "hard.ply");
  EXPECT_TRUE(same_file(a, a));
  EXPECT_TRUE(same_file(a, dir_ / "sym.ply"));
  EXPECT_TRUE(same_file(dir_ / "hard.ply", dir_ / "sym.ply"));
  EXPECT_TRUE(same_file(a, dir_ / "." / "a.ply"));
  EXPECT_FALSE(same_file(a, b)) << "same content, other file";
  EXPECT_FALSE(same_file(a, dir_ / "missing.ply"));
}

}  // namespace
}  // namespace texbake
