#pragma once
// The records a staged build's stages hand each other through the work directory (layouts in
// docs/format.md, "Staged build work directory"), and where assemble finds each chunk's texture
// (TextureSource). Internal to libs/build.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "border_reduce.h"
#include "stage_files.h"
#include "stage_work.h"
#include "terralod/build/chunk_pass.h"
#include "terralod/build/kept_heights.h"
#include "terralod/build/sparse_heights.h"
#include "terralod/build/texture_pass.h"
#include "terralod/build/tile_pyramid.h"
#include "terralod/format/tileset_writer.h"

namespace terralod::stages {

// Heights on the block grid lines and the data's last row and column that a window crossed
// (what SparseHeights keeps), as row or column runs.
struct LineRun {
  uint8_t row = 0;  // 1: along x at y = fixed; 0: along y at x = fixed
  int32_t fixed = 0, start = 0;
  std::vector<float> values;
};

std::vector<LineRun> linesOf(const TreeLayout& layout, GridPoint o, int32_t block,
                             const float* window);

void recordLines(SparseHeights& heights, const std::vector<LineRun>& runs);

struct Pass1Halo {
  double minHeight = 0, maxHeight = 0;
  bool sawVoid = false;
  uint64_t scanned = 0, bounded = 0;
  BlockSquare square;
  std::vector<uint8_t> halo;
  std::vector<LineRun> lines;
};

std::vector<uint8_t> packPass1Halo(const Pass1Halo& h);

Result<Pass1Halo> unpackPass1Halo(std::span<const uint8_t> record, const std::string& path);

// A built chunk's node, record (with the statistics its stage filled in) and mesh blob; its
// texture blob follows.
void packChunkMesh(Packer& p, const BuiltChunk& c, const std::vector<NodeRecord>& nodes);

// Built chunks with their node records: a piece of a chunk file (kChunks).
std::vector<uint8_t> packChunks(const std::vector<BuiltChunk>& chunks,
                                const std::vector<NodeRecord>& nodes);

// A block's kept heights (KeptHeights::blockBits and blockValues), for its pass-2 job: a zstd
// frame (a job holds its blocks' until it ends).
std::vector<uint8_t> packKept(const KeptHeights& kept, GridPoint origin);

Status restoreKept(KeptHeights& kept, GridPoint origin, int32_t block,
                   std::span<const uint8_t> record, const std::string& path);

// Where assemble finds the texture of a chunk it appends: nullopt keeps the chunk file's own.
class TextureSource {
 public:
  virtual ~TextureSource() = default;
  /// The texture for `node` (valid until the next call), or nullopt.
  virtual Result<std::optional<std::span<const uint8_t>>> take(uint32_t node) = 0;
};

// The chunk file's own textures.
class OwnTextures final : public TextureSource {
 public:
  Result<std::optional<std::span<const uint8_t>>> take(uint32_t) override {
    return std::optional<std::span<const uint8_t>>();
  }
};

// A pass-1 job's chunk textures (kChunkTextures: u32 node, then the blob, for every chunk of
// its chunk file in that file's order), read in step with the chunk file.
class ChunkTexturesInStep final : public TextureSource {
 public:
  explicit ChunkTexturesInStep(StageFileReader in) : mIn(std::move(in)) {}
  Result<std::optional<std::span<const uint8_t>>> take(uint32_t node) override {
    auto stored = mIn.get<uint32_t>();
    auto texture = stored && *stored == node ? mIn.getView() : std::nullopt;
    if (!texture) return makeError(mIn.path(), "damaged (records do not add up)");
    return std::optional<std::span<const uint8_t>>(*texture);
  }
  /// Read to its end (no chunk left without its texture), with its checksum right.
  Status finish() {
    if (!mIn.atEnd()) return makeError(mIn.path(), "damaged (records do not add up)");
    return mIn.finish();
  }

 private:
  StageFileReader mIn;
};

// The texture blobs of coarse chunks that pass-2 jobs made (block nodes, and nodes above
// them whose blocks are all one job's): assemble reads them from the jobs' files in step with
// coarse.chunks (both in node order), where the coarse job left them empty. They are most of
// a textured tileset's bytes, so they are copied once, not through coarse.chunks as well.
class JobTextures final : public TextureSource {
 public:
  JobTextures() = default;
  /// Which job made each node's texture (-1: none did), as the coarse job and assemble derive
  /// it from the plan.
  static std::vector<int> madeBy(const StageContext& s, const std::vector<NodeRecord>& nodes) {
    const int32_t blockLevel = blockLevelOf(s.layout, s.block);
    std::vector<int> by(nodes.size(), -1);
    for (int job = 0; job < s.plan.jobs; ++job) {
      const std::vector<uint32_t> blocks = jobBlockNodes(s, job);
      const std::vector<uint8_t> builds = TilePyramid::buildableFrom(nodes, blockLevel, blocks);
      for (size_t i = 0; i < nodes.size(); ++i)
        if (builds[i]) by[i] = job;
      for (uint32_t b : blocks) by[b] = job;
    }
    return by;
  }
  static Result<JobTextures> open(const std::string& work, const StageContext& s) {
    JobTextures t;
    t.mMadeBy = madeBy(s, s.nodes);
    for (int job = 0; job < s.plan.jobs; ++job) {
      auto reader =
          StageFileReader::open(jobTextures(work, s.plan.options, job), StageFile::kJobTextures);
      if (!reader) return reader.error();
      auto count = reader->get<uint64_t>();
      if (!count) return makeError(reader->path(), "damaged (records do not add up)");
      t.mLeft.push_back(*count);
      t.mJobs.push_back(std::move(*reader));
    }
    return t;
  }
  /// The texture a job made for `node` (valid until the next call), or nullopt if none did.
  Result<std::optional<std::span<const uint8_t>>> take(uint32_t node) override {
    if (node >= mMadeBy.size() || mMadeBy[node] < 0)
      return std::optional<std::span<const uint8_t>>();
    const size_t job = size_t(mMadeBy[node]);
    StageFileReader& r = mJobs[job];
    if (mLeft[job] == 0) return makeError(r.path(), "damaged (records do not add up)");
    --mLeft[job];
    auto stored = r.get<uint32_t>();
    auto texture = stored && *stored == node ? r.getView() : std::nullopt;
    if (!texture) return makeError(r.path(), "damaged (records do not add up)");
    return std::optional<std::span<const uint8_t>>(*texture);
  }
  /// Every job's file read to its end, with its checksum right.
  Status finish() {
    for (StageFileReader& r : mJobs)
      if (Status st = r.finish(); !st) return st;
    return {};
  }

 private:
  std::vector<int> mMadeBy;
  std::vector<StageFileReader> mJobs;
  std::vector<uint64_t> mLeft;
};

// Reads built chunks back, copying their statistics into `nodes`, and appends them (a piece
// at a time: the file's checksum is checked at its end, before the tileset can be finished),
// each with the texture `textures` has for it, else its own.
Status appendChunksFrom(const std::string& path, std::vector<NodeRecord>& nodes,
                        TilesetWriter& writer, TextureSource& textures);

// What the coarse stage needs of a block to mesh the levels above it: heights and activations
// of the points coarse chunks use. (The block node's texture goes in its job's textures.)
struct BlockCoarse {
  std::vector<std::pair<uint64_t, float>> heights;
  std::vector<std::pair<uint64_t, uint8_t>> activations;
};

// A pass-2 job's frontier: the tiles of the nodes whose parent it could not build.
std::vector<uint8_t> packFrontier(const std::vector<std::pair<uint32_t, ChunkTiles>>& frontier);

// Reads a job's frontier back a tile at a time (not the whole file beside its copy: the
// coarse job's peak); `expected` lists its nodes.
Result<std::vector<std::pair<uint32_t, ChunkTiles>>> readFrontier(
    const std::string& path, const std::vector<uint32_t>& expected);

std::vector<uint8_t> packBlockCoarse(const BlockCoarse& c);

Result<BlockCoarse> unpackBlockCoarse(std::span<const uint8_t> record, const std::string& path);

struct ReduceSummary {
  double zMin = 0, zMax = 0;
  std::vector<std::pair<uint64_t, uint8_t>> activations;  // halo points at the block level up
};

Result<ReduceSummary> readReduceSummary(const std::string& work);

}  // namespace terralod::stages
