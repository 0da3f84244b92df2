#include "terralod/render/gl_worker.h"

#include <epoxy/gl.h>

namespace terralod {

Result<std::unique_ptr<GlWorker>> GlWorker::start(std::unique_ptr<GlContext> context) {
  std::unique_ptr<GlWorker> worker(new GlWorker(std::move(context)));
  std::unique_lock lock(worker->mMutex);
  worker->mWake.wait(lock, [&] { return worker->mStarted; });
  if (!worker->mStartStatus) {
    Error error = worker->mStartStatus.error();
    lock.unlock();
    return error;  // the destructor joins the thread, which has already returned
  }
  return worker;
}

GlWorker::GlWorker(std::unique_ptr<GlContext> context) : mContext(std::move(context)) {
  mThread = std::thread([this] { run(); });
}

GlWorker::~GlWorker() {
  {
    std::lock_guard lock(mMutex);
    mStopping = true;
    mJobs.clear();
  }
  mWake.notify_all();
  if (mThread.joinable()) mThread.join();
}

std::shared_ptr<GlJob> GlWorker::post(std::function<void()> work) {
  auto job = std::make_shared<GlJob>();
  job->mWork = std::move(work);
  {
    std::lock_guard lock(mMutex);
    mJobs.push_back(job);
  }
  mWake.notify_one();
  return job;
}

void GlWorker::run() {
  Status current = mContext->makeCurrent();
  {
    std::lock_guard lock(mMutex);
    mStartStatus = current;
    mStarted = true;
  }
  mWake.notify_all();
  if (!current) return;
  for (;;) {
    std::shared_ptr<GlJob> job;
    {
      std::unique_lock lock(mMutex);
      mWake.wait(lock, [&] { return mStopping || !mJobs.empty(); });
      if (mStopping) break;
      job = std::move(mJobs.front());
      mJobs.pop_front();
    }
    job->mWork();
    glFinish();  // what the job made is complete before anyone is told
    job->mDone.store(true, std::memory_order_release);
  }
  mContext->releaseCurrent();
  // The context is destroyed with the worker, on the owner's thread, after the join.
}

}  // namespace terralod
