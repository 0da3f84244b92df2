#include "terralod/core/atomic_file.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace terralod {
namespace {

namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
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
  fs::path mDir;
};

TEST_F(AtomicFileTest, AppearsOnlyWhenCommitted) {
  auto f = AtomicFile::create(file("out.txt"));
  ASSERT_TRUE(f.ok()) << f.error().message;
  ASSERT_TRUE(f->write("hello ").ok());
  ASSERT_TRUE(f->write(std::string(5 << 20, 'x')).ok());  // larger than the buffer
  EXPECT_FALSE(fs::exists(file("out.txt")));
  ASSERT_TRUE(f->commit().ok());
  EXPECT_EQ(f->bytesWritten(), 6u + (5u << 20));
  EXPECT_EQ(contents(file("out.txt")), "hello " + std::string(5 << 20, 'x'));
  EXPECT_EQ(entries(), 1u) << "temporary file left behind";
}

TEST_F(AtomicFileTest, AbandonedLeavesNothingAndKeepsTheOldFile) {
  std::ofstream(file("out.txt")) << "old";
  {
    auto f = AtomicFile::create(file("out.txt"));
    ASSERT_TRUE(f.ok());
    ASSERT_TRUE(f->write("new").ok());
    AtomicFile moved = std::move(f.value());  // ownership of the temporary moves with it
  }
  EXPECT_EQ(contents(file("out.txt")), "old");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, RefusesUnusableTargetsNamingThem) {
  auto missing = AtomicFile::create(file("no/dir/out.txt"));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("out.txt: cannot write: directory"), std::string::npos)
      << missing.error().message;
  auto directory = AtomicFile::create(mDir.string());
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.error().message.find("is a directory"), std::string::npos);
  EXPECT_EQ(entries(), 0u);
}

}  // namespace
}  // namespace terralod
