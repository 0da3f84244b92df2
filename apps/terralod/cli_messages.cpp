// The CLI's error and warning lines, and the command line it was started with.

#include <cstdio>

#include "commands.h"

namespace terralod::cli {

int fail(const std::string& message) {
  std::fprintf(stderr, "terralod: error: %s\n", message.c_str());
  return 1;
}

void warn(const std::string& message) {
  std::fprintf(stderr, "terralod: warning: %s\n", message.c_str());
}

namespace {
std::string gCommandLine;
}

const std::string& commandLine() {
  return gCommandLine;
}

void setCommandLine(int argc, char** argv) {
  gCommandLine.clear();
  for (int i = 0; i < argc; ++i) {
    std::string arg = i == 0 ? std::string("terralod") : std::string(argv[i]);
    const bool plain = !arg.empty() && arg.find_first_not_of(
                                           "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                           "0123456789-_./,:=+@%") == std::string::npos;
    if (!plain) {
      std::string q = "'";
      for (char c : arg) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
      arg = q + "'";
    }
    gCommandLine += (i ? " " : "") + arg;
  }
}

}  // namespace terralod::cli
