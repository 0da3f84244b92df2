#pragma once
// `bench --report DIR`: a benchmark people can read at a glance. DIR gets
//   report.md          the figures as a table, the worst frames, the plots and the contact sheet
//   frames.csv         one row per frame (what the plots are drawn from)
//   plots.gp           the gnuplot script that draws the plots (run it again to restyle them)
//   frame_time.png, selection_time.png, triangles.png, resident_mb.png, error_px.png (with a
//                      source raster) — each figure over the flight
//   contact_sheet.jpg  evenly spaced frames of the flight
// The plots are drawn by gnuplot (Debian's gnuplot-nox). Files appear complete or not at all:
// everything is written to a temporary directory beside DIR and moved in at the end; other
// files in DIR are left alone.

#include <nlohmann/json.hpp>
#include <string>

#include "terralod/core/result.h"
#include "terralod/measure/bench_flight.h"

namespace terralod {

/// How many frames the contact sheet shows.
constexpr size_t kReportSheetFrames = 24;

/// Checks, before a long flight, that a report can be written to `dir` (a directory or a new
/// name in an existing one) and that gnuplot is installed.
Status checkReportTarget(const std::string& dir);

/// Writes the report of `flight` (whose figures are summarised in `summary`, bench's JSON) to
/// `dir`. `commandLine` is shown at the top.
Status writeBenchReport(const std::string& dir, const BenchFlightResult& flight,
                        const nlohmann::json& summary, const std::string& commandLine);

}  // namespace terralod
