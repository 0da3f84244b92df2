#pragma once
// The terralod tileset file, versions 1 to 6. docs/format.md is the normative description;
// this header mirrors it. Little-endian throughout. Version 2 adds per-chunk textures (a
// texture blob right after each chunk's geometry blob); version 3 is version 2 with the
// texture blobs' blocks zstd-compressed; version 4 is version 3 whose chunk blobs may leave
// the skirts to the reader (chunk payload version 2), textured or not; version 5 lets chunks
// draw an ancestor's texture, and version 6 stores a shade layer in place of the generated colour.
//
//   [0, 512)            header (fixed size, CRC-protected)
//   [512, ...)          chunk blobs, each readable with one read at a known offset
//   nodeTableOffset     node table: nodeCount records of nodeRecordBytes each
//   metadataOffset      JSON metadata (source, build parameters, statistics)

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

inline constexpr char kTilesetMagic[8] = {'T', 'E', 'R', 'R', 'A', 'L', 'O', 'D'};
inline constexpr uint32_t kTilesetVersion = 7;  ///< the newest version this code reads
/// What static tilesets without textures are written as: version 3 with chunk payloads of
/// version 2 (skirts derived by the reader). Textured static tilesets are written as version 5
/// (version 4 whose chunks may draw an ancestor's texture); VIPM tilesets as version 2 (raw
/// texture blobs); version 1 is no longer written.
inline constexpr uint32_t kTilesetVersionStatic = 4;
inline constexpr uint32_t kTilesetVersionStaticTextured = 5;
/// Textured static tilesets whose generated colour is made by the shader (version 6: version 5
/// whose texture blobs hold a shade layer, BC4, instead of colour; metadata "texture":
/// "color_layer": "shade" and "snow_line").
inline constexpr uint32_t kTilesetVersionStaticShaded = 6;
/// Static tilesets whose RTIN chunks are stored as their bintree (version 7: any of versions 4
/// to 6 whose chunk blobs may be payload version 3, rtin_chunk_codec.h); the default.
inline constexpr uint32_t kTilesetVersionBintreeChunks = 7;
inline constexpr uint32_t kTilesetVersionVipm = 2;
inline constexpr uint32_t kHeaderBytes = 512;
inline constexpr uint32_t kNodeRecordBytes = 64;
/// zstd level of version 4's node table (written once per tileset; higher levels gain ~3 %).
inline constexpr int kNodeTableCompressionLevel = 3;
inline constexpr int kMaxLevels = 16;
inline constexpr uint32_t kNoNode = 0xFFFFFFFFu;

/// How a chunk's geometry is stored. The runtime dispatches on it; new kinds (e.g. progressive
/// VIPM chunks) get new values.
enum class MeshKind : uint8_t {
  kStaticRtin = 1,  ///< static RTIN mesh with per-vertex morph deltas and skirts
  kVipm = 2,        ///< a VIPM chunk blob (vipm_chunk_codec.h); docs/format.md "VIPM tilesets"
};

/// VIPM tilesets (docs/format.md "VIPM tilesets"): two levels, fallback roots of 128 cells over
/// progressive-mesh leaves of 64 cells.
inline constexpr uint32_t kVipmLeafCells = 64;
inline constexpr uint32_t kVipmRootCells = 128;

/// TilesetHeader::flags (version 2).
inline constexpr uint32_t kTilesetTextured = 1u;  ///< every node has a texture blob
/// NodeRecord::flags (version 2).
inline constexpr uint8_t kNodeHasTexture = 1u;
/// NodeRecord::flags (version 5, textured): the chunk has no texture blob of its own and draws
/// its parent's texture over its quarter of the parent's square (recursively: the texture of
/// the nearest ancestor that has one). The builder sets it where the parent's tiles hold the
/// children's texels unresampled, so the chunk shows exactly the texels it would have stored.
inline constexpr uint8_t kNodeInheritsTexture = 2u;

struct TilesetHeader {
  uint32_t version = kTilesetVersionStatic;
  uint32_t flags = 0;
  MeshKind meshKind = MeshKind::kStaticRtin;
  uint32_t levelCount = 0;
  uint32_t leafCells = 0;
  uint32_t rootCells = 0;
  uint32_t rootsX = 0, rootsY = 0;
  uint32_t sourceColumns = 0, sourceRows = 0;
  double spacingX = 1.0, spacingY = 1.0;           ///< metres per cell
  std::array<double, kMaxLevels> levelError{};     ///< root first; levelCount entries used
  std::array<double, 3> extentMin{}, extentMax{};  ///< world metres
  uint64_t nodeCount = 0;
  uint64_t nodeTableOffset = 0, nodeTableBytes = 0;
  uint64_t metadataOffset = 0, metadataBytes = 0;
  uint64_t fileBytes = 0;
  uint64_t filledVoids = 0;
  uint32_t nodeTableCrc = 0, metadataCrc = 0;
  double leafError = 0.0;      ///< --max-error the tileset was built with
  double verticalScale = 1.0;  ///< applied to source heights
  double textureMinTau = 0.0;  ///< version 2, textured: the τ textures were sized for (eq. 7)

  bool textured() const { return (flags & kTilesetTextured) != 0; }

  int32_t depth() const { return int32_t(levelCount) - 1; }
  int32_t chunkCells(int32_t level) const { return int32_t(rootCells >> level); }
};

/// One chunk of the tree. Nodes are stored breadth-first: all roots (row-major), then level 1,
/// and so on; a node's children are consecutive from firstChild in SW, SE, NW, NE order,
/// skipping absent ones (childMask bit i set = child i exists).
struct NodeRecord {
  uint8_t level = 0;
  uint8_t childMask = 0;
  MeshKind meshKind = MeshKind::kStaticRtin;
  uint8_t flags = 0;
  uint32_t x = 0,
           y = 0;  ///< chunk index at its level; the square starts at cell (x, y) * chunkCells
  uint32_t firstChild = kNoNode;
  uint32_t parent = kNoNode;
  float minZ = 0, maxZ = 0;    ///< drawn surface over its whole morph range (skirts excluded)
  uint32_t vertexCount = 0;    ///< surface vertices (skirt vertices excluded)
  uint32_t triangleCount = 0;  ///< surface triangles
  uint32_t skirtTriangleCount = 0;
  uint64_t blobOffset = 0;
  uint32_t blobBytes = 0;
  uint32_t blobCrc = 0;  ///< CRC-32 of the stored blob bytes
  float maxSkirtDepth = 0;
  uint32_t textureBytes = 0;  ///< version 2: texture blob length, at blobOffset + blobBytes

  bool hasTexture() const { return (flags & kNodeHasTexture) != 0; }
  bool inheritsTexture() const { return (flags & kNodeInheritsTexture) != 0; }
};

/// Where a node's texture comes from: `owner`'s texture blob, over the square of side
/// 1 / 2^depth at (column, row) of that square's cells (south-west first, as chunk x and y).
/// owner == node, depth 0 for a node with its own texture.
struct TextureSource {
  uint32_t owner = kNoNode;
  uint32_t depth = 0;
  uint32_t column = 0, row = 0;
};

/// The texture a node draws: its own, or its nearest ancestor's that has one
/// (kNodeInheritsTexture). owner is kNoNode for a tileset without textures.
TextureSource textureSourceOf(const std::vector<NodeRecord>& nodes, uint32_t node);

/// CRC-32 (zlib polynomial) of a byte range.
uint32_t crc32Of(std::span<const uint8_t> bytes);
/// The CRC-32 of bytes whose start had `crc`, followed by `bytes` (crc32Of in pieces).
uint32_t crc32Continue(uint32_t crc, std::span<const uint8_t> bytes);

std::vector<uint8_t> serializeHeader(const TilesetHeader& header);
/// Validates magic, version, size fields and CRC; `subject` names the file in errors.
Result<TilesetHeader> parseHeader(std::span<const uint8_t> bytes, const std::string& subject);

void serializeNode(const NodeRecord& node, uint8_t* out);
/// `version` is the file's: fields a version reserves are not read.
NodeRecord parseNode(const uint8_t* in, uint32_t version);

/// The node table as a file of `version` stores it: up to version 3 the records one after
/// another; from version 4 one zstd frame of the same bytes shuffled (byte 0 of every record,
/// then byte 1, and so on), which puts alike bytes together.
std::vector<uint8_t> encodeNodeTable(const std::vector<NodeRecord>& nodes, uint32_t version);
/// The records of a stored node table (its CRC already checked); `header` says how many and
/// which version.
Result<std::vector<NodeRecord>> decodeNodeTable(std::span<const uint8_t> stored,
                                                const TilesetHeader& header,
                                                const std::string& subject);

/// Checks the node table's structure: levels, parent/child links, ranges inside the file.
Status validateNodes(const TilesetHeader& header, const std::vector<NodeRecord>& nodes,
                     const std::string& subject);

}  // namespace terralod
