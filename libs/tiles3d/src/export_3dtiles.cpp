#include "terralod/tiles3d/export_3dtiles.h"

#include <stb_image_write.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "terralod/core/atomic_file.h"
#include "terralod/format/chunk_position.h"
#include "terralod/format/texture_decode.h"
#include "terralod/measure/export_mesh.h"
#include "terralod/raster/earth_placement.h"
#include "terralod/tiles3d/chunk_glb.h"
#include "terralod/tiles3d/tileset_json.h"

namespace terralod::tiles3d {
namespace {

namespace fs = std::filesystem;

// The chunk's colour tile as JPEG (rows as stored: the southern first, which glTF's v = 0
// addresses), or empty when it has none.
Result<std::vector<uint8_t>> colourJpeg(const ChunkData& chunk, const std::string& subject,
                                        uint32_t& size) {
  const TextureLayer* color =
      chunk.texture ? chunk.texture->find(TextureLayerKind::kColor) : nullptr;
  if (!color) return std::vector<uint8_t>{};
  if (color->encoding != TextureEncoding::kBc1)
    return makeError(subject, "colour texture is not BC1");
  size = color->size;
  const std::vector<uint8_t> rgb = decodeBc1Rgb(color->mips[0], size);
  if (rgb.empty()) return makeError(subject, "colour texture cannot be decoded");
  std::vector<uint8_t> jpeg;
  const auto sink = [](void* context, void* data, int n) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    const auto* p = static_cast<const uint8_t*>(data);
    out->insert(out->end(), p, p + n);
  };
  if (!stbi_write_jpg_to_func(sink, &jpeg, int(size), int(size), 3, rgb.data(), 90))
    return makeError(subject, "colour texture cannot be encoded as JPEG");
  return jpeg;
}

}  // namespace

Result<ExportSummary> export3dTiles(const TilesetReader& tileset, const std::string& dir,
                                    Progress& progress,
                                    const std::function<void(const std::string&)>& warn) {
  const TilesetHeader& h = tileset.header();
  if (h.meshKind != MeshKind::kStaticRtin)
    return makeError(tileset.name(), "3D Tiles export takes static tilesets (VIPM: not yet)");
  std::error_code ec;
  if (fs::exists(dir, ec) && !(fs::is_directory(dir, ec) && fs::is_empty(dir, ec)))
    return makeError(dir, "exists and is not an empty directory");
  const std::string partial = fs::path(dir).lexically_normal().string() + ".partial";
  fs::remove_all(partial, ec);
  if (!fs::create_directories(partial, ec) || ec)
    return makeError(partial, "cannot be created (" + ec.message() + ")");
  // Whatever fails from here leaves nothing behind.
  struct RemoveUnlessDone {
    std::string path;
    bool done = false;
    ~RemoveUnlessDone() {
      std::error_code ignored;
      if (!done) fs::remove_all(path, ignored);
    }
  } cleanup{partial};

  ExportSummary summary;
  const SourceGrid grid = sourceGridOf(h, tileset.metadata());
  auto placed = EarthPlacement::of(grid, tileset.name());
  EarthPlacement placement =
      placed.ok() ? std::move(placed).value()
                  : EarthPlacement::tangentPlane(kDefaultLongitude, kDefaultLatitude);
  if (!placed.ok()) {
    summary.placed = false;
    if (warn)
      warn(placed.error().message + "; placed on a plane tangent to the ellipsoid at longitude " +
           std::to_string(int(kDefaultLongitude)) + ", latitude " +
           std::to_string(int(kDefaultLatitude)));
  }
  const double cx = 0.5 * (h.extentMin[0] + h.extentMax[0]);
  const double cy = 0.5 * (h.extentMin[1] + h.extentMax[1]);
  const double cz = 0.5 * (h.extentMin[2] + h.extentMax[2]);
  auto root = placement.frameAt(cx, cy, cz);
  if (!root) return root.error();
  const glm::dmat4 toRoot = glm::inverse(*root);
  const glm::dmat3 toRootNormal = glm::transpose(glm::inverse(glm::dmat3(toRoot)));

  const auto& nodes = tileset.nodes();
  std::vector<ExportTile> tiles(nodes.size());
  progress.begin("3D Tiles", nodes.size());
  for (uint32_t i = 0; i < nodes.size(); ++i) {
    const NodeRecord& record = nodes[i];
    const std::string subject = tileset.name() + " chunk " + std::to_string(i);
    auto chunk = tileset.readChunkData(i);
    if (!chunk) return chunk.error();
    ChunkMesh mesh;
    mesh.name = "chunk " + std::to_string(i) + " (level " + std::to_string(record.level) + ", " +
                std::to_string(record.x) + ", " + std::to_string(record.y) + ")";
    // Local positions (metres, from the south-west sample), all parts, skirts included.
    std::vector<std::array<double, 3>> local;
    std::vector<std::array<float, 3>> localFloat;
    std::vector<uint32_t> surface;
    for (const ChunkPart& part : chunk->geometry.parts) {
      const uint32_t base = uint32_t(local.size());
      for (const ChunkVertex& v : part.vertices) {
        local.push_back(chunkWorldPosition(h, record, chunk->geometry, v));
        localFloat.push_back({float(local.back()[0] - cx), float(local.back()[1] - cy),
                              float(local.back()[2] - cz)});
      }
      for (size_t k = 0; k < part.indices.size(); ++k) {
        mesh.indices.push_back(base + part.indices[k]);
        if (k < part.surfaceIndexCount) surface.push_back(base + part.indices[k]);
      }
    }
    if (mesh.indices.empty()) return makeError(subject, "has no triangles");
    // Normals from the surface triangles (skirt vertices, in none, point straight up), local
    // then through the chunk's frame and into the root frame.
    std::vector<std::array<float, 3>> normals = angleWeightedNormals(localFloat, surface);
    const double nodeZ = 0.5 * (record.minZ + record.maxZ);
    const auto [ox, oy] = chunkCellOrigin(h, record);
    const double side = h.chunkCells(record.level);
    auto frame = placement.frameAt((double(ox) + 0.5 * side) * h.spacingX,
                                   (double(oy) + 0.5 * side) * h.spacingY, nodeZ);
    if (!frame) return frame.error();
    const glm::dmat3 toEarthNormal = glm::transpose(glm::inverse(glm::dmat3(*frame)));
    for (auto& n : normals) {
      glm::dvec3 v(n[0], n[1], n[2]);
      if (!(glm::dot(v, v) > 0.5)) v = glm::dvec3(0, 0, 1);
      v = toRootNormal * (toEarthNormal * v);
      v /= std::sqrt(glm::dot(v, v));
      mesh.normals.push_back({float(v.x), float(v.y), float(v.z)});
    }
    // Texture coordinates: the tile's texels are edge-aligned over the chunk's square.
    uint32_t size = 0;
    auto jpeg = colourJpeg(*chunk, subject, size);
    if (!jpeg) return jpeg.error();
    if (!jpeg->empty()) {
      mesh.image = std::move(jpeg).value();
      mesh.imageMimeType = "image/jpeg";
      const double texelsPerMetreX = double(size - 1) / (side * h.spacingX);
      const double texelsPerMetreY = double(size - 1) / (side * h.spacingY);
      for (const auto& p : local)
        mesh.texcoords.push_back(
            {float(((p[0] - double(ox) * h.spacingX) * texelsPerMetreX + 0.5) / size),
             float(((p[1] - double(oy) * h.spacingY) * texelsPerMetreY + 0.5) / size)});
    }
    // Through PROJ to Earth, then into the root frame.
    if (Status s = placement.toEarth(local); !s) return makeError(subject, s.error().message);
    for (auto& p : local) {
      const glm::dvec4 r = toRoot * glm::dvec4(p[0], p[1], p[2], 1.0);
      mesh.positions.push_back({r.x, r.y, r.z});
    }
    auto glb = chunkGlb(mesh);
    if (!glb) return makeError(subject, glb.error().message);
    const std::string uri = "tiles/" + std::to_string(record.level) + "/" +
                            std::to_string(record.x) + "/" + std::to_string(record.y) + ".glb";
    const fs::path file = fs::path(partial) / uri;
    fs::create_directories(file.parent_path(), ec);
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(glb->bytes.data()), std::streamsize(glb->bytes.size()));
    if (!out.flush()) return makeError(file.string(), "cannot be written");
    tiles[i] = {record.parent == kNoNode ? kNoParent : record.parent, h.levelError[record.level],
                glb->min, glb->max, uri};
    ++summary.tiles;
    summary.bytes += glb->bytes.size();
    summary.uncompressedBytes += glb->uncompressedBytes;
    summary.maxQuantisationError = std::max(summary.maxQuantisationError, glb->quantisationError);
    progress.advance();
  }
  progress.end();
  // What places the root frame, so that a tool can put a terralod camera (local metres) in
  // the same place exactly: the source grid's georeferencing and the root frame's origin.
  nlohmann::json extras = {{"generator", "terralod export --format 3dtiles"},
                           {"source", fs::path(tileset.name()).filename().string()},
                           {"placed_on_earth", summary.placed},
                           {"root_frame_origin_local", {cx, cy, cz}},
                           {"source_grid",
                            {{"columns", grid.columns},
                             {"rows", grid.rows},
                             {"spacing", {grid.spacingX, grid.spacingY}},
                             {"crs_wkt", grid.crsWkt}}}};
  if (grid.hasGeoTransform) extras["source_grid"]["geotransform"] = grid.geoTransform;
  auto json = tilesetJson(tiles, *root, 2.0 * h.levelError[0], extras);
  if (!json) return json.error();
  {
    auto file = AtomicFile::create(partial + "/tileset.json");
    if (!file) return file.error();
    if (Status s = file->write(json->dump(1)); !s) return s.error();
    if (Status s = file->commit(); !s) return s.error();
  }
  fs::remove(dir, ec);  // an empty directory, if any
  fs::rename(partial, dir, ec);
  if (ec) return makeError(dir, "cannot be put in place (" + ec.message() + ")");
  cleanup.done = true;
  return summary;
}

}  // namespace terralod::tiles3d
