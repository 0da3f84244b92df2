#include "terralod/core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace terralod {

std::string formatDuration(double seconds) {
  char text[64];
  if (seconds < 60) {
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  } else if (seconds < 3600) {
    const int s = static_cast<int>(seconds + 0.5);
    std::snprintf(text, sizeof text, "%d min %02d s", s / 60, s % 60);
  } else {
    const int m = static_cast<int>(seconds / 60 + 0.5);
    std::snprintf(text, sizeof text, "%d h %02d min", m / 60, m % 60);
  }
  return text;
}

TerminalProgress::TerminalProgress() : mEnabled(isatty(STDERR_FILENO) == 1) {}

void TerminalProgress::begin(std::string_view stage, uint64_t total) {
  std::lock_guard lock(mDrawMutex);
  mStage = stage;
  mTotal = total;
  mDone = 0;
  mStart = mLastDraw = std::chrono::steady_clock::now();
}

void TerminalProgress::advance(uint64_t amount) {
  mDone.fetch_add(amount, std::memory_order_relaxed);
  if (!mEnabled) return;
  // Redraw at most ten times a second, and never make a worker wait for the terminal.
  std::unique_lock lock(mDrawMutex, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - mLastDraw < std::chrono::milliseconds(100)) return;
  mLastDraw = now;
  draw(false);
}

void TerminalProgress::end() {
  if (!mEnabled) return;
  std::lock_guard lock(mDrawMutex);
  mDone = mTotal;
  draw(true);
}

void TerminalProgress::draw(bool final) {
  const uint64_t done = std::min<uint64_t>(mDone.load(), mTotal);
  const double fraction = mTotal ? double(done) / double(mTotal) : 1.0;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(filled, '#');
  bar.resize(kWidth, ' ');
  std::string tail;
  if (final) {
    tail = "done in " + formatDuration(elapsed);
  } else if (fraction > 0.01 && elapsed > 0.5) {
    tail = formatDuration(elapsed * (1.0 - fraction) / fraction) + " left";
  }
  std::fprintf(stderr, "\r\033[K%-18s [%s] %3d%%  %s%s", mStage.c_str(), bar.c_str(),
               static_cast<int>(fraction * 100), tail.c_str(), final ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace terralod
