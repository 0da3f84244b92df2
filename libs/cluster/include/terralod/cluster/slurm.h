#pragma once
// Slurm's user commands, as terralod uses them: submit an array job (sbatch), list this user's
// queued and running tasks (squeue), change a pending job's dependency (scontrol), cancel
// (scancel). No accounting database is needed (sacct is not used).

#include <map>
#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

struct SlurmSubmission {
  std::string name;                ///< --job-name
  std::string tasks;               ///< --array, e.g. "0-15" or "3"
  std::string output;              ///< --output pattern
  std::string dependency;          ///< --dependency, empty: none
  std::vector<std::string> extra;  ///< the user's sbatch options
  bool wholeNode = false;          ///< --exclusive (every CPU of a node; its threads use them)
  std::string command;             ///< run by sh (--wrap); $SLURM_ARRAY_TASK_ID is the task
};

/// Submits; returns the array job's id.
Result<std::string> sbatch(const SlurmSubmission& job);
/// This user's tasks that Slurm still holds as pending, running or finishing: id ("123_4") ->
/// squeue's reason (why it waits, e.g. "Dependency", "DependencyNeverSatisfied"; "None").
Result<std::map<std::string, std::string>> liveTasks();
Status setDependency(const std::string& job, const std::string& dependency);
/// Cancels jobs or tasks (ids as sbatch and liveTasks give them); errors are ignored.
void scancel(const std::vector<std::string>& jobs);

/// Splits "--a=1 --b 'x y'" into words (single and double quotes group, no other shell syntax).
std::vector<std::string> splitArguments(const std::string& text);
/// `text` quoted for sh.
std::string shellQuoted(const std::string& text);

}  // namespace terralod
