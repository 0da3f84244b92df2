// Subcommands not written yet.
#include "commands.h"
namespace terralod::cli {
void addExportCommand(CLI::App&, Runner&) {}
void addSynthCommand(CLI::App&, Runner&) {}
}  // namespace terralod::cli
