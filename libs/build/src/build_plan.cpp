#include "terralod/build/build_plan.h"

#include <cmath>
#include <limits>
#include <optional>

#include <nlohmann/json.hpp>

namespace terralod {
namespace {

const char* encodingName(HeightEncoding e) {
  switch (e) {
    case HeightEncoding::kTerrainRgb:
      return "terrain-rgb";
    case HeightEncoding::kTerrarium:
      return "terrarium";
    case HeightEncoding::kPlain:
      break;
  }
  return "none";
}

// encodingName's inverse (parseHeightEncoding's names for the same, without its aliases, and
// without linking dem_reader.cpp's GDAL into terralod-stage).
std::optional<HeightEncoding> encodingOf(const std::string& name) {
  for (const HeightEncoding e :
       {HeightEncoding::kPlain, HeightEncoding::kTerrainRgb, HeightEncoding::kTerrarium})
    if (name == encodingName(e)) return e;
  return std::nullopt;
}

const char* streamingName(Streaming s) {
  switch (s) {
    case Streaming::kNever:
      return "never";
    case Streaming::kAlways:
      return "always";
    case Streaming::kAuto:
      break;
  }
  return "auto";
}

// A nodata value may be NaN or infinite, which JSON numbers cannot be.
nlohmann::json anyDouble(double v) {
  if (std::isfinite(v)) return v;
  return std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf";
}
std::optional<double> anyDoubleOf(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string text = j.get<std::string>();
  if (text == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (text == "inf") return std::numeric_limits<double>::infinity();
  if (text == "-inf") return -std::numeric_limits<double>::infinity();
  return std::nullopt;
}

nlohmann::json sourceJson(const SourceFacts& s) {
  const DemInfo& d = s.info;
  nlohmann::json j = {{"path", d.path},
                      {"columns", d.columns},
                      {"rows", d.rows},
                      {"spacing", {d.spacingX, d.spacingY}},
                      {"spacing_source", d.spacingSource},
                      {"spacing_assumed", d.spacingAssumed},
                      {"height_scale", d.heightScale},
                      {"height_offset", d.heightOffset},
                      {"data_type", d.dataType},
                      {"driver", d.driver},
                      {"crs_wkt", d.crsWkt},
                      {"earth_crs_wkt", d.earthCrsWkt},
                      {"geotransform", d.geoTransform},
                      {"has_geotransform", d.hasGeoTransform},
                      {"south_up", d.southUp},
                      {"encoding", encodingName(d.encoding)},
                      {"band_count", d.bandCount},
                      {"band", d.band},
                      {"looks_like_image", d.looksLikeImage},
                      {"row_latitudes", s.rowLatitudes},
                      {"image_refine", s.imageRefine}};
  if (d.nodata) j["nodata"] = anyDouble(*d.nodata);
  return j;
}

Result<SourceFacts> sourceOf(const nlohmann::json& j, const std::string& subject) {
  SourceFacts s;
  DemInfo& d = s.info;
  d.path = j.at("path").get<std::string>();
  d.columns = j.at("columns").get<int32_t>();
  d.rows = j.at("rows").get<int32_t>();
  const auto spacing = j.at("spacing").get<std::array<double, 2>>();
  d.spacingX = spacing[0];
  d.spacingY = spacing[1];
  d.spacingSource = j.at("spacing_source").get<std::string>();
  d.spacingAssumed = j.at("spacing_assumed").get<bool>();
  d.heightScale = j.at("height_scale").get<double>();
  d.heightOffset = j.at("height_offset").get<double>();
  if (j.contains("nodata")) {
    d.nodata = anyDoubleOf(j.at("nodata"));
    if (!d.nodata) return makeError(subject, "build plan's source nodata is not a number");
  }
  d.dataType = j.at("data_type").get<std::string>();
  d.driver = j.at("driver").get<std::string>();
  d.crsWkt = j.at("crs_wkt").get<std::string>();
  d.earthCrsWkt = j.at("earth_crs_wkt").get<std::string>();
  d.geoTransform = j.at("geotransform").get<std::array<double, 6>>();
  d.hasGeoTransform = j.at("has_geotransform").get<bool>();
  d.southUp = j.at("south_up").get<bool>();
  auto encoding = encodingOf(j.at("encoding").get<std::string>());
  if (!encoding) return makeError(subject, "unknown height encoding of the source");
  d.encoding = *encoding;
  d.bandCount = j.at("band_count").get<int>();
  d.band = j.at("band").get<int>();
  d.looksLikeImage = j.at("looks_like_image").get<bool>();
  s.rowLatitudes = j.at("row_latitudes").get<std::vector<double>>();
  s.imageRefine = j.at("image_refine").get<uint32_t>();
  if (d.columns < 1 || d.rows < 1) return makeError(subject, "build plan's source has no samples");
  return s;
}

}  // namespace

std::string buildPlanJson(const BuildPlan& plan) {
  const BuildOptions& o = plan.options;
  nlohmann::json dem = {{"encoding", encodingName(o.dem.encoding)},
                        {"band", o.dem.band},
                        {"vertical_scale", o.dem.verticalScale},
                        {"max_block_bytes", o.dem.maxBlockBytes}};
  if (o.dem.spacing) dem["spacing"] = *o.dem.spacing;
  nlohmann::json blocks = nlohmann::json::array();
  for (const auto& b : plan.blocks) blocks.push_back(b);
  const nlohmann::json j = {
      {"format", "terralod build plan"},
      {"version", kBuildPlanVersion},
      {"input", o.input},
      {"output", o.output},
      {"dem", dem},
      {"source", sourceJson(plan.source)},
      {"max_error", o.maxError},
      {"chunk_cells", o.chunkCells},
      {"memory_mb", o.memoryMB},
      {"zstd_level", o.compressionLevel},
      {"streaming", streamingName(o.streaming)},
      {"textures", o.textures},
      {"texture_image", o.textureImage},
      {"min_tau", o.textureTau},
      {"texture_sharing", o.textureSharing == TextureSharing::kInherit ? "inherit" : "every-chunk"},
      {"mesher", o.mesher == MeshMethod::kGreedy ? "greedy" : "rtin"},
      {"generated_colour", o.generatedColour == GeneratedColour::kBaked ? "baked" : "shader"},
      {"chunk_codec", o.chunkCodec == ChunkCodec::kMeshopt ? "meshopt" : "bintree"},
      {"block_cells", plan.blockCells},
      {"height_range", {plan.heightLo, plan.heightHi}},
      {"exact_range", plan.exactRange},
      {"attempt", plan.attempt},
      {"jobs", plan.jobs},
      {"blocks", blocks},
  };
  return j.dump(1) + "\n";
}

Result<BuildPlan> parseBuildPlan(const std::string& text, const std::string& subject) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("format", "") != "terralod build plan")
    return makeError(subject, "not a terralod build plan");
  if (j.value("version", 0) != kBuildPlanVersion)
    return makeError(subject, "build plan version " + std::to_string(j.value("version", 0)) +
                                  " (this terralod reads version " +
                                  std::to_string(kBuildPlanVersion) + ")");
  try {
    BuildPlan plan;
    BuildOptions& o = plan.options;
    o.input = j.at("input").get<std::string>();
    o.output = j.at("output").get<std::string>();
    const nlohmann::json& dem = j.at("dem");
    auto encoding = encodingOf(dem.at("encoding").get<std::string>());
    if (!encoding) return makeError(subject, "unknown height encoding");
    o.dem.encoding = *encoding;
    o.dem.band = dem.at("band").get<int>();
    o.dem.verticalScale = dem.at("vertical_scale").get<double>();
    o.dem.maxBlockBytes = dem.at("max_block_bytes").get<uint64_t>();
    if (dem.contains("spacing")) o.dem.spacing = dem.at("spacing").get<std::array<double, 2>>();
    auto source = sourceOf(j.at("source"), subject);
    if (!source) return source.error();
    plan.source = std::move(source).value();
    o.maxError = j.at("max_error").get<double>();
    o.chunkCells = j.at("chunk_cells").get<int32_t>();
    o.memoryMB = j.at("memory_mb").get<uint64_t>();
    o.compressionLevel = j.at("zstd_level").get<int>();
    const std::string streaming = j.at("streaming").get<std::string>();
    o.streaming = streaming == "always"  ? Streaming::kAlways
                  : streaming == "never" ? Streaming::kNever
                                         : Streaming::kAuto;
    o.textures = j.at("textures").get<bool>();
    o.textureImage = j.at("texture_image").get<std::string>();
    o.textureTau = j.at("min_tau").get<double>();
    const std::string sharing = j.at("texture_sharing").get<std::string>();
    if (sharing != "inherit" && sharing != "every-chunk")
      return makeError(subject, "unknown texture sharing \"" + sharing + "\"");
    o.textureSharing =
        sharing == "inherit" ? TextureSharing::kInherit : TextureSharing::kEveryChunk;
    const std::string mesher = j.at("mesher").get<std::string>();
    if (mesher != "rtin" && mesher != "greedy")
      return makeError(subject, "unknown mesher \"" + mesher + "\"");
    o.mesher = mesher == "greedy" ? MeshMethod::kGreedy : MeshMethod::kRtin;
    const std::string colour = j.at("generated_colour").get<std::string>();
    if (colour != "shader" && colour != "baked")
      return makeError(subject, "unknown generated colour \"" + colour + "\"");
    o.generatedColour = colour == "baked" ? GeneratedColour::kBaked : GeneratedColour::kShader;
    const std::string codec = j.at("chunk_codec").get<std::string>();
    if (codec != "bintree" && codec != "meshopt")
      return makeError(subject, "unknown chunk codec \"" + codec + "\"");
    o.chunkCodec = codec == "meshopt" ? ChunkCodec::kMeshopt : ChunkCodec::kBintree;
    plan.blockCells = j.at("block_cells").get<int32_t>();
    const auto range = j.at("height_range").get<std::array<double, 2>>();
    plan.heightLo = range[0];
    plan.heightHi = range[1];
    plan.exactRange = j.at("exact_range").get<bool>();
    plan.attempt = j.at("attempt").get<int>();
    plan.jobs = j.at("jobs").get<int>();
    plan.blocks = j.at("blocks").get<std::vector<std::array<int32_t, 2>>>();
    if (plan.jobs < 1 || plan.blockCells < 1)
      return makeError(subject, "build plan has no jobs or blocks");
    return plan;
  } catch (const nlohmann::json::exception& e) {
    return makeError(subject, std::string("build plan field missing or wrong: ") + e.what());
  }
}

}  // namespace terralod
