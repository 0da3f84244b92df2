#pragma once
// Texture splatting of VIPM chunks: a whole-chunk pass (depth, black; flanges coloured), then
// one pass per material over its index part, depth test EQUAL and additive blending, each
// vertex weighted one-hot by its material, colour = the material's detail texture (tileable,
// in world-space coordinates) lit by the chunk's normal map. One program for all passes
// (invariant positions). Render thread only.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "gl_object.h"
#include "terralod/core/result.h"
#include "terralod/format/tileset_metadata.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/shader_program.h"
#include "terralod/render/terrain_renderer.h"
#include "terralod/runtime/chunk_tree.h"
#include "vipm_gpu_chunk.h"

namespace terralod {

/// A chunk to draw, already at the frame's level; a blot draws in one pass with its blot
/// texture (vipm_blot.h).
struct VipmDraw {
  VipmGpuChunk* chunk = nullptr;
  uint32_t node = 0;
  float morph = 0.0f;
  bool blot = false;
};

/// Where materials fade to their average colours (from `fadeFrom` to `blotFrom` metres from
/// the eye) and blots begin (chunks whose nearest point is at least `blotFrom` away).
/// Default: never.
struct VipmBlotDistances {
  double fadeFrom = 1e30;
  double blotFrom = 2e30;
};

/// What a VipmPass draws: the splatted picture, or a material-ID image (bench's material
/// pops): each pixel's red channel holds the material with the largest weight there, as
/// vipmMaterialOfPixel (vipm_chunk_kind.h) reads it; 0 where nothing was drawn.
enum class VipmImage : uint8_t { kColour, kMaterialIds };

/// Detail textures repeat every this many grid cells.
inline constexpr double kDetailCells = 32.0;

class VipmPass {
 public:
  /// Compiles the program and makes every material's detail texture.
  static Result<VipmPass> create(std::span<const TilesetMaterial> materials);

  using Draw = VipmDraw;
  /// Draws `draws` (their chunks already at the frame's level) into the frame; adds draw
  /// calls and triangles (the whole chunk's and, with skirts on, the flanges') to `stats`.
  /// kMaterialIds leaves out the wireframe (the frame should be cleared to black, no sky).
  void draw(const FrameContext& frame, const ChunkTree& tree, std::span<const Draw> draws,
            DrawStats& stats, VipmImage image = VipmImage::kColour,
            const VipmBlotDistances& blots = {});
  /// Per material: its detail texture's linear mean colour (what blots draw).
  const std::vector<std::array<float, 3>>& averages() const { return mAverages; }

 private:
  VipmPass(ShaderProgram program, std::vector<GlTexture> details,
           std::vector<std::array<float, 3>> colors);
  void setChunk(const ChunkTree& tree, const Draw& d) const;
  // Binds a block's vertex buffers from `firstVertex` on, and its textures.
  void bindBlock(const VipmBlock& block, uint32_t firstVertex) const;
  // Draws blots of one block (two or more, by slot) in one call, with their flanges.
  void drawBlock(const ChunkTree& tree, std::span<const Draw* const> members, bool flanges,
                 DrawStats& stats) const;
  uint32_t drawRange(const VipmGpuChunk& chunk, const VipmGpuChunk::Range& range) const;

  ShaderProgram mProgram;
  GlVertexArray mVertexArray;
  std::vector<GlTexture> mDetails;              // per material
  std::vector<std::array<float, 3>> mColors;    // per material, sRGB 0..1
  std::vector<std::array<float, 3>> mAverages;  // per material, linear: its detail's mean
  std::array<int64_t, 2> mAnchor{};             // per frame: grid point positions are taken from
  std::vector<const Draw*> mBlockDraws;         // per frame: blots by block
  std::vector<uint8_t> mInBlock;                // per frame: per draw, drawn in its block's call
  mutable std::vector<uint64_t> mKey;           // per block call, kept to avoid allocating
  mutable std::vector<uint32_t> mFlangeIndices;
};

}  // namespace terralod
