#pragma once
// A chunk's stored bytes, whatever its mesh kind: what one range read of a node returns.

#include <cstdint>
#include <span>
#include <vector>

namespace terralod {

struct NodeBytes {
  std::vector<uint8_t> bytes;  ///< the mesh blob, then (textured tilesets) the texture blob
  uint32_t meshBytes = 0;      ///< length of the mesh blob at the start of `bytes`

  /// The mesh blob (its CRC checked by the reader).
  std::span<const uint8_t> mesh() const { return std::span(bytes).first(meshBytes); }
  /// The texture blob (carries its own checksums); empty when the node has none.
  std::span<const uint8_t> texture() const { return std::span(bytes).subspan(meshBytes); }
};

}  // namespace terralod
