#include "terralod/runtime/task_runner.h"

namespace terralod {

ThreadPool::ThreadPool(unsigned threads) {
  for (unsigned i = 0; i < (threads ? threads : 1); ++i) mThreads.emplace_back([this] { work(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mMutex);
    mStopping = true;
  }
  mWake.notify_all();
  for (std::thread& t : mThreads) t.join();
}

void ThreadPool::post(std::function<void()> task) {
  {
    std::lock_guard lock(mMutex);
    mTasks.push_back(std::move(task));
  }
  mWake.notify_one();
}

void ThreadPool::work() {
  for (;;) {
    std::function<void()> task;
    {
      std::unique_lock lock(mMutex);
      mWake.wait(lock, [this] { return mStopping || !mTasks.empty(); });
      if (mTasks.empty()) return;  // stopping, and nothing left to finish
      task = std::move(mTasks.front());
      mTasks.pop_front();
    }
    task();
  }
}

void InlineRunner::post(std::function<void()> task) {
  std::lock_guard lock(mMutex);
  mTasks.push_back(std::move(task));
}

bool InlineRunner::runOne() {
  std::function<void()> task;
  {
    std::lock_guard lock(mMutex);
    if (mTasks.empty()) return false;
    task = std::move(mTasks.front());
    mTasks.pop_front();
  }
  task();
  return true;
}

size_t InlineRunner::runAll() {
  size_t n = 0;
  while (runOne()) ++n;
  return n;
}

size_t InlineRunner::pending() const {
  std::lock_guard lock(mMutex);
  return mTasks.size();
}

}  // namespace terralod
