#pragma once
// Runs the terralod CLI (or any program) from integration tests and captures what it printed.

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace terralod::test {

struct RunResult {
  int exitCode = -1;  ///< -1 when killed by a signal
  std::string out;
  std::string err;
  /// stderr's lines, without empty ones.
  std::vector<std::string> errLines() const {
    std::vector<std::string> lines;
    std::istringstream in(err);
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) lines.push_back(line);
    return lines;
  }
};

/// Runs `program args...` with stdout and stderr captured through temporary files; `env` holds
/// NAME=VALUE settings added to the child's environment.
inline RunResult runProgram(const std::string& program, const std::vector<std::string>& args,
                            const std::vector<std::string>& env = {}) {
  namespace fs = std::filesystem;
  char outTemplate[] = "/tmp/terralod-test-out-XXXXXX";
  char errTemplate[] = "/tmp/terralod-test-err-XXXXXX";
  const int outFd = mkstemp(outTemplate);
  const int errFd = mkstemp(errTemplate);
  RunResult result;
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(outFd, STDOUT_FILENO);
    dup2(errFd, STDERR_FILENO);
    for (const std::string& setting : env) putenv(const_cast<char*>(setting.c_str()));
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(program.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(program.c_str(), argv.data());
    execvp(program.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  close(outFd);
  close(errFd);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = readWholeFile(outTemplate);
  result.err = readWholeFile(errTemplate);
  fs::remove(outTemplate);
  fs::remove(errTemplate);
  return result;
}

/// Starts `program args...` in the background with stdout and stderr discarded; returns its
/// process id (the caller waits for it, or kills it).
inline pid_t startProgram(const std::string& program, const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(program.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(program.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

/// Whether `text` (a command's output) contains `part`.
inline bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Runs the terralod CLI built alongside the tests.
inline RunResult runTerralod(const std::vector<std::string>& args,
                             const std::vector<std::string>& env = {}) {
  return runProgram(TERRALOD_CLI, args, env);
}

}  // namespace terralod::test
