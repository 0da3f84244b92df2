// terralod view TILESET: fly over a tileset in a window, with the algorithm's knobs at hand.
// Scriptable for tests: --play F.json --screenshot OUT.png --exit-after-play.

// epoxy before GLFW, which would otherwise include the system's GL header.
#include <epoxy/gl.h>

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <thread>

#include "commands.h"
#include "edit_source.h"
#include "live_editor.h"
#include "render_options.h"
#include "scene_vegetation.h"
#include "terralod/build/vipm_builder.h"
#include "terralod/core/atomic_file.h"
#include "terralod/measure/fly_camera.h"
#include "terralod/render/frame_context.h"
#include "terralod/render/image.h"
#include "terralod/render/terrain_scene.h"
#include "terralod/render/window.h"
#include "terralod/runtime/flight.h"

namespace terralod::cli {
namespace {

constexpr int kFrameHistory = 240;
constexpr double kMouseRadiansPerPixel = 0.003;

struct ViewCommand {
  RenderOptions options;
  std::string play, screenshot, record;
  bool exitAfterPlay = false;
  // The brush (VIPM tilesets): on with --edit, or with a script of strokes to apply.
  bool edit = false, saveEdits = false;
  std::string editSource, editScript;
};

// The brush panel's settings.
struct Brushing {
  int brush = 0;  // raise, lower, smooth, paint
  float radius = 200.0f, amount = 10.0f, strength = 0.5f;
  int material = 0;  // index into the tileset's materials
  std::string status = "B + left click applies the brush";
};

// The terrain point under window pixel (x, y) of the frame just drawn into the bound read
// framebuffer (the window's, or the offscreen target's with vegetation), from its depth (reversed,
// kNearPlane / distance along the view axis); none on the sky.
std::optional<glm::dvec3> pickTerrain(const View& view, double x, double y) {
  const int width = view.camera.width, height = view.camera.height;
  if (x < 0 || y < 0 || x >= width || y >= height) return std::nullopt;
  float depth = 0.0f;
  glReadPixels(int(x), height - 1 - int(y), 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &depth);
  if (!(depth > 0.0f)) return std::nullopt;
  const double ndcX = (std::floor(x) + 0.5) / width * 2.0 - 1.0;
  const double ndcY = 1.0 - (std::floor(y) + 0.5) / height * 2.0;
  const glm::dvec3 ray =
      view.forward + ndcX * view.tanHalfWidth * view.right + ndcY * view.tanHalfHeight * view.up;
  return view.camera.eye + (kNearPlane / double(depth)) * ray;
}

// The editor of the view's brush: the tileset's chunk set (its source read again, every chunk
// kept from the tileset).
Result<std::unique_ptr<LiveEditor>> viewEditor(const ViewCommand& v, const TilesetReader& tileset) {
  if (v.options.tileset.starts_with("http://") || v.options.tileset.starts_with("https://"))
    return Error{"--edit needs a local tileset, not a URL (edits are written back to it)"};
  auto set = openTilesetChunkSet(tileset, v.options.tileset, v.editSource);
  if (!set) return set.error();
  return std::make_unique<LiveEditor>(std::move(*set));
}

// The default framebuffer's back buffer as an image (top row first), before the panel is drawn.
Image readBackBuffer(int width, int height) {
  Image image{width, height, std::vector<uint8_t>(size_t(width) * size_t(height) * 4)};
  std::vector<uint8_t> rows(image.rgba.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
  const size_t stride = size_t(width) * 4;
  for (int y = 0; y < height; ++y)
    std::copy_n(rows.data() + size_t(height - 1 - y) * stride, stride,
                image.rgba.data() + size_t(y) * stride);
  return image;
}

// Key presses (down now, up last frame): GLFW reports states, the viewer wants edges.
struct KeyEdges {
  bool down[GLFW_KEY_LAST + 1] = {};
  bool pressed(GLFWwindow* w, int key) {
    const bool now = glfwGetKey(w, key) == GLFW_PRESS;
    const bool edge = now && !down[key];
    down[key] = now;
    return edge;
  }
};

// A UI-owned copy of what the command line asked for, changed by the panel.
struct Knobs {
  float tau = 2.0f;
  bool morph = true, skirts = true, wireframe = false, freeze = false, textures = true;
  bool boxes = false, fans = false;  // fans: VIPM borders stitched by fans, not flanges
  bool blots = true;                 // far VIPM chunks drawn as blots
  bool superChunks = true;           // a super-chunk's blots in one call
  int colorBy = 0;                   // relief, level, morph, kind
};

FlyInput readInput(GLFWwindow* w, double& lastX, double& lastY, bool& dragging) {
  FlyInput in;
  const ImGuiIO& io = ImGui::GetIO();
  if (!io.WantCaptureKeyboard) {
    auto key = [&](int k) { return glfwGetKey(w, k) == GLFW_PRESS ? 1.0 : 0.0; };
    in.forward = key(GLFW_KEY_W) - key(GLFW_KEY_S);
    in.right = key(GLFW_KEY_D) - key(GLFW_KEY_A);
    in.up = key(GLFW_KEY_E) - key(GLFW_KEY_Q);
    in.fast = key(GLFW_KEY_LEFT_SHIFT) > 0 || key(GLFW_KEY_RIGHT_SHIFT) > 0;
  }
  double x = 0, y = 0;
  glfwGetCursorPos(w, &x, &y);
  const bool pressed = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS ||
                       glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  if (pressed && (dragging || !io.WantCaptureMouse)) {
    if (dragging) {
      in.lookRight = (x - lastX) * kMouseRadiansPerPixel;
      in.lookUp = -(y - lastY) * kMouseRadiansPerPixel;
    }
    dragging = true;
  } else {
    dragging = false;
  }
  lastX = x;
  lastY = y;
  return in;
}

int runView(const ViewCommand& v) {
  if (!v.screenshot.empty())
    if (auto format = imageFormatFor(v.screenshot); !format) return fail(format.error().message);
  auto tileset = TilesetReader::openPathOrUrl(v.options.tileset);  // a path or an http(s):// URL
  if (!tileset) return fail(tileset.error().message);
  std::optional<Flight> playback;
  if (!v.play.empty()) {
    auto parsed = readFlightFile(v.play);
    if (!parsed) return fail(parsed.error().message);
    playback = std::move(parsed).value();
  }
  const std::array<int, 2> size = playback ? std::array<int, 2>{playback->width, playback->height}
                                           : std::array<int, 2>{1280, 800};
  std::unique_ptr<LiveEditor> editor;
  std::vector<TerrainEdit> scripted;
  std::vector<TilesetMaterial> materials = (*tileset)->metadata().materials;
  if (v.edit || !v.editScript.empty()) {
    if (!v.editScript.empty()) {
      auto strokes = readEditScript(v.editScript);
      if (!strokes) return fail(strokes.error().message);
      scripted = std::move(*strokes);
    }
    auto made = viewEditor(v, **tileset);
    if (!made) return fail(made.error().message);
    editor = std::move(*made);
  }
  size_t nextScripted = 0;
  Brushing brushing;
  bool brushWasDown = false;
  auto window = Window::open("terralod view: " + v.options.tileset, size[0], size[1]);
  if (!window) return fail(window.error().message);
  auto created =
      TerrainScene::create(std::move(tileset).value(), sceneOptions(v.options, false, **window));
  if (!created) return fail(created.error().message);
  TerrainScene& scene = **created;
  auto start = camerasFor(v.options, scene.tree());
  if (!start) return fail(start.error().message);
  auto baseStyle = terrainStyle(v.options);
  if (!baseStyle) return fail(baseStyle.error().message);
  baseStyle->stitch = stitchFor(v.options, scene.tileset().header());
  auto vegetation = addSceneVegetation(v.options, scene);
  if (!vegetation) return fail(vegetation.error().message);
  // Vegetation beyond the LDIs reads the terrain's depth: frames go to a target whose depth
  // is a texture, then to the window.
  std::optional<Framebuffer> offscreen;
  const std::vector<Camera> played = playback ? flightCameras(*playback) : std::vector<Camera>{};

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the user's directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL((*window)->handle(), true);
  ImGui_ImplOpenGL3_Init("#version 450 core");

  KeyEdges keys;
  Knobs knobs;
  knobs.tau = float(v.options.tau);
  knobs.morph = !v.options.noMorph;
  knobs.skirts = !v.options.noSkirts;
  knobs.wireframe = v.options.wireframe;
  knobs.boxes = v.options.chunkBoxes;
  knobs.textures = !v.options.noTextures;
  knobs.colorBy = int(baseStyle->colorBy);
  knobs.fans = baseStyle->stitch == VipmStitch::kFans;
  knobs.blots = baseStyle->blots == VipmBlots::kOn;
  knobs.superChunks = baseStyle->superChunks == VipmSuperChunks::kOn;
  FlyCamera fly(start->front());
  double fov = v.options.fovDegrees;
  std::vector<float> frameTimes(kFrameHistory, 0.0f);
  size_t frame = 0;
  bool recording = false, screenshotAsked = false;
  Flight recorded;
  double lastX = 0, lastY = 0;
  bool dragging = false;
  auto previous = std::chrono::steady_clock::now();
  int status = 0;
  auto ground = [&](double x, double y) { return groundHeightBound(scene.tree(), x, y); };
  auto saveRecording = [&]() -> Status {
    const std::string path = v.record.empty() ? "terralod-flight.json" : v.record;
    auto file = AtomicFile::create(path);
    if (!file) return file.error();
    recorded.frames = int(recorded.keyframes.size());
    if (Status s = file->write(flightToJson(recorded) + "\n"); !s) return s;
    std::printf("terralod: recorded %d frames to %s\n", recorded.frames, path.c_str());
    return file->commit();
  };

  while (!(*window)->shouldClose()) {
    glfwPollEvents();
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::min(0.25, std::chrono::duration<double>(now - previous).count());
    previous = now;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();

    const auto [width, height] = (*window)->framebufferSize();
    Camera camera;
    // A scripted edit holds the flight's last frame until every stroke is drawn.
    const bool editing = editor && (nextScripted < scripted.size() || editor->busy() ||
                                    scene.pendingReplacements() != 0);
    if (playback && !played.empty() && frame >= played.size() && editing) frame = played.size() - 1;
    if (playback && frame < played.size()) {
      camera = played[frame];
      camera.width = width;
      camera.height = height;
    } else {
      fly.update(readInput((*window)->handle(), lastX, lastY, dragging), seconds, ground);
      camera = fly.camera(width, height, fov);
    }
    if (!ImGui::GetIO().WantCaptureKeyboard) {
      if (keys.pressed((*window)->handle(), GLFW_KEY_F12)) screenshotAsked = true;
      if (keys.pressed((*window)->handle(), GLFW_KEY_R)) {
        recording = !recording;
        if (recording) {
          recorded = Flight{};
          recorded.fovDegrees = fov;
          recorded.width = width;
          recorded.height = height;
        } else if (Status s = saveRecording(); !s) {
          warn(s.error().message);
        }
      }
    }
    if (recording) recorded.keyframes.push_back({camera.eye, camera.target});

    auto view = makeView(camera);
    if (!view) return fail(view.error().message);
    SelectionOptions selection;
    selection.tau = std::max(0.05f, knobs.tau);
    selection.morph = knobs.morph;
    TerrainStyle style = *baseStyle;
    style.skirts = knobs.skirts;
    style.stitch = knobs.fans ? VipmStitch::kFans : VipmStitch::kFlanges;
    style.blots = knobs.blots ? VipmBlots::kOn : VipmBlots::kOff;
    style.superChunks = knobs.superChunks ? VipmSuperChunks::kOn : VipmSuperChunks::kOff;
    style.wireframe = knobs.wireframe;
    style.chunkBoxes = knobs.boxes;
    style.textures = knobs.textures;
    style.colorBy = ColorBy(knobs.colorBy);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (vegetation->painter)
      if (Status s = bindFramebufferOfSize(offscreen, view->camera.width, view->camera.height); !s)
        return fail(s.error().message);
    const auto drawStart = std::chrono::steady_clock::now();
    auto stats = scene.renderFrame(*view, selection, style, !knobs.freeze);
    if (!stats) return fail(stats.error().message);
    if (offscreen) {
      const int w = view->camera.width, h = view->camera.height;
      glBlitNamedFramebuffer(offscreen->framebufferId(), 0, 0, 0, w, h, 0, 0, w, h,
                             GL_COLOR_BUFFER_BIT, GL_NEAREST);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);  // the panel goes to the window
      glBindFramebuffer(GL_READ_FRAMEBUFFER, offscreen->framebufferId());  // picking: its depth
    }
    frameTimes[frame % kFrameHistory] = float(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - drawStart)
            .count());
    if (editor) {
      if (auto done = editor->poll(scene)) {
        char text[160];
        using What = LiveEditor::Finished::What;
        if (!done->status)
          brushing.status = done->status.error().message;
        else if (done->what == What::kInterim)
          std::snprintf(text, sizeof text,
                        "regenerating %zu chunks (drawn at full resolution meanwhile)...",
                        done->nodes);
        else if (done->what == What::kNear)
          std::snprintf(text, sizeof text,
                        "stroke %zu: %zu chunks rebuilt in %.0f ms; the levels above them...",
                        editor->strokes() + 1, done->nodes, done->ms);
        else if (done->what == What::kStroke)
          std::snprintf(text, sizeof text, "stroke %zu: %zu chunks rebuilt in %.0f ms",
                        editor->strokes(), done->nodes, done->ms);
        else
          std::snprintf(text, sizeof text, "saved %s in %.0f ms", v.options.tileset.c_str(),
                        done->ms);
        if (done->status) brushing.status = text;
      }
      if (nextScripted < scripted.size() && editor->submit(scripted[nextScripted])) ++nextScripted;
      // The brush: B held, left click on the terrain.
      GLFWwindow* handle = (*window)->handle();
      const bool down = glfwGetMouseButton(handle, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
      if (down && !brushWasDown && glfwGetKey(handle, GLFW_KEY_B) == GLFW_PRESS &&
          !ImGui::GetIO().WantCaptureMouse) {
        double x = 0, y = 0;
        glfwGetCursorPos(handle, &x, &y);
        if (auto at = pickTerrain(*view, x, y)) {
          TerrainEdit e{Brush(brushing.brush), at->x, at->y, brushing.radius, brushing.amount, 0};
          if (e.brush == Brush::kSmooth) e.amount = brushing.strength;
          if (e.brush == Brush::kPaint && !materials.empty())
            e.material = materials[size_t(brushing.material)].id;
          brushing.status = editor->submit(e) ? "regenerating..." : "busy: try again";
        }
      }
      brushWasDown = down;
    }

    const bool playedOut = playback && frame + 1 == played.size() && !editing;
    if (screenshotAsked || (playedOut && !v.screenshot.empty())) {
      const std::string path =
          !v.screenshot.empty() && playedOut ? v.screenshot : "terralod-screenshot.png";
      if (Status s = writeImage(readBackBuffer(width, height), path); !s) {
        warn(s.error().message);
        if (playedOut) status = 1;
      } else {
        std::printf("terralod: saved %s\n", path.c_str());
      }
      screenshotAsked = false;
    }

    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::Begin("terralod");
    ImGui::SliderFloat("tau (px)", &knobs.tau, 0.25f, 16.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    ImGui::Checkbox("morph", &knobs.morph);
    ImGui::SameLine();
    ImGui::Checkbox("skirts", &knobs.skirts);
    ImGui::SameLine();
    ImGui::Checkbox("wireframe", &knobs.wireframe);
    ImGui::Checkbox("textures", &knobs.textures);
    ImGui::SameLine();
    ImGui::Checkbox("chunk boxes", &knobs.boxes);
    ImGui::SameLine();
    ImGui::Checkbox("fans", &knobs.fans);
    ImGui::SameLine();
    ImGui::Checkbox("blots", &knobs.blots);
    ImGui::SameLine();
    ImGui::Checkbox("super-chunks", &knobs.superChunks);
    ImGui::Combo("colour", &knobs.colorBy, "relief\0level\0morph\0kind\0");
    ImGui::Checkbox("freeze selection", &knobs.freeze);
    ImGui::SameLine();
    ImGui::Checkbox("walk", &fly.walking);
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::Text("%.0f fps, frame %.1f ms", io.Framerate, frameTimes[frame % kFrameHistory]);
    ImGui::Text("selection %.1f us, %u chunks, %u coarser than wanted", stats->selectMicroseconds,
                stats->selection.selected, stats->selection.coarserThanWanted);
    ImGui::Text("%llu triangles, %u draw calls, %.1f MB on the GPU",
                (unsigned long long)stats->draw.triangles, stats->draw.drawCalls,
                double(scene.gpuBytes()) / 1e6);
    {
      const Residency& residency = scene.residency();
      const ResidencyCounters& c = residency.counters();
      ImGui::Text("resident %.1f of %.0f MB; %zu loading, %zu queued; %llu loads, %llu evicted",
                  double(c.residentBytes) / double(1 << 20), v.options.cacheMB,
                  residency.inFlight(), residency.queued(), (unsigned long long)c.loads,
                  (unsigned long long)c.evictions);
    }
    ImGui::Text("eye %.0f, %.0f, %.0f m", camera.eye.x, camera.eye.y, camera.eye.z);
    ImGui::PlotLines("ms", frameTimes.data(), kFrameHistory, int((frame + 1) % kFrameHistory),
                     nullptr, 0.0f, 50.0f, ImVec2(0, 50));
    ImGui::TextUnformatted(recording ? "recording (R to stop)"
                                     : "R records a flight, F12 saves a screenshot");
    if (editor) {
      ImGui::Separator();
      ImGui::Combo("brush", &brushing.brush, "raise\0lower\0smooth\0paint\0");
      ImGui::SliderFloat("radius (m)", &brushing.radius, 1.0f, 20000.0f, "%.0f",
                         ImGuiSliderFlags_Logarithmic);
      if (brushing.brush == 2)
        ImGui::SliderFloat("strength", &brushing.strength, 0.05f, 1.0f, "%.2f");
      else if (brushing.brush == 3 && !materials.empty())
        ImGui::SliderInt(materials[size_t(brushing.material)].name.c_str(), &brushing.material, 0,
                         int(materials.size()) - 1);
      else
        ImGui::SliderFloat("amount (m)", &brushing.amount, 0.1f, 1000.0f, "%.1f",
                           ImGuiSliderFlags_Logarithmic);
      ImGui::TextUnformatted(brushing.status.c_str());
      ImGui::Text("%zu strokes%s", editor->strokes(), editor->unsaved() ? ", not saved" : "");
      if (ImGui::Button("save") && !editor->save(v.options.tileset)) brushing.status = "busy";
    }
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    (*window)->swapBuffers();
    ++frame;
    if (playedOut && v.exitAfterPlay) break;
  }
  if (recording)
    if (Status s = saveRecording(); !s) warn(s.error().message);
  if (editor && v.saveEdits) {
    // Finish the stroke in progress, then write the tileset back.
    auto finish = [&]() -> Status {
      while (editor->busy()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        if (auto done = editor->poll(scene); done && !done->status) return done->status;
      }
      return {};
    };
    Status saved = finish();
    if (saved && editor->unsaved()) {
      editor->save(v.options.tileset);
      saved = finish();
      if (saved)
        std::printf("terralod: saved %zu strokes to %s\n", editor->strokes(),
                    v.options.tileset.c_str());
    }
    if (!saved) {
      warn(saved.error().message);
      status = 1;
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  return status;
}

}  // namespace

void addViewCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "view",
      "Fly over a tileset in a window: drag the mouse to look, WASD to move (E/Q up/down, shift "
      "faster), R to record a flight, F12 for a screenshot; a panel sets tau, morph, skirts, "
      "wireframe, textures, chunk boxes, colours and freezes the selection");
  auto v = std::make_shared<ViewCommand>();
  addRenderOptions(*cmd, v->options, true);
  cmd->add_option("--play", v->play, "Play a flight file instead of flying by hand");
  cmd->add_option("--screenshot", v->screenshot,
                  "With --play: save the last frame here (.png, or .jpg/.jpeg for JPEG)");
  cmd->add_flag("--exit-after-play", v->exitAfterPlay, "With --play: close after the last frame");
  cmd->add_option("--record", v->record, "Where R saves the recorded flight (JSON)");
  cmd->add_flag("--edit", v->edit,
                "VIPM tilesets: the brush (hold B and click): raise, lower, smooth, paint; "
                "strokes are regenerated while you fly and saved with the panel's save button");
  cmd->add_option("--edit-source", v->editSource,
                  "The raster the tileset was built from (default: the file its metadata names, "
                  "next to it or in the current directory)");
  cmd->add_option("--edit-script", v->editScript,
                  "Apply these strokes (terralod edit's script) one after another as the view "
                  "starts; with --play the last frame waits until they are drawn");
  cmd->add_flag("--save-edits", v->saveEdits,
                "Write the strokes back to the tileset when the view closes");
  cmd->footer(
      "Controls:\n"
      "  drag (left or right button)  look around\n"
      "  W/S, A/D, E/Q                forward/back, left/right, up/down (shift: five times "
      "faster)\n"
      "  R                            start/stop recording a flight (--record, default "
      "terralod-flight.json)\n"
      "  F12                          save a screenshot (terralod-screenshot.png)\n"
      "  B + left click               (--edit) apply the brush set in the panel\n"
      "Examples:\n"
      "  terralod view dem.tlod\n"
      "  terralod view http://host/dem.tlod --tau 1 --chunk-boxes\n"
      "  xvfb-run -a terralod view dem.tlod --play flight.json --screenshot last.png "
      "--exit-after-play\n");
  cmd->callback([&run, v] { run = [v] { return runView(*v); }; });
}

}  // namespace terralod::cli
