#include "terralod/cluster/slurm_build.h"

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <thread>

#include "terralod/cluster/slurm.h"
#include "terralod/format/tileset_reader.h"

namespace terralod {
namespace {

namespace fs = std::filesystem;

// One task of a stage: the Slurm task running it now ("123_4"), how often it was submitted.
struct Task {
  std::string id;
  int submissions = 0;
  bool done = false;
};

struct StageJobs {
  BuildStage stage;
  std::string arrayId;  ///< the stage's first submission (later ones are single retries)
  std::vector<Task> tasks;
};

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

class SlurmDriver {
 public:
  SlurmDriver(const SlurmBuildOptions& options, const BuildPlan& plan, Progress& progress,
              const Warn& warn)
      : mOptions(options),
        mPlanned(plan.options),
        mJobs(plan.jobs),
        mProgress(progress),
        mWarn(warn) {}

  Status run() {
    mProgress.begin("jobs", totalTasks());
    Status status = submitFrom(0);
    while (status && !finished()) {
      waitForStep();
      status = step();
    }
    mProgress.end();
    if (!status) cancelAll();
    return status;
  }

 private:
  // Sleeps pollSeconds between looks at the queue, but wakes as soon as the last stage has
  // recorded its end (a file looked at every 50 ms): the build is done then, and a user (or a
  // script timing it) should not wait up to a poll more.
  void waitForStep() const {
    using Clock = std::chrono::steady_clock;
    const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(mOptions.pollSeconds));
    const std::string last =
        taskStatusPath(mOptions.work, kJobStages[std::size(kJobStages) - 1], 0, "ok");
    while (Clock::now() < until && !fs::exists(last))
      std::this_thread::sleep_for(
          std::min<Clock::duration>(std::chrono::milliseconds(50), until - Clock::now()));
  }

  size_t totalTasks() const {
    size_t n = 0;
    for (BuildStage s : kJobStages) n += perJob(s) ? size_t(mJobs) : 1;
    return n;
  }
  bool finished() const { return !mStages.empty() && mStages.back().tasks.front().done; }

  std::string command(BuildStage stage) const {
    std::string text = "exec";
    for (const std::string& word :
         stageProgram(mPlanned, stage, mOptions.executable, mOptions.stageExecutable))
      text += " " + shellQuoted(word);
    return text + " " + stageName(stage) + " " + shellQuoted(mOptions.work) +
           " --task $SLURM_ARRAY_TASK_ID";
  }
  SlurmSubmission submission(BuildStage stage, const std::string& tasks) const {
    SlurmSubmission job;
    job.name = std::string("terralod-") + stageName(stage);
    job.tasks = tasks;
    job.output = mOptions.work + "/logs/" + stageName(stage) + "-%A_%a.out";
    job.extra = mOptions.sbatchArgs;
    // The coarse job is alone on the critical path and builds its chunks on every thread.
    job.wholeNode = stage == BuildStage::kCoarse;
    job.command = command(stage);
    return job;
  }
  // Waits for the stage's tasks not yet seen done (those are done: depending on them could
  // name jobs Slurm has already forgotten). Empty when all are done.
  static std::string afterOk(const StageJobs& s) {
    std::string dependency;
    for (const Task& t : s.tasks)
      if (!t.done) dependency += ":" + t.id;
    return dependency.empty() ? dependency : "afterok" + dependency;
  }

  // Submits every stage from `first` on, each depending on the one before.
  Status submitFrom(size_t first) {
    mStages.resize(first);
    for (size_t i = first; i < std::size(kJobStages); ++i) {
      const BuildStage stage = kJobStages[i];
      const int count = perJob(stage) ? mJobs : 1;
      SlurmSubmission job = submission(stage, count > 1 ? "0-" + std::to_string(count - 1) : "0");
      if (i > first) job.dependency = afterOk(mStages.back());
      auto id = sbatch(job);
      if (!id) return id.error();
      StageJobs s{stage, *id, {}};
      for (int t = 0; t < count; ++t) s.tasks.push_back({*id + "_" + std::to_string(t), 1, false});
      mStages.push_back(std::move(s));
    }
    return {};
  }

  Status step() {
    // The queue first, then the status files: a task that records its end and leaves the queue
    // in between is then seen done, never lost.
    auto live = liveTasks();
    if (!live) return live.error();
    for (size_t i = 0; i < mStages.size(); ++i) {
      StageJobs& s = mStages[i];
      for (size_t t = 0; t < s.tasks.size(); ++t) {
        Task& task = s.tasks[t];
        if (task.done) continue;
        const int index = int(t);
        const std::string err = taskStatusPath(mOptions.work, s.stage, index, "err");
        if (fs::exists(err))
          return Error{readText(err) + " (" + stageName(s.stage) + " job " + task.id + ")"};
        if (fs::exists(taskStatusPath(mOptions.work, s.stage, index, "replan"))) {
          // Pass 1 again with the corrected height range (the plan is rewritten).
          if (mReplanned) return Error{"internal error: the reduce asked for a third pass 1"};
          mReplanned = true;
          cancelStages(i + 1);
          std::error_code ec;
          fs::remove(taskStatusPath(mOptions.work, s.stage, index, "replan"), ec);
          return submitFrom(0);
        }
        if (const std::string ok = taskStatusPath(mOptions.work, s.stage, index, "ok");
            fs::exists(ok)) {
          task.done = true;
          record(s.stage, readText(ok));
          mProgress.advance();
          continue;
        }
        const auto queued = live->find(task.id);
        if (queued == live->end()) {
          if (Status st = resubmit(i, t); !st) return st;
        } else if (queued->second == "DependencyNeverSatisfied" && i > 0) {
          // It waits on a task that failed and was submitted again after it: point it at the
          // stage before as it stands now.
          (void)setDependency(task.id, afterOk(mStages[i - 1]));
        }
      }
    }
    return {};
  }

  // A task left the queue without recording how it ended.
  Status resubmit(size_t stageIndex, size_t t) {
    StageJobs& s = mStages[stageIndex];
    Task& task = s.tasks[t];
    if (task.submissions > mOptions.retries)
      return Error{std::string(stageName(s.stage)) + " task " + std::to_string(t) +
                   " ended without finishing " + std::to_string(task.submissions) +
                   " times (killed, cancelled, out of memory or its node failed); its last log: " +
                   mOptions.work + "/logs/" + stageName(s.stage) + "-" +
                   task.id.substr(0, task.id.find('_')) + "_" + std::to_string(t) + ".out"};
    // A task cancelled while it waited still waits for the stage before.
    SlurmSubmission job = submission(s.stage, std::to_string(t));
    if (stageIndex > 0) job.dependency = afterOk(mStages[stageIndex - 1]);
    auto id = sbatch(job);
    if (!id) return id.error();
    const std::string lost = task.id;
    task.id = *id + "_" + std::to_string(t);
    mWarn(std::string(stageName(s.stage)) + " task " + std::to_string(t) + " (job " + lost +
          ") ended without finishing; submitted again as job " + task.id + " (retry " +
          std::to_string(task.submissions) + " of " + std::to_string(mOptions.retries) + ")");
    ++task.submissions;
    return redirectNextStage(stageIndex);
  }

  // The next stage's waiting tasks now wait for the stage as it stands: its first array (for
  // the tasks still in it) and each task submitted again on its own.
  Status redirectNextStage(size_t stageIndex) {
    if (stageIndex + 1 >= mStages.size()) return {};
    const StageJobs& next = mStages[stageIndex + 1];
    const std::string dependency = afterOk(mStages[stageIndex]);  // not empty: one was just sent
    std::set<std::string> targets;
    for (const Task& t : next.tasks)
      if (!t.done) targets.insert(t.id.rfind(next.arrayId + "_", 0) == 0 ? next.arrayId : t.id);
    // A task that has started or ended meanwhile cannot be redirected; one that started early
    // finds the stage before unfinished and leaves without a status, and is submitted again
    // like any lost task.
    for (const std::string& target : targets) (void)setDependency(target, dependency);
    return {};
  }

  void cancelStages(size_t first) {
    std::vector<std::string> ids;
    for (size_t i = first; i < mStages.size(); ++i)
      for (const Task& t : mStages[i].tasks)
        if (!t.done) ids.push_back(t.id);
    scancel(ids);
  }
  void cancelAll() { cancelStages(0); }

  // "seconds S peak_rss_mb M" from a task's .ok file.
  void record(BuildStage stage, const std::string& text) {
    double seconds = 0, rss = 0;
    std::sscanf(text.c_str(), "seconds %lf peak_rss_mb %lf", &seconds, &rss);
    StageFigures& f = mFigures[size_t(stage)];
    f.stage = stage;
    ++f.tasks;
    f.maxSeconds = std::max(f.maxSeconds, seconds);
    f.totalSeconds += seconds;
    f.maxRssMB = std::max(f.maxRssMB, rss);
  }

 public:
  std::vector<StageFigures> figures() const {
    return std::vector<StageFigures>(mFigures.begin(), mFigures.end());
  }

 private:
  const SlurmBuildOptions& mOptions;
  const BuildOptions& mPlanned;
  int mJobs;
  Progress& mProgress;
  const Warn& mWarn;
  std::vector<StageJobs> mStages;
  bool mReplanned = false;
  std::array<StageFigures, std::size(kJobStages)> mFigures{};
};

}  // namespace

Result<SlurmBuildResult> buildOnSlurm(const BuildOptions& options, const SlurmBuildOptions& slurm,
                                      Progress& progress, const Warn& warn) {
  const auto start = std::chrono::steady_clock::now();
  SlurmBuildOptions absolute = slurm;
  absolute.work = fs::absolute(slurm.work).lexically_normal().string();
  NullProgress quiet;
  auto plan = planStage(options, absolute.work, slurm.jobs, quiet, warn);
  if (!plan) return plan.error();
  std::error_code ec;
  fs::create_directories(absolute.work + "/logs", ec);
  if (ec) return makeError(absolute.work + "/logs", "cannot create: " + ec.message());
  SlurmDriver driver(absolute, *plan, progress, warn);
  if (Status s = driver.run(); !s) {
    cleanWorkDirectory(absolute.work, KeepLogs::kYes);
    return s.error();
  }
  cleanWorkDirectory(absolute.work, KeepLogs::kNo);
  auto reader = TilesetReader::openFile(plan->options.output);
  if (!reader) return reader.error();
  BuildSummary summary;
  summary.levels = int32_t((*reader)->header().levelCount);
  summary.chunks = (*reader)->nodes().size();
  for (const NodeRecord& n : (*reader)->nodes()) {
    summary.triangles += n.triangleCount;
    summary.vertices += n.vertexCount;
    summary.textureBytes += n.textureBytes;
  }
  summary.fileBytes = fs::file_size(plan->options.output, ec);
  summary.streamed = true;
  summary.totalSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return SlurmBuildResult{summary, driver.figures()};
}

}  // namespace terralod
