#include "terralod/tiles3d/export_3dtiles.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <span>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "local_chunk.h"
#include "terralod/core/atomic_file.h"
#include "terralod/format/chunk_position.h"
#include "terralod/measure/export_mesh.h"
#include "terralod/raster/earth_placement.h"
#include "terralod/tiles3d/chunk_glb.h"
#include "terralod/tiles3d/implicit_tiling.h"
#include "terralod/tiles3d/tileset_json.h"

namespace terralod::tiles3d {
namespace {

namespace fs = std::filesystem;

// Whether δ halves exactly from each level to the next, as implicit tiling's errors do.
bool errorsHalve(const TilesetHeader& h) {
  for (uint32_t level = 1; level < h.levelCount; ++level)
    if (std::abs(h.levelError[level] * 2.0 - h.levelError[level - 1]) >
        1e-9 * h.levelError[level - 1])
      return false;
  return true;
}

// Subtree files of about five levels each, the levels shared out evenly (six levels: two
// subtrees of three, not one of five and one of one).
uint32_t subtreeLevelsFor(uint32_t availableLevels) {
  const uint32_t subtrees = (availableLevels + 4) / 5;
  return (availableLevels + subtrees - 1) / subtrees;
}

Status writeFile(const fs::path& file, const std::vector<uint8_t>& bytes) {
  std::error_code ec;
  fs::create_directories(file.parent_path(), ec);
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out.flush()) return makeError(file.string(), "cannot be written");
  return {};
}

// The root frame's inverse, for positions and (inverse transpose) normals, and its origin in
// local metres.
struct RootFrame {
  glm::dmat4 toRoot;
  glm::dmat3 toRootNormal;
  std::array<double, 3> origin;
};

// Chunk `node` as a glTF in the root frame: its local mesh (local_chunk.h), normals from its
// surface through the chunk's local frame, positions through PROJ.
Result<ChunkGlb> chunkContent(const TilesetReader& tileset, NodeColours& colours, uint32_t node,
                              const EarthPlacement& placement, const RootFrame& root,
                              MaterialLight light) {
  const TilesetHeader& h = tileset.header();
  const NodeRecord& record = tileset.nodes()[node];
  const std::string subject = tileset.name() + " chunk " + std::to_string(node);
  auto chunk = record.meshKind == MeshKind::kVipm ? vipmLocalChunk(tileset, node)
                                                  : staticLocalChunk(tileset, colours, node);
  if (!chunk) return chunk.error();
  if (chunk->indices.empty()) return makeError(subject, "has no triangles");
  ChunkMesh mesh;
  mesh.light = light;
  mesh.name = "chunk " + std::to_string(node) + " (level " + std::to_string(record.level) + ", " +
              std::to_string(record.x) + ", " + std::to_string(record.y) + ")";
  mesh.indices = std::move(chunk->indices);
  mesh.texcoords = std::move(chunk->texcoords);
  mesh.colors = std::move(chunk->colors);
  if (!chunk->image.empty()) {
    mesh.image = std::move(chunk->image);
    mesh.imageMimeType = "image/jpeg";
  }
  std::vector<std::array<double, 3>>& local = chunk->positions;
  // Normals from the surface triangles (skirt and flange vertices, in none, point straight
  // up), local then through the chunk's frame and into the root frame.
  std::vector<std::array<float, 3>> localFloat;
  for (const auto& p : local)
    localFloat.push_back(
        {float(p[0] - root.origin[0]), float(p[1] - root.origin[1]), float(p[2] - root.origin[2])});
  std::vector<std::array<float, 3>> normals = angleWeightedNormals(localFloat, chunk->surface);
  const auto [ox, oy] = chunkCellOrigin(h, record);
  const double side = h.chunkCells(record.level);
  auto frame =
      placement.frameAt((double(ox) + 0.5 * side) * h.spacingX,
                        (double(oy) + 0.5 * side) * h.spacingY, 0.5 * (record.minZ + record.maxZ));
  if (!frame) return frame.error();
  const glm::dmat3 toEarthNormal = glm::transpose(glm::inverse(glm::dmat3(*frame)));
  for (auto& n : normals) {
    glm::dvec3 v(n[0], n[1], n[2]);
    if (!(glm::dot(v, v) > 0.5)) v = glm::dvec3(0, 0, 1);
    v = root.toRootNormal * (toEarthNormal * v);
    v /= std::sqrt(glm::dot(v, v));
    mesh.normals.push_back({float(v.x), float(v.y), float(v.z)});
  }
  // Through PROJ to Earth, then into the root frame.
  if (Status s = placement.toEarth(local); !s) return makeError(subject, s.error().message);
  for (auto& p : local) {
    const glm::dvec4 r = root.toRoot * glm::dvec4(p[0], p[1], p[2], 1.0);
    mesh.positions.push_back({r.x, r.y, r.z});
  }
  auto glb = chunkGlb(mesh);
  if (!glb) return makeError(subject, glb.error().message);
  return glb;
}

struct ImplicitTree {
  std::array<double, 12> rootBox{};
  uint32_t availableLevels = 0, subtreeLevels = 0;
};

// Implicit tiling's root box and subtree files (written under `partial`) for the exported
// tiles at their implicit `keys`; how far content reaches outside its derived box goes into
// `summary`. The root box is the roots' square in the root frame (whose axes are the grid's at
// the data's centre; `centre` is the frame's origin in local metres) over the content's full
// height range. Errors name `subject` (the tileset) or the file that cannot be written.
Result<ImplicitTree> writeImplicitTree(const TilesetHeader& h, std::span<const ExportTile> tiles,
                                       std::span<const TileKey> keys, uint32_t virtualLevels,
                                       std::array<double, 2> centre, const std::string& partial,
                                       const std::string& subject, ExportSummary& summary) {
  ImplicitTree tree;
  const double side = double(uint64_t(h.rootCells) << virtualLevels);
  const double halfX = 0.5 * side * h.spacingX, halfY = 0.5 * side * h.spacingY;
  double zMin = tiles[0].min[2], zMax = tiles[0].max[2];
  for (const ExportTile& t : tiles) {
    zMin = std::min(zMin, t.min[2]);
    zMax = std::max(zMax, t.max[2]);
  }
  tree.rootBox = {
      halfX - centre[0],  halfY - centre[1], 0.5 * (zMin + zMax), halfX, 0, 0, 0, halfY, 0, 0, 0,
      0.5 * (zMax - zMin)};
  for (size_t i = 0; i < tiles.size(); ++i) {
    const std::array<double, 12> b = implicitTileBox(tree.rootBox, keys[i]);
    for (int k = 0; k < 2; ++k) {
      const double half = b[3 + 4 * k];
      summary.implicitBoxExcess =
          std::max({summary.implicitBoxExcess, (b[k] - half) - tiles[i].min[k],
                    tiles[i].max[k] - (b[k] + half)});
    }
  }
  tree.availableLevels = h.levelCount + virtualLevels;
  tree.subtreeLevels = subtreeLevelsFor(tree.availableLevels);
  auto subtrees = subtreeFiles(keys, tree.availableLevels, tree.subtreeLevels);
  if (!subtrees) return makeError(subject, subtrees.error().message);
  for (const SubtreeFile& s : *subtrees)
    if (Status written = writeFile(fs::path(partial) / s.uri, s.bytes); !written)
      return written.error();
  summary.subtrees = subtrees->size();
  return tree;
}

}  // namespace

Result<ExportSummary> export3dTiles(const TilesetReader& tileset, const std::string& dir,
                                    const Export3dTilesOptions& options, Progress& progress,
                                    const std::function<void(const std::string&)>& warn) {
  const TilesetHeader& h = tileset.header();
  const auto& nodes = tileset.nodes();
  const bool halving = errorsHalve(h);
  Tiling tiling = options.tiling;
  if (tiling == Tiling::kAuto)
    tiling = nodes.size() >= kImplicitFromTiles && halving ? Tiling::kImplicit : Tiling::kExplicit;
  if (tiling == Tiling::kImplicit && !halving)
    return makeError(tileset.name(),
                     "its levels' errors do not halve from level to level, as implicit tiling's "
                     "must (use --tiling explicit)");
  // Implicit tiling's root: a square of 2^R x 2^R roots, the levels above them without content.
  uint32_t virtualLevels = 0;
  while ((1u << virtualLevels) < std::max(h.rootsX, h.rootsY)) ++virtualLevels;
  const bool implicit = tiling == Tiling::kImplicit;
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
  summary.tiling = tiling;
  const SourceGrid grid = sourceGridOf(h, tileset.metadata());
  ExportPlacement placed = placementOf(grid, tileset.name());
  const EarthPlacement& placement = placed.placement;
  if (!placed.unplacedReason.empty()) {
    summary.placed = false;
    if (warn)
      warn(placed.unplacedReason + "; placed on a plane tangent to the ellipsoid at longitude " +
           std::to_string(int(kDefaultLongitude)) + ", latitude " +
           std::to_string(int(kDefaultLatitude)));
  }
  const double cx = 0.5 * (h.extentMin[0] + h.extentMax[0]);
  const double cy = 0.5 * (h.extentMin[1] + h.extentMax[1]);
  const double cz = 0.5 * (h.extentMin[2] + h.extentMax[2]);
  auto root = placement.frameAt(cx, cy, cz);
  if (!root) return root.error();
  const glm::dmat4 toRoot = glm::inverse(*root);
  const RootFrame rootFrame{toRoot, glm::transpose(glm::inverse(glm::dmat3(toRoot))), {cx, cy, cz}};

  // Imagery draped over the terrain carries its own light; a generated colour is lit.
  const MaterialLight light =
      tileset.metadata().textureColor.empty() || tileset.metadata().textureColor == "generated"
          ? MaterialLight::kLit
          : MaterialLight::kUnlit;
  std::vector<ExportTile> tiles(nodes.size());
  std::vector<TileKey> keys(nodes.size());
  progress.begin("3D Tiles", nodes.size());
  NodeColours colours(tileset);
  for (uint32_t i = 0; i < nodes.size(); ++i) {
    const NodeRecord& record = nodes[i];
    auto glb = chunkContent(tileset, colours, i, placement, rootFrame, light);
    if (!glb) return glb.error();
    // Files at the tile's implicit coordinates (the same as the chunk's without levels above
    // the roots).
    keys[i] = {record.level + (implicit ? virtualLevels : 0), record.x, record.y};
    const std::string uri = "tiles/" + std::to_string(keys[i].level) + "/" +
                            std::to_string(record.x) + "/" + std::to_string(record.y) + ".glb";
    if (Status s = writeFile(fs::path(partial) / uri, glb->bytes); !s) return s.error();
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
  // The top-level geometricError is the error of drawing nothing: the whole terrain (its
  // extent's diagonal), so that a client draws it from any distance (CesiumJS draws nothing of
  // a tileset whose top-level error projects under its maximum screen-space error).
  const double nothing =
      std::hypot(h.extentMax[0] - h.extentMin[0], h.extentMax[1] - h.extentMin[1],
                 h.extentMax[2] - h.extentMin[2]);
  nlohmann::json json;
  if (implicit) {
    auto written = writeImplicitTree(h, tiles, keys, virtualLevels, {cx, cy}, partial,
                                     tileset.name(), summary);
    if (!written) return written.error();
    const double rootError = h.levelError[0] * double(uint64_t(1) << virtualLevels);
    json = {{"asset", {{"version", "1.1"}, {"generator", "terralod"}}},
            {"geometricError", std::max(nothing, 2.0 * rootError)},
            {"root", implicitRootTile(written->rootBox, rootError, *root, written->availableLevels,
                                      written->subtreeLevels)},
            {"extras", extras}};
  } else {
    auto built = tilesetJson(tiles, *root, std::max(nothing, 2.0 * h.levelError[0]), extras);
    if (!built) return built.error();
    json = std::move(built).value();
  }
  {
    auto file = AtomicFile::create(partial + "/tileset.json");
    if (!file) return file.error();
    if (Status s = file->write(json.dump(1)); !s) return s.error();
    if (Status s = file->commit(); !s) return s.error();
  }
  fs::remove(dir, ec);  // an empty directory, if any
  fs::rename(partial, dir, ec);
  if (ec) return makeError(dir, "cannot be put in place (" + ec.message() + ")");
  cleanup.done = true;
  return summary;
}

}  // namespace terralod::tiles3d
