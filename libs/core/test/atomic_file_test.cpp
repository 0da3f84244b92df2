#include "terralod/core/atomic_file.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace terralod {
namespace {

namespace fs = std::filesystem;

// Every test runs with both kinds of temporary file: unnamed (O_TMPFILE) and the named fallback.
class AtomicFileTest : public ::testing::TestWithParam<AtomicFile::Temporary> {
 protected:
  void SetUp() override {
    std::string name = (fs::temp_directory_path() / "terralod-atomic-XXXXXX").string();
    ASSERT_NE(mkdtemp(name.data()), nullptr);
    mDir = name;
  }
  void TearDown() override { fs::remove_all(mDir); }
  std::string file(const std::string& name) const { return (mDir / name).string(); }
  size_t entries() const { return size_t(std::distance(fs::directory_iterator(mDir), {})); }
  static std::string contents(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  Result<AtomicFile> create(const std::string& name) const {
    return AtomicFile::create(file(name), GetParam());
  }
  fs::path mDir;
};

TEST_P(AtomicFileTest, AppearsOnlyWhenCommitted) {
  auto f = create("out.txt");
  ASSERT_TRUE(f.ok()) << f.error().message;
  ASSERT_TRUE(f->write("hello ").ok());
  ASSERT_TRUE(f->write(std::string(5 << 20, 'x')).ok());  // larger than the buffer
  EXPECT_FALSE(fs::exists(file("out.txt")));
  ASSERT_TRUE(f->commit().ok());
  EXPECT_EQ(f->bytesWritten(), 6u + (5u << 20));
  EXPECT_EQ(contents(file("out.txt")), "hello " + std::string(5 << 20, 'x'));
  EXPECT_EQ(entries(), 1u) << "temporary file left behind";
}

TEST_P(AtomicFileTest, AbandonedLeavesNothingAndKeepsTheOldFile) {
  std::ofstream(file("out.txt")) << "old";
  {
    auto f = create("out.txt");
    ASSERT_TRUE(f.ok());
    ASSERT_TRUE(f->write("new").ok());
    AtomicFile moved = std::move(f.value());  // ownership of the temporary moves with it
  }
  EXPECT_EQ(contents(file("out.txt")), "old");
  EXPECT_EQ(entries(), 1u);
}

TEST_P(AtomicFileTest, ReplacesAnExistingFileOnlyAtCommit) {
  std::ofstream(file("out.txt")) << "old";
  auto f = create("out.txt");
  ASSERT_TRUE(f.ok()) << f.error().message;
  ASSERT_TRUE(f->write("new contents").ok());
  ASSERT_TRUE(f->writeAt(0, std::span(reinterpret_cast<const uint8_t*>("NEW"), 3)).ok());
  EXPECT_EQ(contents(file("out.txt")), "old");
  ASSERT_TRUE(f->commit().ok());
  EXPECT_EQ(contents(file("out.txt")), "NEW contents");
  EXPECT_EQ(entries(), 1u) << "temporary file left behind";
}

TEST_P(AtomicFileTest, KeepsItsTemporaryFileOutOfSightWhileWriting) {
  auto f = create("out.txt");
  ASSERT_TRUE(f.ok()) << f.error().message;
  ASSERT_TRUE(f->write(std::string(5 << 20, 'x')).ok());
  if (GetParam() == AtomicFile::Temporary::kNamed) {
    EXPECT_FALSE(f->unnamed());
    ASSERT_EQ(entries(), 1u);
    EXPECT_EQ(
        fs::directory_iterator(mDir)->path().filename().string().rfind(".out.txt.partial-", 0), 0u);
    return;
  }
  if (!f->unnamed()) GTEST_SKIP() << "this file system has no O_TMPFILE";
  EXPECT_EQ(entries(), 0u) << "an unnamed temporary file has no directory entry";
}

TEST_P(AtomicFileTest, RefusesUnusableTargetsNamingThem) {
  auto missing = AtomicFile::create(file("no/dir/out.txt"), GetParam());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("out.txt: cannot write: directory"), std::string::npos)
      << missing.error().message;
  auto directory = AtomicFile::create(mDir.string(), GetParam());
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.error().message.find("is a directory"), std::string::npos);
  EXPECT_EQ(entries(), 0u);
}

INSTANTIATE_TEST_SUITE_P(BothTemporaryKinds, AtomicFileTest,
                         ::testing::Values(AtomicFile::Temporary::kUnnamedIfPossible,
                                           AtomicFile::Temporary::kNamed),
                         [](const auto& test) {
                           return test.param == AtomicFile::Temporary::kNamed ? "Named" : "Unnamed";
                         });

}  // namespace
}  // namespace terralod
