#include "terralod/measure/bench_report.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "terralod/core/atomic_file.h"
#include "terralod/render/contact_sheet.h"

extern char** environ;

namespace terralod {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPlots[] = {"frame_time.png", "selection_time.png", "triangles.png",
                                  "resident_mb.png", "error_px.png"};

// The first executable `name` on PATH, or empty.
std::string findOnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return {};
}

// Runs `program script` with its standard output discarded; fails unless it exits with 0.
Status runGnuplot(const std::string& program, const std::string& script) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  std::string arg0 = program, arg1 = script;
  char* argv[] = {arg0.data(), arg1.data(), nullptr};
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return Error{program + ": cannot run it"};
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return Error{program + ": lost track of it"};
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return Error{script + ": gnuplot failed to draw the plots"};
  return {};
}

// A gnuplot string literal (single quotes, doubled inside).
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string number(double v, const char* format = "%.6g") {
  if (std::isnan(v)) return "NaN";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

std::string framesCsv(const BenchFlightResult& flight) {
  std::string csv =
      "frame,frame_ms,select_us,upload_ms,triangles,draws,chunks,uploads,evictions,resident_mb,"
      "coarser,waited_on_io,eye_x,eye_y,eye_z,error_px,pop_px,image_pop,holes,easing,culled_chunks,"
      "culled_triangles,vegetation_ms,composite_ms,splats,ldi_tiles,vegetation_pop,"
      "vegetation_ssim,vegetation_coverage_error\n";
  for (size_t i = 0; i < flight.frames.size(); ++i) {
    const FrameRecord& r = flight.frames[i];
    char line[768];
    std::snprintf(line, sizeof line,
                  "%zu,%.4f,%.2f,%.4f,%" PRIu64
                  ",%u,%u,%u,%u,%.3f,%d,%d,%.3f,%.3f,%.3f,%s,%s,%s,%" PRIu64 ",%d,%u,%" PRIu64
                  ",%s,%s,%" PRIu64 ",%u,%s,%s,%s\n",
                  i, r.frameMs, r.selectUs, r.uploadMs, r.triangles, r.draws, r.chunks, r.uploads,
                  r.evictions, r.residentMB, r.coarser ? 1 : 0, r.waitedOnIo ? 1 : 0, r.eye.x,
                  r.eye.y, r.eye.z, number(r.errorPx).c_str(), number(r.popPx).c_str(),
                  number(r.imagePop).c_str(), r.holes, r.easing ? 1 : 0, r.culledChunks,
                  r.culledTriangles, number(r.vegetationMs).c_str(), number(r.compositeMs).c_str(),
                  r.splats, r.ldiTiles, number(r.vegetationPop).c_str(),
                  number(r.vegetationSsim).c_str(), number(r.vegetationCoverageError).c_str());
    csv += line;
  }
  return csv;
}

// One plot per figure, frame number along x; reference lines for the targets.
std::string plotScript(const nlohmann::json& s, bool quality) {
  const bool coarser = s["coarser_than_wanted_frames"].get<uint64_t>() > 0;
  const bool holes = quality && s["holes_total"].get<uint64_t>() > 0;
  std::ostringstream gp;
  gp << "# Draws the bench report's plots from frames.csv (run from the report's directory).\n"
        "set terminal pngcairo size 960,300 font 'sans,9'\n"
        "set datafile separator comma\n"
        "set datafile missing 'NaN'\n"
        "set key top left opaque\n"
        "set grid ytics lc rgb '#dddddd'\n"
        "set xlabel 'frame'\n"
        "set yrange [0:*]\n"
        "set xrange [0:"
     << std::max<uint64_t>(1, s["frames"].get<uint64_t>() - 1) << "]\n";
  const double p50 = s["frame_ms_p50"], p99 = s["frame_ms_p99"];
  gp << "set output 'frame_time.png'\nset ylabel 'ms'\n"
     << "plot 'frames.csv' skip 1 using 1:2 with lines lc rgb '#1f77b4' title 'frame time', \\\n"
     << "  " << number(p50) << " with lines dt 2 lc rgb '#2ca02c' title 'p50 "
     << number(p50, "%.1f") << " ms', \\\n  " << number(p99)
     << " with lines dt 2 lc rgb '#d62728' title 'p99 " << number(p99, "%.1f") << " ms', \\\n"
     << "  '' skip 1 using 1:4 with lines lc rgb '#ff7f0e' title 'uploads'\n";
  gp << "set output 'selection_time.png'\nset ylabel 'µs'\n"
     << "plot 'frames.csv' skip 1 using 1:3 with lines lc rgb '#9467bd' title 'selection'\n";
  gp << "set output 'triangles.png'\nset ylabel 'triangles'\nset y2label 'draw calls'\n"
        "set y2tics\nset y2range [0:*]\n"
     << "plot 'frames.csv' skip 1 using 1:5 with lines lc rgb '#1f77b4' title 'triangles', \\\n"
        "  '' skip 1 using 1:6 axes x1y2 with lines lc rgb '#ff7f0e' title 'draw calls'\n"
        "unset y2tics\nunset y2label\n";
  const double budget = s["cache_mb"];
  gp << "set output 'resident_mb.png'\nset ylabel 'MB'\n"
     << "plot 'frames.csv' skip 1 using 1:10 with lines lc rgb '#1f77b4' title 'resident', \\\n"
     << "  " << number(budget) << " with lines dt 2 lc rgb '#d62728' title 'budget "
     << number(budget, "%.0f") << " MB'";
  if (coarser)
    gp << ", \\\n  '' skip 1 using 1:($11 > 0 ? 0 : NaN) with points pt 7 ps 0.3 "
          "lc rgb '#ff7f0e' title 'frames coarser than wanted'";
  gp << "\n";
  if (quality) {
    // Errors of frames drawn coarser while their chunks stream in can be many times τ; the
    // plot is scaled for the bound and clips them.
    const double tau = s["tau"];
    const double top = std::max(1.5 * tau, 1.1 * s["max_error_px"].get<double>());
    gp << "set output 'error_px.png'\nset ylabel 'pixels'\nset yrange [0:" << number(top) << "]\n"
       << "plot 'frames.csv' skip 1 using 1:($11 > 0 ? NaN : $16) with lines lc rgb '#1f77b4' "
          "title 'screen-space error', \\\n"
       << "  '' skip 1 using 1:17 with lines lc rgb '#2ca02c' title 'pop', \\\n"
       << "  " << number(tau)
       << " with lines dt 2 lc rgb '#d62728' title 'τ = " << number(tau, "%.3g") << "'";
    if (coarser)
      gp << ", \\\n  '' skip 1 using 1:($11 > 0 ? $16 : NaN) with points pt 7 ps 0.3 "
            "lc rgb '#aaaaaa' title 'error while streaming (coarser than wanted)'";
    if (holes)
      gp << ", \\\n  '' skip 1 using 1:($19 > 0 ? 0 : NaN) with points pt 7 ps 0.6 "
            "lc rgb '#000000' title 'frames with holes'";
    gp << "\n";
  }
  return gp.str();
}

std::string figure(const nlohmann::json& s, const char* key, const char* format = "%.3g") {
  if (!s.contains(key)) return "—";
  const auto& v = s[key];
  if (v.is_number_integer() || v.is_number_unsigned()) return std::to_string(v.get<int64_t>());
  if (v.is_number()) return number(v.get<double>(), format);
  return v.dump();
}

// The frame where `key(record)` is largest (NaN skipped); npos if none.
template <typename Key>
size_t worstFrame(const BenchFlightResult& flight, Key key) {
  size_t worst = std::string::npos;
  double best = -1.0;
  for (size_t i = 0; i < flight.frames.size(); ++i) {
    const double v = key(flight.frames[i]);
    if (!std::isnan(v) && v > best) best = v, worst = i;
  }
  return worst;
}

std::string reportMarkdown(const BenchFlightResult& flight, const nlohmann::json& s,
                           const std::string& commandLine, bool quality) {
  std::ostringstream md;
  md << "# terralod bench report\n\n```sh\n" << commandLine << "\n```\n\n";
  md << "- tileset: `" << s["tileset"].get<std::string>() << "`\n"
     << "- OpenGL: " << s["gl"].get<std::string>() << "\n"
     << "- " << figure(s, "frames") << " frames at " << s["size"][0] << "×" << s["size"][1]
     << ", τ = " << figure(s, "tau") << " px, morphing " << (s["morph"] ? "on" : "off")
     << ", skirts " << (s["skirts"] ? "on" : "off") << ", chunk budget " << figure(s, "cache_mb")
     << " MB\n\n";
  md << "| figure | value |\n|---|---|\n"
     << "| frame ms p50 / p99 / max | " << figure(s, "frame_ms_p50") << " / "
     << figure(s, "frame_ms_p99") << " / " << figure(s, "frame_ms_max") << " |\n"
     << "| selection µs p50 / max | " << figure(s, "select_us_p50") << " / "
     << figure(s, "select_us_max") << " |\n"
     << "| triangles p50 / max | " << figure(s, "triangles_p50", "%.0f") << " / "
     << figure(s, "triangles_max", "%.0f") << " |\n"
     << "| draw calls p50 | " << figure(s, "draws_p50") << " |\n"
     << "| resident MB max (budget) | " << figure(s, "resident_mb_max") << " ("
     << figure(s, "cache_mb") << ") |\n"
     << "| upload ms max | " << figure(s, "upload_ms_max") << " |\n"
     << "| loads / evictions / MB read | " << figure(s, "loads") << " / " << figure(s, "evictions")
     << " / " << number(s["bytes_read"].get<double>() / double(1 << 20), "%.1f") << " |\n"
     << "| frames waiting on IO | " << figure(s, "frames_waiting_on_io") << " |\n"
     << "| frames coarser than wanted | " << figure(s, "coarser_than_wanted_frames") << " |\n";
  if (s.contains("max_texel_per_px"))
    md << "| max pixels per texel | " << figure(s, "max_texel_per_px", "%.4g") << " |\n";
  if (s.contains("max_texel_per_px_source_limited"))
    md << "| max pixels per texel, source-limited layers | "
       << figure(s, "max_texel_per_px_source_limited") << " |\n";
  if (quality)
    md << "| max error px (complete frames / all) | " << figure(s, "max_error_px", "%.4g") << " / "
       << figure(s, "max_error_px_all", "%.4g") << " |\n"
       << "| max pop px | " << figure(s, "max_pop_px", "%.4g") << " |\n";
  if (quality && s.contains("max_morph_step_px"))
    md << "| max morph step px (VIPM: all motion between frames) | "
       << figure(s, "max_morph_step_px", "%.4g") << " |\n";
  if (s.contains("material_pop_px"))
    md << "| material pop px max / p99 (VIPM; morph step) | " << figure(s, "material_pop_px")
       << " / " << figure(s, "material_pop_px_p99") << " (" << figure(s, "material_morph_step_px")
       << ") |\n";
  if (quality)
    md << "| holes total | " << figure(s, "holes_total") << " |\n"
       << "| image pop mean /255 (average; with frames while streaming) | "
       << figure(s, "image_pop_mean", "%.4g") << " (" << figure(s, "image_pop_mean_avg", "%.4g")
       << "; " << figure(s, "image_pop_mean_all", "%.4g") << ") |\n";
  md << "\n";

  auto describe = [&](const char* what, size_t i, double value, const char* unit) {
    if (i == std::string::npos) return;
    const FrameRecord& r = flight.frames[i];
    md << "- " << what << ": frame " << i << ", " << number(value, "%.4g") << " " << unit
       << " (eye " << number(r.eye.x, "%.1f") << ", " << number(r.eye.y, "%.1f") << ", "
       << number(r.eye.z, "%.1f") << ")\n";
  };
  md << "Worst frames:\n\n";
  const size_t slowest = worstFrame(flight, [](const FrameRecord& r) { return r.frameMs; });
  describe("slowest", slowest, flight.frames[slowest].frameMs, "ms");
  if (quality) {
    const size_t err = worstFrame(
        flight, [](const FrameRecord& r) { return r.coarser ? double(NAN) : r.errorPx; });
    if (err != std::string::npos) describe("largest error", err, flight.frames[err].errorPx, "px");
    const size_t pop = worstFrame(flight, [](const FrameRecord& r) { return r.popPx; });
    if (pop != std::string::npos) describe("largest pop", pop, flight.frames[pop].popPx, "px");
    const size_t holes =
        worstFrame(flight, [](const FrameRecord& r) { return r.holes ? double(r.holes) : NAN; });
    if (holes != std::string::npos)
      describe("most holes", holes, double(flight.frames[holes].holes), "pixels");
  }
  md << "\n## Over the flight\n\n"
     << "![Frame time](frame_time.png)\n\n![Selection time](selection_time.png)\n\n"
     << "![Triangles and draw calls](triangles.png)\n\n![Resident memory](resident_mb.png)\n\n";
  if (quality) md << "![Screen-space error, pops and holes](error_px.png)\n\n";
  md << "## Frames\n\nFrames";
  for (size_t i = 0; i < flight.keptFrameIndices.size(); ++i)
    md << (i ? ", " : " ") << flight.keptFrameIndices[i];
  md << ", left to right, top to bottom:\n\n![Contact sheet](contact_sheet.jpg)\n\n"
     << "Every frame's figures are in `frames.csv`; `gnuplot plots.gp` draws the plots again.\n";
  return md.str();
}

Status writeText(const fs::path& path, const std::string& text) {
  auto file = AtomicFile::create(path.string());
  if (!file) return file.error();
  if (Status s = file->write(text); !s) return s;
  return file->commit();
}

// The report directory named by `dir`; "out/" is "out", not a directory inside "out".
fs::path reportDirectory(const std::string& dir) {
  fs::path target(dir);
  while (!target.has_filename() && target.has_relative_path()) target = target.parent_path();
  return target;
}

}  // namespace

Status checkReportTarget(const std::string& dir) {
  std::error_code ec;
  const fs::path target = reportDirectory(dir);
  if (fs::exists(target, ec) && !fs::is_directory(target, ec))
    return Error{dir + ": exists and is not a directory"};
  const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec))
    return Error{dir + ": its parent directory " + parent.string() + " does not exist"};
  if (::access(parent.c_str(), W_OK) != 0) return Error{dir + ": not writable"};
  if (findOnPath("gnuplot").empty())
    return Error{dir +
                 ": gnuplot is needed to draw the report's plots and was not found "
                 "(scripts/install-deps.sh installs it)"};
  return {};
}

Status writeBenchReport(const std::string& dir, const BenchFlightResult& flight,
                        const nlohmann::json& summary, const std::string& commandLine) {
  if (Status s = checkReportTarget(dir); !s) return s;
  const fs::path target = reportDirectory(dir);
  const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Everything goes to a temporary directory first, removed on any failure.
  std::string pattern = (parent / (".terralod-report-XXXXXX")).string();
  if (!::mkdtemp(pattern.data())) return Error{dir + ": cannot create a temporary directory"};
  const fs::path temp(pattern);
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  } cleanup{temp};

  const bool quality = summary.contains("max_error_px");
  std::vector<std::string> files = {"report.md", "frames.csv", "plots.gp", "contact_sheet.jpg"};
  for (const char* plot : kPlots)
    if (quality || std::string(plot) != "error_px.png") files.push_back(plot);

  if (Status s = writeText(temp / "frames.csv", framesCsv(flight)); !s) return s;
  if (Status s = writeText(temp / "plots.gp", plotScript(summary, quality)); !s) return s;
  if (Status s =
          writeText(temp / "report.md", reportMarkdown(flight, summary, commandLine, quality));
      !s)
    return s;
  if (Status s = writeJpeg(makeContactSheet(flight.keptImages, 6, 256),
                           (temp / "contact_sheet.jpg").string());
      !s)
    return s;
  // gnuplot resolves the script's file names against its working directory: a wrapper script
  // changes into the temporary directory first.
  const std::string wrapper = (temp / "draw.gp").string();
  if (Status s = writeText(wrapper, "cd " + quoted(temp.string()) + "\nload 'plots.gp'\n"); !s)
    return s;
  if (Status s = runGnuplot(findOnPath("gnuplot"), wrapper); !s) return s;
  for (const std::string& name : files)
    if (!fs::exists(temp / name)) return Error{dir + ": gnuplot did not draw " + name};

  std::error_code ec;
  fs::create_directories(target, ec);
  if (ec) return Error{dir + ": cannot create it: " + ec.message()};
  for (const std::string& name : files) {
    fs::rename(temp / name, target / name, ec);
    if (ec) return Error{(target / name).string() + ": cannot move it into place: " + ec.message()};
  }
  return {};
}

}  // namespace terralod
