#include "terralod/cluster/slurm.h"

#include <cstdlib>
#include <sstream>

#include "terralod/core/subprocess.h"

namespace terralod {
namespace {

std::string firstLine(const std::string& text) {
  const size_t end = text.find('\n');
  return end == std::string::npos ? text : text.substr(0, end);
}

// Slurm's commands print their reasons first and their conclusion last.
std::string lastLine(std::string text) {
  while (!text.empty() && text.back() == '\n') text.pop_back();
  const size_t start = text.rfind('\n');
  return start == std::string::npos ? text : text.substr(start + 1);
}

Result<std::string> run(const std::vector<std::string>& argv) {
  auto out = runProgram(argv);
  if (!out) return makeError(argv[0], out.error().message + "; is Slurm installed (slurm-wlm)?");
  if (out->exitStatus != 0) {
    std::string why = lastLine(out->err.empty() ? out->out : out->err);
    if (why.empty()) why = "exit status " + std::to_string(out->exitStatus);
    if (!std::getenv("SLURM_CONF"))
      why += "; SLURM_CONF is not set (scripts/slurm-local.sh start prints it for a local cluster)";
    return makeError(argv[0], "failed (" + why + ")");
  }
  return out->out;
}

}  // namespace

Result<std::string> sbatch(const SlurmSubmission& job) {
  std::vector<std::string> argv = {"sbatch",
                                   "--parsable",
                                   "--job-name=" + job.name,
                                   "--array=" + job.tasks,
                                   "--output=" + job.output,
                                   "--kill-on-invalid-dep=no"};
  if (!job.dependency.empty()) argv.push_back("--dependency=" + job.dependency);
  if (job.wholeNode) argv.push_back("--exclusive");
  argv.insert(argv.end(), job.extra.begin(), job.extra.end());
  argv.push_back("--wrap=" + job.command);
  auto out = run(argv);
  if (!out) return out.error();
  // "123" or "123;cluster".
  std::string id = firstLine(*out);
  id = id.substr(0, id.find(';'));
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
    return makeError("sbatch", "printed no job id (\"" + firstLine(*out) + "\")");
  return id;
}

Result<std::map<std::string, std::string>> liveTasks() {
  auto out = run({"squeue", "--me", "--noheader", "--array", "--format=%i|%r"});
  if (!out) return out.error();
  std::map<std::string, std::string> tasks;
  std::istringstream lines(*out);
  for (std::string line; std::getline(lines, line);) {
    const size_t bar = line.find('|');
    if (bar == std::string::npos) continue;
    auto trim = [](std::string t) {
      const size_t a = t.find_first_not_of(' '), b = t.find_last_not_of(' ');
      return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
    };
    tasks[trim(line.substr(0, bar))] = trim(line.substr(bar + 1));
  }
  return tasks;
}

Status setDependency(const std::string& job, const std::string& dependency) {
  auto out = run({"scontrol", "update", "JobId=" + job, "Dependency=" + dependency});
  if (!out) return out.error();
  return {};
}

void scancel(const std::vector<std::string>& jobs) {
  if (jobs.empty()) return;
  std::vector<std::string> argv = {"scancel"};
  argv.insert(argv.end(), jobs.begin(), jobs.end());
  (void)runProgram(argv);
}

std::vector<std::string> splitArguments(const std::string& text) {
  std::vector<std::string> words;
  std::string word;
  bool inWord = false;
  char quote = 0;
  for (char c : text) {
    if (quote) {
      if (c == quote)
        quote = 0;
      else
        word += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      inWord = true;
    } else if (c == ' ' || c == '\t' || c == '\n') {
      if (inWord) words.push_back(word);
      word.clear();
      inWord = false;
    } else {
      word += c;
      inWord = true;
    }
  }
  if (inWord) words.push_back(word);
  return words;
}

std::string shellQuoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace terralod
