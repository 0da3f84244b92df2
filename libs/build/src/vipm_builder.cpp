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
#include "terralod/build/vipm_chunks.h"
#include "terralod/core/parallel.h"
#include "terralod/format/terrain_edits_json.h"
#include "terralod/format/tileset_metadata.h"
#include "terralod/format/tileset_writer.h"
#include "terralod/materials/dem_classification.h"
#include "terralod/materials/material_raster.h"
#include "terralod/materials/terrain_edits.h"
#include "terralod/raster/void_fill.h"
#include "vipm_chunk_reuse.h"

namespace terralod {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

constexpr int32_t kLeaf = int32_t(kVipmLeafCells), kRoot = int32_t(kVipmRootCells);
// The header's textureMinTau: the default --min-tau (informative; VIPM normal maps have one
// texel per grid point whatever τ).
constexpr double kVipmTextureTau = 2.0;

// A chunk's grid points along one axis: clipped at the data's far edge.
int32_t pointsFrom(int32_t first, int32_t cells, int32_t side) {
  return std::min(side, cells - first) + 1;
}

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

TreeLayout vipmLayout(const DemInfo& info) {
  TreeLayout l;
  l.cellsX = info.columns - 1;
  l.cellsY = info.rows - 1;
  l.leafCells = kLeaf;
  l.depth = 1;
  l.rootCells = kRoot;
  l.rootsX = (l.cellsX + kRoot - 1) / kRoot;
  l.rootsY = (l.cellsY + kRoot - 1) / kRoot;
  return l;
}

// The largest height range of any root's grid points.
double largestRootRange(const Heightfield& h, const TreeLayout& layout) {
  double largest = 0.0;
  for (int32_t ry = 0; ry < layout.rootsY; ++ry)
    for (int32_t rx = 0; rx < layout.rootsX; ++rx) {
      const int32_t x0 = rx * kRoot, y0 = ry * kRoot;
      const int32_t w = pointsFrom(x0, layout.cellsX, kRoot),
                    hh = pointsFrom(y0, layout.cellsY, kRoot);
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      for (int32_t y = y0; y < y0 + hh; ++y)
        for (int32_t x = x0; x < x0 + w; ++x) {
          lo = std::min(lo, h(x, y));
          hi = std::max(hi, h(x, y));
        }
      largest = std::max(largest, double(hi) - double(lo));
    }
  return largest;
}

// A built chunk's mesh fields into its node record.
void takeMeshFields(NodeRecord& n, const NodeRecord& built) {
  n.meshKind = built.meshKind;
  n.minZ = built.minZ;
  n.maxZ = built.maxZ;
  n.vertexCount = built.vertexCount;
  n.triangleCount = built.triangleCount;
}

// How far each drawn chunk's border strays from the source samples, over all its levels.
struct Deviations {
  int32_t leavesX = 0, leavesY = 0, rootsX = 0, rootsY = 0;
  std::vector<double> leaf, root, rootSeams;

  double leafAt(int32_t x, int32_t y) const {
    if (x < 0 || y < 0 || x >= leavesX || y >= leavesY) return 0.0;
    return leaf[size_t(y) * size_t(leavesX) + size_t(x)];
  }
  double rootAt(int32_t x, int32_t y) const {
    if (x < 0 || y < 0 || x >= rootsX || y >= rootsY) return 0.0;
    return root[size_t(y) * size_t(rootsX) + size_t(x)];
  }
  // A root and its leaves.
  double familyAt(int32_t x, int32_t y) const {
    double d = rootAt(x, y);
    for (int32_t k = 0; k < 4; ++k) d = std::max(d, leafAt(2 * x + (k & 1), 2 * y + (k >> 1)));
    return d;
  }
};

// maxSkirtDepth of every node (docs/format.md "Node fields"): two borders drawn side by side
// are at most their deviations apart, so a flange as deep as its own deviation plus the
// largest of any chunk that can be drawn beside it closes the gap.
void setFlangeDepths(std::vector<NodeRecord>& nodes, const Deviations& d, double zStep) {
  static constexpr int32_t kDx[4] = {1, -1, 0, 0}, kDy[4] = {0, 0, 1, -1};
  for (NodeRecord& n : nodes) {
    if (n.level == 0) continue;
    const int32_t x = int32_t(n.x), y = int32_t(n.y);
    double outside = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int32_t nx = x + kDx[k], ny = y + kDy[k];
      outside = std::max(outside, d.leafAt(nx, ny));
      if ((nx >> 1) != (x >> 1) || (ny >> 1) != (y >> 1))  // another root's
        outside = std::max(outside, d.rootAt(nx >> 1, ny >> 1));
    }
    n.maxSkirtDepth = floatAbove(d.leafAt(x, y) + outside + zStep);
  }
  for (NodeRecord& n : nodes) {
    if (n.level != 0) continue;
    const int32_t x = int32_t(n.x), y = int32_t(n.y);
    double outside = 0.0;
    for (int k = 0; k < 4; ++k) outside = std::max(outside, d.familyAt(x + kDx[k], y + kDy[k]));
    // Its children's shared sides: each side's polyline is within the seam deviation.
    const double seams = 2.0 * d.rootSeams[size_t(y) * size_t(d.rootsX) + size_t(x)];
    double depth = std::max(d.rootAt(x, y) + outside, seams) + zStep;
    for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c)
      depth = std::max(depth, double(nodes[n.firstChild + c].maxSkirtDepth));
    n.maxSkirtDepth = floatAbove(depth);
  }
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

Result<BuildSummary> buildVipmTileset(const BuildOptions& options, Progress& progress,
                                      const std::function<void(const std::string&)>& warn) {
  const auto start = Clock::now();
  if (Status s = checkOptions(options); !s) return s.error();
  BuildSummary summary;
  auto opened = DemReader::open(options.input, options.dem);
  if (!opened) return opened.error();
  const DemReader& reader = **opened;
  const DemInfo& info = reader.info();
  summary.sourceSamples = uint64_t(info.columns) * uint64_t(info.rows);
  const unsigned threads = options.threads ? options.threads : hardwareThreads();
  const TreeLayout layout = vipmLayout(info);
  if (layout.rootsX > 4096 || layout.rootsY > 4096)
    return makeError(info.path, "is too large for a VIPM tileset (at most 524288 cells a side)");
  auto writer = TilesetWriter::create(options.output);  // fail on it before any work
  if (!writer) return writer.error();

  auto heights = readDem(reader, options, progress, summary);
  if (!heights) return heights.error();
  summary.loadSeconds = secondsSince(start);
  auto materials = readMaterials(reader, options, progress);
  if (!materials) return materials.error();
  summary.materials = uint32_t(materials->materials.size());
  warnAboutSource(info, warn);

  const double rootRange = largestRootRange(*heights, layout);
  const double zStep = vipmTilesetZStep(options.maxError, rootRange);
  if (zStep > options.maxError) {  // rounding alone would take half the error budget
    char text[256];
    std::snprintf(text, sizeof text,
                  "--max-error %g m is too fine for 16-bit heights over a root's %.0f m of "
                  "relief; use at least %.3g m",
                  options.maxError, rootRange, vipmTilesetZStep(rootRange / 65000.0, rootRange));
    return makeError(info.path, text);
  }
  std::vector<NodeRecord> nodes = enumerateNodes(layout);
  const size_t rootCount = size_t(layout.rootsX) * size_t(layout.rootsY);
  const size_t leafCount = nodes.size() - rootCount;

  // Stage: the leaves, in parallel.
  const auto meshStart = Clock::now();
  VipmLeafParams params;
  params.zStep = zStep;
  params.maxError = options.maxError;
  params.rules = options.materialRules;
  params.coarsestError = options.blotError.leafError(options.maxError);
  params.compressionLevel = options.compressionLevel;
  std::vector<VipmLeaf> leaves(leafCount);
  // Every node's normal map, from the source heights (never from its mesh).
  std::vector<std::vector<uint8_t>> normalMaps(nodes.size());
  // An earlier build's chunks that no new stroke reaches (an edit), kept as they are.
  const std::optional<VipmChunkReuse> reuse = VipmChunkReuse::open(options, info, zStep);
  std::vector<uint8_t> reused(nodes.size(), 0);
  auto keep = [&](size_t i, int32_t x0, int32_t y0, int32_t w, int32_t h, auto&& reuseChunk,
                  auto& out) {
    auto old = reuse ? reuse->clean(uint32_t(i), x0, y0, w, h) : std::nullopt;
    if (!old) return false;
    auto chunk = reuseChunk(std::vector<uint8_t>(old->mesh().begin(), old->mesh().end()), *heights,
                            *materials, x0, y0, w, h, zStep);
    if (!chunk) return false;
    out = std::move(*chunk);
    normalMaps[i].assign(old->texture().begin(), old->texture().end());
    reused[i] = 1;
    return true;
  };
  progress.begin("vipm chunks", leafCount + rootCount);
  parallelFor(leafCount, threads, [&](size_t k, unsigned) {
    const size_t i = rootCount + k;
    const NodeRecord& n = nodes[i];
    const int32_t x0 = int32_t(n.x) * kLeaf, y0 = int32_t(n.y) * kLeaf;
    const int32_t w = pointsFrom(x0, layout.cellsX, kLeaf),
                  h = pointsFrom(y0, layout.cellsY, kLeaf);
    if (!keep(i, x0, y0, w, h, reuseVipmLeaf, leaves[k])) {
      leaves[k] = buildVipmLeaf(*heights, *materials, x0, y0, w, h, params);
      normalMaps[i] = buildVipmNormalMap(*heights, x0, y0, kLeaf, info.spacingX, info.spacingY);
    }
    progress.advance(1);
  });

  // The leaves' node fields, and the roots' level error: at least twice every leaf's
  // coarsest error, so that a leaf draws its coarsest level where its root takes over (and
  // levels stay ordered on flat ground too).
  Deviations deviations;
  deviations.leavesX = layout.chunksX(1);
  deviations.leavesY = layout.chunksY(1);
  deviations.rootsX = layout.rootsX;
  deviations.rootsY = layout.rootsY;
  deviations.leaf.assign(size_t(deviations.leavesX) * size_t(deviations.leavesY), 0.0);
  deviations.root.assign(rootCount, 0.0);
  deviations.rootSeams.assign(rootCount, 0.0);
  double largestCoarsest = 0.0;
  std::vector<double> leafSeconds;
  for (size_t k = 0; k < leafCount; ++k) {
    NodeRecord& n = nodes[rootCount + k];
    const VipmLeaf& leaf = leaves[k];
    takeMeshFields(n, leaf.node);
    deviations.leaf[size_t(n.y) * size_t(deviations.leavesX) + n.x] = leaf.borderDeviation;
    largestCoarsest = std::max(largestCoarsest, double(leaf.coarsest.error));
    summary.collapses += leaf.collapses;
    if (!reused[rootCount + k]) leafSeconds.push_back(leaf.seconds);
  }
  const double rootLevelError = 2.0 * std::max(largestCoarsest, options.maxError);

  // Stage: the roots, blot chunks from their children's coarsest levels.
  std::vector<VipmRoot> roots(rootCount);
  parallelFor(rootCount, threads, [&](size_t r, unsigned) {
    const NodeRecord& n = nodes[r];
    std::vector<const CoarseMesh*> children;
    for (uint32_t c = 0; c < uint32_t(std::popcount(unsigned(n.childMask))); ++c)
      children.push_back(&leaves[n.firstChild + c - rootCount].coarsest);
    const int32_t x0 = int32_t(n.x) * kRoot, y0 = int32_t(n.y) * kRoot;
    const int32_t w = pointsFrom(x0, layout.cellsX, kRoot),
                  h = pointsFrom(y0, layout.cellsY, kRoot);
    // Kept only while the roots' level error (every root's error floor) is what it was.
    if (!(reuse && reuse->rootLevelError() == rootLevelError &&
          keep(r, x0, y0, w, h, reuseVipmRoot, roots[r]))) {
      roots[r] = buildVipmRoot(*heights, *materials, children, x0, y0, w, h, zStep, rootLevelError,
                               options.compressionLevel);
      normalMaps[r] = buildVipmNormalMap(*heights, x0, y0, kRoot, info.spacingX, info.spacingY);
    }
    progress.advance(1);
  });
  progress.end();
  for (size_t r = 0; r < rootCount; ++r) {
    NodeRecord& n = nodes[r];
    const VipmRoot& root = roots[r];
    takeMeshFields(n, root.node);
    const size_t at = size_t(n.y) * size_t(layout.rootsX) + n.x;
    deviations.root[at] = root.borderDeviation;
    deviations.rootSeams[at] = root.seamDeviation;
    summary.collapses += root.collapses;
  }
  setFlangeDepths(nodes, deviations, zStep);

  // The blobs in node order.
  double zMin = std::numeric_limits<double>::infinity(), zMax = -zMin;
  for (size_t i = 0; i < nodes.size(); ++i) {
    NodeRecord& n = nodes[i];
    const std::vector<uint8_t>& blob = i < rootCount ? roots[i].blob : leaves[i - rootCount].blob;
    auto offset = (*writer)->appendBlob(blob);
    if (!offset) return offset.error();
    n.blobOffset = *offset;
    n.blobBytes = uint32_t(blob.size());
    n.blobCrc = crc32Of(blob);
    // The texture blob right after it (docs/format.md "Version 2: textures").
    if (auto at = (*writer)->appendBlob(normalMaps[i]); !at) return at.error();
    n.flags |= kNodeHasTexture;
    n.textureBytes = uint32_t(normalMaps[i].size());
    summary.textureBytes += n.textureBytes;
    zMin = std::min(zMin, double(n.minZ));
    zMax = std::max(zMax, double(n.maxZ));
    summary.vertices += n.vertexCount;
    summary.triangles += n.triangleCount;
  }
  summary.meshSeconds = secondsSince(meshStart);
  if (!leafSeconds.empty()) {
    std::sort(leafSeconds.begin(), leafSeconds.end());
    summary.chunkSecondsMedian = leafSeconds[leafSeconds.size() / 2];
    summary.chunkSecondsMax = leafSeconds.back();
  }
  summary.levels = 2;
  summary.chunks = nodes.size();
  summary.reusedChunks = uint64_t(std::count(reused.begin(), reused.end(), uint8_t{1}));

  TilesetHeader header;
  header.version = 2;  // with texture blobs: the normal maps
  header.flags |= kTilesetTextured;
  header.textureMinTau = kVipmTextureTau;
  header.meshKind = MeshKind::kVipm;
  header.levelCount = 2;
  header.leafCells = kVipmLeafCells;
  header.rootCells = kVipmRootCells;
  header.rootsX = uint32_t(layout.rootsX);
  header.rootsY = uint32_t(layout.rootsY);
  header.sourceColumns = uint32_t(info.columns);
  header.sourceRows = uint32_t(info.rows);
  header.spacingX = info.spacingX;
  header.spacingY = info.spacingY;
  header.levelError[0] = rootLevelError;
  header.levelError[1] = options.maxError;
  header.extentMin = {0.0, 0.0, zMin};
  header.extentMax = {layout.cellsX * info.spacingX, layout.cellsY * info.spacingY, zMax};
  header.filledVoids = summary.filledVoids;
  header.leafError = options.maxError;
  header.verticalScale = options.dem.verticalScale;
  if (Status s =
          (*writer)->finish(header, nodes, metadataJson(info, options, summary, *materials, zStep));
      !s)
    return s.error();
  std::error_code ec;
  summary.fileBytes = std::filesystem::file_size(options.output, ec);
  summary.totalSeconds = secondsSince(start);
  return summary;
}

}  // namespace terralod
