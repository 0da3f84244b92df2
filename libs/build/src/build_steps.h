#pragma once
// Steps a local build and a staged (cluster) build share, so both make the same bytes: whether
// the input is streamed, the height range an estimate-based budget starts from, and the file's
// header, statistics and metadata.

#include <array>
#include <string>
#include <vector>

#include "terralod/build/build_plan.h"
#include "terralod/build/builder.h"
#include "terralod/build/error_budget.h"
#include "terralod/build/texture_pass.h"
#include "terralod/build/tree_layout.h"
#include "terralod/format/tileset_format.h"
#include "terralod/raster/dem_reader.h"

namespace terralod {

class ImageDrape;

/// Whether a local build reads the input in windows (else whole, into memory).
bool streamsInput(const BuildOptions& options, const DemInfo& info);

/// The height range a streamed build's budget starts from: the reader's estimate widened by a
/// quarter of its span and 50 m each way ({0, 0} without an estimate). Checked once every
/// sample has been seen; a second attempt uses the true range.
std::array<double, 2> guessHeightRange(const DemReader& reader);

/// Whether a build stores the shade layer (the generated colour made in the shader, version 6)
/// rather than a colour layer.
bool storesShade(const BuildOptions& options);
/// How the build's static chunks are stored (BuildOptions::chunkCodec).
ChunkPayloadVersion chunkPayloadOf(const BuildOptions& options);

/// What the texture pass needs to know of the raster and the draped image (null: none).
SourceFacts sourceFactsOf(const DemReader& reader, const ImageDrape* image);

/// The texture pyramid's plan and the generated colour's inputs (without sea voids, which only
/// an in-memory build with voids knows). `image` is the draped image the blocks' texels are
/// made from: null in a stage that makes none (source.imageRefine still says what it is).
TextureBuild textureBuildFor(const BuildOptions& options, const TreeLayout& layout,
                             const ErrorBudget& budget, const SourceFacts& source,
                             const ImageDrape* image);

/// Vertex, triangle and texture totals of the built nodes.
void summarizeNodes(const std::vector<NodeRecord>& nodes, BuildSummary& summary);
/// Flags the nodes of the plan's inherited levels (kNodeInheritsTexture): they were written
/// without a texture blob and draw their parent's.
void markInheritedTextures(const std::vector<TextureLevel>& plan, std::vector<NodeRecord>& nodes);

TilesetHeader staticHeader(const DemInfo& info, const BuildOptions& options,
                           const TreeLayout& layout, const ErrorBudget& budget, double zMin,
                           double zMax, uint64_t filledVoids);

std::string tilesetMetadataJson(const DemInfo& info, const BuildOptions& options,
                                const BuildSummary& s, const TreeLayout& layout,
                                const TextureBuild* textures);

}  // namespace terralod
