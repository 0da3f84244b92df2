// terralod export: not written yet.
#include "commands.h"
namespace terralod::cli {
void addExportCommand(CLI::App&, Runner&) {}
}  // namespace terralod::cli
