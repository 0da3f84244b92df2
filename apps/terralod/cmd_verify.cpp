// terralod verify TILESET --source INPUT

#include <cstdio>

#include "cli_checks.h"
#include "commands.h"
#include "terralod/verify/verifier.h"

namespace terralod::cli {
namespace {

void printVipmChecks(const VipmVerifyStats& v) {
  std::printf(
      "  VIPM: %llu LODs, smallest (recorded - true error) %.4f m; %llu collapses, %llu "
      "break a material rule (%s); vertex materials %s: %llu differ; parts agree at %llu "
      "LODs; roots' finest LOD vs children's coarsest: %llu samples, largest difference %.6f m; "
      "normal maps: %llu (%llu texels) within BC5's loss of the source's, largest difference "
      "%.4f\n",
      (unsigned long long)v.lods, v.worstErrorMargin, (unsigned long long)v.collapsesChecked,
      (unsigned long long)v.ruleViolations,
      v.rulesPromised ? "built with the rules" : "built with --no-material-rules",
      v.materialsFromSource ? "against the source's" : "not checked against the source",
      (unsigned long long)v.materialMismatches, (unsigned long long)v.partLevelsChecked,
      (unsigned long long)v.fallbackSamples, v.fallbackMismatch,
      (unsigned long long)v.normalMapsChecked, (unsigned long long)v.normalTexels,
      v.worstNormalDeviation);
  if (v.upperNodes > 0)
    std::printf(
        "  VIPM above the roots: %llu nodes, each at up to %u LODs against every sample and "
        "its sides at every LOD; %llu join exactly their children's coarsest LODs' points\n",
        (unsigned long long)v.upperNodes, unsigned(kVipmUpperLevelsVerified),
        (unsigned long long)v.upperJoins);
}

}  // namespace

void addVerifyCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "verify",
      "Check a tileset against its source: true error of every chunk <= its level's bound, full "
      "coverage, morph targets equal the parent surface, skirts deep enough against any "
      "neighbour, checksums");
  auto tileset = std::make_shared<std::string>();
  auto source = std::make_shared<std::string>();
  auto options = std::make_shared<VerifyOptions>();
  cmd->add_option("TILESET", *tileset,
                  "Tileset: a .tlod file, or an http(s):// URL of one (read with range requests)")
      ->required();
  cmd->add_option("--source", *source, "The raster the tileset was built from")->required();
  cmd->add_option("--materials", options->materialsPath,
                  "VIPM tilesets built with --materials: that categorical raster, to check every "
                  "vertex's material against (without it, against the stored materials only)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--palette", options->palettePath, "The --palette the tileset was built with")
      ->check(CLI::ExistingFile);
  cmd->add_option("--threads", options->threads, "Worker threads (default: all cores)")
      ->check(wholeNumber<unsigned>());
  cmd->footer(
      "Example:\n"
      "  terralod verify dem.tlod --source dem.tif\n"
      "Exit status 1 with a list of failures if any promise is broken.\n");
  cmd->callback([&run, tileset, source, options] {
    run = [tileset, source, options] {
      TerminalProgress progress;
      auto report = verifyTileset(*tileset, *source, *options, progress);
      if (!report) return fail(report.error().message);
      const VerifyReport& r = *report;
      std::printf("%s against %s: %llu chunks\n", tileset->c_str(), source->c_str(),
                  (unsigned long long)r.chunks);
      std::printf(
          "  level   bound(m)  max error(m)  samples      uncovered  height step(m)  morph "
          "mismatch(m) vs allowed(m)\n");
      for (size_t l = 0; l < r.levels.size(); ++l) {
        const LevelCheck& c = r.levels[l];
        char morph[64] = "       - (roots: no parent)";
        if (l > 0)
          std::snprintf(morph, sizeof morph, "%12.6f %s %.6f", c.maxMorphMismatch,
                        c.maxMorphMismatch <= c.morphTolerance ? "≤" : ">", c.morphTolerance);
        std::printf("  %5zu  %9.4f  %12.4f  %11llu  %9llu  %14.6f  %s\n", l, c.bound, c.maxError,
                    (unsigned long long)c.samples, (unsigned long long)c.uncovered, c.heightStep,
                    morph);
      }
      std::printf(
          "  morph mismatch allowed = (height step + parent level's step) / 2 + 1e-6 m: a fully "
          "morphed chunk shows its parent's exact surface rounded to its own step, the parent "
          "draws its vertices rounded to its step, and both are linear over the chunk's "
          "triangles (which refine the parent's)\n");
      if (r.morphGap > 0)
        std::printf(
            "  ...plus %g x the parent level's bound: built with --mesher greedy, whose chunks "
            "may flip their parent's edges where their fully morphed surface stays that close "
            "to the parent's\n",
            r.morphGap);
      if (r.vipm) printVipmChecks(*r.vipm);
      std::printf("  %s: %llu chunk pairs, %llu border samples, smallest margin %.4f m\n",
                  r.vipm ? "flanges" : "skirts", (unsigned long long)r.skirtPairs,
                  (unsigned long long)r.skirtSamples, r.worstSkirtMargin);
      if (r.ok()) {
        std::printf("verify: OK\n");
        return 0;
      }
      for (const std::string& f : r.failures) std::fprintf(stderr, "  FAIL %s\n", f.c_str());
      if (r.failureCount > r.failures.size())
        std::fprintf(stderr, "  ... and %llu more\n",
                     (unsigned long long)(r.failureCount - r.failures.size()));
      return fail(*tileset + ": verification failed with " + std::to_string(r.failureCount) +
                  " problem(s)");
    };
  });
}

}  // namespace terralod::cli
