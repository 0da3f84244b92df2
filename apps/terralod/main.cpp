// terralod: build, inspect, verify, export, render and benchmark chunked-LOD terrain tilesets.

#include <exception>

#include "commands.h"
#include "terralod/raster/dem_reader.h"

int main(int argc, char** argv) {
  using namespace terralod::cli;
  CLI::App app{
      "terralod: massive terrain with chunked level of detail.\n"
      "Build a tileset from any elevation raster, then inspect, verify, edit, export, render or "
      "benchmark it."};
  app.require_subcommand(1, 1);
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string("terralod: error: ") + e.what() + " (see --help)\n";
  });
  setCommandLine(argc, argv);
  Runner run;
  addBuildCommand(app, run);
  addBuildStageCommand(app, run);
  addSynthCommand(app, run);
  addInfoCommand(app, run);
  addVerifyCommand(app, run);
  addExportCommand(app, run);
  addWhereCommand(app, run);
  addRenderCommand(app, run);
  addBenchCommand(app, run);
  addViewCommand(app, run);
  addClassifyCommand(app, run);
  addEditCommand(app, run);
  addVegetationCommand(app, run);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help exits 0; every usage error exits 1, like every other error.
    return app.exit(e) == 0 ? 0 : 1;
  }
  terralod::setGdalCacheBytes(uint64_t{64} << 20);
  try {
    return run ? run() : 0;
  } catch (const std::bad_alloc&) {
    return fail("out of memory");
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what());
  }
}
