#pragma once
// Where the chunk loader's work runs: a pool of worker threads, or inline on demand (tests get
// deterministic order and timing by running posted tasks themselves).

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace terralod {

class TaskRunner {
 public:
  virtual ~TaskRunner() = default;
  /// Queues `task`; it runs once, on some thread, some time later. Thread-safe.
  virtual void post(std::function<void()> task) = 0;
};

/// Worker threads taking tasks first in, first out. The destructor finishes queued tasks.
class ThreadPool final : public TaskRunner {
 public:
  explicit ThreadPool(unsigned threads);
  ~ThreadPool() override;
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;
  void post(std::function<void()> task) override;

 private:
  void work();
  std::mutex mMutex;
  std::condition_variable mWake;
  std::deque<std::function<void()>> mTasks;
  bool mStopping = false;
  std::vector<std::thread> mThreads;
};

/// Holds tasks until runAll() / runOne() runs them on the calling thread.
class InlineRunner final : public TaskRunner {
 public:
  void post(std::function<void()> task) override;
  /// Runs tasks (including ones posted meanwhile) until none are left; returns how many ran.
  size_t runAll();
  /// Runs the oldest task, if any.
  bool runOne();
  size_t pending() const;

 private:
  mutable std::mutex mMutex;
  std::deque<std::function<void()>> mTasks;
};

}  // namespace terralod
