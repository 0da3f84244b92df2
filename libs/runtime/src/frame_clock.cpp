#include "terralod/runtime/frame_clock.h"

#include <thread>

namespace terralod {

double SteadyFrameClock::nowMilliseconds() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - mOrigin)
      .count();
}

void SteadyFrameClock::sleepMicroseconds(double microseconds) {
  std::this_thread::sleep_for(std::chrono::duration<double, std::micro>(microseconds));
}

}  // namespace terralod
