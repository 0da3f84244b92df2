// terralod view TILESET: fly over a tileset in a window, with the algorithm's knobs at hand.
// Scriptable for tests: --play F.json --screenshot OUT.png --exit-after-play.

// epoxy before GLFW, which would otherwise include the system's GL header.
#include <epoxy/gl.h>

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <chrono>
#include <cstdio>

#include "commands.h"
#include "render_options.h"
#include "terralod/core/atomic_file.h"
#include "terralod/measure/fly_camera.h"
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
};

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
    style.wireframe = knobs.wireframe;
    style.chunkBoxes = knobs.boxes;
    style.textures = knobs.textures;
    style.colorBy = ColorBy(knobs.colorBy);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    const auto drawStart = std::chrono::steady_clock::now();
    auto stats = scene.renderFrame(*view, selection, style, !knobs.freeze);
    if (!stats) return fail(stats.error().message);
    frameTimes[frame % kFrameHistory] = float(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - drawStart)
            .count());

    const bool playedOut = playback && frame + 1 == played.size();
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
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    (*window)->swapBuffers();
    ++frame;
    if (playedOut && v.exitAfterPlay) break;
  }
  if (recording)
    if (Status s = saveRecording(); !s) warn(s.error().message);
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
  cmd->footer(
      "Controls:\n"
      "  drag (left or right button)  look around\n"
      "  W/S, A/D, E/Q                forward/back, left/right, up/down (shift: five times "
      "faster)\n"
      "  R                            start/stop recording a flight (--record, default "
      "terralod-flight.json)\n"
      "  F12                          save a screenshot (terralod-screenshot.png)\n"
      "Examples:\n"
      "  terralod view dem.tlod\n"
      "  terralod view http://host/dem.tlod --tau 1 --chunk-boxes\n"
      "  xvfb-run -a terralod view dem.tlod --play flight.json --screenshot last.png "
      "--exit-after-play\n");
  cmd->callback([&run, v] { run = [v] { return runView(*v); }; });
}

}  // namespace terralod::cli
