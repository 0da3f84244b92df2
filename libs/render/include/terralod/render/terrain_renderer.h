#pragma once
// Draws a selection of chunks: one multi-draw-indirect call per texture array pair (a few per
// frame; gl_DrawIDARB picks each draw's placement), the morph in the vertex shader, skirts on or
// off, shaded relief or diagnostic colours, a sky behind. Render thread only; create and destroy it
// where its GlContext is current.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "terralod/core/result.h"
#include "terralod/render/gpu_chunk_store.h"
#include "terralod/render/shader_program.h"
#include "terralod/runtime/chunk_tree.h"
#include "terralod/runtime/selection.h"
#include "terralod/runtime/view.h"

namespace terralod {

enum class ColorBy { kRelief, kLevel, kMorph };

/// The near plane's distance from the eye (reversed-Z, no far plane).
inline constexpr double kNearPlaneMetres = 0.05;

struct TerrainStyle {
  ColorBy colorBy = ColorBy::kRelief;
  bool wireframe = false;  ///< draw triangle edges over the surface
  bool skirts = true;
  bool textures = true;     ///< false: ignore chunk textures, light from the drawn geometry
  bool sky = true;          ///< false: empty pixels keep exactly the background colour
  bool chunkBoxes = false;  ///< outline each drawn chunk's bounding box, coloured by level
  std::array<uint8_t, 3> background{0x9C, 0xC3, 0xE6};  ///< sRGB; the sky overhead
  double sunAzimuthDegrees = 315.0;                     ///< clockwise from north
  double sunElevationDegrees = 40.0;
};

struct DrawStats {
  uint32_t chunks = 0;        ///< selected chunks that were on the GPU and drawn
  uint32_t missing = 0;       ///< selected chunks not in the store (skipped)
  uint32_t drawCalls = 0;     ///< GL draw calls issued (multi-draws count once)
  uint32_t drawCommands = 0;  ///< indirect commands in them
  uint64_t triangles = 0;     ///< triangles drawn, skirts included when on
};

class TerrainRenderer {
 public:
  /// Compiles the shaders.
  static Result<TerrainRenderer> create();
  ~TerrainRenderer();
  TerrainRenderer(TerrainRenderer&& other) noexcept;
  TerrainRenderer& operator=(TerrainRenderer&&) = delete;
  TerrainRenderer(const TerrainRenderer&) = delete;
  TerrainRenderer& operator=(const TerrainRenderer&) = delete;

  /// The tileset's texture sizes per level (root first), for sampling mips where the builder
  /// put their texels (texture_placement.h). Without them GL's own sampling is used.
  void setTextureSizes(std::span<const uint32_t> colorSizes, std::span<const uint32_t> normalSizes);

  /// Clears the bound framebuffer (viewport: the view's size) and draws the selected chunks
  /// of `tree` that `store` holds.
  DrawStats draw(const View& view, const ChunkTree& tree, std::span<const SelectedChunk> selection,
                 const GpuChunkStore& store, const TerrainStyle& style);

 private:
  TerrainRenderer(std::vector<ShaderProgram> terrain, ShaderProgram sky, ShaderProgram boxes);
  void drawBoxes(const View& view, const ChunkTree& tree, std::span<const SelectedChunk> selection,
                 const GpuChunkStore& store, const glm::mat4& viewProjection);

  // The terrain program for each piecewise mask (mPiecewise's bits), then sky and boxes.
  std::vector<ShaderProgram> mTerrain;
  ShaderProgram mSky, mBoxes;
  uint32_t mBoxArray = 0, mBoxBuffer = 0;
  uint64_t mBoxBufferBytes = 0;
  std::vector<float> mBoxLines;
  uint32_t mVertexArray = 0, mDrawBuffer = 0, mIndirectBuffer = 0, mPlacementBuffer = 0;
  // Per level (root first): bit 0 when its colour mips need piecewise sampling, bit 1 its
  // normal mips. Draws are grouped by it and drawn with the program variant for it.
  std::vector<uint8_t> mPiecewise;
  uint64_t mDrawBufferBytes = 0, mIndirectBufferBytes = 0;
  uint32_t mBoundVertexBuffer = 0;
  // Per-frame staging, kept to avoid allocating once they are big enough.
  struct PendingDraw {
    uint64_t group = 0;      // colour array << 32 | normal array; all ones: untextured
    uint32_t piecewise = 0;  // mPiecewise of the chunk's level when textured
    uint32_t colorSize = 0, normalSize = 0;
    std::array<float, 16> draw{};
    std::array<uint32_t, 5> command{};
  };
  std::vector<PendingDraw> mPending;
  std::vector<float> mDraws;
  std::vector<uint32_t> mCommands;
};

}  // namespace terralod
