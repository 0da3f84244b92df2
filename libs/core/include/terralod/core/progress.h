#pragma once
// Progress reporting for long jobs. The terminal implementation draws one updating line
// with a bar, percentage and ETA on stderr, and stays silent when stderr is not a terminal.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>

namespace terralod {

/// Receives progress of one stage at a time. advance() may be called from any thread.
class Progress {
 public:
  virtual ~Progress() = default;
  virtual void begin(std::string_view stage, uint64_t total) = 0;
  virtual void advance(uint64_t amount = 1) = 0;
  virtual void end() = 0;
};

/// Discards everything (tests, library use without a terminal).
class NullProgress final : public Progress {
 public:
  void begin(std::string_view, uint64_t) override {}
  void advance(uint64_t) override {}
  void end() override {}
};

/// A bar with ETA on stderr when it is a TTY; otherwise silent.
class TerminalProgress final : public Progress {
 public:
  TerminalProgress();
  void begin(std::string_view stage, uint64_t total) override;
  void advance(uint64_t amount = 1) override;
  void end() override;

 private:
  void draw(bool final);

  bool mEnabled;
  std::string mStage;
  uint64_t mTotal = 0;
  std::atomic<uint64_t> mDone{0};
  std::chrono::steady_clock::time_point mStart;
  std::chrono::steady_clock::time_point mLastDraw;
  std::mutex mDrawMutex;
};

/// Formats seconds as "12.3 s", "4 min 05 s" or "1 h 02 min".
std::string formatDuration(double seconds);

}  // namespace terralod
