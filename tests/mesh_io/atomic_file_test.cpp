// write_atomically: the target appears only complete, failures leave nothing.
#include "mesh_io/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
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

}  // namespace
}  // namespace texbake
