#pragma once
// The render tests' scene: a headless GL context and a TerrainScene over a tileset file.

#include <memory>
#include <string>

#include "terralod/format/tileset_reader.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"

namespace terralod::test {

/// Whether every frame waits until what it wants is resident (fixed pictures) or streams.
enum class Frames : uint8_t { kComplete, kStreamed };

/// Members are freed in reverse: the scene before its context.
struct HeadlessScene {
  std::unique_ptr<GlContext> context;
  std::unique_ptr<TerrainScene> scene;
};

/// Makes the context, then opens `path` in a scene; the error message, or "" when it worked.
inline std::string openHeadlessScene(const std::string& path, Frames frames, HeadlessScene& out) {
  out = {};
  auto context = GlContext::createHeadless();
  if (!context) return context.error().message;
  out.context = std::move(context).value();
  auto tileset = TilesetReader::openFile(path);
  if (!tileset) return tileset.error().message;
  SceneOptions options;
  options.complete = frames == Frames::kComplete;
  auto scene = TerrainScene::create(std::move(tileset).value(), options);
  if (!scene) return scene.error().message;
  out.scene = std::move(scene).value();
  return "";
}

}  // namespace terralod::test
