#pragma once
// A chunk of either kind in local metres (x east, y north from the south-west sample, z the
// source's heights), with what colours it, before export_3dtiles.cpp places it on Earth.
//  - static chunks: every part, skirts included; the colour tile as JPEG and its coordinates;
//  - VIPM chunks: the finest level (leaves: the full mesh; roots and the nodes above: their
//    children's coarsest levels joined), each vertex its material's colour, and a flange
//    hanging the node's maxSkirtDepth below every border edge (the outline and the T-junctions
//    where a root joins its children), as the renderer's flanges close the cracks between
//    chunks drawn at different levels.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/node_colour.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::tiles3d {

struct LocalChunk {
  std::vector<std::array<double, 3>> positions;
  std::vector<uint32_t> indices;                ///< every triangle: surface, skirts, flanges
  std::vector<uint32_t> surface;                ///< the surface's triangles alone (for normals)
  std::vector<std::array<float, 2>> texcoords;  ///< with an image: glTF's, v from the south
  std::vector<uint8_t> image;                   ///< JPEG; empty: none
  std::vector<std::array<uint8_t, 3>> colors;   ///< linear RGB per position; empty: none
};

/// `colours`: the tileset's (a chunk may draw its part of an ancestor's texture).
Result<LocalChunk> staticLocalChunk(const TilesetReader& tileset, NodeColours& colours,
                                    uint32_t node);
Result<LocalChunk> vipmLocalChunk(const TilesetReader& tileset, uint32_t node);

/// Flanges (skirts) under every edge that only one triangle of `chunk.surface` uses, `depth`
/// metres deep, facing out: new vertices and triangles appended (colours copied).
void addBorderFlanges(LocalChunk& chunk, double depth);

}  // namespace terralod::tiles3d
