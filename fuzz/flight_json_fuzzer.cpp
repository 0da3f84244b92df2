// Fuzzes the flight file parser (parseFlight, what render, bench and view read from --flight
// and --play), then what the CLI does with an accepted flight: its cameras and their views.
// An accepted flight must also survive flightToJson and parse again to the same flight.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "terralod/runtime/flight.h"
#include "terralod/runtime/view.h"

namespace {

bool sameFlight(const terralod::Flight& a, const terralod::Flight& b) {
  if (a.fovDegrees != b.fovDegrees || a.width != b.width || a.height != b.height ||
      a.frames != b.frames || a.keyframes.size() != b.keyframes.size())
    return false;
  for (size_t i = 0; i < a.keyframes.size(); ++i)
    if (a.keyframes[i].eye != b.keyframes[i].eye || a.keyframes[i].target != b.keyframes[i].target)
      return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto flight = terralod::parseFlight(text, "fuzz.json");
  if (!flight) return 0;
  auto again = terralod::parseFlight(terralod::flightToJson(*flight), "again.json");
  if (!again || !sameFlight(*flight, *again)) __builtin_trap();
  // Up to a million frames are valid; a few thousand keep one input fast.
  if (flight->frames > 2000 || flight->keyframes.size() > 2000) return 0;
  for (const terralod::Camera& camera : terralod::flightCameras(*flight))
    (void)terralod::makeView(camera);
  return 0;
}
