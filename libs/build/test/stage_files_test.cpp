// A job's per-block stage records (stage_files.h): what one job writes, the next reads back
// record by record, and a file for another job or a damaged one is refused, naming it.

#include "stage_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace terralod {
namespace {

namespace fs = std::filesystem;

class StageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    mDir = fs::temp_directory_path() /
           ("terralod-stage-files-" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(mDir);
    fs::create_directories(mDir);
  }
  void TearDown() override { fs::remove_all(mDir); }
  std::string path(const std::string& name) const { return (mDir / name).string(); }
  fs::path mDir;
};

const std::vector<std::vector<uint8_t>> kRecords = {{1, 2, 3}, {}, std::vector<uint8_t>(5000, 7)};

TEST_F(StageFiles, BlockRecordsComeBackInOrder) {
  const std::string file = path("job-0.halo");
  ASSERT_TRUE(writeBlockRecords(file, StageFile::kPass1Halos, kRecords));
  auto back = BlockRecords::read(file, StageFile::kPass1Halos, kRecords.size());
  ASSERT_TRUE(back) << back.error().message;
  ASSERT_EQ(back->size(), kRecords.size());
  for (size_t i = 0; i < kRecords.size(); ++i)
    EXPECT_EQ(std::vector<uint8_t>((*back)[i].begin(), (*back)[i].end()), kRecords[i]) << i;
}

TEST_F(StageFiles, BlockRecordsOfAnotherJobOrKindAreRefused) {
  const std::string file = path("job-1.grid");
  ASSERT_TRUE(writeBlockRecords(file, StageFile::kPass1Grids, kRecords));
  auto fewer = BlockRecords::read(file, StageFile::kPass1Grids, kRecords.size() - 1);
  ASSERT_FALSE(fewer);
  EXPECT_EQ(fewer.error().message, file + ": was written for another block layout");
  auto kind = BlockRecords::read(file, StageFile::kReducedHalos, kRecords.size());
  ASSERT_FALSE(kind);
  EXPECT_NE(kind.error().message.find(file + ": is a stage file of another kind"),
            std::string::npos)
      << kind.error().message;
}

TEST_F(StageFiles, DamagedBlockRecordsAreRefused) {
  const std::string file = path("job-2.coarse");
  ASSERT_TRUE(writeBlockRecords(file, StageFile::kBlockCoarse, kRecords));
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.size() - 3] = char(bytes[bytes.size() - 3] ^ 0x40);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  auto back = BlockRecords::read(file, StageFile::kBlockCoarse, kRecords.size());
  ASSERT_FALSE(back);
  EXPECT_NE(back.error().message.find(file + ": damaged"), std::string::npos)
      << back.error().message;
}

// Pieces given out of order (as threads finish blocks) are written in order: the file reads
// back as the pieces joined. One never given fails the commit, and no file appears.
TEST_F(StageFiles, OrderedPiecesAreWrittenInTheirOrder) {
  const std::vector<std::vector<uint8_t>> pieces = {{1, 2}, {3}, {}, {4, 5, 6}, {7}};
  const std::string file = path("job-3.chunks");
  {
    auto out = StageFileWriter::create(file, StageFile::kChunks);
    ASSERT_TRUE(out) << out.error().message;
    OrderedStageWriter ordered(std::move(*out));
    for (size_t i : {3u, 1u, 0u, 4u, 2u}) ordered.put(i, pieces[i]);
    ASSERT_TRUE(ordered.commit(pieces.size()));
  }
  auto in = StageFileReader::open(file, StageFile::kChunks);
  ASSERT_TRUE(in) << in.error().message;
  std::vector<uint8_t> back;
  while (!in->atEnd()) back.push_back(*in->get<uint8_t>());
  EXPECT_TRUE(in->finish());
  EXPECT_EQ(back, (std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7}));

  const std::string missing = path("job-4.chunks");
  {
    auto out = StageFileWriter::create(missing, StageFile::kChunks);
    ASSERT_TRUE(out) << out.error().message;
    OrderedStageWriter ordered(std::move(*out));
    for (size_t i : {0u, 1u, 3u, 4u}) ordered.put(i, pieces[i]);
    auto committed = ordered.commit(pieces.size());
    ASSERT_FALSE(committed);
    EXPECT_NE(committed.error().message.find("internal error"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(missing));
}

}  // namespace
}  // namespace terralod
