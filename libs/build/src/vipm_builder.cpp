#include "terralod/build/vipm_builder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "load_heights.h"
#include "source_metadata.h"
#include "terralod/build/chunk_pass.h"
#include "terralod/build/tree_layout.h"
#include "terralod/build/vipm_chunk_set.h"
#include "terralod/build/vipm_chunks.h"
#include "terralod/core/parallel.h"
#include "terralod/format/terrain_edits_json.h"
#include "terralod/format/tileset_metadata.h"
#include "terralod/format/tileset_writer.h"
#include "terralod/materials/dem_classification.h"
#include "terralod/materials/material_raster.h"
#include "terralod/materials/terrain_edits.h"
#include "terralod/raster/void_fill.h"
#include "vipm_cells.h"

namespace terralod {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// The header's textureMinTau: the default --min-tau (informative; VIPM normal maps have one
// texel per grid point whatever τ).
constexpr double kVipmTextureTau = 2.0;

Status checkOptions(const BuildOptions& options) {
  if (!options.textureImage.empty())
    return Error{"--texture does not apply to --kind vipm (colour comes from the materials)"};
  if (options.chunkCells != 0 && options.chunkCells != kLeaf)
    return Error{"--chunk-cells: VIPM chunks are always " + std::to_string(kLeaf) + " cells"};
  if (!options.palettePath.empty() && options.materialsPath.empty())
    return Error{"--palette names the classes of --materials, which is missing"};
  if (options.blotError.leafError(options.maxError) < options.maxError)
    return Error{"--blot-error must be at least --max-error"};
  return {};
}

// Stage: the DEM, whole, voids filled, the edits applied.
Result<Heightfield> readDem(const DemReader& reader, const BuildOptions& options,
                            Progress& progress, BuildSummary& summary) {
  const DemInfo& info = reader.info();
  const uint64_t bytes = summary.sourceSamples * (sizeof(float) + 1);
  if (bytes > options.memoryMB << 20)
    return makeError(info.path, "the raster needs " + std::to_string(bytes >> 20) +
                                    " MB, more than --memory-mb " +
                                    std::to_string(options.memoryMB) +
                                    " (VIPM builds read it whole)");
  auto heights = loadHeights(reader, progress);
  if (!heights) return heights.error();
  auto filled = fillVoids(*heights, info.path);
  if (!filled) return filled.error();
  summary.filledVoids = *filled;
  applyHeightEdits(options.edits, info.spacingX, info.spacingY, *heights);
  return heights;
}

// Stage: the material of every grid point.
Result<MaterialMap> readMaterials(const DemReader& reader, const BuildOptions& options,
                                  Progress& progress) {
  MaterialRasterOptions rasterOptions;
  rasterOptions.palettePath = options.palettePath;
  auto map = options.materialsPath.empty()
                 ? classifyDem(reader, &progress)
                 : readMaterialRaster(options.materialsPath, reader, rasterOptions);
  if (!map) return map;
  const DemInfo& info = reader.info();
  if (Status s = applyPaintEdits(options.edits, info.spacingX, info.spacingY, *map, info.path); !s)
    return s.error();
  return map;
}

std::string metadataJson(const DemInfo& info, const BuildOptions& options, const BuildSummary& s,
                         const MaterialMap& materials, double zStep) {
  nlohmann::json list = nlohmann::json::array();
  for (const Material& m : materials.materials)
    list.push_back({{"id", m.id}, {"name", m.name}, {"color", colorHex(m.color)}});
  const double blotMetres = options.blotError.leafError(options.maxError);
  nlohmann::json j = {
      {"generator", "terralod"},
      {"kind", "vipm"},
      {"source", sourceMetadata(info)},
      {"materials", list},
      {"build",
       {{"max_error", options.maxError},
        {"chunk_cells", kLeaf},
        {"material_rules", options.materialRules == MaterialRules::kOn},
        {"blot_error", std::isfinite(blotMetres) ? nlohmann::json(blotMetres) : nlohmann::json()},
        {"materials", options.materialsPath.empty()
                          ? std::string("classification")
                          : std::filesystem::path(options.materialsPath).filename().string()},
        {"vertical_scale", options.dem.verticalScale},
        {"z_step", zStep},
        {"zstd_level", options.compressionLevel}}},
      {"texture", {{"layers", "normal"}, {"normals", "source"}, {"bytes", s.textureBytes}}},
      {"stats",
       {{"vertices", s.vertices},
        {"triangles", s.triangles},
        {"collapses", s.collapses},
        {"filled_voids", s.filledVoids}}},
  };
  if (!options.edits.empty())
    j["edits"] = nlohmann::json::parse(terrainEditScript(options.edits))["edits"];
  return j.dump(2);
}

}  // namespace

double BlotError::leafError(double maxError) const {
  switch (mode) {
    case Mode::kTimesMaxError:
      return value * maxError;
    case Mode::kMetres:
      return value;
    case Mode::kOff:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

namespace {

// What the chunks are made of: the DEM whole (voids filled, edits applied) and its materials.
struct SourceData {
  DemInfo info;
  Heightfield heights;
  MaterialMap materials;
};

Result<SourceData> readSource(const BuildOptions& options, Progress& progress,
                              BuildSummary& summary,
                              const std::function<void(const std::string&)>& warn) {
  const auto start = Clock::now();
  if (Status s = checkOptions(options); !s) return s.error();
  auto opened = DemReader::open(options.input, options.dem);
  if (!opened) return opened.error();
  const DemReader& reader = **opened;
  SourceData source;
  source.info = reader.info();
  summary.sourceSamples = uint64_t(source.info.columns) * uint64_t(source.info.rows);
  const TreeLayout layout = vipmTreeLayout(source.info);  // the 128-cell nodes
  if (layout.rootsX > 4096 || layout.rootsY > 4096)
    return makeError(source.info.path,
                     "is too large for a VIPM tileset (at most 524288 cells a side)");
  auto heights = readDem(reader, options, progress, summary);
  if (!heights) return heights.error();
  source.heights = std::move(*heights);
  summary.loadSeconds = secondsSince(start);
  auto materials = readMaterials(reader, options, progress);
  if (!materials) return materials.error();
  source.materials = std::move(*materials);
  summary.materials = uint32_t(source.materials.materials.size());
  warnAboutSource(source.info, warn);
  return source;
}

}  // namespace

Result<VipmChunkSet> openVipmChunkSet(const BuildOptions& options, Progress& progress) {
  BuildSummary summary;
  auto source = readSource(options, progress, summary, [](const std::string&) {});
  if (!source) return source.error();
  return VipmChunkSet::build(options, source->info, std::move(source->heights),
                             std::move(source->materials), summary.filledVoids, progress);
}

namespace {

// The set's blobs in node order (each followed by its texture blob, docs/format.md "Version 2:
// textures"), header and metadata through `writer`; adds the counts to `summary`.
Status writeChunkSet(TilesetWriter& writer, const VipmChunkSet& set, BuildSummary& summary) {
  const DemInfo& info = set.info();
  const BuildOptions& options = set.options();
  const TreeLayout& layout = set.layout();
  std::vector<NodeRecord> nodes = set.nodes();
  double zMin = std::numeric_limits<double>::infinity(), zMax = -zMin;
  for (size_t i = 0; i < nodes.size(); ++i) {
    NodeRecord& n = nodes[i];
    const NodeBytes bytes = set.nodeBytes(uint32_t(i));
    auto offset = writer.appendBlob(bytes.mesh());
    if (!offset) return offset.error();
    n.blobOffset = *offset;
    n.blobBytes = bytes.meshBytes;
    n.blobCrc = crc32Of(bytes.mesh());
    if (auto at = writer.appendBlob(bytes.texture()); !at) return at.error();
    n.flags |= kNodeHasTexture;
    n.textureBytes = uint32_t(bytes.texture().size());
    summary.textureBytes += n.textureBytes;
    zMin = std::min(zMin, double(n.minZ));
    zMax = std::max(zMax, double(n.maxZ));
    summary.vertices += n.vertexCount;
    summary.triangles += n.triangleCount;
  }
  summary.levels = layout.levelCount();
  summary.chunks = nodes.size();

  TilesetHeader header;
  header.version = kTilesetVersionVipm;  // with texture blobs: the normal maps
  header.flags |= kTilesetTextured;
  header.textureMinTau = kVipmTextureTau;
  header.meshKind = MeshKind::kVipm;
  header.levelCount = uint32_t(layout.levelCount());
  header.leafCells = kVipmLeafCells;
  header.rootCells = uint32_t(layout.rootCells);
  header.rootsX = uint32_t(layout.rootsX);
  header.rootsY = uint32_t(layout.rootsY);
  header.sourceColumns = uint32_t(info.columns);
  header.sourceRows = uint32_t(info.rows);
  header.spacingX = info.spacingX;
  header.spacingY = info.spacingY;
  for (size_t level = 0; level < set.levelErrors().size(); ++level)
    header.levelError[level] = set.levelErrors()[level];
  header.extentMin = {0.0, 0.0, zMin};
  header.extentMax = {layout.cellsX * info.spacingX, layout.cellsY * info.spacingY, zMax};
  header.filledVoids = summary.filledVoids;
  header.leafError = options.maxError;
  header.verticalScale = options.dem.verticalScale;
  return writer.finish(header, nodes,
                       metadataJson(info, options, summary, set.materials(), set.zStep()));
}

}  // namespace

Status writeVipmTileset(const VipmChunkSet& set, const std::string& output) {
  auto writer = TilesetWriter::create(output);
  if (!writer) return writer.error();
  BuildSummary summary = set.summary();
  summary.textureBytes = summary.vertices = summary.triangles = 0;
  return writeChunkSet(**writer, set, summary);
}

Result<BuildSummary> buildVipmTileset(const BuildOptions& options, Progress& progress,
                                      const std::function<void(const std::string&)>& warn) {
  const auto start = Clock::now();
  BuildSummary summary;
  // Fail on the output before any work.
  if (Status s = checkOptions(options); !s) return s.error();
  auto writer = TilesetWriter::create(options.output);
  if (!writer) return writer.error();
  auto source = readSource(options, progress, summary, warn);
  if (!source) return source.error();

  // Stage: the chunks.
  const auto meshStart = Clock::now();
  auto set = VipmChunkSet::build(options, source->info, std::move(source->heights),
                                 std::move(source->materials), summary.filledVoids, progress, warn);
  if (!set) return set.error();
  const BuildSummary& built = set->summary();
  summary.collapses = built.collapses;
  summary.chunkSecondsMedian = built.chunkSecondsMedian;
  summary.chunkSecondsMax = built.chunkSecondsMax;
  summary.reusedChunks = built.reusedChunks;
  if (Status s = writeChunkSet(**writer, *set, summary); !s) return s.error();
  summary.meshSeconds = secondsSince(meshStart);
  std::error_code ec;
  summary.fileBytes = std::filesystem::file_size(options.output, ec);
  summary.totalSeconds = secondsSince(start);
  return summary;
}

}  // namespace terralod
