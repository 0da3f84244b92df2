#pragma once
// One chunk as 3D Tiles content: a glTF 2.0 binary with one mesh of one indexed triangle
// primitive (POSITION, NORMAL, TEXCOORD_0 when textured, COLOR_0 when coloured), its vertex and
// index data quantised (KHR_mesh_quantization: positions unsigned 16-bit over the chunk's bounds,
// normals signed 8-bit, texture coordinates normalised unsigned 16-bit) and compressed with
// meshoptimizer's codecs (EXT_meshopt_compression, with a fallback buffer as the extension asks),
// the colour image (PNG or JPEG) as the material's base colour. The node's matrix undoes the
// quantisation and turns the root frame's z-up into glTF's y-up (3D Tiles turns it back). Pure:
// bytes out.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod::tiles3d {

/// Lit: a rough, non-metallic PBR material lit by the client's light. Unlit
/// (KHR_materials_unlit): the colour shown as it is, for imagery that already carries its
/// light (aerial or satellite photographs), as photogrammetry content is usually drawn.
enum class MaterialLight : uint8_t { kLit, kUnlit };

/// A chunk's mesh in the tileset's root frame (metres, z up).
struct ChunkMesh {
  std::vector<std::array<double, 3>> positions;
  std::vector<std::array<float, 3>> normals;    ///< unit; one per position
  std::vector<std::array<float, 2>> texcoords;  ///< glTF's: v down; empty without an image
  /// Per position, linear RGB 0..255 (glTF's COLOR_0, the material's base colour multiplied by
  /// it), or empty.
  std::vector<std::array<uint8_t, 3>> colors;
  std::vector<uint32_t> indices;  ///< triangles, counter-clockwise from outside
  std::vector<uint8_t> image;     ///< PNG or JPEG bytes; empty: untextured
  std::string imageMimeType;      ///< "image/png" or "image/jpeg"
  std::string name;               ///< the node's name (e.g. "chunk 12 (L2 3,1)")
  MaterialLight light = MaterialLight::kLit;
};

struct ChunkGlb {
  std::vector<uint8_t> bytes;
  std::array<double, 3> min{}, max{};  ///< the positions' bounds (root frame)
  double quantisationError = 0;        ///< largest distance from a position to its quantised one
  uint64_t uncompressedBytes = 0;      ///< the vertex and index data before meshopt
};

/// Fails when the mesh is empty, its arrays disagree in length (normals, colours), an index is
/// out of range, or
/// the image is given without texture coordinates (or its type is not PNG or JPEG).
Result<ChunkGlb> chunkGlb(const ChunkMesh& mesh);

}  // namespace terralod::tiles3d
