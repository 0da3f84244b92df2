#pragma once
// The frame driver's clock: the per-frame upload budget and the waits of complete frames.
// Injected so tests run with a fake one (deterministic budgets, waits that run inline loads).

#include <chrono>

namespace terralod {

class FrameClock {
 public:
  virtual ~FrameClock() = default;
  /// Monotonic time in milliseconds (any origin).
  virtual double nowMilliseconds() = 0;
  /// Blocks for about `microseconds` (a complete frame waiting for its loads).
  virtual void sleepMicroseconds(double microseconds) = 0;
};

/// std::chrono::steady_clock and std::this_thread::sleep_for.
class SteadyFrameClock final : public FrameClock {
 public:
  double nowMilliseconds() override;
  void sleepMicroseconds(double microseconds) override;

 private:
  std::chrono::steady_clock::time_point mOrigin = std::chrono::steady_clock::now();
};

}  // namespace terralod
