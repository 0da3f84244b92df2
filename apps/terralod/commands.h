#pragma once
// Each subcommand registers itself on the root CLI and sets `run` when chosen.

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace terralod::cli {

using Runner = std::function<int()>;

void addBuildCommand(CLI::App& root, Runner& run);
void addInfoCommand(CLI::App& root, Runner& run);
void addVerifyCommand(CLI::App& root, Runner& run);
void addExportCommand(CLI::App& root, Runner& run);
void addSynthCommand(CLI::App& root, Runner& run);
void addRenderCommand(CLI::App& root, Runner& run);
void addBenchCommand(CLI::App& root, Runner& run);
void addViewCommand(CLI::App& root, Runner& run);
void addClassifyCommand(CLI::App& root, Runner& run);
void addEditCommand(CLI::App& root, Runner& run);
void addVegetationCommand(CLI::App& root, Runner& run);
void addWhereCommand(CLI::App& root, Runner& run);
void addBuildStageCommand(CLI::App& root, Runner& run);

/// The command line terralod was started with, arguments quoted where the shell needs it (for
/// reports that say how they were made).
const std::string& commandLine();
void setCommandLine(int argc, char** argv);

/// Prints "terralod: error: <message>" on stderr and returns the exit code 1.
int fail(const std::string& message);
/// Prints "terralod: warning: <message>" on stderr.
void warn(const std::string& message);

}  // namespace terralod::cli
