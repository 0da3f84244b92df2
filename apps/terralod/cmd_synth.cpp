// terralod synth --size N [--seed S] [--spacing M] -o OUT.tif

#include <chrono>
#include <cstdio>

#include "cli_checks.h"
#include "commands.h"
#include "terralod/raster/synthetic_dem_writer.h"

namespace terralod::cli {

void addSynthCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "synth",
      "Write a deterministic synthetic DEM (ridged mountains, hills, valleys and flats) as a "
      "tiled GeoTIFF, streamed to disk tile row by tile row");
  auto options = std::make_shared<SyntheticDemOptions>();
  auto size = std::make_shared<int64_t>(0);
  cmd->add_option("--size", *size,
                  "Samples per side (2.." + std::to_string(kMaxSyntheticSide) +
                      "); any size, e.g. 8193 for 2^13+1")
      ->required()
      ->check(wholeNumber<int64_t>());
  cmd->add_option("--seed", options->seed, "Seed; the same seed gives the same terrain")
      ->capture_default_str()
      ->check(wholeNumber<uint64_t>());
  cmd->add_option("--spacing", options->spacing, "Metres between samples")
      ->capture_default_str()
      ->check(positiveNumber());
  cmd->add_option("--compress", options->compression, "GeoTIFF compression")
      ->capture_default_str()
      ->check(CLI::IsMember({"zstd", "deflate", "lzw", "none"}));
  cmd->add_option("--threads", options->threads, "Worker threads (default: all cores)")
      ->check(wholeNumber<unsigned>());
  cmd->add_option("-o,--output", options->output, "GeoTIFF to write")->required();
  cmd->footer(
      "Example:\n"
      "  terralod synth --size 8193 --seed 1 -o synth.tif\n");
  cmd->callback([&run, options, size] {
    run = [options, size] {
      options->columns = options->rows = *size;
      TerminalProgress progress;
      const auto start = std::chrono::steady_clock::now();
      if (Status written = writeSyntheticDem(*options, progress); !written)
        return fail(written.error().message);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double samples = double(*size) * double(*size);
      std::printf(
          "terralod: wrote %s: %lldx%lld samples at %g m, seed %llu, %.2f s (%.1f M samples/s)\n",
          options->output.c_str(), (long long)*size, (long long)*size, options->spacing,
          (unsigned long long)options->seed, seconds, samples / seconds / 1e6);
      return 0;
    };
  });
}

}  // namespace terralod::cli
