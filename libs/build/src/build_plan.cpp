#include "terralod/build/build_plan.h"

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
    auto encoding = parseHeightEncoding(dem.at("encoding").get<std::string>());
    if (!encoding) return makeError(subject, "unknown height encoding");
    o.dem.encoding = *encoding;
    o.dem.band = dem.at("band").get<int>();
    o.dem.verticalScale = dem.at("vertical_scale").get<double>();
    o.dem.maxBlockBytes = dem.at("max_block_bytes").get<uint64_t>();
    if (dem.contains("spacing")) o.dem.spacing = dem.at("spacing").get<std::array<double, 2>>();
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
