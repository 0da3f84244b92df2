// terralod render TILESET -o OUT.png|OUT.jpg [camera, selection and style options]
// terralod render TILESET (--flight F.json | --auto-flight) --frames-dir DIR

#include <cstdio>
#include <filesystem>

#include "cli_checks.h"
#include "commands.h"
#include "render_options.h"
#include "scene_vegetation.h"
#include "terralod/render/contact_sheet.h"
#include "terralod/render/framebuffer.h"
#include "terralod/render/gl_context.h"
#include "terralod/render/terrain_scene.h"
#include "vegetation_reference.h"

namespace terralod::cli {
namespace {

constexpr int kContactSheetFrames = 24;

struct RenderCommand {
  RenderOptions options;
  std::string output;
  std::string framesDir;
  int every = 1;  ///< render every k-th frame of a flight
};

std::string framePath(const std::string& dir, size_t i) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05zu.png", i);
  return (std::filesystem::path(dir) / name).string();
}

int runRender(const RenderCommand& r) {
  const bool flight = !r.options.flightFile.empty() || r.options.autoFlight;
  if (flight && r.framesDir.empty()) return fail("a flight needs --frames-dir DIR for its frames");
  if (!flight && r.output.empty()) return fail("give -o OUT.png (or a flight with --frames-dir)");
  if (!r.output.empty())
    if (auto format = imageFormatFor(r.output); !format) return fail(format.error().message);
  if (!r.framesDir.empty() && !std::filesystem::is_directory(r.framesDir))
    return fail(r.framesDir + ": not a directory");
  auto selection = selectionOptions(r.options);
  if (!selection) return fail(selection.error().message);
  auto style = terrainStyle(r.options);
  if (!style) return fail(style.error().message);

  auto tileset = TilesetReader::openPathOrUrl(r.options.tileset);  // a path or an http(s):// URL
  if (!tileset) return fail(tileset.error().message);
  auto context = GlContext::createHeadless();
  if (!context) return fail(context.error().message);
  auto scene =
      TerrainScene::create(std::move(tileset).value(), sceneOptions(r.options, true, **context));
  if (!scene) return fail(scene.error().message);
  style->stitch = stitchFor(r.options, (*scene)->tileset().header());
  auto vegetation = addSceneVegetation(r.options, **scene);
  if (!vegetation) return fail(vegetation.error().message);
  std::unique_ptr<VegetationReference> reference;
  if (r.options.vegetationReference) {
    if (!vegetation->painter) return fail("--vegetation-reference needs --vegetation V.tlv");
    // The plants ray traced instead of the LDIs warped (and nothing else beyond their range).
    reference = std::make_unique<VegetationReference>(*vegetation, **scene);
    vegetation->layer->setPainter(reference->painter());
    if (vegetation->far) vegetation->far->setEnabled(false);
  }
  auto cameras = camerasFor(r.options, (*scene)->tree());
  if (!cameras) return fail(cameras.error().message);
  if (cameras->empty()) return fail("the flight has no frames");

  std::vector<Image> sheet;
  // Frames rendered, and every how many flight frames one goes on the contact sheet.
  const size_t rendered = (cameras->size() + size_t(r.every) - 1) / size_t(r.every);
  const size_t every = size_t(r.every) * std::max<size_t>(1, (rendered + kContactSheetFrames - 1) /
                                                                 kContactSheetFrames);
  std::optional<Framebuffer> target;
  bool warnedCoarser = false;  // once per run
  for (size_t i = 0; i < cameras->size(); i += size_t(r.every)) {
    auto view = makeView((*cameras)[i]);
    if (!view) return fail("frame " + std::to_string(i) + ": " + view.error().message);
    if (Status s = bindFramebufferOfSize(target, view->camera.width, view->camera.height); !s)
      return fail(s.error().message);
    auto frame = (*scene)->renderFrame(*view, *selection, *style);
    if (!frame) return fail(frame.error().message);
    if (frame->selection.coarserThanWanted > 0 && !warnedCoarser) {
      // A complete frame still coarser than it wants: the rest did not fit or failed to load.
      const std::string where = flight ? "frame " + std::to_string(i) + ": " : "";
      std::fprintf(stderr,
                   "terralod: warning: %s%u chunks drawn coarser than --tau allows: the finer "
                   "chunks they want did not fit the %g MB budget or could not be read (give a "
                   "larger --cache-mb)\n",
                   where.c_str(), frame->selection.coarserThanWanted, r.options.cacheMB);
      warnedCoarser = true;
    }
    const Image image = target->readPixels();
    const std::string path = flight ? framePath(r.framesDir, i) : r.output;
    if (Status written = flight ? writePng(image, path) : writeImage(image, path); !written)
      return fail(written.error().message);
    if (flight && i % every == 0) sheet.push_back(image);
    if (!flight)
      std::printf("terralod: wrote %s: %u chunks, %llu triangles, %u draw calls, select %.0f us\n",
                  path.c_str(), frame->selection.selected,
                  (unsigned long long)frame->draw.triangles, frame->draw.drawCalls,
                  frame->selectMicroseconds);
    if (!flight && vegetation->painter && !reference) {
      const veg::VegetationFrameStats& v = vegetation->painter->lastFrame();
      std::printf(
          "terralod: vegetation: %u tiles (%u excluded by --vegetation-where), %llu splats, "
          "%llu depth pixels, select %.1f ms, warp %.1f ms (reading LDIs %.1f ms), merge %.1f ms, "
          "composite %.1f ms\n",
          v.warp.tiles, v.field.excluded, (unsigned long long)v.warp.splats,
          (unsigned long long)v.warp.depthPixels, v.selectMs, v.warp.warpMs, v.readMs,
          v.warp.mergeMs, vegetation->layer->times().compositeMs);
    }
  }
  if (flight) {
    const std::string sheetPath =
        (std::filesystem::path(r.framesDir) / "contact_sheet.png").string();
    if (Status written = writePng(makeContactSheet(sheet, 6, 256), sheetPath); !written)
      return fail(written.error().message);
    std::printf("terralod: wrote %zu frames and %s\n", rendered, sheetPath.c_str());
  }
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "render",
      "Render a tileset headless (OpenGL through EGL) to PNG: one view, or every frame of a "
      "flight plus a contact sheet");
  auto r = std::make_shared<RenderCommand>();
  addRenderOptions(*cmd, r->options, true);
  cmd->add_option("-o,--output", r->output,
                  "Image to write (a single view): .png, or .jpg/.jpeg for JPEG");
  cmd->add_option("--frames-dir", r->framesDir,
                  "Directory for a flight's frames (frame_00000.png, ...) and contact_sheet.png");
  cmd->add_option(
         "--every", r->every,
         "Render only every k-th frame of a flight (frame files keep their flight numbers)")
      ->check(wholeNumber<int>(1));
  cmd->footer(
      "Examples:\n"
      "  terralod render dem.tlod -o overview.png\n"
      "  terralod render dem.tlod --eye 16000,2000,4200 --target 19000,16000,1700 --tau 1 -o "
      "view.png\n"
      "  terralod render dem.tlod --color-by level --wireframe --chunk-boxes -o levels.png\n"
      "  terralod render dem.tlod --auto-flight --every 30 --frames-dir frames/\n"
      "World coordinates: x east, y north, z up, metres from the south-west sample.\n");
  cmd->callback([&run, r] { run = [r] { return runRender(*r); }; });
}

}  // namespace terralod::cli
