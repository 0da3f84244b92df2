// terralod info TILESET [--json]

#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "terralod/format/tileset_reader.h"
#include "terralod/format/vipm_chunk_codec.h"

namespace terralod::cli {
namespace {

struct LevelStats {
  uint64_t chunks = 0, vertices = 0, triangles = 0, skirtTriangles = 0, bytes = 0, textureBytes = 0;
};

std::string kindName(const TilesetHeader& h) {
  return h.meshKind == MeshKind::kVipm ? "vipm" : "static";
}

// [{id, name, color}], material index order (empty for static tilesets).
nlohmann::json materialsJson(const TilesetMetadata& metadata) {
  nlohmann::json list = nlohmann::json::array();
  for (const TilesetMaterial& m : metadata.materials)
    list.push_back({{"id", m.id}, {"name", m.name}, {"color", colorHex(m.color)}});
  return list;
}

int printInfo(const std::string& path, bool json) {
  auto opened = TilesetReader::openPathOrUrl(path);  // a path or an http(s):// URL
  if (!opened) return fail(opened.error().message);
  const TilesetReader& t = **opened;
  const TilesetHeader& h = t.header();
  std::vector<LevelStats> levels(h.levelCount);
  LevelStats total;
  for (const NodeRecord& n : t.nodes()) {
    LevelStats& l = levels[n.level];
    for (LevelStats* s : {&l, &total}) {
      s->chunks += 1;
      s->vertices += n.vertexCount;
      s->triangles += n.triangleCount;
      s->skirtTriangles += n.skirtTriangleCount;
      s->bytes += n.blobBytes;
      s->textureBytes += n.textureBytes;
    }
  }
  // Geometry: everything but the textures (tables and metadata included, as in version 1).
  const uint64_t geometryBytes = h.fileBytes - total.textureBytes;
  nlohmann::json metadata = nlohmann::json::parse(t.metadataJson(), nullptr, false);
  const uint64_t samples = uint64_t(h.sourceColumns) * h.sourceRows;
  if (json) {
    nlohmann::json j;
    j["file"] = path;
    j["format_version"] = h.version;
    j["kind"] = kindName(h);
    j["materials"] = materialsJson(t.metadata());
    j["levels"] = h.levelCount;
    j["chunks"] = total.chunks;
    j["vertices"] = total.vertices;
    j["triangles"] = total.triangles;
    j["skirt_triangles"] = total.skirtTriangles;
    j["file_bytes"] = h.fileBytes;
    j["chunk_bytes"] = total.bytes;
    j["bytes_per_vertex"] = total.vertices ? double(geometryBytes) / double(total.vertices) : 0.0;
    j["textured"] = h.textured();
    if (h.textured()) {
      j["texture_bytes"] = total.textureBytes;
      j["texture_min_tau"] = h.textureMinTau;
    }
    j["bytes_per_sample"] = double(h.fileBytes) / double(samples);
    j["leaf_error"] = h.leafError;
    j["level_error"] =
        std::vector<double>(h.levelError.begin(), h.levelError.begin() + h.levelCount);
    j["extent"] = {{"min", h.extentMin}, {"max", h.extentMax}};
    j["spacing"] = {h.spacingX, h.spacingY};
    j["source_size"] = {h.sourceColumns, h.sourceRows};
    j["filled_voids"] = h.filledVoids;
    j["leaf_cells"] = h.leafCells;
    j["root_cells"] = h.rootCells;
    j["roots"] = {h.rootsX, h.rootsY};
    nlohmann::json perLevel = nlohmann::json::array();
    for (uint32_t l = 0; l < h.levelCount; ++l) {
      perLevel.push_back({{"level", l},
                          {"error", h.levelError[l]},
                          {"chunk_cells", h.chunkCells(int32_t(l))},
                          {"chunks", levels[l].chunks},
                          {"vertices", levels[l].vertices},
                          {"triangles", levels[l].triangles},
                          {"bytes", levels[l].bytes},
                          {"texture_bytes", levels[l].textureBytes}});
    }
    j["per_level"] = perLevel;
    if (!metadata.is_discarded()) j["metadata"] = metadata;
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("%s: terralod tileset, format version %u\n", path.c_str(), h.version);
  if (!metadata.is_discarded() && metadata.contains("source")) {
    const auto& s = metadata["source"];
    std::printf("  source          %s (%s, %s), %u x %u samples\n", s.value("file", "?").c_str(),
                s.value("driver", "?").c_str(), s.value("data_type", "?").c_str(), h.sourceColumns,
                h.sourceRows);
    std::printf("  spacing         %.4f x %.4f m (%s)\n", h.spacingX, h.spacingY,
                s.value("spacing_source", "?").c_str());
  }
  std::printf("  kind            %s\n",
              h.meshKind == MeshKind::kVipm
                  ? "vipm (a progressive mesh per 64-cell leaf, fallback roots)"
                  : "static (chunked LOD, RTIN meshes)");
  const auto& materials = t.metadata().materials;
  for (size_t i = 0; i < materials.size(); ++i)
    std::printf("  %-15s %zu: %s (id %u, %s)\n", i == 0 ? "materials" : "", i,
                materials[i].name.c_str(), unsigned(materials[i].id),
                colorHex(materials[i].color).c_str());
  std::printf("  extent          x %.1f..%.1f  y %.1f..%.1f  z %.1f..%.1f m\n", h.extentMin[0],
              h.extentMax[0], h.extentMin[1], h.extentMax[1], h.extentMin[2], h.extentMax[2]);
  std::printf("  filled voids    %llu (%.3f%% of samples)\n", (unsigned long long)h.filledVoids,
              100.0 * double(h.filledVoids) / double(samples));
  std::printf("  tree            %u levels, %u x %u roots of %u cells, leaves of %u cells\n",
              h.levelCount, h.rootsX, h.rootsY, h.rootCells, h.leafCells);
  if (h.textured() && h.meshKind == MeshKind::kVipm) {
    std::printf(
        "  textures        normal maps only (BC5, one texel per grid point up to the 128-cell "
        "roots, %u a side above, from the source heights)\n",
        vipmNormalMapCells(h.rootCells) + 1);
  } else if (h.textured() && !metadata.is_discarded() && metadata.contains("texture")) {
    const auto& texture = metadata["texture"];
    const bool shade = texture.value("color_layer", "color") == "shade";
    std::printf("  textures        colour %s%s, normals from the DEM, sized for tau <= %.2f px\n",
                texture.value("color", "?").c_str(),
                shade ? " by the shader (stored: water and occlusion, BC4)" : "", h.textureMinTau);
  }
  std::printf("  level  error(m)    chunks    vertices   triangles       bytes  bytes/vertex%s\n",
              h.textured() ? "  texture bytes  texels/side" : "");
  const nlohmann::json* texturePlan = !metadata.is_discarded() && metadata.contains("texture")
                                          ? &metadata["texture"]["levels"]
                                          : nullptr;
  for (uint32_t l = 0; l < h.levelCount; ++l) {
    const LevelStats& s = levels[l];
    std::printf("  %5u  %8.3f  %8llu  %10llu  %10llu  %10llu  %12.2f", l, h.levelError[l],
                (unsigned long long)s.chunks, (unsigned long long)s.vertices,
                (unsigned long long)s.triangles, (unsigned long long)s.bytes,
                s.vertices ? double(s.bytes) / double(s.vertices) : 0.0);
    if (h.textured()) {
      std::printf("  %13llu", (unsigned long long)s.textureBytes);
      if (texturePlan && texturePlan->is_array() && l < texturePlan->size()) {
        const auto& level = (*texturePlan)[l];
        std::printf("  %5u%s/%u%s%s", level.value("color_size", 0u),
                    level.value("color_source_limited", false) ? "*" : "",
                    level.value("normal_size", 0u),
                    level.value("normal_source_limited", false) ? "*" : "",
                    level.value("inherited", false) ? " (the parent's)" : "");
      } else if (h.meshKind == MeshKind::kVipm) {
        std::printf("  %5s/%u*", "-", vipmNormalMapCells(h.rootCells >> l) + 1);  // normals only
      }
    }
    std::printf("\n");
  }
  std::printf("  total             %8llu  %10llu  %10llu  %10llu  %12.2f",
              (unsigned long long)total.chunks, (unsigned long long)total.vertices,
              (unsigned long long)total.triangles, (unsigned long long)geometryBytes,
              total.vertices ? double(geometryBytes) / double(total.vertices) : 0.0);
  if (h.textured()) std::printf("  %13llu", (unsigned long long)total.textureBytes);
  std::printf("\n");
  if (h.textured())
    std::printf(
        "  (texels/side: colour or shade/normal; * = source-limited: the source's resolution;\n"
        "   the parent's: the level draws its parents' textures, which hold its texels)\n");
  std::printf("  file            %llu bytes, %.3f bytes per source sample\n",
              (unsigned long long)h.fileBytes, double(h.fileBytes) / double(samples));
  return 0;
}

}  // namespace

void addInfoCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand("info", "Describe a tileset: levels, errors, sizes, source");
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("TILESET", *path,
                  "Tileset: a .tlod file, or an http(s):// URL of one (read with range requests)")
      ->required();
  cmd->add_flag("--json", *json, "Machine-readable output");
  cmd->footer(
      "Examples:\n"
      "  terralod info dem.tlod\n"
      "  terralod info http://example.com/tiles/dem.tlod --json\n");
  cmd->callback([&run, path, json] { run = [path, json] { return printInfo(*path, *json); }; });
}

}  // namespace terralod::cli
