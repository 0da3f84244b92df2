#pragma once
// A thread with its own OpenGL context sharing the render context's objects, for GL work that
// must not stall a frame: allocating GPU memory ahead of need (drivers may commit and clear it
// at once; Mesa's llvmpipe does, at several ms per MB here). Jobs run in order; each job's GL
// work is finished (glFinish) before it is marked done, so the render thread can use what it
// made as soon as it sees done().

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "terralod/render/gl_context.h"

namespace terralod {

/// A posted job: done() turns true (on any thread's view) once its GL work has completed.
class GlJob {
 public:
  bool done() const { return mDone.load(std::memory_order_acquire); }

 private:
  friend class GlWorker;
  std::function<void()> mWork;
  std::atomic<bool> mDone{false};
};

class GlWorker {
 public:
  /// Starts the thread and makes `context` (from GlContext::createShared) current on it.
  /// Fails if the context cannot be made current there.
  static Result<std::unique_ptr<GlWorker>> start(std::unique_ptr<GlContext> context);
  /// Drops jobs not started, waits for the running one, and releases the context.
  ~GlWorker();
  GlWorker(const GlWorker&) = delete;
  GlWorker& operator=(const GlWorker&) = delete;

  /// Queues `work` (run on the worker with its context current). Any thread.
  std::shared_ptr<GlJob> post(std::function<void()> work);

 private:
  explicit GlWorker(std::unique_ptr<GlContext> context);
  void run();

  std::unique_ptr<GlContext> mContext;
  std::mutex mMutex;
  std::condition_variable mWake;
  std::deque<std::shared_ptr<GlJob>> mJobs;
  bool mStopping = false;
  bool mStarted = false;
  Status mStartStatus;
  std::thread mThread;
};

}  // namespace terralod
