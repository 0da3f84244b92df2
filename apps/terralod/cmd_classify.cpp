// terralod classify IMAGE -o CLASSES.tif [--palette PALETTE.json] [--sieve PIXELS]

#include <cstdio>

#include "commands.h"
#include "terralod/materials/classify_image.h"
#include "terralod/materials/palette.h"

namespace terralod::cli {

void addClassifyCommand(CLI::App& root, Runner& run) {
  auto* cmd = root.add_subcommand(
      "classify",
      "Turn a colour image into a categorical raster for `build --materials`: each pixel takes "
      "the palette class of the nearest colour");
  struct Options {
    std::string image, output, palette;
    ClassifyOptions classify;
  };
  auto options = std::make_shared<Options>();
  cmd->add_option("IMAGE", options->image, "8-bit RGB image GDAL reads (bands 1, 2, 3)")
      ->required();
  cmd->add_option("-o,--output", options->output,
                  "One-band Byte GeoTIFF to write (colour table and class names included)")
      ->required();
  cmd->add_option("--palette", options->palette,
                  "JSON palette: {\"classes\": [{\"value\": 1, \"name\": \"forest\", \"color\": "
                  "[34, 90, 40]}, ...]} (default: water, vegetation, soil, rock, snow, shadow)");
  cmd->add_option("--sieve", options->classify.sievePixels,
                  "Merge every 8-connected region of fewer pixels than this into its largest "
                  "neighbour (GDAL's sieve filter; a minimum mapping unit against speckle)")
      ->check(CLI::Range(0, 1 << 20));
  cmd->footer(
      "Example:\n"
      "  terralod classify landsat_rgb.tif --palette palette.json --sieve 16 -o classes.tif\n");
  cmd->callback([&run, options] {
    run = [options] {
      std::vector<Material> palette = defaultImagePalette();
      if (!options->palette.empty()) {
        auto read = readPalette(options->palette);
        if (!read) return fail(read.error().message);
        palette = std::move(read).value();
      }
      auto result = classifyImage(options->image, palette, options->output, options->classify);
      if (!result) return fail(result.error().message);
      std::printf("terralod: wrote %s: %dx%d pixels,", options->output.c_str(), result->columns,
                  result->rows);
      const double total = double(result->columns) * double(result->rows);
      for (size_t i = 0; i < palette.size(); ++i)
        std::printf(" %s %.1f%%%s", palette[i].name.c_str(), 100.0 * result->counts[i] / total,
                    i + 1 < palette.size() ? "," : "");
      if (result->masked) std::printf(", masked %.1f%%", 100.0 * result->masked / total);
      std::printf("\n");
      return 0;
    };
  });
}

}  // namespace terralod::cli
