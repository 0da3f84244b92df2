#include "build_steps.h"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "source_metadata.h"
#include "terralod/build/surface_texels.h"
#include "terralod/raster/image_drape.h"
#include "terralod/raster/void_fill.h"

namespace terralod {

bool streamsInput(const BuildOptions& options, const DemInfo& info) {
  const uint64_t samples = uint64_t(info.columns) * uint64_t(info.rows);
  const bool fitsMemory = samples * sizeof(float) <= options.memoryMB << 20;
  return options.streaming == Streaming::kAlways ||
         (options.streaming == Streaming::kAuto &&
          (!fitsMemory || samples > options.streamAboveSamples) &&
          info.encoding == HeightEncoding::kPlain);
}

std::array<double, 2> guessHeightRange(const DemReader& reader) {
  auto estimate = reader.approximateHeightRange();
  if (!estimate) return {0.0, 0.0};
  const double span = (*estimate)[1] - (*estimate)[0];
  return {(*estimate)[0] - 0.25 * span - 50.0, (*estimate)[1] + 0.25 * span + 50.0};
}

ChunkPayloadVersion chunkPayloadOf(const BuildOptions& options) {
  return options.chunkCodec == ChunkCodec::kBintree ? ChunkPayloadVersion::kRtinCoded
                                                    : ChunkPayloadVersion::kDerivedSkirts;
}

bool storesShade(const BuildOptions& options) {
  return options.textures && options.textureImage.empty() &&
         options.generatedColour == GeneratedColour::kShader;
}

SourceFacts sourceFactsOf(const DemReader& reader, const ImageDrape* image) {
  SourceFacts facts;
  facts.info = reader.info();
  facts.rowLatitudes = reader.gridRowLatitudes();
  facts.imageRefine = image ? image->refine() : 0;
  return facts;
}

TextureBuild textureBuildFor(const BuildOptions& options, const TreeLayout& layout,
                             const ErrorBudget& budget, const SourceFacts& source,
                             const ImageDrape* image) {
  const DemInfo& info = source.info;
  TextureBuild textures;
  textures.plan = planTextures(layout, budget.levelError, info.spacingX, info.spacingY,
                               options.textureTau, std::max(1u, source.imageRefine));
  if (options.textureSharing == TextureSharing::kEveryChunk)
    for (TextureLevel& level : textures.plan) level.inherited = false;
  textures.surface.spacingX = info.spacingX;
  textures.surface.spacingY = info.spacingY;
  textures.surface.columns = info.columns;
  textures.surface.rows = info.rows;
  textures.surface.rowLatitudes = std::make_shared<const std::vector<double>>(source.rowLatitudes);
  textures.image = image;
  textures.colourKind = storesShade(options) ? TextureLayerKind::kShade : TextureLayerKind::kColor;
  textures.zstdLevel = options.compressionLevel;
  if (textures.colourKind == TextureLayerKind::kShade) halveColourTiles(textures.plan);
  return textures;
}

void summarizeNodes(const std::vector<NodeRecord>& nodes, BuildSummary& summary) {
  for (const NodeRecord& n : nodes) {
    summary.textureBytes += n.textureBytes;
    summary.vertices += n.vertexCount;
    summary.triangles += n.triangleCount;
    summary.skirtTriangles += n.skirtTriangleCount;
  }
  summary.chunks = nodes.size();
}

void markInheritedTextures(const std::vector<TextureLevel>& plan, std::vector<NodeRecord>& nodes) {
  for (NodeRecord& n : nodes)
    if (n.level < plan.size() && plan[n.level].inherited) n.flags |= kNodeInheritsTexture;
}

TilesetHeader staticHeader(const DemInfo& info, const BuildOptions& options,
                           const TreeLayout& layout, const ErrorBudget& budget, double zMin,
                           double zMax, uint64_t filledVoids) {
  TilesetHeader header;
  header.levelCount = uint32_t(layout.levelCount());
  header.leafCells = uint32_t(layout.leafCells);
  header.rootCells = uint32_t(layout.rootCells);
  header.rootsX = uint32_t(layout.rootsX);
  header.rootsY = uint32_t(layout.rootsY);
  header.sourceColumns = uint32_t(info.columns);
  header.sourceRows = uint32_t(info.rows);
  header.spacingX = info.spacingX;
  header.spacingY = info.spacingY;
  for (int32_t l = 0; l < layout.levelCount(); ++l)
    header.levelError[size_t(l)] = budget.levelError[size_t(l)];
  header.extentMin = {0.0, 0.0, zMin};
  header.extentMax = {layout.cellsX * info.spacingX, layout.cellsY * info.spacingY, zMax};
  header.filledVoids = filledVoids;
  header.leafError = options.maxError;
  header.verticalScale = options.dem.verticalScale;
  header.version = kTilesetVersionStatic;
  if (options.textures) {
    header.version =
        storesShade(options) ? kTilesetVersionStaticShaded : kTilesetVersionStaticTextured;
    header.flags |= kTilesetTextured;
    header.textureMinTau = options.textureTau;
  }
  // Version 7 holds any of 4 to 6 with RTIN-coded chunks.
  if (options.chunkCodec == ChunkCodec::kBintree) header.version = kTilesetVersionBintreeChunks;
  return header;
}

std::string tilesetMetadataJson(const DemInfo& info, const BuildOptions& options,
                                const BuildSummary& s, const TreeLayout& layout,
                                const TextureBuild* textures) {
  const nlohmann::json source = sourceMetadata(info);
  nlohmann::json j = {
      {"generator", "terralod"},
      {"source", source},
      {"build",
       {{"max_error", options.maxError},
        {"chunk_cells", layout.leafCells},
        {"vertical_scale", options.dem.verticalScale},
        {"zstd_level", options.compressionLevel}}},
      {"stats",
       {{"vertices", s.vertices},
        {"triangles", s.triangles},
        {"skirt_triangles", s.skirtTriangles},
        {"filled_voids", s.filledVoids}}},
  };
  if (options.mesher == MeshMethod::kGreedy) {
    j["build"]["mesher"] = "greedy";
    j["build"]["morph_gap"] = kGreedyMorphGap;
  }
  if (textures) {
    nlohmann::json levels = nlohmann::json::array();
    for (const TextureLevel& t : textures->plan)
      levels.push_back({{"color_size", t.colorSize},
                        {"normal_size", t.normalSize},
                        {"color_source_limited", t.colorFlags != 0},
                        {"normal_source_limited", t.normalFlags != 0},
                        {"inherited", t.inherited}});
    j["texture"] = {
        {"color", options.textureImage.empty()
                      ? "generated"
                      : std::filesystem::path(options.textureImage).filename().string()},
        {"min_tau", options.textureTau},
        {"color_refine", s.textureRefine ? s.textureRefine : 1},
        {"bytes", s.textureBytes},
        {"levels", levels}};
    // Where the generated colour's snow line comes from (surface_texels.h).
    const auto& latitudes = textures->surface.rowLatitudes;
    if (latitudes && !latitudes->empty()) {
      const auto [lo, hi] = std::minmax_element(latitudes->begin(), latitudes->end());
      j["texture"]["latitude"] = {*lo, *hi};
    } else {
      j["texture"]["latitude_assumed"] = kUnknownLatitude;
    }
    if (textures->colourKind == TextureLayerKind::kShade) {
      j["texture"]["color_layer"] = "shade";
      const uint32_t rows = uint32_t(std::max(1, textures->surface.rows));
      j["texture"]["snow_line"] = {
          {"last_row", rows - 1},
          {"metres",
           snowLineSamples(
               latitudes ? std::span<const double>(*latitudes) : std::span<const double>(), rows)}};
    }
    if (textures->surface.seaVoids) j["texture"]["sea_voids"] = textures->surface.seaVoids->count();
  }
  return j.dump(2);
}

}  // namespace terralod
